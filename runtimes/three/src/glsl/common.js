// GLSL shared by the fur passes: crates/pelt-render/src/common.wgsl's helpers and the atlas addressing of
// docs/export.md ("Conventions": Atlas). Geometry is placed in object space, as in the WGSL;
// lighting runs in world space (the light and eye are the scene's).

export const common = /* glsl */`
uniform float peltFurDepth;
uniform float peltLayerSpacing;
// x columns, y rows, z tile (texels), w unused.
uniform vec4 peltAtlas;
// The atlas in texels.
uniform vec2 peltAtlasSize;

// common.wgsl growth(): the normal plus the comb's tangential part (Lengyel et al. 2001, §3).
vec3 peltGrowth( vec3 normal, vec3 comb ) {
	return normal + comb - normal * dot( normal, comb );
}

// common.wgsl unit_or().
vec3 peltUnitOr( vec3 v, vec3 fallback ) {
	float len2 = dot( v, v );
	return len2 > 1e-24 ? v * inversesqrt( len2 ) : fallback;
}

// common.wgsl view_vector(): unit vector from world point p toward the viewer.
vec3 peltViewVector( vec3 p ) {
	if ( isOrthographic ) {
		return normalize( vec3( viewMatrix[ 0 ][ 2 ], viewMatrix[ 1 ][ 2 ], viewMatrix[ 2 ][ 2 ] ) );
	}
	return normalize( cameraPosition - p );
}

// common.wgsl MIN_SPREAD, triangle_spread(), density_of_growth() and
// hair_density(): the shells and fins lift the mesh along diverging growth directions, which
// stretches the tile's hair over 1 + a h + b h² times a triangle's area at height h (share of the
// fur depth), while the strands keep their count and width; the hair there thins by as much,
// within [MIN_SPREAD, 1 / MIN_SPREAD].
const float PELT_MIN_SPREAD = 0.25;

vec2 peltTriangleSpread( vec3 e1, vec3 e2, vec3 d1, vec3 d2 ) {
	vec3 area = cross( e1, e2 );
	float norm = dot( area, area );
	if ( ! ( norm > 0.0 ) ) return vec2( 0.0 );
	vec3 linear = cross( e1, d2 ) + cross( d1, e2 );
	return vec2( dot( linear, area ), dot( cross( d1, d2 ), area ) ) / norm;
}

float peltDensityOfGrowth( float grown ) {
	return 1.0 / clamp( abs( grown ), PELT_MIN_SPREAD, 1.0 / PELT_MIN_SPREAD );
}

float peltHairDensity( vec2 spread, float height ) {
	return peltDensityOfGrowth( 1.0 + height * ( spread.x + height * spread.y ) );
}

// common.wgsl spread_out() on a straight alpha: the optical depth -ln(1 - a) times density.
float peltSpreadOut( float alpha, float density ) {
	if ( density == 1.0 || alpha <= 0.0 ) return alpha;
	return 1.0 - pow( max( 1.0 - alpha, 1e-7 ), density );
}

// The atlas coordinates of tile UV uv in layer's cell (docs/export.md "Atlas"; what the WGSL's
// array layers do): fract(uv) in the cell at column layer % columns, row layer / columns from
// the top, kept half a texel inside the cell so bilinear reads never cross into a neighbour.
vec2 peltAtlasUv( vec2 uv, int layer ) {
	int columns = int( peltAtlas.x );
	float tile = peltAtlas.z;
	vec2 cell = vec2( float( layer % columns ), float( layer / columns ) );
	vec2 inCell = clamp( fract( uv ) * tile, vec2( 0.5 ), vec2( tile - 0.5 ) );
	return ( cell * tile + inCell ) / peltAtlasSize;
}
`;
