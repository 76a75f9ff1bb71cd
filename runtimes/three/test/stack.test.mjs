// Atlas cells, shell layers and the LOD's shell count (src/stack.js), and the extension's
// attribute names (src/extension.js).

import assert from 'node:assert/strict';
import { existsSync, readFileSync } from 'node:fs';
import { test } from 'node:test';

import { checkExtension, furPrimitives, threeAttributeName } from '../src/extension.js';
import { atlasCell, atlasUv, lodShells, shellLayer } from '../src/stack.js';
import { glbJson } from './support/glb.mjs';
import { GLB } from './support/paths.mjs';

const ATLAS = { columns: 3, rows: 3, tile: 32, width: 96, height: 96 };

test( 'layer l sits at column l % columns, row l / columns from the top', () => {

	assert.deepEqual( atlasCell( 0, 3 ), [ 0, 0 ] );
	assert.deepEqual( atlasCell( 2, 3 ), [ 2, 0 ] );
	assert.deepEqual( atlasCell( 7, 3 ), [ 1, 2 ] );

} );

test( 'atlas UVs: fract(uv) in the cell, half a texel from its borders', () => {

	const close = ( a, b ) => assert.ok( Math.abs( a[ 0 ] - b[ 0 ] ) < 1e-12 && Math.abs( a[ 1 ] - b[ 1 ] ) < 1e-12, `${a} vs ${b}` );
	close( atlasUv( [ 0.5, 0.5 ], 0, ATLAS ), [ 16 / 96, 16 / 96 ] );
	close( atlasUv( [ 2.5, -0.5 ], 4, ATLAS ), [ 48 / 96, 48 / 96 ] );
	// Cell borders clamp half a texel inside: layer 1 spans texels 32..64 of the first row.
	close( atlasUv( [ 0, 0 ], 1, ATLAS ), [ 32.5 / 96, 0.5 / 96 ] );
	close( atlasUv( [ 0.99999, 0.99999 ], 1, ATLAS ), [ 63.5 / 96, 31.5 / 96 ] );

} );

test( 'shell s of S shows layer round(s (L - 1) / S), halves up', () => {

	assert.deepEqual( [ 1, 2, 3, 4, 5, 6, 7 ].map( ( s ) => shellLayer( s, 7, 8 ) ), [ 1, 2, 3, 4, 5, 6, 7 ] );
	// The fallback's four shells of docs/export.md: round(s · 7 / 4) = 2, 4, 5, 7 (3.5 rounds up).
	assert.deepEqual( [ 1, 2, 3, 4 ].map( ( s ) => shellLayer( s, 4, 8 ) ), [ 2, 4, 5, 7 ] );
	assert.deepEqual( [ 1, 2 ].map( ( s ) => shellLayer( s, 2, 8 ) ), [ 4, 7 ] );

} );

test( 'LOD: shells follow the fur depth in pixels, at least a quarter of them', () => {

	assert.equal( lodShells( 100, 16 ), 16 );
	assert.equal( lodShells( 9.2, 16 ), 10 );
	assert.equal( lodShells( 1, 16 ), 4 );
	assert.equal( lodShells( 0, 7 ), 2 );
	assert.equal( lodShells( 0, 1 ), 1 );
	assert.equal( lodShells( Infinity, 7 ), 7 );
	assert.equal( lodShells( 3, 16, { shellsPerPixel: 2, minShare: 0 } ), 6 );

} );

test( 'GLTFLoader keeps custom attribute names lower-cased, standard ones renamed', () => {

	assert.equal( threeAttributeName( '_PELT_LENGTH' ), '_pelt_length' );
	assert.equal( threeAttributeName( 'TEXCOORD_1' ), 'uv1' );
	assert.equal( threeAttributeName( 'COLOR_0' ), 'color' );
	assert.equal( threeAttributeName( 'JOINTS_0' ), 'skinIndex' );

} );

test( 'the extension checks catch what the runtime relies on', () => {

	const ext = {
		version: 1,
		stack: { layers: 8, shells: 7, shell_layers: [ 1, 2, 3, 4, 5, 6, 7 ], layer_spacing: 0.125, fur_depth: 0.1, uv_scale: 2, atlas: ATLAS, transfer: null },
		attributes: { uv: 'TEXCOORD_1', color: 'COLOR_0', length: '_PELT_LENGTH', comb: '_PELT_COMB', dpdu: '_PELT_DPDU', dpdv: '_PELT_DPDV' },
		textures: { skin: 0, shells_atlas: 1, tangents_atlas: 2, fin: 3, transfer: [] },
		fallback: [ 1, 2, 3, 4 ],
	};
	assert.equal( checkExtension( ext, 'x' ), ext );
	assert.throws( () => checkExtension( { ...ext, version: 2 }, 'x' ), /version 2/ );
	assert.throws( () => checkExtension( { ...ext, stack: { ...ext.stack, shell_layers: [ 1, 8, 3, 4, 5, 6, 7 ] } }, 'x' ), /outside/ );
	assert.throws( () => checkExtension( { ...ext, textures: { ...ext.textures, transfer: [ 4 ] } }, 'x' ), /transfer/ );

} );

test( 'the exported character carries the extension on its skin primitives', { skip: ! existsSync( GLB ) && `no ${GLB}` }, () => {

	const json = glbJson( readFileSync( GLB ) );
	const found = furPrimitives( json );
	assert.ok( found.length >= 1 );
	for ( const [ m, p, ext ] of found ) {

		assert.equal( p, 0 );
		assert.equal( ext.fallback.length, 4 );
		for ( const name of Object.values( ext.attributes ) ) assert.ok( name in json.meshes[ m ].primitives[ p ].attributes, name );

	}

} );
