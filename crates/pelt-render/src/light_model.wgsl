#define_import_path pelt::light_model

// The lighting models' interface, stated once. Each pass is one shader for both models; the
// shader def `PRT` (set by `shaders.rs`) picks PRT (prt-shell-fur §2.4, `prt.wgsl`), its absence
// Kajiya–Kay (Lengyel et al. 2001, §2.4, `lighting.wgsl`). A pass imports its part of the model
// under `#ifdef PRT` as `model`. Both models provide the same items, with the same signatures:
//
// The skin and shells: `pelt::surface_kk` or `pelt::surface_prt` (with `pelt::surface`'s types)
//   struct SurfaceIn: what the vertex shader reads (vertex buffers, or a pulled corner).
//   struct SurfaceVarying: what crosses from vertex to fragment, packed.
//   struct SurfaceOut: what the fragment reads; at least `uv`, `color`, `length`, `layer` and
//     `coarse` (the array layers of the level drawn and of the next coarser one).
//   fn surface_vertex(v: SurfaceIn, layers: Layers, stand: f32, painted: bool) -> SurfaceVarying
//     The vertex of `layers` lifted to level-0 height `stand` (in layers: `shell_stand` for a
//     shell, the hull's own layer for a march), with its painted length or the multiplier 1.
//   fn surface_fragment(v: SurfaceVarying) -> SurfaceOut
//   fn surface_spread(s: SurfaceOut, stand: f32) -> vec2<f32>
//     How the fragment's triangle grows with height (`triangle_spread`), its position standing
//     `stand` (share of the fur depth) high: call it before any discard.
//   fn surface_wrap(s: SurfaceOut) -> f32
//     The terminator band's width there (Kajiya–Kay's `terminator_wrap`; PRT fades its light in
//     `prt_rotate.wgsl` and returns 0), from screen derivatives: call it before any discard.
//   fn shade_surface(s: SurfaceOut, texels: Texels, opacity: f32, grad: vec4<f32>, wrap: f32)
//     -> vec4<f32>
//     A shell's cross-faded texels × vertex color, lit; premultiplied, opacity × texel alpha.
//     `grad`: the tile UV's screen derivatives, taken before any discard; `wrap` as above.
//   struct SkinVarying (PRT: its `SurfaceVarying`), fn skin_vertex(v: SurfaceIn) -> SkinVarying,
//   fn skin_fragment(v: SkinVarying) -> vec3<f32>: the skin, opaque, at height 0.
//   fn march_frame(s: SurfaceOut) -> MarchFrame: the hull fragment's point, tile frame, how the
//     surface turns there (`SurfaceSteps`), how far the open border is, with their screen
//     derivatives, and how its triangle grows with height (call it before any discard).
//   fn march_light(s: SurfaceOut, f: MarchFrame, uv: vec2<f32>, layers: Layers, alpha: f32,
//                  grad: vec4<f32>, heights: Shown) -> HairLight
//     The lighting of the marched composite, shown by layer `layers` read at `uv` (`alpha` its
//     texel's own opacity); `heights` the mean height of the layers it holds and its color by
//     height (`march.wgsl` `shown`).
//   fn march_heights(layers: Layers, coarse: bool, mip: f32) -> vec2<f32>
//     The mean and mean square of the level-0 heights (in layers) a marched layer's texel holds
//     (`march.wgsl` `composite`), or (`coarse`) its coarser twin's, read at mip level `mip`.
//   fn plane_light(s: SurfaceOut, f: MarchFrame, uv: vec2<f32>, layers: Layers,
//                  grad: vec4<f32>, heights: Shown) -> HairLight: the same for the virtual
//     planes.
//   fn march_banks(s: SurfaceOut, f: MarchFrame) -> vec2<f32>
//     The Banks strengths the march darkens its composite by under the hull's painted length:
//     x ambient, y direct (PRT: none).
// The fins: `pelt::fin_kk` or `pelt::fin_prt`
//   struct FinOut: what crosses from vertex to fragment.
//   fn fin_vertex(v: FinIn, c: FinCorner) -> FinOut
//   fn fin_fragment(f: FinOut) -> vec4<f32>: the fin's texel, lit, premultiplied.
// The guard strands: `pelt::strand_kk` or `pelt::strand_prt`
//   fn shade_strand(v: StrandOut, tangent: vec3<f32>, height: f32) -> vec4<f32>
//     The strand's premultiplied albedo and coverage (`v.color`) lit at `height`.
//
// Below, what the fin and strand passes hand their model.

// A fin vertex (`pelt_core::scene::fin_mesh::FinVertex` and the color and length buffers).
struct FinIn {
    @location(5) uv: vec2<f32>,
    @location(6) color: vec4<f32>,
    @location(7) length: f32,
    // The skin vertices of the edge's two ends (`skin_vertices`: a corner takes its end's
    // position, normal and comb, the fin its plane from both); which one this corner stands on.
    @location(8) ends: vec2<u32>,
    @location(9) along: f32,
};

// A fin corner lifted off the skin, what the model's `fin_vertex` starts from.
struct FinCorner {
    clip: vec4<f32>,
    position: vec3<f32>,
    // The end's vertex normal and growth direction.
    normal: vec3<f32>,
    growth: vec3<f32>,
    // The end's tile frame: object units per tile unit along u and v (`SurfaceVertex`).
    dpdu: vec3<f32>,
    dpdv: vec3<f32>,
    // Fade × fin opacity × vertex opacity.
    opacity: f32,
    // The hair's number per unit of the fin's width at this corner's height over the tile's
    // (`fin_density` in `fins.wgsl`; `spread_out` applies it).
    density: f32,
    // The terminator band's width at the edge (Kajiya–Kay's `terminator_wrap`).
    wrap: f32,
};

// A strand's corner, from `strands.wgsl`'s vertex to its fragment shader.
struct StrandOut {
    @builtin(position) clip: vec4<f32>,
    // Premultiplied albedo, coverage.
    @location(0) color: vec4<f32>,
    // Where the strand runs; the fragment's height (share of the fur depth).
    @location(1) tangent_height: vec4<f32>,
    @location(2) normal: vec3<f32>,
    @location(3) position: vec3<f32>,
    // The band's heights, [low, high).
    @location(4) @interpolate(flat) band: vec2<f32>,
    // The root triangle's skin vertices and the root's weights (PRT's lighting there).
    @location(5) @interpolate(flat) corners: vec3<u32>,
    @location(6) @interpolate(flat) weights: vec3<f32>,
    // The strand, which seeds its stochastic coverage.
    @location(7) @interpolate(flat) strand: u32,
    // The terminator band's width at the root (Kajiya–Kay's `terminator_wrap`); the root's
    // painted length multiplier.
    @location(8) @interpolate(flat) wrap_length: vec2<f32>,
};
