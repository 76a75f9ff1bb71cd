// GLSL of the PRT lighting (prt-shell-fur §2.4), after crates/pelt-render/src/prt_rotate.wgsl (each vertex's
// tile frame, the light faded past its terminator), crates/pelt-render/src/prt.wgsl (`transfer_radiance`,
// `mean_transfer`, `mean_radiance`) and crates/pelt-render/src/prt_light.rs (a uniform sky plus the
// directional light as a uniform SH cap). As in the renderer, each vertex holds the lighting
// turned into its tile frame and the fragments interpolate it; the renderer rotates the whole
// lighting with SH rotation matrices, this runtime evaluates the cap about the light's direction
// in the tile frame (the cap is symmetric about its direction and the sky is constant, so both
// turn exactly that way). Per vertex, vPeltLight[t] holds the light's coefficients 4t .. 4t + 3
// without its color; the sky adds to coefficient 0.

/** Defines for `order` bands in `textures` RGBA transfer textures. */
export function prtCommon( order, textures ) {

	return /* glsl */`
#define PELT_ORDER ${order}
#define PELT_COEFFS ${order * order}
#define PELT_TRANSFER_TEXTURES ${textures}
`;

}

/**
 * prt.wgsl hot_spot(): how much of the lighting clears of the transfer's shadow at a point, the
 * light's share of it (lighting.rs `hot_spot_share`) × the path it shares with the view, from
 * 0.05 up. Needs the lighting chunk (peltSharedPath).
 */
export const prtHotSpot = /* glsl */`
uniform float peltHotSpotShare;
const float PELT_HOT_SPOT_MIN = 0.05;

float peltHotSpot( vec3 position ) {
	float clear = peltSharedPath( peltLightDirection, peltViewVector( position ) );
	return peltHotSpotShare * max( clear - PELT_HOT_SPOT_MIN, 0.0 ) / ( 1.0 - PELT_HOT_SPOT_MIN );
}
`;

