// GLSL of the fins (Lengyel et al. 2001, §2.3): crates/pelt-render/src/fins.wgsl (`vs_main`: the quad on its
// edge along each end's growth direction, the fade max(0, 2|p| − 1) with p = fin normal · view at
// the edge's midpoint), common.wgsl (`fin_texel`), fin_kk.wgsl (lit at the corners, Kajiya–Kay
// of the hair spread about the growth direction as the tangent atlas's directions are,
// src/tangents.js) and fin_prt.wgsl (the hair's mean transfer at the row's height).
// A corner carries its own end (position, normal, JOINTS_0 / WEIGHTS_0 as skinIndex /
// skinWeight) and the other end's position, normal and skin, and skins both, so that all four
// corners find the same fin plane. Defines: PELT_PRT.

import { common } from './common.js';
import { lighting } from './lighting.js';
import { prtCommon, prtFragment, prtHotSpot, prtVertex } from './prt.js';

export function finVertex( order, textures ) {

	return /* glsl */`
${common}
${lighting}
${order > 0 ? prtCommon( order, textures ) + prtVertex + prtHotSpot : ''}
#include <skinning_pars_vertex>

attribute vec3 peltOther;
attribute vec3 peltOtherNormal;
attribute vec4 peltOtherJoints;
attribute vec4 peltOtherWeights;
attribute vec3 peltOtherComb;
attribute vec3 peltComb;
attribute vec4 peltColor;
// Fin texture u, v (0 at the top of the fur, 1 at the skin) and the end's length multiplier.
attribute vec3 peltFin;
attribute vec3 peltDpdu;
attribute vec3 peltDpdv;
// The skin's curvature at the end (src/curvature.js): the PRT light's terminator band.
attribute float peltCurvature;

uniform float peltFinOpacity;

#ifndef PELT_PRT
// fin_kk.wgsl frame.fin_tangents: E[d dᵀ] of the hair's directions in the tile frame, packed
// (xx, yy, zz, xy), (xz, yz, 0, 0) (src/tangents.js); zero without hair.
uniform vec4 peltFinTangents[ 2 ];

// fin_kk.wgsl moment_of(): aᵀ M a for the packed symmetric M.
float peltMomentOf( vec3 a, vec4 m0, vec4 m1 ) {
	return m0.x * a.x * a.x + m0.y * a.y * a.y + m0.z * a.z * a.z
		+ 2.0 * ( m0.w * a.x * a.y + m1.x * a.x * a.z + m1.y * a.y * a.z );
}

// fin_kk.wgsl spread_squares(): the mean of (d·a)² over the hair's unit directions d carried from
// the tile frame by the columns du, dv, up, for a = the light and the half vector; the growth
// direction t's own squares where there is no hair to take them from.
vec2 peltSpreadSquares( vec3 du, vec3 dv, vec3 up, vec3 t, vec3 halfway ) {
	vec4 m0 = peltFinTangents[ 0 ];
	vec4 m1 = peltFinTangents[ 1 ];
	vec3 light = peltLightDirection;
	float norm = m0.x * dot( du, du ) + m0.y * dot( dv, dv ) + m0.z * dot( up, up )
		+ 2.0 * ( m0.w * dot( du, dv ) + m1.x * dot( du, up ) + m1.y * dot( dv, up ) );
	if ( ! ( norm > 1e-20 ) ) {
		float u = dot( t, light );
		float v = dot( t, halfway );
		return vec2( u * u, v * v );
	}
	vec3 l = vec3( dot( du, light ), dot( dv, light ), dot( up, light ) );
	vec3 h = vec3( dot( du, halfway ), dot( dv, halfway ), dot( up, halfway ) );
	return vec2( peltMomentOf( l, m0, m1 ), peltMomentOf( h, m0, m1 ) ) / norm;
}
#endif

// fin_kk.wgsl FinOut in straight alpha: color × the lighting's scale and u; the highlight's
// multiple of the light color, v, the opacity and the hair's density (fins.wgsl fin_density).
// fin_prt.wgsl's: color, the hot spot in place of the highlight, and the end's lighting
// (vPeltLight).
varying vec4 vScaleU;
varying vec4 vShineVOpacityDensity;

#ifdef USE_SKINNING
// The blended bone matrix of joints / weights, as three.js's skinnormal_vertex builds it.
mat4 peltSkinMatrix( vec4 joints, vec4 weights ) {
	mat4 m = weights.x * getBoneMatrix( joints.x ) + weights.y * getBoneMatrix( joints.y )
		+ weights.z * getBoneMatrix( joints.z ) + weights.w * getBoneMatrix( joints.w );
	return bindMatrixInverse * m * bindMatrix;
}
#endif

// fins.wgsl CULLED: outside the view volume, so a faded-out fin is dropped whole.
const vec4 PELT_CULLED = vec4( 2.0, 2.0, 2.0, 1.0 );

void main() {
	vec3 p0 = position;
	vec3 n0 = normal;
	vec3 p1 = peltOther;
	vec3 n1 = peltOtherNormal;
	vec3 comb = peltComb;
	vec3 comb1 = peltOtherComb;
	vec3 dpdu = peltDpdu;
	vec3 dpdv = peltDpdv;
#ifdef USE_SKINNING
	mat4 own = peltSkinMatrix( skinIndex, skinWeight );
	mat4 other = peltSkinMatrix( peltOtherJoints, peltOtherWeights );
	p0 = ( own * vec4( p0, 1.0 ) ).xyz;
	n0 = ( own * vec4( n0, 0.0 ) ).xyz;
	comb = ( own * vec4( comb, 0.0 ) ).xyz;
	dpdu = ( own * vec4( dpdu, 0.0 ) ).xyz;
	dpdv = ( own * vec4( dpdv, 0.0 ) ).xyz;
	p1 = ( other * vec4( p1, 1.0 ) ).xyz;
	n1 = ( other * vec4( n1, 0.0 ) ).xyz;
	comb1 = ( other * vec4( comb1, 0.0 ) ).xyz;
#endif
	mat3 toWorld = mat3( modelMatrix );
	mat3 normalToWorld = transpose( inverse( toWorld ) );
	vec3 w0 = ( modelMatrix * vec4( p0, 1.0 ) ).xyz;
	vec3 w1 = ( modelMatrix * vec4( p1, 1.0 ) ).xyz;
	vec3 wn0 = normalToWorld * n0;
	// fins.wgsl vs_main: the plane of the ends' summed normals × the edge, none where that has
	// no direction; p at the midpoint, the same at all four corners.
	vec3 edge = w1 - w0;
	vec3 plane = cross( wn0 + normalToWorld * n1, edge );
	float span = length( plane );
	vec3 finNormal = span > 1e-9 * length( edge ) ? plane / span : vec3( 0.0 );
	float p = dot( finNormal, peltViewVector( 0.5 * ( w0 + w1 ) ) );
	float fade = max( 0.0, 2.0 * abs( p ) - 1.0 ) * peltFinOpacity;
	// v = 0 at the top of the fur, 1 at the skin.
	vec3 g = peltGrowth( n0, comb );
	vec3 lifted = p0 + ( 1.0 - peltFin.y ) * peltFurDepth * peltFin.z * g;
	vec4 world = modelMatrix * vec4( lifted, 1.0 );
	gl_Position = fade > 0.0 ? projectionMatrix * viewMatrix * world : PELT_CULLED;
	float opacity = fade * peltColor.a;
	vec3 n = peltUnitOr( wn0, vec3( 0.0, 0.0, 1.0 ) );
	// fins.wgsl fin_density(): the edge lifted by the ends' growth vectors' difference is that
	// much longer along itself at this corner's height, its hairs that much farther apart.
	vec3 lift = toWorld * ( peltFurDepth * max( peltFin.z, 0.0 ) * ( peltGrowth( n1, comb1 ) - g ) );
	float e2 = dot( edge, edge );
	float density = peltDensityOfGrowth( e2 > 0.0 ? 1.0 + ( 1.0 - peltFin.y ) * dot( lift, edge ) / e2 : 1.0 );
#ifdef PELT_PRT
	// fin_prt.wgsl fin_vertex(): lit per fragment from the ends' lighting.
	vScaleU = vec4( peltColor.rgb, peltFin.x );
	vShineVOpacityDensity = vec4( peltHotSpot( world.xyz ), peltFin.y, opacity, density );
	peltTileLighting( wn0, toWorld * dpdu, toWorld * dpdv,
		peltTerminatorWrap( peltCurvature, peltFurDepth ) );
#else
	// fin_kk.wgsl fin_vertex(): the hair stands about the growth direction, spread as the
	// tangent atlas's directions are; lit at the corner.
	vec3 t = peltUnitOr( toWorld * g, n );
	vec3 view = peltViewVector( world.xyz );
	vec3 up = toWorld * ( peltFurDepth * max( peltFin.z, 0.0 ) * g );
	vec2 squares = peltSpreadSquares( toWorld * dpdu, toWorld * dpdv, up, t, peltHalfVector( n, view ) );
	// fins.wgsl vs_main: the terminator band at the edge, from how its normals turn.
	float wrap = peltTerminatorWrap( peltEdgeCurvature( p0, n0, p1, n1 ), peltFurDepth * peltFin.z );
	vec4 k = peltSpreadHairTerms( squares, n, view, 1.0 - peltFin.y, peltFin.z, wrap );
	vScaleU = vec4( peltColor.rgb * k.rgb, peltFin.x );
	vShineVOpacityDensity = vec4( k.w, peltFin.y, opacity, density );
#endif
}
`;

}

