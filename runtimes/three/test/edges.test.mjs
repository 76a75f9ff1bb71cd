// The fins' edge list (src/edges.js) and fin geometry (src/geometry.js) on small meshes.

import assert from 'node:assert/strict';
import { test } from 'node:test';

import { BufferGeometry, Float32BufferAttribute, Uint16BufferAttribute } from 'three';

import { finPlane, finQuads, meshEdges, weldVertices } from '../src/edges.js';
import { finGeometry, shellGeometry } from '../src/geometry.js';
import { FIN_SEED, unitRandom } from '../src/random.js';

// Two triangles of a unit square in z = 0 facing +z; vertex 4 is a seam copy of vertex 2.
const POSITIONS = new Float32Array( [ 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 1, 1, 0 ] );
const NORMALS = new Float32Array( [ 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1 ] );
const INDEX = [ 0, 1, 2, 0, 4, 3 ];

test( 'each edge is listed once, in the order the triangles name it', () => {

	assert.deepEqual( meshEdges( [ 0, 1, 2, 0, 2, 3 ] ), [ [ 0, 1 ], [ 1, 2 ], [ 0, 2 ], [ 2, 3 ], [ 0, 3 ] ] );

} );

test( 'seam copies are welded, so a seam edge gets one fin', () => {

	const canonical = weldVertices( POSITIONS, NORMALS );
	assert.deepEqual( Array.from( canonical ), [ 0, 1, 2, 3, 2 ] );
	assert.equal( meshEdges( INDEX ).length, 6 );
	assert.deepEqual( meshEdges( INDEX, canonical ), [ [ 0, 1 ], [ 1, 2 ], [ 0, 2 ], [ 2, 3 ], [ 0, 3 ] ] );

} );

test( 'a copy with another normal stays apart (a crease keeps both fins)', () => {

	const normals = NORMALS.slice();
	normals[ 12 ] = 1;
	assert.equal( weldVertices( POSITIONS, normals )[ 4 ], 4 );

} );

test( 'degenerate triangles add no edge', () => {

	assert.deepEqual( meshEdges( [ 0, 0, 1 ] ), [ [ 0, 1 ] ] );

} );

test( 'the fin plane is edge × summed normals; none where the normals run along the edge', () => {

	const plane = finPlane( [ 0, 0, 0 ], [ 2, 0, 0 ], [ 0, 0, 1 ], [ 0, 0, 1 ] );
	assert.equal( plane.length, 2 );
	assert.deepEqual( plane.normal.map( ( c ) => c + 0 ), [ 0, 1, 0 ] );
	assert.equal( finPlane( [ 0, 0, 0 ], [ 1, 0, 0 ], [ 1, 0, 0 ], [ 1, 0, 0 ] ), null );
	assert.equal( finPlane( [ 0, 0, 0 ], [ 0, 0, 0 ], [ 0, 0, 1 ], [ 0, 0, 1 ] ), null );

} );

test( 'fin texture intervals: u0 in [0, 1) from a fixed seed, u1 - u0 = edge length × uv_scale', () => {

	const edges = [ [ 0, 1 ], [ 1, 2 ], [ 0, 2 ] ];
	const quads = finQuads( edges, POSITIONS, NORMALS, [ 1, 1, 1 ], 2 );
	assert.equal( quads.length, 3 );
	for ( const [ k, q ] of quads.entries() ) {

		assert.ok( q.u0 >= 0 && q.u0 < 1 );
		assert.equal( q.u0, unitRandom( FIN_SEED, k ) );

	}

	assert.ok( Math.abs( quads[ 2 ].u1 - quads[ 2 ].u0 - 2 * Math.SQRT2 ) < 1e-12 );
	assert.deepEqual( finQuads( edges, POSITIONS, NORMALS, [ 1, 1, 1 ], 2 ), quads, 'deterministic' );

} );

test( 'edges bald at both ends get no fin', () => {

	const quads = finQuads( [ [ 0, 1 ], [ 1, 2 ] ], POSITIONS, NORMALS, [ 0, 0, 1 ], 1 );
	assert.deepEqual( quads.map( ( q ) => [ q.a, q.b ] ), [ [ 1, 2 ] ] );

} );

test( 'unitRandom spreads over [0, 1)', () => {

	const values = Array.from( { length: 1000 }, ( _, i ) => unitRandom( FIN_SEED, i ) );
	const mean = values.reduce( ( a, b ) => a + b ) / values.length;
	assert.ok( values.every( ( v ) => v >= 0 && v < 1 ) );
	assert.ok( Math.abs( mean - 0.5 ) < 0.05, `mean ${mean}` );

} );

