// Example: a Pelt `engine`-mode GLB (`?model=path`, default character_engine.glb next to this
// page) with its fur drawn by PeltShellFurPlugin, its animations playing, a fixed camera.
// `?lighting=kajiya-kay` or `prt` picks the fur's lighting model. `?paused` stops the clock (tests drive it through window.pelt.setTime). window.pelt:
//   ready          Promise of a summary of what the plugin found
//   setTime(s)     poses the animation at s seconds and renders that one frame
//   drawCalls      {total, fur} of a frame (fur: with the fur minus without it)
//   frameTimeMs    mean time of a frame over FRAME_SAMPLES renders, GPU included
//   toggleFur(on)  shows or hides every fur
//   toggleGuardHairs(on)  shows or hides the guard hairs' ribbons only
//   setZoom(z)     zooms the fixed camera (1: the object fills the view; less: it recedes)
//   drawnShells()  the shells each fur drew in the last frame (the distance LOD's choice)
// `?skin=gltf` keeps the skin's glTF material instead of the fur's skin shading.
// `?scene=url` takes a scene description (reference/make_reference.py's scene.json: model, image
// size, camera view and projection matrices, light) instead of the defaults: the page then
// draws the frame the wgpu preview drew, on black, every shell, no LOD.

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { EffectComposer } from 'three/addons/postprocessing/EffectComposer.js';
import { OutputPass } from 'three/addons/postprocessing/OutputPass.js';
import { RenderPass } from 'three/addons/postprocessing/RenderPass.js';

import { PeltShellFurPlugin } from '../src/index.js';

const FRAME_SAMPLES = 20;
const params = new URLSearchParams( location.search );
const modelUrl = params.get( 'model' ) || 'character_engine.glb';
const status = document.getElementById( 'status' );

const canvas = document.getElementById( 'view' );
// preserveDrawingBuffer: the frame stays readable until the next render (screenshots).
const renderer = new THREE.WebGLRenderer( { canvas, antialias: false, preserveDrawingBuffer: true } );
renderer.setPixelRatio( 1 );
renderer.setSize( canvas.width, canvas.height, false );

const scene = new THREE.Scene();
scene.background = new THREE.Color( 0x1d2630 );
// For anything the fur shaders do not draw: the fur's default light (lighting.js) in three.js
// units, where a directional light of intensity π lights a white surface facing it to 1.
const sun = new THREE.DirectionalLight( 0xffffff, Math.PI );
sun.position.set( 0.4, 0.75, 0.5 );
scene.add( sun, new THREE.AmbientLight( 0xffffff, 0.12 * Math.PI ) );

const camera = new THREE.PerspectiveCamera( 35, canvas.width / canvas.height, 0.05, 100 );
let mixer = null;
let plugin = null;

// The scene is drawn into a linear float target and encoded to sRGB once at the end: the shells
// blend over each other in linear light, as the preview's sRGB target blends them (blending the
// encoded values darkens every translucent layer).
const composer = new EffectComposer( renderer );
composer.addPass( new RenderPass( scene, camera ) );
composer.addPass( new OutputPass() );

function render() {

	// The composer's passes reset the counts: sum them over the frame.
	renderer.info.autoReset = false;
	renderer.info.reset();
	composer.render();
	renderer.info.autoReset = true;
	return renderer.info.render.calls;

}

function toggleFur( on ) {

	for ( const fur of plugin.furs ) fur.visible = on;

}

// Shows or hides only the guard hairs' ribbons (the rest of the fur as it is).
function toggleGuardHairs( on ) {

	for ( const fur of plugin.furs ) if ( fur.strands ) fur.strands.visible = on;

}

// Draw calls of one frame with and without the fur.
function measureDrawCalls() {

	const total = render();
	toggleFur( false );
	const bare = render();
	toggleFur( true );
	render();
	return { total, fur: total - bare, perFur: plugin.furs.map( ( f ) => f.drawCalls ) };

}

// Mean frame time: the renders are queued, one pixel read waits for the GPU to finish them.
function measureFrameTime() {

	const gl = renderer.getContext();
	const pixel = new Uint8Array( 4 );
	render();
	gl.readPixels( 0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel );
	const start = performance.now();
	for ( let i = 0; i < FRAME_SAMPLES; i ++ ) render();
	gl.readPixels( 0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel );
	return ( performance.now() - start ) / FRAME_SAMPLES;

}

// The names of the materials of the meshes shown (the fur's own excepted), each once.
function visibleMaterials( root ) {

	const names = new Set();
	root.traverseVisible( ( object ) => {

		if ( object.isMesh && ! plugin.furs.some( ( f ) => f.shells === object || f.fins === object ) ) names.add( object.material.name );

	} );
	return [ ...names ].sort();

}