/** The vertex side: the light in the tile frame (prt_rotate.wgsl `main`, prt_light.rs). */
export const prtVertex = /* glsl */`
uniform float peltCapWeights[ PELT_ORDER ];
varying vec4 vPeltLight[ PELT_TRANSFER_TEXTURES ];

// prt_rotate.wgsl TERMINATOR_WRAP: the widest band past the terminator, and the width over which
// the light fades out down to the band's edge.
const float PELT_PRT_TERMINATOR_WRAP = 0.3;

// crates/pelt-core/src/prt/sh.rs eval_unit(): every basis function at the unit direction d (index l² + l + m,
// orthonormal, no Condon–Shortley phase): Y_l^m = √2 Q_l^m(z) Re((x + iy)^m) (Im for m < 0),
// Q by the normalized three-term recurrence in l.
void peltShEval( vec3 d, out float y[ PELT_COEFFS ] ) {
	float qmm = 0.28209479177387814;
	float c = 1.0;
	float s = 0.0;
	for ( int m = 0; m < PELT_ORDER; m ++ ) {
		float mf = float( m );
		if ( m > 0 ) {
			qmm *= sqrt( ( 2.0 * mf + 1.0 ) / ( 2.0 * mf ) );
			float c2 = d.x * c - d.y * s;
			s = d.x * s + d.y * c;
			c = c2;
		}
		float qPrev = 0.0;
		float q = qmm;
		for ( int l = m; l < PELT_ORDER; l ++ ) {
			float lf = float( l );
			if ( l > m ) {
				float a = sqrt( ( 4.0 * lf * lf - 1.0 ) / ( lf * lf - mf * mf ) );
				float b = sqrt( ( ( lf - 1.0 ) * ( lf - 1.0 ) - mf * mf ) / ( 4.0 * ( lf - 1.0 ) * ( lf - 1.0 ) - 1.0 ) );
				float next = a * ( d.z * q - b * qPrev );
				qPrev = q;
				q = next;
			}
			int center = l * l + l;
			if ( m == 0 ) {
				y[ center ] = q;
			} else {
				y[ center + m ] = 1.4142135623730951 * q * c;
				y[ center - m ] = 1.4142135623730951 * q * s;
			}
		}
	}
}

// prt_rotate.wgsl main(): the vertex's orthonormal tile frame (z the normal, x the tangential
// part of dP/du, y = z × x, mirrored where dP/dv points the other way) turns the direction
// toward the light into tile coordinates; the light fades out past the vertex's terminator,
// band (peltTerminatorWrap of the vertex's curvature) beyond it in N·L. Its
// cap's coefficients there are √(4π / (2l + 1)) z_l Y_l^m (sh.rs zonal_to_direction), the band
// weights precomputed (peltCapWeights). Writes vPeltLight.
void peltTileLighting( vec3 normal, vec3 dpdu, vec3 dpdv, float band ) {
	vec3 z = dot( normal, normal ) > 1e-24 ? normalize( normal ) : vec3( 0.0, 0.0, 1.0 );
	vec3 x = dpdu - z * dot( z, dpdu );
	if ( dot( x, x ) <= 1e-8 * dot( dpdu, dpdu ) ) {
		// No usable dP/du: any tangent will do (the pelt is nearly isotropic about the normal).
		x = abs( z.x ) > 0.9 ? vec3( 0.0, 1.0, 0.0 ) : vec3( 1.0, 0.0, 0.0 );
		x = x - z * dot( z, x );
	}
	x = normalize( x );
	vec3 y = cross( z, x );
	float mirror = dot( y, dpdv ) < 0.0 ? -1.0 : 1.0;
	vec3 l = peltLightDirection;
	float shown = clamp( ( dot( z, l ) + band ) / PELT_PRT_TERMINATOR_WRAP, 0.0, 1.0 );
	float basis[ PELT_COEFFS ];
	peltShEval( normalize( vec3( dot( x, l ), mirror * dot( y, l ), dot( z, l ) ) ), basis );
	float light[ 4 * PELT_TRANSFER_TEXTURES ];
	for ( int k = 0; k < 4 * PELT_TRANSFER_TEXTURES; k ++ ) light[ k ] = 0.0;
	for ( int b = 0; b < PELT_ORDER; b ++ ) {
		for ( int m = -b; m <= b; m ++ ) {
			int k = b * b + b + m;
			light[ k ] = shown * peltCapWeights[ b ] * basis[ k ];
		}
	}
	for ( int t = 0; t < PELT_TRANSFER_TEXTURES; t ++ ) {
		vPeltLight[ t ] = vec4( light[ 4 * t ], light[ 4 * t + 1 ], light[ 4 * t + 2 ], light[ 4 * t + 3 ] );
	}
}
`;

// Sampler arrays take constant indices only, so the per-texture code is written out.
function perTexture( textures, body ) {

	return Array.from( { length: textures }, ( _, t ) => body( t ) ).join( '\n' );

}

/**
 * The fragment side for `textures` transfer textures: the shells' and skin's transfer (`peltTransfer0`
 * ..), or with `means` the fins' mean transfer per layer (`peltLayerMeans`: RGBA float, texel
 * (t, layer) = the means of coefficients 4t .. 4t + 3).
 */
