// The fur's three.js materials: ShaderMaterials (three.js adds the skinning, color space and
// tone mapping chunks) over the GLSL ports in glsl/, with their uniforms. Blending is straight
// alpha over, which gives the renderer's premultiplied blend of the premultiplied colors.

import {
	DoubleSide,
	FrontSide,
	NormalBlending,
	ShaderMaterial,
	Vector2,
	Vector3,
	Vector4,
} from 'three';

import { finFragment, finVertex } from './glsl/fins.js';
import { strandFragment, strandVertex } from './glsl/strands.js';
import { surfaceFragment, surfaceVertex } from './glsl/surface.js';

/** Uniforms every fur material shares: the stack's placement and the lighting. */
function sharedUniforms( stack, light ) {

	const a = stack.atlas;
	return {
		peltFurDepth: { value: stack.fur_depth },
		peltLayerSpacing: { value: stack.layer_spacing },
		peltAtlas: { value: new Vector4( a.columns, a.rows, a.tile, 0 ) },
		peltAtlasSize: { value: new Vector2( a.width, a.height ) },
		peltLightDirection: { value: new Vector3( ...light.direction ) },
		peltLightColor: { value: new Vector3( ...light.color ) },
		peltAmbient: { value: new Vector3( ...light.ambient ) },
		peltAmbientGradient: { value: light.ambientGradient.map( ( g ) => new Vector3( ...g ) ) },
		peltKajiyaKay: { value: new Vector4( ...light.kajiyaKay ) },
		peltSelfShadow: { value: light.selfShadow },
	};

}

/** Four floats per entry, zero-padded: the per-texture vec4s of the transfer decoding. */
function vec4s( values, count ) {

	return Array.from( { length: count }, ( _, t ) => new Vector4( ...[ 0, 1, 2, 3 ].map( ( c ) => values[ 4 * t + c ] ?? 0 ) ) );

}

/**
 * The PRT uniforms: the sky, the light's cap per band and its hot spot share, the 8-bit decoding,
 * the textures, and the hair's mean transfer per layer (`layerMeans`).
 */
function prtUniforms( stack, light, textures, layerMeans ) {

	const count = stack.transfer.textures;
	const u = {
		peltSky: { value: new Vector3( ...light.sky ) },
		peltCapWeights: { value: light.capWeights },
		peltHotSpotShare: { value: light.hotSpotShare },
		peltLayerMeans: { value: layerMeans },
		peltTopLayer: { value: stack.layers - 1 },
		peltTransferScale: { value: vec4s( stack.transfer.scale, count ) },
		peltTransferBias: { value: vec4s( stack.transfer.bias, count ) },
	};
	textures.transfer.forEach( ( texture, t ) => {

		u[ `peltTransfer${t}` ] = { value: texture };

	} );
	return u;

}

function prtDefines( prt, defines ) {

	if ( prt ) defines.PELT_PRT = '';
	return defines;

}

/**
 * The shells' material, or with `skin` the skin's (layer 0, opaque). `light` is lightingValues'
 * result; `prt` whether PRT lights the fur, `layerMeans` its mean transfer texture; `alphaTest`
 * the shells' opacity threshold.
 */
export function surfaceMaterial( { stack, textures, light, prt, layerMeans, skin = false, alphaTest } ) {

	const order = prt ? stack.transfer.order : 0;
	const uniforms = {
		...sharedUniforms( stack, light ),
		peltShellAtlas: { value: textures.shellsAtlas },
		peltAlphaTest: { value: alphaTest },
	};
	if ( prt ) Object.assign( uniforms, prtUniforms( stack, light, textures, layerMeans ) );
	else uniforms.peltTangentAtlas = { value: textures.tangentsAtlas };
	const defines = prtDefines( prt, skin ? { PELT_SKIN: '' } : { PELT_SHELLS: stack.shells } );
	if ( skin ) {

		uniforms.peltSkinTexture = { value: textures.skin };

	} else {

		uniforms.peltLayers = { value: stack.layers };
		uniforms.peltDrawn = { value: stack.shells };
		uniforms.peltShellLayers = { value: stack.shell_layers.slice() };

	}

	return new ShaderMaterial( {
		name: skin ? 'PELT_shell_fur skin' : 'PELT_shell_fur shells',
		uniforms,
		defines,
		vertexShader: surfaceVertex( order, prt ? stack.transfer.textures : 0 ),
		fragmentShader: surfaceFragment( order, prt ? stack.transfer.textures : 0 ),
		side: FrontSide,
		transparent: ! skin,
		depthWrite: skin,
		blending: NormalBlending,
	} );

}

/**
 * The fins' material; `layerMeans` is the PRT's mean transfer texture, `finTangents` (Kajiya–Kay)
 * the hair directions' packed second moment (tangents.js).
 */
export function finMaterial( { stack, textures, light, prt, finOpacity, layerMeans, finTangents } ) {

	const order = prt ? stack.transfer.order : 0;
	const uniforms = {
		...sharedUniforms( stack, light ),
		peltFinTexture: { value: textures.fin },
		peltFinOpacity: { value: finOpacity },
	};
	if ( prt ) Object.assign( uniforms, prtUniforms( stack, light, textures, layerMeans ) );
	else {

		// Without the moment (zeros), the fins are lit along the growth direction.
		const m = finTangents ?? new Array( 8 ).fill( 0 );
		uniforms.peltFinTangents = { value: [ new Vector4( ...m.slice( 0, 4 ) ), new Vector4( ...m.slice( 4, 8 ) ) ] };

	}

	return new ShaderMaterial( {
		name: 'PELT_shell_fur fins',
		uniforms,
		defines: prtDefines( prt, {} ),
		vertexShader: finVertex( order, prt ? stack.transfer.textures : 0 ),
		fragmentShader: finFragment( order, prt ? stack.transfer.textures : 0 ),
		side: DoubleSide,
		transparent: true,
		depthWrite: false,
		blending: NormalBlending,
	} );

}

/**
 * The guard hairs' ribbons (glsl/strands.js), Kajiya–Kay lit under either model; drawn before
 * the shells and writing depth, so the shells in front blend over them (the preview's "depth"
 * strand order). `strandPixels`: the strand LOD keeps a share of the strands thinner than this
 * many pixels, drawn that wide (0: every strand at its width, its coverage as opacity).
 */
export function strandMaterial( { stack, light, strandPixels = 1 } ) {

	return new ShaderMaterial( {
		name: 'PELT_shell_fur guard hairs',
		uniforms: {
			...sharedUniforms( stack, light ),
			peltPixelHeight: { value: 1 },
			// src/render: RenderSettings::strand_pixels' default, strands.rs MIN_KEPT.
			peltStrandPixels: { value: strandPixels },
			peltMinKept: { value: 1 / 16 },
		},
		vertexShader: strandVertex,
		fragmentShader: strandFragment,
		side: DoubleSide,
		transparent: true,
		depthWrite: true,
		blending: NormalBlending,
	} );

}
