// The fur's geometry, built once per skin primitive: the shells as one instanced draw of the
// skin's own vertex buffers (shells.wgsl: instance i is shell i + 1), the fins as one quad per
// edge (crates/pelt-render/src/fin_mesh.rs layout: corners a, b at the skin, then a, b at the top).

import {
	BufferAttribute,
	BufferGeometry,
	Float32BufferAttribute,
	InstancedBufferGeometry,
	Uint16BufferAttribute,
	Uint32BufferAttribute,
} from 'three';

import { vertexCurvature } from './curvature.js';
import { threeAttributeName } from './extension.js';
import { finQuads, meshEdges, weldVertices } from './edges.js';

// The extension's attributes under the names the fur shaders read.
const SHADER_NAMES = { uv: 'peltUv', color: 'peltColor', length: 'peltLength', comb: 'peltComb', dpdu: 'peltDpdu', dpdv: 'peltDpdv' };

/** The skin geometry's attributes the extension names, keyed as `ext.attributes`. */
export function furAttributes( geometry, ext ) {

	const out = {};
	for ( const [ key, gltfName ] of Object.entries( ext.attributes ) ) {

		const name = threeAttributeName( gltfName );
		const attribute = geometry.getAttribute( name );
		if ( ! attribute ) throw new Error( `PELT_shell_fur: the primitive has no ${gltfName} attribute (three.js "${name}")` );
		out[ key ] = attribute;

	}

	for ( const name of [ 'position', 'normal' ] ) {

		if ( ! geometry.getAttribute( name ) ) throw new Error( `PELT_shell_fur: the primitive has no ${name} attribute` );

	}

	return out;

}

/** Adds the shader names of the extension's attributes to `geometry` (the same buffers). */
export function aliasFurAttributes( geometry, attributes ) {

	for ( const [ key, attribute ] of Object.entries( attributes ) ) geometry.setAttribute( SHADER_NAMES[ key ], attribute );
	return geometry;

}

/** Every shell in one instanced draw over the skin's buffers; `curvature` as skinCurvature gives. */
export function shellGeometry( skin, attributes, shells, curvature = skinCurvature( skin ) ) {

	const g = new InstancedBufferGeometry();
	g.setIndex( skin.index );
	for ( const name of [ 'position', 'normal', 'skinIndex', 'skinWeight' ] ) {

		if ( skin.getAttribute( name ) ) g.setAttribute( name, skin.getAttribute( name ) );

	}

	aliasFurAttributes( g, attributes );
	g.setAttribute( 'peltCurvature', new Float32BufferAttribute( curvature, 1 ) );
	g.instanceCount = shells;
	if ( skin.boundingSphere ) g.boundingSphere = skin.boundingSphere.clone();
	if ( skin.boundingBox ) g.boundingBox = skin.boundingBox.clone();
	return g;

}

/** The skin's curvature per vertex at rest (src/curvature.js), for the PRT light's terminator band. */
export function skinCurvature( skin ) {

	const position = flat( skin.getAttribute( 'position' ), 3 );
	const index = skin.index ? skin.index.array : Uint32Array.from( { length: position.length / 3 }, ( _, i ) => i );
	return vertexCurvature( position, flat( skin.getAttribute( 'normal' ), 3 ), index );

}

/** An attribute's values as a flat Float32Array of `size` components (interleaved, normalized). */
function flat( attribute, size ) {

	const out = new Float32Array( attribute.count * size );
	const get = [ 'getX', 'getY', 'getZ', 'getW' ];
	for ( let i = 0; i < attribute.count; i ++ ) {

		for ( let c = 0; c < size; c ++ ) {

			out[ i * size + c ] = c < attribute.itemSize ? attribute[ get[ c ] ]( i ) : ( c === 3 ? 1 : 0 );

		}

	}

	return out;

}

