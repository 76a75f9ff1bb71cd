// Spherical harmonics, the light's cap and the 8-bit transfer (src/sh.js, src/lighting.js).

import assert from 'node:assert/strict';
import { test } from 'node:test';

import { MAX_PRT_ORDER, lightingValues, resolveLighting, usesPrt } from '../src/lighting.js';
import { bandOf, capZonal, decodeTransfer, layerMeans, projectCap, shEval, transferSlot } from '../src/sh.js';

const close = ( a, b, eps = 1e-9 ) => assert.ok( Math.abs( a - b ) <= eps, `${a} vs ${b}` );

test( 'the basis: real, orthonormal, no Condon-Shortley phase, index l² + l + m', () => {

	const d = [ 0.36, 0.48, 0.8 ];
	const [ x, y, z ] = d;
	const y3 = shEval( 3, d );
	const c1 = Math.sqrt( 3 / ( 4 * Math.PI ) );
	const expected = [
		0.5 / Math.sqrt( Math.PI ),
		c1 * y, c1 * z, c1 * x,
		0.5 * Math.sqrt( 15 / Math.PI ) * x * y,
		0.5 * Math.sqrt( 15 / Math.PI ) * y * z,
		0.25 * Math.sqrt( 5 / Math.PI ) * ( 3 * z * z - 1 ),
		0.5 * Math.sqrt( 15 / Math.PI ) * x * z,
		0.25 * Math.sqrt( 15 / Math.PI ) * ( x * x - y * y ),
	];
	expected.forEach( ( e, k ) => close( y3[ k ], e, 1e-12 ) );

} );

test( 'the basis is orthonormal over the sphere (order 5, quadrature)', () => {

	const order = 5;
	const n = order * order;
	const gram = new Float64Array( n * n );
	const rows = 200;
	const columns = 400;
	for ( let i = 0; i < rows; i ++ ) {

		const theta = ( i + 0.5 ) * Math.PI / rows;
		const weight = Math.sin( theta ) * ( Math.PI / rows ) * ( 2 * Math.PI / columns );
		for ( let j = 0; j < columns; j ++ ) {

			const phi = ( j + 0.5 ) * 2 * Math.PI / columns;
			const y = shEval( order, [ Math.sin( theta ) * Math.cos( phi ), Math.sin( theta ) * Math.sin( phi ), Math.cos( theta ) ] );
			for ( let a = 0; a < n; a ++ ) for ( let b = 0; b < n; b ++ ) gram[ a * n + b ] += weight * y[ a ] * y[ b ];

		}

	}

	for ( let a = 0; a < n; a ++ ) for ( let b = 0; b < n; b ++ ) close( gram[ a * n + b ], a === b ? 1 : 0, 2e-3 );

} );

test( 'the cap: a delta at radius 0, only the constant over the whole sphere', () => {

	capZonal( 4, 0 ).forEach( ( z, l ) => close( z, Math.sqrt( ( 2 * l + 1 ) / ( 4 * Math.PI ) ), 1e-12 ) );
	const sphere = capZonal( 4, Math.PI );
	close( sphere[ 0 ], 1 / Math.sqrt( 4 * Math.PI ), 1e-12 );
	for ( const z of sphere.slice( 1 ) ) close( z, 0, 1e-12 );
	// A delta light's coefficients are the basis at its direction.
	const d = [ 0, 0.6, 0.8 ];
	const cap = projectCap( 3, d, 0 );
	shEval( 3, d ).forEach( ( y, k ) => close( cap[ k ], y, 1e-12 ) );

} );

test( '8-bit transfer: coefficient k in texture k / 4, channel k % 4, byte / 255 · scale + bias', () => {

	assert.deepEqual( [ 0, 3, 4, 8 ].map( transferSlot ), [ [ 0, 0 ], [ 0, 3 ], [ 1, 0 ], [ 2, 0 ] ] );
	assert.deepEqual( [ 0, 1, 3, 4, 8, 9 ].map( bandOf ), [ 0, 1, 1, 2, 2, 3 ] );
	const transfer = { scale: [ 2, 0.5 ], bias: [ -1, 0.25 ] };
	close( decodeTransfer( 255, 0, transfer ), 1 );
	close( decodeTransfer( 0, 0, transfer ), -1 );
	close( decodeTransfer( 51, 1, transfer ), 0.35 );

} );

test( 'layer means: opacity-weighted over the layer\'s cell, the plain mean where it is empty', () => {

	// Two layers side by side in 2×2-texel cells; one transfer texture, order 1.
	const stack = { layers: 2, atlas: { columns: 2, rows: 1, tile: 2, width: 4, height: 2 }, transfer: { coefficients: 1, scale: [ 1 ], bias: [ 0 ] } };
	const transfer = new Uint8Array( 4 * 4 * 2 );
	const shells = new Uint8Array( 4 * 4 * 2 );
	const put = ( x, y, value, alpha ) => {

		transfer[ 4 * ( y * 4 + x ) ] = value;
		shells[ 4 * ( y * 4 + x ) + 3 ] = alpha;

	};

	// Layer 0: values 255 (opaque) and 0 (transparent) -> weighted mean 1.
	put( 0, 0, 255, 255 );
	put( 1, 0, 0, 0 );
	put( 0, 1, 255, 255 );
	put( 1, 1, 0, 0 );
	// Layer 1: empty; values 0, 0, 51, 102 -> plain mean 153 / 4 / 255.
	put( 2, 1, 51, 0 );
	put( 3, 1, 102, 0 );
	const means = layerMeans( [ transfer ], shells, stack );
	close( means[ 0 ], 1, 1e-6 );
	close( means[ 1 ], 153 / 4 / 255, 1e-6 );

} );

test( 'lighting defaults are the preview\'s, the light over π, PRT only with transfer', () => {

	const lighting = resolveLighting();
	const values = lightingValues( lighting, 3 );
	close( values.color[ 0 ], 1 );
	close( Math.hypot( ...values.direction ), 1, 1e-12 );
	assert.deepEqual( values.kajiyaKay, [ 0.9, 0.25, 1, 48 ] );
	close( values.sky[ 0 ], Math.sqrt( 4 * Math.PI ) * 0.1 / Math.PI );
	assert.equal( values.capWeights.length, 3 );
	// The sun (1 per channel after the π) against the sky's radiance 0.1: 1 / 1.1 of the light.
	close( values.hotSpotShare, 1 / 1.1 );
	assert.equal( usesPrt( lighting, { transfer: null } ), false );
	assert.equal( usesPrt( lighting, { transfer: { order: 3 } } ), true );
	assert.equal( usesPrt( lighting, { transfer: { order: MAX_PRT_ORDER + 1 } } ), false, 'auto falls back to Kajiya-Kay' );
	assert.equal( usesPrt( resolveLighting( { model: 'kajiya-kay' } ), { transfer: { order: 3 } } ), false );
	assert.throws( () => usesPrt( resolveLighting( { model: 'prt' } ), { transfer: null } ) );
	assert.throws( () => usesPrt( resolveLighting( { model: 'prt' } ), { transfer: { order: MAX_PRT_ORDER + 1 } } ) );

} );
