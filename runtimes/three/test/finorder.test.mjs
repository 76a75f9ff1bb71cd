// The fins' back-to-front order (src/finorder.js) against orders worked out by hand.

import assert from 'node:assert/strict';
import { test } from 'node:test';

import { backToFront, finCenters } from '../src/finorder.js';

/** The fins drawn in order, read back from the triangles' first corners. */
const drawn = ( indices ) => Array.from( { length: indices.length / 6 }, ( _, k ) => indices[ 6 * k ] / 4 );

test( 'fin centers are the midpoints of their edges at the skin', () => {

	// One fin: corners (a at the skin, b at the skin, a lifted, b lifted).
	const corners = new Float32Array( [ 0, 0, 0, 2, 0, 0, 0, 0, 5, 2, 0, 5 ] );
	assert.deepEqual( Array.from( finCenters( corners, 1 ) ), [ 1, 0, 0 ] );

} );

test( 'farthest fin first from a perspective eye; ties to the lower fin', () => {

	// Fins at z = 1, 5, 3, 5 seen from the origin: 1 and 3 tie at 5, then 2 (3), then 0 (1).
	const centers = new Float32Array( [ 0, 0, 1, 0, 0, 5, 0, 0, 3, 0, 0, 5 ] );
	const indices = backToFront( centers, [ 0, 0, 0, 1 ], new Uint16Array( 24 ) );
	assert.deepEqual( drawn( indices ), [ 1, 3, 2, 0 ] );
	// Each fin's two triangles as finGeometry builds them.
	assert.deepEqual( Array.from( indices.subarray( 0, 6 ) ), [ 4, 5, 7, 4, 7, 6 ] );

} );

test( 'an orthographic eye orders by depth along the direction toward the viewer', () => {

	// The viewer looks down −x from far along +x: the fin at x = −2 is farthest.
	const centers = new Float32Array( [ 1, 9, 0, -2, 0, 0, 0, -9, 0 ] );
	assert.deepEqual( drawn( backToFront( centers, [ 1, 0, 0, 0 ], new Uint32Array( 18 ) ) ), [ 1, 2, 0 ] );

} );
