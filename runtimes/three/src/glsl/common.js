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
