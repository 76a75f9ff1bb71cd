// The fur of one skin primitive's three.js mesh (docs/export.md, "Drawing"): the shells in one
// instanced draw and the fins in one draw, both skinned like the skin when it is a SkinnedMesh,
// alpha-blended after the opaque pass; with guard hairs, their ribbons in one more draw
// (strands.js). The ribbons are created first, then the fins: three.js draws transparent
// objects at the same depth in creation order, and the renderer draws the fins (pass b) before
// the shells (pass c). The fins within their draw go farthest first (finorder.js), re-sorted
// when the eye moves.

import { Matrix4, Mesh, SkinnedMesh, Sphere, Vector2, Vector3 } from 'three';

import { backToFront, finCenters } from './finorder.js';
import { aliasFurAttributes, finGeometry, furAttributes, shellGeometry, skinCurvature } from './geometry.js';
import { finMaterial, strandMaterial, surfaceMaterial } from './materials.js';
import { keptIndices, ribbonGeometry } from './strands.js';
import { lodShells, pixelsPerUnit } from './stack.js';

const _size = new Vector2();
const _sphere = new Sphere();
const _eye = new Vector3();
const _toLocal = new Matrix4();
const _joint = new Matrix4();
const _finEye = new Vector3();

// The fins are re-sorted when the eye, in their own space, has moved this share of its
// distance to the fur (or turned this many radians, seen by an orthographic camera).
const FIN_RESORT = 1e-3;

export class PeltFur {

	/**
	 * `skin`: the skin primitive's Mesh or SkinnedMesh; `ext`: its extension object; `textures`:
	 * loadFurTextures' result; `light`: lightingValues' result; `prt`: whether PRT lights it;
	 * `layerMeans`: the hair's mean transfer texture under PRT; `finTangents`: the hair
	 * directions' second moment under Kajiya–Kay (tangents.js); `guardHairs`: the three.js lines
	 * of the extension's guard-hair primitive, when it has one; `options`: the plugin's.
	 */
	constructor( { skin, ext, textures, light, prt, layerMeans = null, finTangents = null, guardHairs = null, options = {} } ) {

		const stack = ext.stack;
		this.skin = skin;
		this.stack = stack;
		this.prt = prt;
		this.lod = options.lod === false ? null : { ...options.lod };
		const attributes = furAttributes( skin.geometry, ext );
		const lengths = attributes.length;
		this.maxLength = 0;
		for ( let i = 0; i < lengths.count; i ++ ) this.maxLength = Math.max( this.maxLength, lengths.getX( i ) );
		if ( ! skin.geometry.boundingSphere ) skin.geometry.computeBoundingSphere();
		this.restSphere = skin.geometry.boundingSphere.clone();

		const common = { stack, textures, light, prt, layerMeans };
		const make = ( geometry, material, name ) => {

			const mesh = skin.isSkinnedMesh ? new SkinnedMesh( geometry, material ) : new Mesh( geometry, material );
			mesh.name = `${skin.name} ${name}`;
			// The fur reaches past the skin's bounds and a skinned mesh moves them.
			mesh.frustumCulled = false;
			mesh.castShadow = false;
			mesh.receiveShadow = false;
			// Picking finds the skin itself.
			mesh.raycast = () => {};
			// A child at the skin's own place: it follows the skin's node, and a SkinnedMesh child
			// has the skin's world matrix, so the same bind matrices.
			skin.add( mesh );
			if ( skin.isSkinnedMesh ) mesh.bind( skin.skeleton, skin.bindMatrix );
			return mesh;

		};

		this.strands = null;
		this.drawnStrandSegments = 0;
		if ( guardHairs && options.guardHairs !== false ) {

			const geometry = ribbonGeometry( guardHairs.geometry, ext.guardHairs.radius, stack.fur_depth );
			this.strands = make( geometry, strandMaterial( { ...common, strandPixels: options.strandPixels ?? 1 } ), 'guard hairs' );
			this.strands.onBeforeRender = ( renderer, scene, camera ) => this.updateStrands( renderer, camera );
			this.drawnStrandSegments = geometry.index.count / 6;

		}

		this.fins = null;
		const curvature = skinCurvature( skin.geometry );
		const finsGeometry = options.fins === false ? null : finGeometry( skin.geometry, attributes, stack, curvature );
		if ( finsGeometry ) {

			const material = finMaterial( { ...common, finOpacity: options.finOpacity ?? 1, finTangents } );
			this.fins = make( finsGeometry, material, 'fins' );
			this.finCenters = finCenters( finsGeometry.getAttribute( 'position' ).array, finsGeometry.userData.fins );
			this.sortedEye = null;
			this.fins.onBeforeRender = ( renderer, scene, camera ) => this.sortFins( camera );

		}

		const shellMaterial = surfaceMaterial( { ...common, alphaTest: options.alphaTest ?? 1 / 255 } );
		this.shells = make( shellGeometry( skin.geometry, attributes, stack.shells, curvature ), shellMaterial, 'shells' );
		// Held by the skin's geometry too, which frees it with its own buffers (and reads it when shaded).
		skin.geometry.setAttribute( 'peltCurvature', this.shells.geometry.getAttribute( 'peltCurvature' ) );
		this.shells.onBeforeRender = ( renderer, scene, camera ) => this.updateLod( renderer, camera );
		this.drawnShells = stack.shells;

		this.originalSkinMaterial = skin.material;
		if ( options.shadeSkin ) {

			aliasFurAttributes( skin.geometry, attributes );
			skin.material = surfaceMaterial( { ...common, skin: true } );

		}

	}

	/** Draw calls the fur adds to the skin's: one for the shells, one for the fins, one for the guard hairs. */
	get drawCalls() {

		return this.visible ? 1 + ( this.fins ? 1 : 0 ) + ( this.strands ? 1 : 0 ) : 0;

	}

