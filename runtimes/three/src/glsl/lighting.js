// GLSL port of crates/pelt-render/src/lighting.wgsl: the modified Banks / Kajiya–Kay hair model of Lengyel
// et al. 2001, §2.4, evaluated per fragment, with Banks-style darkening toward the skin and the
// wrapped terminator. Colors are linear; `peltLightColor` is the light's color over π, as the
// WGSL's frame.light_color.

export const lighting = /* glsl */`
uniform vec3 peltLightDirection;
uniform vec3 peltLightColor;
uniform vec3 peltAmbient;
// The ambient's change per unit of the normal's x, y and z.
uniform vec3 peltAmbientGradient[ 3 ];
// Kd, Ks, Pd, Ps.
uniform vec4 peltKajiyaKay;
// Banks self-shadow strength b.
uniform float peltSelfShadow;

// common.wgsl TERMINATOR_WRAP and HOT_SPOT_WIDTH, lighting.wgsl MIN_SLANT_COS.
const float PELT_TERMINATOR_WRAP = 0.3;
const float PELT_MIN_SLANT_COS = 0.1;
const float PELT_HOT_SPOT_WIDTH = 0.35;

// lighting.wgsl terminator_wrap(): the band past the terminator where hair height above a surface
// of curvature κ still sees the light, √(2 h κ), at most PELT_TERMINATOR_WRAP.
float peltTerminatorWrap( float curvature, float height ) {
	return min( sqrt( 2.0 * max( height, 0.0 ) * curvature ), PELT_TERMINATOR_WRAP );
}

// common.wgsl edge_curvature(): how fast the normal turns along the edge p0 → p1; 0 if flat or
// concave.
float peltEdgeCurvature( vec3 p0, vec3 n0, vec3 p1, vec3 n1 ) {
	vec3 edge = p1 - p0;
	return max( dot( n1 - n0, edge ) / max( dot( edge, edge ), 1e-30 ), 0.0 );
}

// lighting.wgsl shared_path(): how much of the light's path is the view ray's own (the hot spot).
float peltSharedPath( vec3 light, vec3 view ) {
	float apart = acos( clamp( dot( light, view ), -1.0, 1.0 ) );
	return exp( -apart / PELT_HOT_SPOT_WIDTH );
}

// lighting.wgsl banks_strengths(): x for the ambient light, y for the light seen from view,
// under hair of painted length hairLength (bald skin is not darkened).
vec2 peltBanksStrengths( vec3 normal, vec3 light, vec3 view, float hairLength ) {
	float b = clamp( peltSelfShadow, 0.0, 1.0 );
	float fur = max( hairLength, 0.0 );
	float slant = 1.0 / max( dot( normal, light ), PELT_MIN_SLANT_COS );
	float direct = 1.0 - pow( max( 1.0 - b, 1e-8 ), slant * ( 1.0 - peltSharedPath( light, view ) ) * fur );
	float ambient = fur == 1.0 ? b : 1.0 - pow( max( 1.0 - b, 1e-8 ), fur );
	return vec2( ambient, direct );
}

// lighting.wgsl banks_at(): darkening of strength b at height (share of the fur depth).
float peltBanksAt( float b, float height ) {
	return 1.0 - b * ( 1.0 - clamp( height, 0.0, 1.0 ) );
}

// lighting.wgsl ambient_at(): the ambient light at a surface facing normal.
vec3 peltAmbientAt( vec3 normal ) {
	vec3 a = peltAmbient + normal.x * peltAmbientGradient[ 0 ] + normal.y * peltAmbientGradient[ 1 ]
		+ normal.z * peltAmbientGradient[ 2 ];
	return max( a, vec3( 0.0 ) );
}

// lighting.wgsl half_vector(): between the light and view (normal where they cancel).
vec3 peltHalfVector( vec3 normal, vec3 view ) {
	return peltUnitOr( peltLightDirection + view, normal );
}

// lighting.wgsl spread_hair_parts(), as its HairParts: ambient, direct (rgb) and the highlight's
// multiple of the light color (shine), for hair whose squared cosines to the light and to the
// half vector are squares ((T·L)², (T·H)²) on average.
void peltSpreadHairParts( vec2 squares, vec3 normal, vec3 view, float wrap, out vec3 ambient, out vec3 direct, out float shine ) {
	vec3 l = peltLightDirection;
	// The floor keeps pow's base positive.
	float diffuse = pow( max( 1.0 - squares.x, 1e-8 ), 0.5 * peltKajiyaKay.z );
	float specular = pow( max( 1.0 - squares.y, 1e-8 ), 0.5 * peltKajiyaKay.w );
	// The body's shadow, wrapped over the terminator, fading at the hot spot.
	float body = clamp( ( dot( normal, l ) + wrap ) / ( 1.0 + wrap ), 0.0, 1.0 );
	float lit = mix( body, 1.0, peltSharedPath( l, view ) );
	ambient = peltAmbientAt( normal );
	direct = peltLightColor * lit * ( peltKajiyaKay.x * diffuse );
	shine = lit * ( peltKajiyaKay.y * specular );
}

// lighting.wgsl parts_terms() of spread_hair_parts(): peltHairTerms of spread hair.
vec4 peltSpreadHairTerms( vec2 squares, vec3 normal, vec3 view, float height, float hairLength, float wrap ) {
	vec3 ambient;
	vec3 direct;
	float shine;
	peltSpreadHairParts( squares, normal, view, wrap, ambient, direct, shine );
	vec2 b = peltBanksStrengths( normal, peltLightDirection, view, hairLength );
	float darkened = peltBanksAt( b.y, height );
	return vec4( ambient * peltBanksAt( b.x, height ) + direct * darkened, shine * darkened );
}

// lighting.wgsl hair_terms() (hair_parts: one tangent's squared cosines): the lighting's scale
// (rgb, multiplies the albedo) and shine (w, times the light color) at height (share of the fur
// depth) of hair of painted length hairLength.
vec4 peltHairTerms( vec3 tangent, vec3 normal, vec3 view, float height, float hairLength, float wrap ) {
	float u = dot( tangent, peltLightDirection );
	float v = dot( tangent, peltHalfVector( normal, view ) );
	return peltSpreadHairTerms( vec2( u * u, v * v ), normal, view, height, hairLength, wrap );
}

// lighting.wgsl shade() in straight alpha: the lit color of hair of straight albedo (the texel's
// rgb × vertex color), albedo × scale + light color × shine. Premultiplying by the fragment's
// alpha gives the WGSL's albedo × scale + alpha × add.
vec3 peltShade( vec3 albedo, vec3 tangent, vec3 normal, vec3 view, float height, float hairLength, float wrap ) {
	vec4 k = peltHairTerms( tangent, normal, view, height, hairLength, wrap );
	return albedo * k.rgb + peltLightColor * k.w;
}

// lighting.wgsl shade_skin(): the skin under the roots, wrapped N·L instead of the hair terms,
// Banks-darkened like the roots of painted length hairLength above it.
vec3 peltShadeSkin( vec3 albedo, vec3 normal, vec3 view, float hairLength, float wrap ) {
	vec3 l = peltLightDirection;
	float lit = clamp( ( dot( normal, l ) + wrap ) / ( 1.0 + wrap ), 0.0, 1.0 );
	vec2 b = peltBanksStrengths( normal, l, view, hairLength );
	vec3 light = peltAmbientAt( normal ) * ( 1.0 - b.x ) + peltLightColor * ( lit * ( 1.0 - b.y ) );
	return albedo * ( peltKajiyaKay.x * light );
}
`;