function squareGeometry( skinned ) {

	const g = new BufferGeometry();
	g.setAttribute( 'position', new Float32BufferAttribute( POSITIONS, 3 ) );
	g.setAttribute( 'normal', new Float32BufferAttribute( NORMALS, 3 ) );
	g.setAttribute( 'uv1', new Float32BufferAttribute( new Float32Array( 10 ), 2 ) );
	g.setAttribute( 'color', new Float32BufferAttribute( new Float32Array( 20 ).fill( 1 ), 4 ) );
	g.setAttribute( '_pelt_length', new Float32BufferAttribute( new Float32Array( [ 1, 1, 1, 0.5, 1 ] ), 1 ) );
	for ( const name of [ '_pelt_comb', '_pelt_dpdu', '_pelt_dpdv' ] ) g.setAttribute( name, new Float32BufferAttribute( new Float32Array( 15 ), 3 ) );
	if ( skinned ) {

		g.setAttribute( 'skinIndex', new Uint16BufferAttribute( new Uint16Array( [ 0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, 2, 0, 0, 0 ] ), 4 ) );
		g.setAttribute( 'skinWeight', new Float32BufferAttribute( new Float32Array( 20 ).map( ( _, i ) => ( i % 4 === 0 ? 1 : 0 ) ), 4 ) );

	}

	g.setIndex( INDEX );
	return g;

}

const ATTRIBUTES = ( g ) => ( {
	uv: g.getAttribute( 'uv1' ), color: g.getAttribute( 'color' ), length: g.getAttribute( '_pelt_length' ),
	comb: g.getAttribute( '_pelt_comb' ), dpdu: g.getAttribute( '_pelt_dpdu' ), dpdv: g.getAttribute( '_pelt_dpdv' ),
} );

test( 'fin geometry: four corners per fin, each with its own end and the other end', () => {

	const g = squareGeometry( true );
	const fins = finGeometry( g, ATTRIBUTES( g ), { uv_scale: 1 } );
	assert.equal( fins.userData.fins, 5 );
	assert.equal( fins.getAttribute( 'position' ).count, 20 );
	assert.equal( fins.index.count, 30 );
	// Fin 1 stands on edge (1, 2): corners 1-2-1-2 at own ends, 2-1-2-1 as other ends.
	const at = ( name, corner ) => Array.from( fins.getAttribute( name ).array.slice( 3 * corner, 3 * corner + 3 ) );
	assert.deepEqual( at( 'position', 4 ), [ 1, 0, 0 ] );
	assert.deepEqual( at( 'peltOther', 4 ), [ 1, 1, 0 ] );
	assert.deepEqual( at( 'position', 5 ), [ 1, 1, 0 ] );
	assert.deepEqual( at( 'peltOther', 5 ), [ 1, 0, 0 ] );
	// u, v (1 at the skin, 0 at the top), length of the own end.
	assert.equal( at( 'peltFin', 4 )[ 1 ], 1 );
	assert.equal( at( 'peltFin', 6 )[ 1 ], 0 );
	assert.equal( fins.getAttribute( 'skinIndex' ).getX( 5 ), 2 );
	assert.equal( fins.getAttribute( 'peltOtherJoints' ).getX( 5 ), 1 );
	assert.deepEqual( Array.from( fins.index.array.slice( 6, 12 ) ), [ 4, 5, 7, 4, 7, 6 ] );

} );

test( 'unskinned fins carry no joints', () => {

	const g = squareGeometry( false );
	const fins = finGeometry( g, ATTRIBUTES( g ), { uv_scale: 1 } );
	assert.equal( fins.getAttribute( 'skinIndex' ), undefined );
	assert.equal( fins.getAttribute( 'peltOtherJoints' ), undefined );

} );

test( 'the shells share the skin\'s buffers and draw one instance per shell', () => {

	const g = squareGeometry( true );
	const shells = shellGeometry( g, ATTRIBUTES( g ), 7 );
	assert.equal( shells.instanceCount, 7 );
	assert.equal( shells.index, g.index );
	assert.equal( shells.getAttribute( 'position' ), g.getAttribute( 'position' ) );
	assert.equal( shells.getAttribute( 'peltLength' ), g.getAttribute( '_pelt_length' ) );
	assert.equal( shells.getAttribute( 'skinWeight' ), g.getAttribute( 'skinWeight' ) );

} );
