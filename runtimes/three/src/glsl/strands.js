// GLSL of the guard hairs (docs/export.md, "Guard hairs"; crates/pelt-render/src/strands.wgsl and
// strand_kk.wgsl): each segment a ribbon facing the eye, `2 · radius` wide and at least a pixel,
// a thinner strand's coverage as its opacity (the preview's "depth" strand order), lit with the
// shells' Kajiya–Kay terms along the segment and Banks-darkened by its height.

import { common } from './common.js';
import { lighting } from './lighting.js';

// What the vertex shader hands the fragment shader: albedo, the segment's direction, the root's
// normal, the ribbon's point (world), the height in fur depths, the coverage.
const varyings = /* glsl */`
varying vec4 vColor;
varying vec3 vTangent;
varying vec3 vNormal;
varying vec3 vPosition;
varying float vHeight;
varying float vCoverage;
`;

export const strandVertex = /* glsl */`
${common}
${lighting}
#include <skinning_pars_vertex>

// The segment's far point minus its near point (object space), the edge of the ribbon this
// corner is on (−1, +1), the radius at this point (object units), the linear albedo, the
// surface normal at the strand's root, and the point's height in fur depths.
attribute vec3 peltSegment;
attribute float peltSide;
attribute float peltRadius;
attribute vec4 peltColor;
attribute vec3 peltRootNormal;
attribute float peltHeight;
// The strand's root (object space) and its LOD rank in [0, 1), and its radius there.
attribute vec4 peltRoot;
attribute float peltRootRadius;

// The viewport's height in pixels.
uniform float peltPixelHeight;
// The strand LOD (strands.wgsl vs_main): a strand thinner at its root than this many pixels is
// kept with probability its width over it (at least peltMinKept) and drawn that much wider.
uniform float peltStrandPixels;
uniform float peltMinKept;

${varyings}

void main() {
	vec3 transformed = vec3( position );
	vec3 segment = peltSegment;
	vec3 objectNormal = peltRootNormal;
	vec3 root = peltRoot.xyz;
#ifdef USE_SKINNING
	// Every point of a strand carries its root's joints: the strand turns rigidly with them.
	#include <skinbase_vertex>
	#include <skinnormal_vertex>
	segment = ( skinMatrix * vec4( segment, 0.0 ) ).xyz;
	root = ( bindMatrixInverse * ( skinMatrix * ( bindMatrix * vec4( root, 1.0 ) ) ) ).xyz;
	#include <skinning_vertex>
#endif
	vec4 world = modelMatrix * vec4( transformed, 1.0 );
	mat3 toWorld = mat3( modelMatrix );
	vec3 along = peltUnitOr( toWorld * segment, vec3( 0.0, 1.0, 0.0 ) );
	vec3 view = peltViewVector( world.xyz );
	vec3 across = peltUnitOr( cross( along, view ), peltUnitOr( cross( along, vec3( 0.0, 0.0, 1.0 ) ), vec3( 1.0, 0.0, 0.0 ) ) );
	// Pixels per world unit here: the ribbon is at least a pixel wide.
	float depth = isOrthographic ? 1.0 : max( - ( viewMatrix * world ).z, 1e-6 );
	float pixelsPerUnit = 0.5 * peltPixelHeight * projectionMatrix[ 1 ][ 1 ] / depth;
	float scale = length( toWorld[ 0 ] );
	// The strand LOD, measured at the root so that every corner of the strand agrees.
	float widen = 1.0;
	if ( peltStrandPixels > 0.0 ) {
		vec4 rootWorld = modelMatrix * vec4( root, 1.0 );
		float rootDepth = isOrthographic ? 1.0 : max( - ( viewMatrix * rootWorld ).z, 1e-6 );
		float rootWidth = peltRootRadius * scale * peltPixelHeight * projectionMatrix[ 1 ][ 1 ] / rootDepth;
		float keep = clamp( rootWidth / peltStrandPixels, peltMinKept, 1.0 );
		if ( peltRoot.w >= keep ) {
			gl_Position = vec4( 2.0, 2.0, 2.0, 1.0 );  // outside the view: dropped
			return;
		}
		widen = 1.0 / keep;
	}
	float width = 2.0 * peltRadius * widen * scale * pixelsPerUnit;
	float drawn = max( width, 1.0 );
	vCoverage = width / drawn;
	vec3 edge = world.xyz + across * ( peltSide * 0.5 * drawn / pixelsPerUnit );
	gl_Position = projectionMatrix * viewMatrix * vec4( edge, 1.0 );
	vColor = peltColor;
	vTangent = along;
	vNormal = toWorld * objectNormal;
	vPosition = edge;
	vHeight = peltHeight;
}
`;

export const strandFragment = /* glsl */`
${common}
${lighting}

${varyings}

void main() {
	vec3 n = peltUnitOr( vNormal, vec3( 0.0, 0.0, 1.0 ) );
	vec3 t = peltUnitOr( vTangent, n );
	// strand_kk.wgsl shade_strand(), straight alpha.
	// The root triangle's curvature is not in the file: the widest band (strands.wgsl root_wrap).
	gl_FragColor = vec4( peltShade( vColor.rgb, t, n, peltViewVector( vPosition ), vHeight, 1.0, PELT_TERMINATOR_WRAP ), vColor.a * vCoverage );
	#include <tonemapping_fragment>
	#include <colorspace_fragment>
}
`;
