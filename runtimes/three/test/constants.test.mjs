// The lighting and density constants the GLSL chunks restate from the preview's WGSL (GLSL
// cannot import WGSL): a change on one side that the other misses fails here, not as a picture
// that drifts.

import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';

const wgslDir = new URL( '../../../crates/pelt-render/src/', import.meta.url );
const glslDir = new URL( '../src/glsl/', import.meta.url );

// `[GLSL chunk, its constant, WGSL module, the constant it restates]`.
const RESTATED = [
	[ 'lighting.js', 'PELT_TERMINATOR_WRAP', 'common.wgsl', 'TERMINATOR_WRAP' ],
	[ 'lighting.js', 'PELT_MIN_SLANT_COS', 'lighting.wgsl', 'MIN_SLANT_COS' ],
	[ 'lighting.js', 'PELT_HOT_SPOT_WIDTH', 'common.wgsl', 'HOT_SPOT_WIDTH' ],
	[ 'prt.js', 'PELT_HOT_SPOT_MIN', 'prt.wgsl', 'HOT_SPOT_MIN' ],
	[ 'prt.js', 'PELT_PRT_TERMINATOR_WRAP', 'prt_rotate.wgsl', 'TERMINATOR_WRAP' ],
	[ 'prt.js', 'PELT_HOT_SPOT_FLOOR', 'hot_spot.wgsl', 'HOT_SPOT_FLOOR' ],
	[ 'fins.js', 'PELT_FIN_ANISOTROPY', 'common.wgsl', 'FIN_ANISOTROPY' ],
	[ 'common.js', 'PELT_MIN_SPREAD', 'common.wgsl', 'MIN_SPREAD' ],
];

// The one value `pattern` captures in `file` under `dir`; fails when it is missing or repeated.
function constant( dir, file, pattern ) {

	const text = readFileSync( new URL( file, dir ), 'utf8' );
	const found = [ ...text.matchAll( pattern ) ];
	assert.equal( found.length, 1, `${ file }: ${ found.length } definitions of ${ pattern }` );
	return Number( found[ 0 ][ 1 ] );

}

test( 'every constant a GLSL chunk restates has its WGSL value', () => {

	for ( const [ chunk, glslName, module, wgslName ] of RESTATED ) {

		const glsl = constant( glslDir, chunk, new RegExp( `const float ${ glslName } = ([-\\d.e]+);`, 'g' ) );
		const wgsl = constant( wgslDir, module, new RegExp( `const ${ wgslName }: f32 = ([-\\d.e]+);`, 'g' ) );
		assert.ok( Number.isFinite( glsl ), `${ chunk } ${ glslName }` );
		assert.equal( glsl, wgsl, `${ chunk } ${ glslName } against ${ module } ${ wgslName }` );

	}

} );