/** The fins' geometry (null when no edge has a fin), from the skin's vertices at rest. */
export function finGeometry( skin, attributes, stack, curvature = skinCurvature( skin ) ) {

	const position = flat( skin.getAttribute( 'position' ), 3 );
	const normal = flat( skin.getAttribute( 'normal' ), 3 );
	const length = flat( attributes.length, 1 );
	const index = skin.index ? skin.index.array : Uint32Array.from( { length: position.length / 3 }, ( _, i ) => i );
	const edges = meshEdges( index, weldVertices( position, normal ) );
	const quads = finQuads( edges, position, normal, length, stack.uv_scale );
	if ( quads.length === 0 ) return null;

	const skinned = !! ( skin.getAttribute( 'skinIndex' ) && skin.getAttribute( 'skinWeight' ) );
	// Per corner: what it reads of its own end and of the other end.
	const own = {
		position: [ position, 3 ],
		normal: [ normal, 3 ],
		peltComb: [ flat( attributes.comb, 3 ), 3 ],
		peltColor: [ flat( attributes.color, 4 ), 4 ],
		peltDpdu: [ flat( attributes.dpdu, 3 ), 3 ],
		peltDpdv: [ flat( attributes.dpdv, 3 ), 3 ],
		peltCurvature: [ curvature, 1 ],
	};
	const other = { peltOther: [ position, 3 ], peltOtherNormal: [ normal, 3 ], peltOtherComb: own.peltComb };
	let joints = null;
	let weights = null;
	if ( skinned ) {

		joints = flat( skin.getAttribute( 'skinIndex' ), 4 );
		weights = flat( skin.getAttribute( 'skinWeight' ), 4 );
		own.skinWeight = [ weights, 4 ];
		other.peltOtherJoints = [ joints, 4 ];
		other.peltOtherWeights = [ weights, 4 ];

	}

	const corners = 4 * quads.length;
	const out = {};
	for ( const [ name, [ , size ] ] of Object.entries( { ...own, ...other } ) ) out[ name ] = new Float32Array( corners * size );
	const fin = new Float32Array( corners * 3 );
	const skinIndex = skinned ? new Uint16Array( corners * 4 ) : null;
	const copy = ( name, [ source, size ], corner, vertex ) => {

		out[ name ].set( source.subarray( vertex * size, vertex * size + size ), corner * size );

	};

	quads.forEach( ( q, f ) => {

		// (end, other end, u, v): v = 1 at the skin, 0 at the top of the fur.
		const layout = [ [ q.a, q.b, q.u0, 1 ], [ q.b, q.a, q.u1, 1 ], [ q.a, q.b, q.u0, 0 ], [ q.b, q.a, q.u1, 0 ] ];
		layout.forEach( ( [ end, far, u, v ], k ) => {

			const corner = 4 * f + k;
			for ( const [ name, spec ] of Object.entries( own ) ) copy( name, spec, corner, end );
			for ( const [ name, spec ] of Object.entries( other ) ) copy( name, spec, corner, far );
			fin.set( [ u, v, length[ end ] ], 3 * corner );
			if ( skinned ) skinIndex.set( joints.subarray( 4 * end, 4 * end + 4 ), 4 * corner );

		} );

	} );

	const g = new BufferGeometry();
	for ( const [ name, [ , size ] ] of Object.entries( { ...own, ...other } ) ) g.setAttribute( name, new Float32BufferAttribute( out[ name ], size ) );
	g.setAttribute( 'peltFin', new Float32BufferAttribute( fin, 3 ) );
	if ( skinned ) g.setAttribute( 'skinIndex', new Uint16BufferAttribute( skinIndex, 4 ) );
	// fins.rs quad_triangles: [0, 1, 3, 0, 3, 2] per quad.
	const indices = corners > 65535 ? new Uint32Array( 6 * quads.length ) : new Uint16Array( 6 * quads.length );
	quads.forEach( ( _, f ) => indices.set( [ 0, 1, 3, 0, 3, 2 ].map( ( k ) => 4 * f + k ), 6 * f ) );
	g.setIndex( corners > 65535 ? new Uint32BufferAttribute( indices, 1 ) : new BufferAttribute( indices, 1 ) );
	g.computeBoundingSphere();
	g.userData.fins = quads.length;
	return g;

}
