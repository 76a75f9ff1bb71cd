// The hair directions' second moment for the fins' lighting (src/tangents.js), against moments
// worked out by hand for atlases of known directions.

import assert from 'node:assert/strict';
import { test } from 'node:test';

import { tangentMoments } from '../src/tangents.js';

// Three layers in a 2 × 2 atlas of 2-texel cells (the fourth cell unused).
const stack = { layers: 3, atlas: { columns: 2, rows: 2, tile: 2, width: 4, height: 4 } };

/** Atlases whose texel (x, y) holds `direction(x, y, layer)` (packed 0.5 d + 0.5) and `alpha(...)` coverage. */
function atlases( direction, alpha ) {

	const tangents = new Uint8Array( 4 * 16 );
	const shells = new Uint8Array( 4 * 16 );
	for ( let layer = 0; layer < stack.layers; layer ++ ) {

		const x0 = ( layer % 2 ) * 2;
		const y0 = Math.floor( layer / 2 ) * 2;
		for ( let y = y0; y < y0 + 2; y ++ ) {

			for ( let x = x0; x < x0 + 2; x ++ ) {

				const at = 4 * ( y * 4 + x );
				direction( x - x0, y - y0, layer ).forEach( ( c, k ) => {

					tangents[ at + k ] = Math.round( ( 0.5 * c + 0.5 ) * 255 );

				} );
				shells[ at + 3 ] = alpha( x - x0, y - y0, layer );

			}

		}

	}

	return { tangents, shells };

}

const close = ( a, b, eps ) => assert.ok( Math.abs( a - b ) <= eps, `${a} vs ${b}` );

test( 'hair straight up has all its moment along z; hair leaning both ways splits it', () => {

	const up = atlases( () => [ 0, 0, 1 ], () => 128 );
	const m = tangentMoments( up.tangents, up.shells, stack );
	// Within the packing's half step of straight up.
	[ 0, 0, 1, 0, 0, 0, 0, 0 ].forEach( ( e, k ) => close( m[ k ], e, 0.01 ) );

	// Half the texels lean 45° toward +x, half toward −x: E[x²] = E[z²] = ½, E[xz] = 0.
	const s = Math.SQRT1_2;
	const lean = atlases( ( x ) => [ x === 0 ? s : -s, 0, s ], () => 200 );
	const n = tangentMoments( lean.tangents, lean.shells, stack );
	close( n[ 0 ], 0.5, 0.01 );
	close( n[ 2 ], 0.5, 0.01 );
	close( n[ 4 ], 0, 0.01 );
	close( n[ 0 ] + n[ 1 ] + n[ 2 ], 1, 1e-3 );

} );

test( 'each texel weighs by its coverage, and the skin layer not at all', () => {

	// Layer 0 (the skin) along x under full coverage, layers 1 and 2 along y under a quarter and
	// z under three quarters: E[y²] = ¼, E[z²] = ¾.
	const axes = [ [ 1, 0, 0 ], [ 0, 1, 0 ], [ 0, 0, 1 ] ];
	const { tangents, shells } = atlases( ( x, y, layer ) => axes[ layer ], ( x, y, layer ) => [ 255, 51, 153 ][ layer ] );
	const m = tangentMoments( tangents, shells, stack );
	close( m[ 0 ], 0, 0.01 );
	close( m[ 1 ], 0.25, 0.01 );
	close( m[ 2 ], 0.75, 0.01 );

	// No hair at all: zeros, so that the fins fall back to the growth direction.
	const bald = atlases( () => [ 0, 0, 1 ], ( x, y, layer ) => ( layer === 0 ? 255 : 0 ) );
	assert.deepEqual( tangentMoments( bald.tangents, bald.shells, stack ), [ 0, 0, 0, 0, 0, 0, 0, 0 ] );

} );
