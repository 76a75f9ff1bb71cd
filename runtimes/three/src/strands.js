// The guard hairs of a fur (docs/export.md, "Guard hairs"): the extension's `LINES` primitive,
// which three.js loads as plain lines, drawn instead as ribbons facing the eye (glsl/strands.js),
// skinned like the skin; every corner also carries its strand's root and LOD rank. Each segment becomes a quad of four corners that carry both its ends, so
// the vertex shader turns it toward the eye; no geometry shader (WebGL has none).

import { BufferAttribute, BufferGeometry } from 'three';

import { threeAttributeName } from './extension.js';

/**
 * Each point's share of its strand (0 at the root, 1 at the tip), its strand's unit root-to-tip
 * direction and its root point, from the segments `pairs` (each point paired with the next of
 * its strand). A point no segment reaches is a root; a malformed chain stops after `count` steps.
 */
export function strandShape( positions, pairs, count ) {

	const next = new Int32Array( count ).fill( - 1 );
	const reached = new Uint8Array( count );
	for ( let s = 0; s < pairs.length; s += 2 ) {

		next[ pairs[ s ] ] = pairs[ s + 1 ];
		reached[ pairs[ s + 1 ] ] = 1;

	}

	const height = new Float32Array( count );
	const direction = new Float32Array( 3 * count );
	const rootOf = Int32Array.from( { length: count }, ( _, p ) => p );
	const chain = [];
	for ( let root = 0; root < count; root ++ ) {

		if ( reached[ root ] || next[ root ] < 0 ) continue;
		chain.length = 0;
		for ( let p = root; p >= 0 && chain.length <= count; p = next[ p ] ) chain.push( p );
		const tip = chain[ chain.length - 1 ];
		const d = [ 0, 1, 2 ].map( ( c ) => positions[ 3 * tip + c ] - positions[ 3 * root + c ] );
		const length = Math.hypot( ...d ) || 1;
		chain.forEach( ( p, k ) => {

			height[ p ] = k / ( chain.length - 1 );
			rootOf[ p ] = root;
			for ( let c = 0; c < 3; c ++ ) direction[ 3 * p + c ] = d[ c ] / length;

		} );

	}

	return { height, direction, rootOf };

}

/**
 * A strand's rank for the strand LOD, uniform in [0, 1) and fixed by its root point's index
 * (the PCG output function over it): the LOD keeps the strands of rank below a share.
 */
export function strandRank( root ) {

	let h = Math.imul( root >>> 0, 747796405 ) + 2891336453 >>> 0;
	h = Math.imul( ( h >>> ( ( h >>> 28 ) + 4 ) ) ^ h, 277803737 ) >>> 0;
	h = ( ( h >>> 22 ) ^ h ) >>> 0;
	return ( h >>> 8 ) / 16777216;

}

/**
 * The ribbons' geometry from the lines' geometry: four corners per segment (near end twice, far
 * end twice), two triangles; `radius` is the glTF name of the radius attribute, `furDepth` the
 * stack's (object units). With the root normals the exporter writes (`NORMAL`), a point's
 * height is its rise above the root along the normal in fur depths (painted lengths taken as
 * 1), as the renderer's; without, its share of the strand, and the strand's direction stands in
 * for the normal.
 */
