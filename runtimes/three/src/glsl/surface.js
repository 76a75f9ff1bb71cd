// GLSL of the skin and the shells (Lengyel et al. 2001, §2.3): crates/pelt-render/src/surface.wgsl (`lift`,
// the shared vertex), shells.wgsl (every shell in one instanced draw, the layer per instance, the
// alpha test), skin.wgsl, surface_kk.wgsl (`shade_surface`, `hair_tangent`, `skin_fragment`) and
// surface_prt.wgsl. Defines: PELT_SKIN (the skin itself, layer 0, opaque; else the shells),
// PELT_PRT (PRT lighting, else Kajiya–Kay), PELT_SHELLS (the stack's shell count).

import { common } from './common.js';
import { lighting } from './lighting.js';
import { prtCommon, prtFragment, prtVertex } from './prt.js';

// surface_kk.wgsl SurfaceVarying, in world space: position and painted length, normal and
// uv.x, dP/du and uv.y, dP/dv, the tile's up axis (the growth vector, which also tells how the
// hair thins), color, layer. PRT needs no dP/dv in the fragment (surface_prt.wgsl), but the
// lighting (vPeltLight).
const varyings = /* glsl */`
varying vec4 vPositionLength;
varying vec4 vNormalU;
varying vec4 vDpduV;
#ifndef PELT_PRT
varying vec3 vDpdv;
#endif
varying vec3 vUp;
varying vec4 vColor;
flat varying int vLayer;
`;

/** The vertex shader; `order` > 0 for PRT with `textures` transfer textures. */
export function surfaceVertex( order, textures ) {

	return /* glsl */`
${common}
${lighting}
${order > 0 ? prtCommon( order, textures ) + prtVertex : ''}
#include <skinning_pars_vertex>

attribute vec2 peltUv;
attribute vec4 peltColor;
attribute float peltLength;
attribute vec3 peltComb;
attribute vec3 peltDpdu;
attribute vec3 peltDpdv;
// The skin's curvature at the vertex (src/curvature.js): the PRT light's terminator band.
attribute float peltCurvature;

#ifndef PELT_SKIN
// Layers of the volume, and the shells drawn now (the LOD's instance count).
uniform int peltLayers;
uniform int peltDrawn;
// The layer each of the stack's shells shows (stack.shell_layers).
uniform int peltShellLayers[ PELT_SHELLS ];
#endif

${varyings}

#ifndef PELT_SKIN
// common.wgsl shell_layers(): shell instance + 1 shows the stack's own layer when every shell
// is drawn, else round(s (L − 1) / drawn) (halves up), so fewer shells keep the full depth.
int peltShellLayer( int instance ) {
	if ( peltDrawn == PELT_SHELLS ) return peltShellLayers[ instance ];
	int s = instance + 1;
	return ( 2 * s * ( peltLayers - 1 ) + peltDrawn ) / ( 2 * peltDrawn );
}
#endif

void main() {
	vec3 objectNormal = vec3( normal );
	vec3 transformed = vec3( position );
	vec3 comb = peltComb;
	vec3 dpdu = peltDpdu;
	vec3 dpdv = peltDpdv;
#ifdef USE_SKINNING
	// The comb and dP/du, dP/dv are directions skinned with the normal's blended matrix
	// (docs/export.md "Fur on a skin"); the offset follows the skinned position.
	#include <skinbase_vertex>
	#include <skinnormal_vertex>
	comb = ( skinMatrix * vec4( comb, 0.0 ) ).xyz;
	dpdu = ( skinMatrix * vec4( dpdu, 0.0 ) ).xyz;
	dpdv = ( skinMatrix * vec4( dpdv, 0.0 ) ).xyz;
	#include <skinning_vertex>
#endif
#ifdef PELT_SKIN
	// skin.wgsl vs_main: the skin at height 0 (its lighting reads the painted length).
	int layer = 0;
	float hairLength = 1.0;
#else
	int layer = peltShellLayer( gl_InstanceID );
	float hairLength = peltLength;
#endif
	// surface.wgsl lift(): P + l · layer_spacing · fur_depth · length · growth(N, C).
	vec3 up = peltFurDepth * hairLength * peltGrowth( objectNormal, comb );
	vec3 lifted = transformed + float( layer ) * peltLayerSpacing * up;
	vec4 world = modelMatrix * vec4( lifted, 1.0 );
	gl_Position = projectionMatrix * viewMatrix * world;

	mat3 toWorld = mat3( modelMatrix );
	vec3 worldNormal = transpose( inverse( toWorld ) ) * objectNormal;
	vPositionLength = vec4( world.xyz, peltLength );
	vNormalU = vec4( worldNormal, peltUv.x );
	vDpduV = vec4( toWorld * dpdu, peltUv.y );
#ifdef PELT_PRT
	peltTileLighting( worldNormal, vDpduV.xyz, toWorld * dpdv,
		peltTerminatorWrap( peltCurvature, peltFurDepth ) );
#else
	vDpdv = toWorld * dpdv;
#endif
	vUp = toWorld * up;
	vColor = peltColor;
	vLayer = layer;
}
`;

}

