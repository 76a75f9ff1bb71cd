// The skin's curvature per vertex (src/curvature.js) against its analytic value.

import assert from 'node:assert/strict';
import { test } from 'node:test';

import { vertexCurvature } from '../src/curvature.js';

// A latitude–longitude grid of n × 2n quads over a sphere of `radius`, normals out (or in).
function sphere( radius, n, inward ) {

	const position = [];
	const normal = [];
	for ( let i = 0; i <= n; i ++ ) {

		for ( let j = 0; j <= 2 * n; j ++ ) {

			const theta = Math.PI * ( 0.1 + 0.8 * i / n );
			const phi = Math.PI * j / n;
			const d = [ Math.sin( theta ) * Math.cos( phi ), Math.sin( theta ) * Math.sin( phi ), Math.cos( theta ) ];
			position.push( ...d.map( ( c ) => radius * c ) );
			normal.push( ...d.map( ( c ) => ( inward ? - c : c ) ) );

		}

	}

	const at = ( i, j ) => i * ( 2 * n + 1 ) + j;
	const index = [];
	for ( let i = 0; i < n; i ++ ) {

		for ( let j = 0; j < 2 * n; j ++ ) index.push( at( i, j ), at( i + 1, j ), at( i + 1, j + 1 ), at( i, j ), at( i + 1, j + 1 ), at( i, j + 1 ) );

	}

	return { position: new Float32Array( position ), normal: new Float32Array( normal ), index };

}

test( 'a sphere curves at one over its radius, a hollow and a plane not at all', () => {

	// Normals along the radius turn by e / R along any edge e: (e / R)·e / |e|² = 1 / R.
	const out = sphere( 2.5, 8, false );
	for ( const k of vertexCurvature( out.position, out.normal, out.index ) ) assert.ok( Math.abs( k - 0.4 ) < 1e-5, `${k}` );
	const hollow = sphere( 2.5, 8, true );
	assert.ok( vertexCurvature( hollow.position, hollow.normal, hollow.index ).every( ( k ) => k === 0 ) );
	const flat = sphere( 1, 4, false );
	for ( let v = 0; v < flat.position.length / 3; v ++ ) {

		flat.position[ 3 * v + 2 ] = 0;
		flat.normal.set( [ 0, 0, 1 ], 3 * v );

	}

	assert.ok( vertexCurvature( flat.position, flat.normal, flat.index ).every( ( k ) => k === 0 ) );

} );