	get visible() {

		return this.shells.visible;

	}

	set visible( value ) {

		this.shells.visible = value;
		if ( this.fins ) this.fins.visible = value;
		if ( this.strands ) this.strands.visible = value;

	}

	/** The three.js objects the fur added. */
	get meshes() {

		return [ this.strands, this.fins, this.shells ].filter( ( mesh ) => mesh !== null );

	}

	/**
	 * Distance LOD (crates/pelt-render/src/lod.rs): the fur's depth in pixels at the bounding sphere's centre
	 * picks the shells drawn, at least a quarter of them; fewer shells keep the full depth.
	 */
	updateLod( renderer, camera ) {

		let drawn = this.stack.shells;
		if ( this.lod ) {

			const target = renderer.getRenderTarget();
			if ( target ) _size.set( target.width, target.height );
			else renderer.getDrawingBufferSize( _size );
			_sphere.copy( this.restSphere ).applyMatrix4( this.shells.matrixWorld );
			const scale = this.shells.matrixWorld.getMaxScaleOnAxis();
			const ppu = pixelsPerUnit( _sphere.center.toArray(), camera.matrixWorldInverse, camera.projectionMatrix, _size.x, _size.y );
			const furPixels = ppu * scale * this.stack.fur_depth * this.maxLength;
			drawn = lodShells( furPixels, this.stack.shells, this.lod );

		}

		this.drawnShells = drawn;
		this.shells.geometry.instanceCount = drawn;
		this.shells.material.uniforms.peltDrawn.value = drawn;

	}

	/**
	 * Draws the fins farthest from the eye first (finorder.js): re-sorts their triangles when the
	 * eye, in the fins' rest space (following a skin's first joint), moved by more than
	 * FIN_RESORT of its distance to the fur since the last sort.
	 */
	sortFins( camera ) {

		// Homogeneous: a position (w = 1) or, orthographic, the unit direction toward the viewer.
		const w = camera.isOrthographicCamera ? 0 : 1;
		// Into the fins' rest space: a skinned mesh's vertices move with the skeleton's first
		// joint (the armature in Pelt's exports, whose rest bind also holds the object's
		// placement), as three.js skins them: bindMatrix⁻¹ · joint · inverse bind · bindMatrix.
		_toLocal.copy( this.fins.matrixWorld );
		const skeleton = this.fins.isSkinnedMesh ? this.fins.skeleton : null;
		if ( skeleton && skeleton.bones.length > 0 ) {

			_joint.multiplyMatrices( skeleton.bones[ 0 ].matrixWorld, skeleton.boneInverses[ 0 ] );
			_toLocal.multiply( this.fins.bindMatrixInverse ).multiply( _joint ).multiply( this.fins.bindMatrix );

		}

		_toLocal.invert();
		// A scratch vector: this runs every frame, and most frames stop at the test below.
		const eye = w === 0
			? _finEye.setFromMatrixColumn( camera.matrixWorld, 2 ).transformDirection( _toLocal )
			: _finEye.setFromMatrixPosition( camera.matrixWorld ).applyMatrix4( _toLocal );
		const last = this.sortedEye;
		if ( last && last.w === w ) {

			const reach = w === 0 ? 1 : eye.distanceTo( this.restSphere.center ) + this.restSphere.radius;
			if ( last.eye.distanceTo( eye ) <= FIN_RESORT * reach ) return;

		}

		const index = this.fins.geometry.index;
		backToFront( this.finCenters, [ eye.x, eye.y, eye.z, w ], index.array );
		index.needsUpdate = true;
		this.sortedEye = { eye: eye.clone(), w };

	}

	/**
	 * The ribbons' viewport height, and the strand LOD's draw range: only the strands the shader
	 * may keep at the fur's nearest point to the eye are drawn (the shader decides each one).
	 */
	updateStrands( renderer, camera ) {

		const target = renderer.getRenderTarget();
		if ( target ) _size.set( target.width, target.height );
		else renderer.getDrawingBufferSize( _size );
		const uniforms = this.strands.material.uniforms;
		uniforms.peltPixelHeight.value = _size.y;
		_sphere.copy( this.restSphere ).applyMatrix4( this.strands.matrixWorld );
		// The sphere's point nearest the eye.
		_eye.setFromMatrixPosition( camera.matrixWorld ).sub( _sphere.center );
		const distance = _eye.length();
		const nearest = distance > _sphere.radius ? _sphere.center.clone().addScaledVector( _eye, _sphere.radius / distance ) : null;
		const scale = this.strands.matrixWorld.getMaxScaleOnAxis();
		const ppu = nearest ? scale * pixelsPerUnit( nearest.toArray(), camera.matrixWorldInverse, camera.projectionMatrix, _size.x, _size.y ) : Infinity;
		const geometry = this.strands.geometry;
		const count = keptIndices( geometry.userData.strandLod, ppu, uniforms.peltStrandPixels.value, uniforms.peltMinKept.value );
		geometry.setDrawRange( 0, count );
		this.drawnStrandSegments = count / 6;

	}

	/** Removes the fur and gives the skin its own material back. */
	dispose() {

		for ( const mesh of this.meshes ) {

			mesh.removeFromParent();
			mesh.material.dispose();

		}

		// The shells' geometry owns no buffers (disposing it would free the skin's, its curvature's too).
		if ( this.fins ) this.fins.geometry.dispose();
		if ( this.strands ) this.strands.geometry.dispose();

		if ( this.skin.material !== this.originalSkinMaterial ) {

			this.skin.material.dispose();
			this.skin.material = this.originalSkinMaterial;

		}

	}

}