export function ribbonGeometry( lines, radius, furDepth = 1 ) {

	const position = lines.getAttribute( 'position' );
	const color = lines.getAttribute( 'color' );
	const radii = lines.getAttribute( threeAttributeName( radius ) );
	if ( ! position || ! color || ! radii ) throw new Error( `PELT_shell_fur guard hairs: the LINES primitive lacks POSITION, COLOR_0 or ${radius}` );
	const count = position.count;
	const pairs = lines.index ? lines.index.array : Uint32Array.from( { length: count - ( count % 2 ) }, ( _, i ) => i );
	const points = new Float32Array( count * 3 );
	for ( let p = 0; p < count; p ++ ) points.set( [ position.getX( p ), position.getY( p ), position.getZ( p ) ], 3 * p );
	const shape = strandShape( points, pairs, count );
	const normals = lines.getAttribute( 'normal' );
	const rootNormal = shape.direction;
	const height = shape.height;
	if ( normals ) {

		for ( let p = 0; p < count; p ++ ) {

			const n = [ normals.getX( p ), normals.getY( p ), normals.getZ( p ) ];
			const r = shape.rootOf[ p ];
			const rise = [ 0, 1, 2 ].reduce( ( sum, c ) => sum + n[ c ] * ( points[ 3 * p + c ] - points[ 3 * r + c ] ), 0 );
			rootNormal.set( n, 3 * p );
			height[ p ] = Math.max( rise, 0 ) / furDepth;

		}

	}

	const skinIndex = lines.getAttribute( 'skinIndex' );
	const skinWeight = lines.getAttribute( 'skinWeight' );

	const segments = pairs.length / 2;
	const corners = 4 * segments;
	const out = {
		position: new Float32Array( 3 * corners ),
		peltSegment: new Float32Array( 3 * corners ),
		peltSide: new Float32Array( corners ),
		peltRadius: new Float32Array( corners ),
		peltColor: new Float32Array( 4 * corners ),
		peltRootNormal: new Float32Array( 3 * corners ),
		peltHeight: new Float32Array( corners ),
		peltRoot: new Float32Array( 4 * corners ),
		peltRootRadius: new Float32Array( corners ),
	};
	if ( skinIndex && skinWeight ) {

		out.skinIndex = new Uint16Array( 4 * corners );
		out.skinWeight = new Float32Array( 4 * corners );

	}

	// Segments in order of their strand's LOD rank, so that the strands a frame keeps are one
	// range of the index buffer (`strandLod`: each strand's rank and where its segments end).
	const rankOf = ( s ) => strandRank( shape.rootOf[ pairs[ 2 * s ] ] );
	const order = Uint32Array.from( { length: segments }, ( _, s ) => s );
	const ranks = Float32Array.from( order, rankOf );
	order.sort( ( a, b ) => ranks[ a ] - ranks[ b ] || a - b );
	const lod = { ranks: [], ends: [], maxRootRadius: 0 };
	const index = new Uint32Array( 6 * segments );
	for ( let i = 0; i < segments; i ++ ) {

		const s = order[ i ];
		const ends = [ pairs[ 2 * s ], pairs[ 2 * s + 1 ] ];
		const strandRoot = shape.rootOf[ ends[ 0 ] ];
		if ( lod.ranks.length === 0 || shape.rootOf[ pairs[ 2 * order[ i - 1 ] ] ] !== strandRoot ) {

			lod.ranks.push( ranks[ s ] );
			lod.ends.push( 0 );
			lod.maxRootRadius = Math.max( lod.maxRootRadius, radii.getX( strandRoot ) );

		}

		lod.ends[ lod.ends.length - 1 ] = 6 * ( i + 1 );
		const segment = [ 0, 1, 2 ].map( ( c ) => points[ 3 * ends[ 1 ] + c ] - points[ 3 * ends[ 0 ] + c ] );
		for ( let k = 0; k < 4; k ++ ) {

			const v = 4 * i + k;
			const p = ends[ k >> 1 ];
			out.position.set( points.subarray( 3 * p, 3 * p + 3 ), 3 * v );
			out.peltSegment.set( segment, 3 * v );
			out.peltSide[ v ] = ( k & 1 ) ? 1 : - 1;
			out.peltRadius[ v ] = radii.getX( p );
			out.peltColor.set( [ color.getX( p ), color.getY( p ), color.getZ( p ), color.itemSize > 3 ? color.getW( p ) : 1 ], 4 * v );
			out.peltRootNormal.set( rootNormal.subarray( 3 * p, 3 * p + 3 ), 3 * v );
			out.peltHeight[ v ] = height[ p ];
			const root = shape.rootOf[ p ];
			out.peltRoot.set( [ points[ 3 * root ], points[ 3 * root + 1 ], points[ 3 * root + 2 ], strandRank( root ) ], 4 * v );
			out.peltRootRadius[ v ] = radii.getX( root );
			if ( out.skinIndex ) {

				out.skinIndex.set( [ skinIndex.getX( p ), skinIndex.getY( p ), skinIndex.getZ( p ), skinIndex.getW( p ) ], 4 * v );
				out.skinWeight.set( [ skinWeight.getX( p ), skinWeight.getY( p ), skinWeight.getZ( p ), skinWeight.getW( p ) ], 4 * v );

			}

		}

		index.set( [ 4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 2, 4 * i + 1, 4 * i + 3 ], 6 * i );

	}

	const geometry = new BufferGeometry();
	const sizes = { position: 3, peltSegment: 3, peltSide: 1, peltRadius: 1, peltColor: 4, peltRootNormal: 3, peltHeight: 1, peltRoot: 4, peltRootRadius: 1, skinIndex: 4, skinWeight: 4 };
	for ( const [ name, array ] of Object.entries( out ) ) geometry.setAttribute( name, new BufferAttribute( array, sizes[ name ] ) );
	geometry.setIndex( new BufferAttribute( index, 1 ) );
	geometry.userData.strandLod = { ranks: Float32Array.from( lod.ranks ), ends: Uint32Array.from( lod.ends ), maxRootRadius: lod.maxRootRadius };
	return geometry;

}

/**
 * Indices to draw of `lod` (ribbonGeometry's `strandLod`) when the nearest of the strands' roots
 * is `pixelsPerUnit` pixels per object unit (crates/pelt-render/src/strands.rs kept_strands): the strands of
 * rank below what the shader may keep there, a quarter more for its own measure.
 */
export function keptIndices( lod, pixelsPerUnit, strandPixels, minKept ) {

	if ( ! ( strandPixels > 0 ) || ! Number.isFinite( pixelsPerUnit ) ) return lod.ends.length ? lod.ends[ lod.ends.length - 1 ] : 0;
	const keep = 1.25 * Math.max( 2 * lod.maxRootRadius * pixelsPerUnit / strandPixels, minKept );
	let kept = 0;
	while ( kept < lod.ranks.length && lod.ranks[ kept ] < keep ) kept ++;
	return kept === 0 ? 0 : lod.ends[ kept - 1 ];

}
