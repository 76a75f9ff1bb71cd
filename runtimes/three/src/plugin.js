// The GLTFLoader plugin for PELT_shell_fur (docs/export.md, "glTF: `engine` mode and the
// `PELT_shell_fur` extension"). After the scene is built, every mesh primitive that carries the
// extension gets its fur (fur.js), and the fallback primitives, which stand in for the fur in
// viewers without the extension, are hidden.
//
//   loader.register( ( parser ) => new PeltShellFurPlugin( parser, options ) );
//
// Options: `lighting` (lighting.js DEFAULT_LIGHTING's fields), `lod` ({shellsPerPixel,
// minShare}, or false for every shell always), `fins` (false for none), `guardHairs` (false:
// leave the guard hairs' lines as three.js loaded them), `strandPixels` (the strand LOD: a share
// of the strands thinner than this many pixels drawn that wide, as the renderer's
// `strand_pixels`; 0 for every strand at its width), `finOpacity`,
// `alphaTest`, `shadeSkin` (true: the skin too is drawn with the renderer's skin shading instead
// of its glTF material), `onFur(fur)` (called for each fur built).

import { DataTexture, FloatType, NearestFilter, RGBAFormat } from 'three';

import { EXTENSION_NAME, furPrimitives } from './extension.js';
import { PeltFur } from './fur.js';
import { lightingValues, resolveLighting, usesPrt } from './lighting.js';
import { imageBytes } from './pixels.js';
import { layerMeans } from './sh.js';
import { tangentMoments } from './tangents.js';
import { loadFurTextures } from './textures.js';

/**
 * The fins' mean transfer per layer as a float texture: texel (t, layer) holds the means of
 * coefficients 4t .. 4t + 3 (zero past the last).
 */
function layerMeansTexture( textures, stack ) {

	const bytes = imageBytes( [ ...textures.transfer.map( ( t ) => t.image ), textures.shellsAtlas.image ] );
	const shellBytes = bytes.pop();
	const means = layerMeans( bytes, shellBytes, stack );
	const n = stack.transfer.coefficients;
	const columns = stack.transfer.textures;
	const data = new Float32Array( 4 * columns * stack.layers );
	for ( let layer = 0; layer < stack.layers; layer ++ ) {

		for ( let k = 0; k < n; k ++ ) data[ 4 * layer * columns + k ] = means[ layer * n + k ];

	}

	const texture = new DataTexture( data, columns, stack.layers, RGBAFormat, FloatType );
	texture.minFilter = NearestFilter;
	texture.magFilter = NearestFilter;
	texture.needsUpdate = true;
	return texture;

}

/** The hair directions' second moment for the fins' Kajiya–Kay lighting (tangents.js). */
function finTangentMoments( textures, stack ) {

	const [ tangents, shells ] = imageBytes( [ textures.tangentsAtlas.image, textures.shellsAtlas.image ] );
	return tangentMoments( tangents, shells, stack );

}

export class PeltShellFurPlugin {

	constructor( parser, options = {} ) {

		this.parser = parser;
		this.name = EXTENSION_NAME;
		this.options = options;
		/** Every fur built, in file order. */
		this.furs = [];
		/** The fallback meshes hidden. */
		this.hidden = [];

	}

	async afterRoot( result ) {

		const parser = this.parser;
		const entries = furPrimitives( parser.json );
		if ( entries.length === 0 ) return;
		const lighting = resolveLighting( this.options.lighting );

		// The three.js meshes of each glTF primitive (a mesh used by several nodes has several).
		const byPrimitive = new Map();
		for ( const scene of result.scenes ) {

			scene.traverse( ( object ) => {

				const ref = object.isMesh || object.isLine ? parser.associations.get( object ) : undefined;
				if ( ref?.meshes === undefined || ref.primitives === undefined ) return;
				const key = `${ref.meshes}:${ref.primitives}`;
				if ( ! byPrimitive.has( key ) ) byPrimitive.set( key, [] );
				byPrimitive.get( key ).push( object );

			} );

		}

		for ( const [ m, p, ext ] of entries ) {

			const skins = byPrimitive.get( `${m}:${p}` ) || [];
			if ( skins.length === 0 ) continue;
			const textures = await loadFurTextures( parser, ext );
			const prt = usesPrt( lighting, ext.stack );
			const light = lightingValues( lighting, prt ? ext.stack.transfer.order : 0 );
			const means = prt ? layerMeansTexture( textures, ext.stack ) : null;
			const finTangents = prt || this.options.fins === false ? null : finTangentMoments( textures, ext.stack );
			for ( const skin of skins ) {

				for ( const f of ext.fallback ) {

					for ( const stand of byPrimitive.get( `${m}:${f}` ) || [] ) {

						if ( stand.parent !== skin.parent ) continue;
						stand.visible = false;
						this.hidden.push( stand );

					}

				}

				// The guard hairs' lines beside this skin, drawn as ribbons by the fur instead.
				const lines = ext.guardHairs && this.options.guardHairs !== false
					? ( byPrimitive.get( `${m}:${ext.guardHairs.primitive}` ) || [] ).find( ( l ) => l.parent === skin.parent )
					: undefined;
				if ( lines ) {

					lines.visible = false;
					this.hidden.push( lines );

				}

				const fur = new PeltFur( { skin, ext, textures, light, prt, layerMeans: means, finTangents, guardHairs: lines, options: this.options } );
				this.furs.push( fur );
				this.options.onFur?.( fur );

			}

		}

		result.userData.peltFur = this.furs;

	}

}
