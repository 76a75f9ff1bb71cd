// The example in headless Chromium (WebGL 2 through SwiftShader): the plugin finds the
// extension, hides the fallback, draws the fur in two draw calls per object, the fur adds
// coverage around the silhouette, the animation moves it and the distance LOD thins it; and the
// frame the wgpu preview drew of a nodding Suzanne (reference/make_reference.py) comes out with
// the same mean luminance within 10 %, with guard hairs too, drawn as ribbons, under PRT, and with
// its hair thinned where the shells spread (make
// check-three then bounds their ꟻLIP differences with reference/compare.py); and the character Blender's add-on exported (eyes and all) draws and
// bends. Screenshots go to test/out/. The browser is the system's
// (PELT_CHROMIUM, default /usr/bin/chromium); nothing is downloaded. A missing model, reference
// or browser fails the tests.

import assert from 'node:assert/strict';
import { existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import puppeteer from 'puppeteer-core';

import { BIG_GLB, BLENDER_GLB, GLB, OUT_DIR, PACKAGE_DIR, REFERENCE } from './support/paths.mjs';
import { serve } from './support/server.mjs';

const CHROMIUM = process.env.PELT_CHROMIUM || '/usr/bin/chromium';
// Pixels the fur must add outside the bare silhouette, and the nod must change.
const MIN_FUR_PIXELS = 500;
const MIN_MOVED_PIXELS = 500;
// A channel step that counts as a change between two frames (8-bit).
const CHANGED = 8;

// Mean luminance over the preview's object may differ by this share.
const LUMINANCE_TOLERANCE = 0.10;
// On the thinning scene, the whole object's, the crown's and the outer fringe's mean luminance
// may differ by this share (measured: see the test).
const THIN_TOLERANCE = 0.05;
const missing = ! existsSync( GLB ) ? `no ${GLB} (make check-gltf writes it)`
	: ! existsSync( BIG_GLB ) ? `no ${BIG_GLB} (make check-gltf writes it)`
	: ! existsSync( BLENDER_GLB ) ? `no ${BLENDER_GLB} (make check-three has the add-on export it)`
	: ! existsSync( CHROMIUM ) ? `no ${CHROMIUM} (make system-deps installs Debian's chromium)`
		: ! existsSync( join( REFERENCE, 'scene.json' ) ) ? `no reference scene in ${REFERENCE} (make check-three writes it)` : null;

let server;
let browser;
let profile;

before( async () => {

	assert.equal( missing, null, missing );
	server = await serve( PACKAGE_DIR, { '/model.glb': GLB, '/big.glb': BIG_GLB, '/blender.glb': BLENDER_GLB }, REFERENCE );
	profile = mkdtempSync( join( tmpdir(), 'pelt-three-' ) );
	browser = await puppeteer.launch( {
		executablePath: CHROMIUM,
		headless: true,
		args: [
			'--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
			'--disable-background-networking', '--disable-component-update', '--disable-sync',
			'--no-first-run', '--disable-quic', '--disable-extensions', `--user-data-dir=${profile}`,
		],
	} );

} );

after( async () => {

	await browser?.close();
	await server?.close();
	if ( profile ) rmSync( profile, { recursive: true, force: true } );

} );

/** Opens the example with `query` on `model` (a served path); the page, its problems and pelt.ready's summary. */
async function openExample( query, model = '/model.glb' ) {

	const page = await browser.newPage();
	const problems = [];
	page.on( 'pageerror', ( error ) => problems.push( `page error: ${error.message}` ) );
	page.on( 'console', ( message ) => {

		if ( message.type() === 'error' ) problems.push( `console error: ${message.text()}` );

	} );
	page.on( 'requestfailed', ( request ) => {

		// Chromium at times reports a fetch whose body streams into the page as aborted though all
		// of it arrived; a load that really fails rejects pelt.ready.
		const reason = request.failure()?.errorText;
		if ( reason !== 'net::ERR_ABORTED' ) problems.push( `request failed: ${request.url()} (${reason})` );

	} );
	page.on( 'response', ( response ) => {

		if ( response.status() >= 400 ) problems.push( `HTTP ${response.status()}: ${response.url()}` );

	} );
	await page.setViewport( { width: 512, height: 512 } );
	await page.goto( `${server.url}/example/index.html?model=${model}&paused&${query}`, { waitUntil: 'load' } );
	const summary = await page.evaluate( () => window.pelt.ready );
	return { page, problems, summary };

}

/**
 * Renders the frame at `time` with the fur on or off (and its guard hairs unless `strands` is
 * false); its RGBA bytes and a PNG data URL.
 */
async function frame( page, time, fur, strands = true ) {

	const { rgba, png } = await page.evaluate( ( time, fur, strands ) => {

		window.pelt.toggleFur( fur );
		if ( ! strands ) window.pelt.toggleGuardHairs( false );
		window.pelt.setTime( time );
		const canvas = document.getElementById( 'view' );
		const copy = new OffscreenCanvas( canvas.width, canvas.height ).getContext( '2d' );
		copy.drawImage( canvas, 0, 0 );
		const bytes = copy.getImageData( 0, 0, canvas.width, canvas.height ).data;
		let binary = '';
		for ( let i = 0; i < bytes.length; i += 0x8000 ) binary += String.fromCharCode( ...bytes.subarray( i, i + 0x8000 ) );
		return { rgba: btoa( binary ), png: canvas.toDataURL( 'image/png' ) };

	}, time, fur, strands );
	return { rgba: Buffer.from( rgba, 'base64' ), png };

}

function save( name, image ) {

	mkdirSync( OUT_DIR, { recursive: true } );
	writeFileSync( join( OUT_DIR, name ), Buffer.from( image.png.split( ',' )[ 1 ], 'base64' ) );

}

const isBackground = ( rgba, i, background ) =>
	Math.abs( rgba[ i ] - background[ 0 ] ) <= 2 && Math.abs( rgba[ i + 1 ] - background[ 1 ] ) <= 2 && Math.abs( rgba[ i + 2 ] - background[ 2 ] ) <= 2;

/**
 * Pixels of the object in `bare`, pixels that are background in `bare` and not in `furred`
 * (the fur's coverage past the silhouette), and the reverse. The background is the corner pixel.
 */
function coverage( bare, furred ) {

	const background = bare.rgba.subarray( 0, 3 );
	let added = 0;
	let lost = 0;
	let object = 0;
	for ( let i = 0; i < bare.rgba.length; i += 4 ) {

		const was = isBackground( bare.rgba, i, background );
		const is = isBackground( furred.rgba, i, background );
		if ( ! was ) object ++;
		if ( was && ! is ) added ++;
		if ( ! was && is ) lost ++;

	}

	return { added, lost, object };

}

function changedPixels( a, b ) {

	let changed = 0;
	for ( let i = 0; i < a.rgba.length; i += 4 ) {

		if ( Math.max( Math.abs( a.rgba[ i ] - b.rgba[ i ] ), Math.abs( a.rgba[ i + 1 ] - b.rgba[ i + 1 ] ), Math.abs( a.rgba[ i + 2 ] - b.rgba[ i + 2 ] ) ) > CHANGED ) changed ++;

	}

	return changed;

}

function assertFurCovers( t, label, bare, furred ) {

	const c = coverage( bare, furred );
	t.diagnostic( `${label}: bare object ${c.object} px, fur adds ${c.added} px outside it (needs > ${MIN_FUR_PIXELS}), uncovers ${c.lost}` );
	assert.ok( c.object > 10_000, `the bare object shows (${c.object} px)` );
	assert.ok( c.added > MIN_FUR_PIXELS, `fur adds ${c.added} px around the silhouette` );
	assert.equal( c.lost, 0, 'the fur hides nothing of the object' );

}

test( 'the example draws the fur of the exported character (PRT)', { timeout: 90_000 }, async ( t ) => {

	const { page, problems, summary } = await openExample( '' );
	const webgl = await page.evaluate( () => {

		const gl = document.createElement( 'canvas' ).getContext( 'webgl2' );
		const info = gl?.getExtension( 'WEBGL_debug_renderer_info' );
		return gl ? gl.getParameter( info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER ) : null;

	} );
	assert.ok( webgl, 'WebGL 2 is available' );
	t.diagnostic( `WebGL 2: ${webgl}` );
	assert.deepEqual( problems, [] );
	assert.equal( summary.extension, true );
	assert.equal( summary.animation, 'Nod' );
	const character = summary.furs.find( ( f ) => f.skinned );
	assert.ok( character, 'a skinned fur' );
	assert.equal( character.hiddenFallback, 4, 'the four fallback shells are hidden' );
	assert.equal( summary.hidden.length, 4 * summary.furs.length );
	assert.ok( character.fins > 100, `fins: ${character.fins}` );
	assert.ok( summary.furs.every( ( f ) => f.prt ), 'the file\'s transfer lights the fur' );

	// Two draw calls per fur (shells, fins): with its skin at most three.
	const { total, fur, perFur } = summary.drawCalls;
	assert.equal( fur, perFur.reduce( ( a, b ) => a + b, 0 ), 'the measured difference is the furs\' draws' );
	for ( const calls of perFur ) assert.ok( calls + 1 <= 3, `${calls} fur draw calls + the skin` );
	t.diagnostic( `draw calls: ${total} in all, ${fur} for ${summary.furs.length} furs (${perFur.join( ', ' )})` );
	t.diagnostic( `frame time: ${summary.frameTimeMs.toFixed( 2 )} ms (mean of 20 frames, 512 × 512)` );

	const bare0 = await frame( page, 0, false );
	const fur0 = await frame( page, 0, true );
	const bareHalf = await frame( page, 0.5, false );
	const furHalf = await frame( page, 0.5, true );
	save( 'bare_t0.png', bare0 );
	save( 'fur_t0.png', fur0 );
	save( 'bare_t0.5.png', bareHalf );
	save( 'fur_t0.5.png', furHalf );
	assertFurCovers( t, 't = 0', bare0, fur0 );
	assertFurCovers( t, 't = 0.5 s', bareHalf, furHalf );

	const moved = changedPixels( fur0, furHalf );
	const movedBare = changedPixels( bare0, bareHalf );
	t.diagnostic( `the nod changes ${moved} px with fur, ${movedBare} px bare (needs > ${MIN_MOVED_PIXELS})` );
	assert.ok( moved > MIN_MOVED_PIXELS );
	assert.ok( movedBare > MIN_MOVED_PIXELS );

	// setTime is deterministic: the same time renders the same frame.
	const again = await frame( page, 0.5, true );
	assert.equal( changedPixels( furHalf, again ), 0 );

	// Distance LOD: far away fewer shells, at least a quarter of them.
	const lod = await page.evaluate( () => {

		window.pelt.setZoom( 0.1 );
		window.pelt.setTime( 0 );
		const far = window.pelt.drawnShells();
		window.pelt.setZoom( 1 );
		window.pelt.setTime( 0 );
		return { far, near: window.pelt.drawnShells() };

	} );
	t.diagnostic( `shells drawn close up ${lod.near}, far away ${lod.far} (of ${summary.furs.map( ( f ) => f.shells )})` );
	summary.furs.forEach( ( f, i ) => {

		assert.equal( lod.near[ i ], f.shells );
		assert.ok( lod.far[ i ] < f.shells && lod.far[ i ] >= Math.ceil( f.shells / 4 ), `${lod.far[ i ]} shells far away` );

	} );
	assert.deepEqual( problems, [] );
	await page.close();

} );

test( 'a 30k-triangle skinned character with 32 shells and fins: two draw calls for its fur', { timeout: 90_000 }, async ( t ) => {

	const { page, problems, summary } = await openExample( 'lighting=kajiya-kay', '/big.glb' );
	assert.deepEqual( problems, [] );
	assert.equal( summary.furs.length, 1 );
	const [ fur ] = summary.furs;
	assert.ok( fur.skinned );
	assert.equal( fur.shells, 32 );
	assert.ok( fur.fins > 30_000, `fins: ${fur.fins}` );
	const { total, perFur } = summary.drawCalls;
	t.diagnostic( `30720 triangles, 32 shells, ${fur.fins} fins: ${perFur[ 0 ]} fur draw calls (+ the skin), ${total} in all; frame time ${summary.frameTimeMs.toFixed( 1 )} ms at 512 × 512` );
	assert.ok( perFur[ 0 ] + 1 <= 3, `${perFur[ 0 ]} fur draw calls + the skin` );
	const bare = await frame( page, 0, false );
	const furred = await frame( page, 0, true );
	save( 'big_t0.png', furred );
	assertFurCovers( t, '30k triangles', bare, furred );
	assert.deepEqual( problems, [] );
	await page.close();

} );

test( 'the example draws the character Blender\'s add-on exported', { timeout: 90_000 }, async ( t ) => {

	// tests/blender/test_export_skinned.py's user flow: half a tube mirrored, on a two-bone
	// armature whose action bends it, its top rows "eyes" in a material of their own, bald.
	const { page, problems, summary } = await openExample( '', '/blender.glb' );
	assert.deepEqual( problems, [] );
	assert.equal( summary.extension, true );
	assert.ok( summary.animation, 'the armature\'s action came along' );
	assert.ok( summary.duration > 0.2, `animation of ${summary.duration} s` );
	const body = summary.furs.find( ( f ) => f.name.startsWith( 'Body' ) );
	assert.ok( body?.skinned, `a skinned fur on the body (${summary.furs.map( ( f ) => f.name )})` );
	assert.equal( body.hiddenFallback, 4 );
	assert.ok( summary.materials.includes( 'Eyes' ), `the eyes' own material shows: ${summary.materials}` );
	t.diagnostic( `fur ${body.name}: ${body.shells} shells, ${body.fins} fins; materials shown: ${summary.materials.join( ', ' )}` );

	const bare = await frame( page, 0, false );
	const furred = await frame( page, 0, true );
	// Just before the end: the looping clip wraps to its start at the end itself.
	const end = 0.99 * summary.duration;
	const bentBare = await frame( page, end, false );
	const bent = await frame( page, end, true );
	save( 'blender_t0.png', furred );
	save( 'blender_bent.png', bent );
	assertFurCovers( t, 'Blender export, rest', bare, furred );
	assertFurCovers( t, 'Blender export, bent', bentBare, bent );
	const moved = changedPixels( furred, bent );
	t.diagnostic( `the bend changes ${moved} px` );
	assert.ok( moved > MIN_MOVED_PIXELS );
	assert.deepEqual( problems, [] );
	await page.close();

} );

test( 'Kajiya-Kay lighting and the skin\'s own glTF material', { timeout: 90_000 }, async ( t ) => {

	const { page, problems, summary } = await openExample( 'lighting=kajiya-kay&skin=gltf' );
	assert.deepEqual( problems, [] );
	assert.ok( summary.furs.every( ( f ) => ! f.prt ) );
	t.diagnostic( `Kajiya-Kay frame time: ${summary.frameTimeMs.toFixed( 2 )} ms, fur draw calls ${summary.drawCalls.fur}` );
	const bare = await frame( page, 0, false );
	const furred = await frame( page, 0, true );
	save( 'kajiya_kay_t0.png', furred );
	assertFurCovers( t, 'Kajiya-Kay, t = 0', bare, furred );
	assert.deepEqual( problems, [] );
	await page.close();

} );

/** Relative luminance of an 8-bit sRGB pixel, linear. */
function luminance( rgba, i ) {

	const linear = ( c ) => ( c <= 10.31475 ? c / 3294.6 : ( ( c / 255 + 0.055 ) / 1.055 ) ** 2.4 );
	return 0.2126 * linear( rgba[ i ] ) + 0.7152 * linear( rgba[ i + 1 ] ) + 0.0722 * linear( rgba[ i + 2 ] );

}

/** The RGBA bytes of a PNG the server serves, decoded by the page as they are stored. */
async function servedImage( page, url ) {

	return Buffer.from( await page.evaluate( async ( url ) => {

		const blob = await ( await fetch( url ) ).blob();
		const bitmap = await createImageBitmap( blob, { premultiplyAlpha: 'none', colorSpaceConversion: 'none' } );
		const copy = new OffscreenCanvas( bitmap.width, bitmap.height ).getContext( '2d' );
		copy.drawImage( bitmap, 0, 0 );
		const bytes = copy.getImageData( 0, 0, bitmap.width, bitmap.height ).data;
		let binary = '';
		for ( let i = 0; i < bytes.length; i += 0x8000 ) binary += String.fromCharCode( ...bytes.subarray( i, i + 0x8000 ) );
		return btoa( binary );

	}, url ), 'base64' );

}

/**
 * Mean luminance of `three` over `preview` over the pixels the preview draws (on black): the
 * pixel count and the ratio; the diagnostic states `tolerance`, the bound the caller holds it to.
 */
function luminanceRatio( t, preview, three, tolerance = LUMINANCE_TOLERANCE ) {

	assert.equal( preview.length, three.length, 'the same image size' );
	let covered = 0;
	let previewSum = 0;
	let threeSum = 0;
	for ( let i = 0; i < preview.length; i += 4 ) {

		if ( Math.max( preview[ i ], preview[ i + 1 ], preview[ i + 2 ] ) <= 2 ) continue;
		covered ++;
		previewSum += luminance( preview, i );
		threeSum += luminance( three, i );

	}

	const ratio = threeSum / previewSum;
	t.diagnostic( `mean luminance over ${covered} px: preview ${( previewSum / covered ).toFixed( 4 )}, three.js ${( threeSum / covered ).toFixed( 4 )} (ratio ${ratio.toFixed( 3 )}, must be within ${tolerance})` );
	return { covered, ratio };

}

/** The example draws reference/make_reference.py's scene `prefix`scene.json as the preview drew it. */
async function drawsThePreviewsFrame( t, prefix, prt ) {

	const description = JSON.parse( readFileSync( join( REFERENCE, `${prefix}scene.json` ), 'utf8' ) );
	const { page, problems, summary } = await openExample( `scene=/reference/${prefix}scene.json` );
	assert.deepEqual( problems, [] );
	assert.equal( summary.furs.length, 1 );
	assert.equal( summary.furs[ 0 ].prt, prt, prt ? 'lit by PRT' : 'lit by Kajiya-Kay' );
	assert.equal( summary.furs[ 0 ].drawnShells, description.shells, 'every shell, as the preview' );
	const three = await frame( page, description.time, true );
	save( `${prefix}reference_three.png`, three );
	const preview = await servedImage( page, `/reference/${prefix}preview.png` );
	const { covered, ratio } = luminanceRatio( t, preview, three.rgba );
	assert.ok( covered > 20_000, `the preview covers ${covered} px` );
	const time = await page.evaluate( () => window.pelt.frameTimeMs );
	t.diagnostic( `frame time ${time.toFixed( 1 )} ms at ${description.width} × ${description.height}` );
	assert.ok( Math.abs( ratio - 1 ) <= LUMINANCE_TOLERANCE, `luminance ratio ${ratio.toFixed( 3 )}` );
	assert.deepEqual( problems, [] );
	await page.close();

}

test( 'the example draws the frame the wgpu preview draws', { timeout: 120_000 }, ( t ) => drawsThePreviewsFrame( t, '', false ) );

test( 'the example draws the frame the wgpu preview draws under PRT', { timeout: 120_000 }, ( t ) => drawsThePreviewsFrame( t, 'prt_', true ) );

/**
 * The skin's disc in `bare` (the fur off): its centre and radius in pixels, from its pixels'
 * centroid and count.
 */
function skinDisc( bare ) {

	const background = bare.rgba.subarray( 0, 3 );
	const side = Math.sqrt( bare.rgba.length / 4 );
	let count = 0;
	let sx = 0;
	let sy = 0;
	for ( let i = 0; i < bare.rgba.length; i += 4 ) {

		if ( isBackground( bare.rgba, i, background ) ) continue;
		count ++;
		sx += ( i / 4 ) % side;
		sy += Math.floor( i / 4 / side );

	}

	return { x: sx / count, y: sy / count, radius: Math.sqrt( count / Math.PI ), side };

}

/** Mean luminance of `image` (RGBA bytes) over the ring from `from` to `to` skin radii of `disc`. */
function ringLuminance( image, disc, from, to ) {

	let pixels = 0;
	let sum = 0;
	for ( let i = 0; i < image.length; i += 4 ) {

		const r = Math.hypot( ( i / 4 ) % disc.side - disc.x, Math.floor( i / 4 / disc.side ) - disc.y ) / disc.radius;
		if ( r < from || r >= to ) continue;
		pixels ++;
		sum += luminance( image, i );

	}

	return sum / pixels;

}

test( 'the hair thins where the shells spread, as the preview thins it', { timeout: 120_000 }, async ( t ) => {

	// A sphere under a coat half its radius deep: the top shell spreads over 2.25 times the
	// skin's area, so the preview's hair there is 1 / 2.25 as dense. It shows where the eye looks
	// down through every layer (the crown, within half the skin's radius) and past the skin's
	// outline, where only the upper, most spread layers and the fins' tips stand (beyond 1.2
	// radii); the fins' own light and order show around the outline. Measured (three.js over
	// the preview, whole, crown, outer fringe): 1.007, 1.041, 0.994; without the thinning 1.071,
	// 1.098, 1.12; with the fins lit along one tangent 0.937, 1.041, 0.929; with the fins drawn
	// in file order, not farthest first, 0.901 (a dark ring around the skin).
	const description = JSON.parse( readFileSync( join( REFERENCE, 'thin_scene.json' ), 'utf8' ) );
	const { page, problems } = await openExample( 'scene=/reference/thin_scene.json' );
	assert.deepEqual( problems, [] );
	const three = await frame( page, description.time, true );
	const bare = await frame( page, description.time, false );
	save( 'thin_three.png', three );
	const preview = await servedImage( page, '/reference/thin_preview.png' );
	const whole = luminanceRatio( t, preview, three.rgba, THIN_TOLERANCE );
	assert.ok( whole.covered > 20_000, `the preview covers ${whole.covered} px` );
	assert.ok( Math.abs( whole.ratio - 1 ) <= THIN_TOLERANCE, `luminance ratio ${whole.ratio.toFixed( 3 )}` );
	const disc = skinDisc( bare );
	assert.ok( disc.radius > 40, `the skin's disc is ${disc.radius.toFixed( 1 )} px across` );
	for ( const [ name, from, to ] of [ [ 'crown', 0, 0.5 ], [ 'outer fringe', 1.2, 2 ] ] ) {

		const ratio = ringLuminance( three.rgba, disc, from, to ) / ringLuminance( preview, disc, from, to );
		t.diagnostic( `${name} (${from}–${to} skin radii): three.js over the preview ${ratio.toFixed( 3 )} (must be within ${THIN_TOLERANCE})` );
		assert.ok( Math.abs( ratio - 1 ) <= THIN_TOLERANCE, `${name}: luminance ratio ${ratio.toFixed( 3 )}` );

	}

	assert.deepEqual( problems, [] );
	await page.close();

} );

test( 'the guard hairs draw as ribbons, as the preview draws its strands', { timeout: 180_000 }, async ( t ) => {

	const description = JSON.parse( readFileSync( join( REFERENCE, 'strands_scene.json' ), 'utf8' ) );
	const { page, problems, summary } = await openExample( 'scene=/reference/strands_scene.json' );
	assert.deepEqual( problems, [] );
	const fur = summary.furs[ 0 ];
	t.diagnostic( `${description.guard_strands} guard strands, ${fur.guardHairSegments} ribbon segments (${fur.guardHairSegmentsDrawn} drawn by the strand LOD), ${summary.drawCalls.fur} fur draw calls` );
	assert.ok( fur.guardHairSegments >= description.guard_strands, 'a segment or more per strand' );
	// Sub-pixel strands at this distance: the LOD draws a share of them, not none.
	assert.ok( fur.guardHairSegmentsDrawn > 0 && fur.guardHairSegmentsDrawn < fur.guardHairSegments );
	assert.equal( summary.drawCalls.fur, 3, 'shells, fins and the ribbons: one draw each' );
	// The lines three.js loaded are hidden: the ribbons stand in for them.
	assert.equal( summary.hiddenLines, 1 );
	const three = await frame( page, description.time, true );
	save( 'strands_three.png', three );
	const bare = await frame( page, description.time, true, false );
	save( 'strands_three_without.png', bare );
	// The ribbons draw: they change a good share of the fur's pixels and reach past the shells.
	const c = coverage( bare, three );
	const moved = changedPixels( bare, three );
	t.diagnostic( `the ribbons change ${moved} px and add ${c.added} px past the shells' fringe` );
	assert.ok( moved > 5_000 && c.added > 200, `ribbons change ${moved} px, add ${c.added} px` );
	const preview = await servedImage( page, '/reference/strands_preview.png' );
	const { covered, ratio } = luminanceRatio( t, preview, three.rgba );
	assert.ok( covered > 20_000, `the preview covers ${covered} px` );
	const time = await page.evaluate( () => window.pelt.frameTimeMs );
	t.diagnostic( `frame time ${time.toFixed( 1 )} ms at ${description.width} × ${description.height} with the ribbons` );
	assert.ok( Math.abs( ratio - 1 ) <= LUMINANCE_TOLERANCE, `luminance ratio ${ratio.toFixed( 3 )}` );
	assert.deepEqual( problems, [] );
	await page.close();

} );