export function prtFragment( textures, means ) {

	const common = /* glsl */`
uniform vec3 peltSky;
varying vec4 vPeltLight[ PELT_TRANSFER_TEXTURES ];
uniform highp sampler2D peltLayerMeans;
uniform int peltTopLayer;
${prtHotSpot}

// prt.wgsl mean_transfer(): the hair's mean transfer at height (share of the fur depth), linear
// between the layers around it; texture t holds coefficients 4t .. 4t + 3.
vec4 peltMeanTransfer( int t, float height ) {
	float at = clamp( height / peltLayerSpacing, 0.0, float( peltTopLayer ) );
	int below = min( int( at ), peltTopLayer );
	int above = min( below + 1, peltTopLayer );
	return mix( texelFetch( peltLayerMeans, ivec2( t, below ), 0 ), texelFetch( peltLayerMeans, ivec2( t, above ), 0 ), at - float( below ) );
}

// prt.wgsl mean_radiances(): the lighting dotted with the hair's mean transfer at height and at
// the top layer.
void peltMeanRadiances( float height, out vec3 here, out vec3 top ) {
	float sumHere = 0.0;
	float sumTop = 0.0;
	float constantHere = 0.0;
	float constantTop = 0.0;
${perTexture( textures, ( t ) => /* glsl */`	{
		vec4 m = peltMeanTransfer( ${t}, height );
		vec4 tip = texelFetch( peltLayerMeans, ivec2( ${t}, peltTopLayer ), 0 );
		sumHere += dot( vPeltLight[ ${t} ], m );
		sumTop += dot( vPeltLight[ ${t} ], tip );
		${t === 0 ? 'constantHere = m.x; constantTop = tip.x;' : ''}
	}` )}
	here = peltSky * constantHere + peltLightColor * sumHere;
	top = peltSky * constantTop + peltLightColor * sumTop;
}

// prt.wgsl HOT_SPOT_FLOOR and hot_spot_factor(): unshadowed over shadowed radiance, the top
// layer's mean radiance over the mean at the height, weighed by the hot spot.
const float PELT_HOT_SPOT_FLOOR = 0.05;

vec3 peltHotSpotFactor( vec3 here, vec3 top, float hot ) {
	top = max( top, vec3( 0.0 ) );
	vec3 ratio = top / max( here, max( PELT_HOT_SPOT_FLOOR * top, vec3( 1e-6 ) ) );
	return 1.0 + hot * ( max( ratio, vec3( 1.0 ) ) - 1.0 );
}
`;
	if ( means ) {

		return common + /* glsl */`
// prt.wgsl mean_radiance(): the lighting dotted with the hair's mean transfer at height (share
// of the fur depth), raised by the hot spot; the fins have no transfer of their own.
vec3 peltMeanRadiance( float height, float hot ) {
	vec3 here;
	vec3 top;
	peltMeanRadiances( height, here, top );
	return max( here, vec3( 0.0 ) ) * peltHotSpotFactor( here, top, hot );
}
`;

	}

	return common + /* glsl */`
${perTexture( textures, ( t ) => `uniform sampler2D peltTransfer${t};` )}
// Per texture, the 8-bit decoding of its four coefficients: value = byte / 255 · scale + bias.
uniform vec4 peltTransferScale[ PELT_TRANSFER_TEXTURES ];
uniform vec4 peltTransferBias[ PELT_TRANSFER_TEXTURES ];

// prt.wgsl transfer_radiance(): Σ_k L_k t_k with the transfer of the texel at atlasUv
// (coefficient k in texture k / 4, channel k % 4), raised by the hot spot at height. The files
// keep straight transfer, so there is no division by the texel's opacity.
vec3 peltTransferRadiance( vec2 atlasUv, float height, float hot ) {
	float sum = 0.0;
	float constant = 0.0;
${perTexture( textures, ( t ) => /* glsl */`	{
		vec4 c = texture( peltTransfer${t}, atlasUv ) * peltTransferScale[ ${t} ] + peltTransferBias[ ${t} ];
		sum += dot( vPeltLight[ ${t} ], c );
		${t === 0 ? 'constant = c.x;' : ''}
	}` )}
	// A band-limited light rings slightly negative past the terminator.
	vec3 radiance = max( peltSky * constant + peltLightColor * sum, vec3( 0.0 ) );
	if ( hot <= 0.0 ) return radiance;
	vec3 here;
	vec3 top;
	peltMeanRadiances( height, here, top );
	return radiance * peltHotSpotFactor( here, top, hot );
}
`;

}
