// The guard hairs' ribbons (src/strands.js): each point's height along its strand and the
// strand's direction, and four corners per segment carrying both its ends.

import assert from 'node:assert/strict';
import { test } from 'node:test';

import { BufferAttribute, BufferGeometry } from 'three';

import { keptIndices, ribbonGeometry, strandRank, strandShape } from '../src/strands.js';

// Two strands as the exporter writes them: points root first, each paired with the next.
// Strand A: 0 → 1 → 2 straight up z; strand B: 3 → 4 along x.
const POSITIONS = new Float32Array( [ 0, 0, 0, 0, 0, 1, 0, 0, 2, 5, 0, 0, 7, 0, 0 ] );
const PAIRS = new Uint32Array( [ 0, 1, 1, 2, 3, 4 ] );

/** The two strands as three.js loads the exporter's LINES primitive. */
function linesGeometry() {

	const lines = new BufferGeometry();
	lines.setAttribute( 'position', new BufferAttribute( POSITIONS, 3 ) );
	lines.setAttribute( 'color', new BufferAttribute( new Float32Array( 20 ).fill( 0.5 ), 4 ) );
	lines.setAttribute( '_pelt_radius', new BufferAttribute( new Float32Array( [ 0.1, 0.05, 0.01, 0.2, 0.1 ] ), 1 ) );
	lines.setIndex( new BufferAttribute( PAIRS, 1 ) );
	return lines;

}

test( 'heights run from 0 at the root to 1 at the tip, directions root to tip', () => {

	const { height, direction } = strandShape( POSITIONS, PAIRS, 5 );
	assert.deepEqual( [ ...height ], [ 0, 0.5, 1, 0, 1 ] );
	assert.deepEqual( [ ...direction.subarray( 0, 9 ) ], [ 0, 0, 1, 0, 0, 1, 0, 0, 1 ] );
	assert.deepEqual( [ ...direction.subarray( 9, 15 ) ], [ 1, 0, 0, 1, 0, 0 ] );

} );

test( 'a malformed chain (a loop) ends instead of hanging', () => {

	const { height } = strandShape( POSITIONS, new Uint32Array( [ 0, 1, 1, 0 ] ), 5 );
	assert.ok( height.every( Number.isFinite ) );

} );

test( 'each segment becomes four corners with both ends and two triangles', () => {

	const lines = linesGeometry();
	const ribbons = ribbonGeometry( lines, '_PELT_RADIUS' );
	assert.equal( ribbons.getAttribute( 'position' ).count, 12 );
	assert.equal( ribbons.index.count, 18 );
	// Segment 1 (points 1 → 2): corners 4, 5 at point 1, corners 6, 7 at point 2.
	const position = ribbons.getAttribute( 'position' );
	assert.deepEqual( [ 4, 5, 6, 7 ].map( ( v ) => position.getZ( v ) ), [ 1, 1, 2, 2 ] );
	assert.deepEqual( [ 4, 5, 6, 7 ].map( ( v ) => ribbons.getAttribute( 'peltSide' ).getX( v ) ), [ - 1, 1, - 1, 1 ] );
	assert.deepEqual( [ 4, 5, 6, 7 ].map( ( v ) => ribbons.getAttribute( 'peltRadius' ).getX( v ) ), [ 0.05, 0.05, 0.01, 0.01 ].map( Math.fround ) );
	const segment = ribbons.getAttribute( 'peltSegment' );
	for ( const v of [ 4, 5, 6, 7 ] ) assert.deepEqual( [ segment.getX( v ), segment.getY( v ), segment.getZ( v ) ], [ 0, 0, 1 ] );
	assert.deepEqual( [ 4, 5, 6, 7 ].map( ( v ) => ribbons.getAttribute( 'peltHeight' ).getX( v ) ), [ 0.5, 0.5, 1, 1 ] );
	// Without the radius attribute the file is refused by name.
	lines.deleteAttribute( '_pelt_radius' );
	assert.throws( () => ribbonGeometry( lines, '_PELT_RADIUS' ), /_PELT_RADIUS/ );

} );

test( 'strand ranks are fixed by the root and spread evenly over [0, 1)', () => {

	const ranks = Array.from( { length: 20_000 }, ( _, i ) => strandRank( i ) );
	assert.ok( ranks.every( ( r ) => r >= 0 && r < 1 ) );
	assert.equal( strandRank( 17 ), strandRank( 17 ) );
	// Each tenth of [0, 1) holds a tenth of them, to 5 %.
	const tenths = new Array( 10 ).fill( 0 );
	for ( const r of ranks ) tenths[ Math.floor( r * 10 ) ] ++;
	for ( const count of tenths ) assert.ok( Math.abs( count - 2000 ) < 100, `${tenths}` );

} );

test( 'segments run in order of their strand\'s rank, and the LOD draws a prefix of them', () => {

	const lines = linesGeometry();
	const lod = ribbonGeometry( lines, '_PELT_RADIUS' ).userData.strandLod;
	const [ a, b ] = [ strandRank( 0 ), strandRank( 3 ) ];
	// Strand A (root 0, two segments) and strand B (root 3, one), by rank.
	assert.deepEqual( [ ...lod.ranks ], [ Math.fround( Math.min( a, b ) ), Math.fround( Math.max( a, b ) ) ] );
	assert.deepEqual( [ ...lod.ends ], a < b ? [ 12, 18 ] : [ 6, 18 ] );
	assert.equal( lod.maxRootRadius, Math.fround( 0.2 ) );
	// Thick on screen: every strand; no LOD: every strand; far: the lower-ranked strand or none.
	assert.equal( keptIndices( lod, 100, 1, 1 / 16 ), 18 );
	assert.equal( keptIndices( lod, 1e-6, 0, 1 / 16 ), 18 );
	const far = keptIndices( lod, 1e-6, 1, 1 / 16 );
	const expected = [ a, b ].filter( ( r ) => r < 1.25 / 16 ).length;
	assert.equal( far, [ 0, lod.ends[ 0 ], 18 ][ expected ] );

} );
