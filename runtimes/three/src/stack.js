// The shell stack on the CPU: atlas cells and the layer each shell shows (docs/export.md,
// "Conventions": Stack, Atlas), and how many shells the distance LOD draws. The shaders
// (glsl/common.js) do the same arithmetic per vertex and fragment; these mirror them for tests and
// for the uniforms.

/** Column and row (from the top) of layer `layer`'s cell in an atlas of `columns` columns. */
export function atlasCell( layer, columns ) {

	return [ layer % columns, Math.floor( layer / columns ) ];

}

/**
 * Normalized texture coordinates of tile UV `uv` in the cell of `layer`: `fract(uv)` inside the
 * cell, kept half a texel from its borders so that bilinear reads stay in the cell (the glsl
 * `peltAtlasUv`). No flip: row 0 of the image is v = 0.
 */
export function atlasUv( uv, layer, atlas ) {

	const [ column, row ] = atlasCell( layer, atlas.columns );
	const inCell = ( t ) => Math.min( Math.max( ( t - Math.floor( t ) ) * atlas.tile, 0.5 ), atlas.tile - 0.5 );
	return [
		( column * atlas.tile + inCell( uv[ 0 ] ) ) / atlas.width,
		( row * atlas.tile + inCell( uv[ 1 ] ) ) / atlas.height,
	];

}

/**
 * The layer shell `s` (1-based) of `drawn` shows in a stack of `layers` layers:
 * round(s (L − 1) / drawn), halves up, in integers (common.wgsl `shell_layers`).
 */
export function shellLayer( s, drawn, layers ) {

	return Math.floor( ( 2 * s * ( layers - 1 ) + drawn ) / ( 2 * drawn ) );

}

/**
 * Shells to draw for fur `furPixels` pixels deep on screen (crates/pelt-render/src/lod.rs `choose`: the
 * projected fur depth times `shellsPerPixel`), between `minShare` of the stack's shells (at least
 * one) and all of them.
 */
export function lodShells( furPixels, shells, { shellsPerPixel = 1, minShare = 0.25 } = {} ) {

	const lo = Math.max( 1, Math.ceil( shells * minShare ) );
	if ( ! Number.isFinite( furPixels ) ) return shells;
	return Math.min( shells, Math.max( lo, Math.ceil( furPixels * shellsPerPixel ) ) );

}

/**
 * Pixels per world unit at world point `center` for a camera with `projection` (a three.js
 * Matrix4, column-major elements) and `view` matrices and a drawing buffer of `width` × `height`
 * pixels (lod.rs `projected_scale`); `Infinity` when the point is at or behind the eye.
 */
export function pixelsPerUnit( center, view, projection, width, height ) {

	const v = view.elements;
	const p = projection.elements;
	const vp = [ 0, 1, 2, 3 ].map( ( r ) => v[ r ] * center[ 0 ] + v[ 4 + r ] * center[ 1 ] + v[ 8 + r ] * center[ 2 ] + v[ 12 + r ] );
	const w = p[ 3 ] * vp[ 0 ] + p[ 7 ] * vp[ 1 ] + p[ 11 ] * vp[ 2 ] + p[ 15 ] * vp[ 3 ];
	if ( ! ( w > 0 ) ) return Infinity;
	const halfExtent = 0.5 * Math.max( Math.abs( p[ 0 ] ) * width, Math.abs( p[ 5 ] ) * height );
	return halfExtent / w;

}