export function finFragment( order, textures ) {

	return /* glsl */`
${common}
${lighting}
${order > 0 ? prtCommon( order, textures ) + prtFragment( textures, true ) : ''}

uniform sampler2D peltFinTexture;

varying vec4 vScaleU;
varying vec4 vShineVOpacityDensity;

// common.wgsl FIN_ANISOTROPY and fin_texel(): the mip level follows the footprint along the fur's
// height (up to 8 times finer than along the edge), so that fins near the silhouette, squeezed
// along their edge, keep their rows apart.
const float PELT_FIN_ANISOTROPY = 8.0;

vec4 peltFinTexel( vec2 uv ) {
	vec2 size = vec2( textureSize( peltFinTexture, 0 ) );
	float across = length( dFdx( uv ) * size );
	float down = length( dFdy( uv ) * size );
	float footprint = max( min( across, down ), max( across, down ) / PELT_FIN_ANISOTROPY );
	return textureLod( peltFinTexture, uv, log2( max( footprint, 1e-6 ) ) );
}

void main() {
	vec2 uv = vec2( vScaleU.w, vShineVOpacityDensity.y );
	vec4 texel = peltFinTexel( uv );
	float alpha = peltSpreadOut( texel.a, vShineVOpacityDensity.w ) * vShineVOpacityDensity.z;
#ifdef PELT_PRT
	// fin_prt.wgsl fin_fragment(): texel × color × the mean transfer at the row's height, lit.
	gl_FragColor = vec4( texel.rgb * vScaleU.rgb * peltMeanRadiance( 1.0 - uv.y, vShineVOpacityDensity.x ), alpha );
#else
	// fin_kk.wgsl fin_fragment() in straight alpha.
	gl_FragColor = vec4( texel.rgb * vScaleU.rgb + peltLightColor * vShineVOpacityDensity.x, alpha );
#endif
	#include <tonemapping_fragment>
	#include <colorspace_fragment>
}
`;

}