// The camera looks at the first furred object from the front, a little above and aside.
function frame( object ) {

	const sphere = new THREE.Box3().setFromObject( object, true ).getBoundingSphere( new THREE.Sphere() );
	const distance = sphere.radius / Math.sin( THREE.MathUtils.degToRad( camera.fov / 2 ) );
	const direction = new THREE.Vector3( 0.35, 0.3, 1 ).normalize();
	camera.position.copy( sphere.center ).addScaledVector( direction, distance );
	camera.lookAt( sphere.center );
	camera.updateMatrixWorld();

}

// The camera, canvas and background of a scene description.
function useScene( description ) {

	canvas.width = description.width;
	canvas.height = description.height;
	renderer.setSize( description.width, description.height, false );
	composer.setSize( description.width, description.height );
	scene.background = new THREE.Color( 0x000000 );
	camera.matrixAutoUpdate = false;
	camera.matrixWorldInverse.fromArray( description.view );
	camera.matrixWorld.copy( camera.matrixWorldInverse ).invert();
	camera.projectionMatrix.fromArray( description.projection );
	camera.projectionMatrixInverse.copy( camera.projectionMatrix ).invert();

}

async function load() {

	const loader = new GLTFLoader();
	const description = params.has( 'scene' ) ? await ( await fetch( params.get( 'scene' ) ) ).json() : null;
	const lighting = params.has( 'lighting' ) ? { model: params.get( 'lighting' ) } : {};
	if ( description ) Object.assign( lighting, { model: 'kajiya-kay', ...description.lighting } );
	const shadeSkin = params.get( 'skin' ) !== 'gltf';
	const options = { shadeSkin, lighting, ...( description ? { lod: false } : {} ) };
	loader.register( ( parser ) => ( plugin = new PeltShellFurPlugin( parser, options ) ) );
	const gltf = await loader.loadAsync( description ? new URL( description.model, new URL( params.get( 'scene' ), location.href ) ).href : modelUrl );
	scene.add( gltf.scene );
	if ( ! plugin || plugin.furs.length === 0 ) throw new Error( `${modelUrl} has no PELT_shell_fur primitive` );
	if ( gltf.animations.length > 0 ) {

		mixer = new THREE.AnimationMixer( gltf.scene );
		for ( const clip of gltf.animations ) mixer.clipAction( clip ).play();

	}

	mixer?.setTime( 0 );
	scene.updateMatrixWorld( true );
	if ( description ) useScene( description );
	else frame( plugin.furs[ 0 ].skin );
	window.pelt.drawCalls = measureDrawCalls();
	window.pelt.frameTimeMs = measureFrameTime();
	const summary = {
		extension: gltf.parser.json.extensionsUsed?.includes( 'PELT_shell_fur' ) ?? false,
		animation: gltf.animations[ 0 ]?.name ?? null,
		duration: gltf.animations[ 0 ]?.duration ?? 0,
		hidden: plugin.hidden.map( ( m ) => m.name ),
		hiddenLines: plugin.hidden.filter( ( m ) => m.isLine ).length,
		materials: visibleMaterials( gltf.scene ),
		furs: plugin.furs.map( ( f ) => ( {
			name: f.skin.name,
			skinned: f.skin.isSkinnedMesh === true,
			shells: f.stack.shells,
			drawnShells: f.drawnShells,
			fins: f.fins ? f.fins.geometry.userData.fins : 0,
			prt: f.prt,
			guardHairSegments: f.strands ? f.strands.geometry.index.count / 6 : 0,
			guardHairSegmentsDrawn: f.drawnStrandSegments,
			hiddenFallback: plugin.hidden.filter( ( m ) => m.parent === f.skin.parent ).length,
		} ) ),
		drawCalls: window.pelt.drawCalls,
		frameTimeMs: window.pelt.frameTimeMs,
	};
	status.textContent = `${summary.furs.length} fur(s), ${summary.drawCalls.fur} fur draw calls, ${summary.frameTimeMs.toFixed( 1 )} ms`;
	if ( ! params.has( 'paused' ) ) animate();
	return summary;

}

function animate() {

	const timer = new THREE.Timer();
	timer.connect( document );
	renderer.setAnimationLoop( ( time ) => {

		timer.update( time );
		mixer?.update( timer.getDelta() );
		render();

	} );

}

window.pelt = {
	ready: null,
	setTime( seconds ) {

		renderer.setAnimationLoop( null );
		mixer?.setTime( seconds );
		return render();

	},
	drawCalls: { total: 0, fur: 0 },
	frameTimeMs: NaN,
	toggleFur,
	toggleGuardHairs,
	setZoom( zoom ) {

		camera.zoom = zoom;
		camera.updateProjectionMatrix();

	},
	drawnShells: () => plugin.furs.map( ( f ) => f.drawnShells ),
};
window.pelt.ready = load().catch( ( error ) => {

	status.textContent = String( error );
	throw error;

} );
