// The fins' edges (Lengyel et al. 2001, §2.3, Figure 3; crates/pelt-core/src/mesh/fins.rs): one fin per mesh edge,
// built once on the CPU from the index buffer. The exporter splits vertices at patch seams, so
// copies of one vertex (same position and normal) are welded first: a seam edge gets one fin,
// not one per side.

import { FIN_SEED, unitRandom } from './random.js';

/**
 * For each vertex, the first vertex with the same position and normal (bit for bit): the copies
 * a seam split made share it.
 */
export function weldVertices( positions, normals ) {

	const count = positions.length / 3;
	const canonical = new Uint32Array( count );
	const seen = new Map();
	// The key is the six floats' bit patterns.
	const p = new Float32Array( 6 );
	const u = new Uint32Array( p.buffer );
	for ( let i = 0; i < count; i ++ ) {

		for ( let c = 0; c < 3; c ++ ) {

			p[ c ] = positions[ 3 * i + c ];
			p[ 3 + c ] = normals ? normals[ 3 * i + c ] : 0;

		}

		const key = `${u[ 0 ]},${u[ 1 ]},${u[ 2 ]},${u[ 3 ]},${u[ 4 ]},${u[ 5 ]}`;
		const first = seen.get( key );
		if ( first === undefined ) {

			seen.set( key, i );
			canonical[ i ] = i;

		} else {

			canonical[ i ] = first;

		}

	}

	return canonical;

}

/**
 * The mesh's edges as pairs `[a, b]` (a < b, welded vertex indices), each once, in the order
 * the triangles first name them. `index` lists triangles (three indices each); `canonical` is
 * weldVertices' table, or none to keep vertices apart.
 */
export function meshEdges( index, canonical ) {

	const edges = [];
	const seen = new Set();
	const at = canonical ? ( i ) => canonical[ i ] : ( i ) => i;
	for ( let t = 0; t + 2 < index.length; t += 3 ) {

		for ( let k = 0; k < 3; k ++ ) {

			let a = at( index[ t + k ] );
			let b = at( index[ t + ( k + 1 ) % 3 ] );
			if ( a === b ) continue;
			if ( a > b ) [ a, b ] = [ b, a ];
			// Vertex counts stay below 2^26, so the pair fits a double exactly.
			const key = a * 67108864 + b;
			if ( seen.has( key ) ) continue;
			seen.add( key );
			edges.push( [ a, b ] );

		}

	}

	return edges;

}

/**
 * Unit normal of the fin plane over an edge (edge × the sum of the end normals) and the edge's
 * length, or null where there is no plane (crates/pelt-core/src/mesh/fins.rs `fin_plane`).
 */
export function finPlane( pa, pb, na, nb ) {

	const e = [ pb[ 0 ] - pa[ 0 ], pb[ 1 ] - pa[ 1 ], pb[ 2 ] - pa[ 2 ] ];
	const len = Math.hypot( e[ 0 ], e[ 1 ], e[ 2 ] );
	const n = [ na[ 0 ] + nb[ 0 ], na[ 1 ] + nb[ 1 ], na[ 2 ] + nb[ 2 ] ];
	const f = [ n[ 1 ] * e[ 2 ] - n[ 2 ] * e[ 1 ], n[ 2 ] * e[ 0 ] - n[ 0 ] * e[ 2 ], n[ 0 ] * e[ 1 ] - n[ 1 ] * e[ 0 ] ];
	const fLen = Math.hypot( f[ 0 ], f[ 1 ], f[ 2 ] );
	if ( len === 0 || ! ( fLen > 1e-9 * len ) ) return null;
	return { normal: f.map( ( c ) => c / fLen ), length: len };

}

/**
 * The fins: for every edge with a fin plane and fur at an end, `{a, b, u0, u1}` with the fin
 * texture running from u0 (random in [0, 1), fixed seed, by edge number) to u0 + edge length ·
 * uvScale (docs/export.md, "Conventions": Fins).
 */
export function finQuads( edges, positions, normals, lengths, uvScale, seed = FIN_SEED ) {

	const vec = ( array, i ) => [ array[ 3 * i ], array[ 3 * i + 1 ], array[ 3 * i + 2 ] ];
	const quads = [];
	edges.forEach( ( [ a, b ], k ) => {

		if ( ! ( lengths[ a ] > 0 || lengths[ b ] > 0 ) ) return;
		const plane = finPlane( vec( positions, a ), vec( positions, b ), vec( normals, a ), vec( normals, b ) );
		if ( plane === null ) return;
		const u0 = unitRandom( seed, k );
		quads.push( { a, b, u0, u1: u0 + plane.length * uvScale } );

	} );
	return quads;

}