/** The fragment shader; `order` > 0 for PRT with `textures` transfer textures. */
export function surfaceFragment( order, textures ) {

	return /* glsl */`
${common}
${lighting}
${order > 0 ? prtCommon( order, textures ) + prtFragment( textures, false ) : ''}

uniform sampler2D peltShellAtlas;
#ifdef PELT_SKIN
// Layer 0 on its own, repeating with mipmaps (the WGSL's tile sampler).
uniform sampler2D peltSkinTexture;
#endif
#ifndef PELT_PRT
uniform sampler2D peltTangentAtlas;
#endif
// Shell fragments below this opacity are dropped (settings.rs alpha_test).
uniform float peltAlphaTest;

${varyings}

// common.wgsl screen_spread(): triangle_spread() from the screen steps of the lifted position
// and its growth vector up (stand: the lift's share of up). Uniform control flow.
vec2 peltScreenSpread( vec3 position, vec3 up, float stand ) {
	vec3 ux = dFdx( up );
	vec3 uy = dFdy( up );
	return peltTriangleSpread( dFdx( position ) - stand * ux, dFdy( position ) - stand * uy, ux, uy );
}

#ifndef PELT_PRT
// surface_kk.wgsl hair_tangent(): the tangent map's direction d (rgb = 0.5 d + 0.5, tile frame)
// carried to the surface, t = d.x dP/du + d.y dP/dv + d.z · up.
vec3 peltHairTangent( vec2 atlasUv, vec3 n ) {
	vec3 d = texture( peltTangentAtlas, atlasUv ).xyz * 2.0 - 1.0;
	return peltUnitOr( d.x * vDpduV.xyz + d.y * vDpdv + d.z * vUp, n );
}
#endif

void main() {
	vec3 position = vPositionLength.xyz;
	vec2 uv = vec2( vNormalU.w, vDpduV.w );
	vec2 atlasUv = peltAtlasUv( uv, vLayer );
	// Straight alpha, rgb decoded from sRGB by the sampler.
#ifdef PELT_SKIN
	vec4 texel = texture( peltSkinTexture, uv );
#else
	vec4 texel = texture( peltShellAtlas, atlasUv );
#endif
	vec3 n = peltUnitOr( vNormalU.xyz, vec3( 0.0, 0.0, 1.0 ) );
	vec3 view = peltViewVector( position );
#ifndef PELT_PRT
	// surface_kk.wgsl surface_wrap(), before any discard (screen derivatives): the terminator
	// band under the hair painted here.
	vec3 dpx = dFdx( position );
	vec3 dpy = dFdy( position );
	float kx = dot( dFdx( n ), dpx ) / max( dot( dpx, dpx ), 1e-30 );
	float ky = dot( dFdy( n ), dpy ) / max( dot( dpy, dpy ), 1e-30 );
	float furHeight = peltFurDepth * vPositionLength.w;
	float wrap = peltTerminatorWrap( max( max( kx, ky ), 0.0 ), furHeight );
#endif
#ifdef PELT_SKIN
	// skin.wgsl fs_main: layer 0 (premultiplied) × vertex color, opaque.
	vec3 albedo = texel.rgb * texel.a * vColor.rgb;
	#ifdef PELT_PRT
	// surface_prt.wgsl skin_fragment(): lit by the transfer of its own layer, under hair of
	// painted length l its darkening of the bare skin (bare_skin) to the power l (painted_skin).
	vec3 furred = albedo * peltTransferRadiance( atlasUv, 0.0, peltHotSpot( position ) );
	float l = vPositionLength.w;
	vec3 bare = peltShadeSkin( albedo, n, view, 0.0, 0.0 );
	vec3 through = max( furred, vec3( 0.0 ) ) / max( bare, vec3( 1e-6 ) );
	gl_FragColor = vec4( l == 1.0 ? furred : bare * pow( max( through, vec3( 1e-8 ) ), vec3( max( l, 0.0 ) ) ), 1.0 );
	#else
	// surface_kk.wgsl skin_fragment().
	gl_FragColor = vec4( peltShadeSkin( albedo, n, view, vPositionLength.w, wrap ), 1.0 );
	#endif
#else
	// shells.wgsl fs_main: the hair's density at the shell's height over its triangle (screen
	// derivatives: before any discard); bald faces and (nearly) empty texels draw nothing.
	float height = float( vLayer ) * peltLayerSpacing;
	float density = peltHairDensity( peltScreenSpread( position, vUp, height ), height );
	float alpha = texel.a * vColor.a;
	if ( vPositionLength.w <= 0.0 || alpha < peltAlphaTest ) discard;
	alpha = peltSpreadOut( alpha, density );
	vec3 albedo = texel.rgb * vColor.rgb;
	#ifdef PELT_PRT
	// surface_prt.wgsl shade_surface(): texel × color × the transfer dotted with the light.
	gl_FragColor = vec4( albedo * peltTransferRadiance( atlasUv, height, peltHotSpot( position ) ), alpha );
	#else
	// surface_kk.wgsl shade_surface(), straight alpha: the blend premultiplies.
	gl_FragColor = vec4( peltShade( albedo, peltHairTangent( atlasUv, n ), n, view, height, vPositionLength.w, wrap ), alpha );
	#endif
#endif
	#include <tonemapping_fragment>
	#include <colorspace_fragment>
}
`;

}
