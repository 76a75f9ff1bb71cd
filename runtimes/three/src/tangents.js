// How the hair's directions spread about their mean, for the fins' Kajiya–Kay lighting
// (crates/pelt-render/src/tangent_spread.rs `tangent_moments`, fin_kk.wgsl `spread_squares`). A
// fin shows a column of hair side by side; lit by one tangent, the growth direction, a light
// along it would light the fin not at all, while the hairs leaning about it catch it. The fins
// take the mean of (T·L)² over the hair instead, which the second moment E[d dᵀ] of the tangent
// atlas's directions gives in any frame. Computed here from the atlases as the renderer does from
// its volume (the extension stores no moment of its own).

/**
 * E[d dᵀ] of the unit hair directions d of the tangent atlas (tile frame: x along u, y along v,
 * z up), each texel of the hair layers (not the skin, layer 0) weighed by its coverage (the shell
 * atlas's alpha); packed as the renderer's `fin_tangents`: [xx, yy, zz, xy, xz, yz, 0, 0]. Zeros
 * without hair. `tangentTexels` and `shellTexels` are RGBA bytes of the atlases, rows from the
 * top.
 */
export function tangentMoments( tangentTexels, shellTexels, stack ) {

	const { atlas, layers } = stack;
	const sum = new Float64Array( 7 );
	for ( let layer = 1; layer < layers; layer ++ ) {

		const x0 = ( layer % atlas.columns ) * atlas.tile;
		const y0 = Math.floor( layer / atlas.columns ) * atlas.tile;
		for ( let y = y0; y < y0 + atlas.tile; y ++ ) {

			for ( let x = x0; x < x0 + atlas.tile; x ++ ) {

				const at = 4 * ( y * atlas.width + x );
				const w = shellTexels[ at + 3 ] / 255;
				if ( w <= 0 ) continue;
				const d = [ 0, 1, 2 ].map( ( k ) => tangentTexels[ at + k ] / 127.5 - 1 );
				const norm = d[ 0 ] * d[ 0 ] + d[ 1 ] * d[ 1 ] + d[ 2 ] * d[ 2 ];
				if ( norm <= 0 ) continue;
				// The packed direction is unit up to 8-bit rounding: d dᵀ / |d|².
				const scale = w / norm;
				sum[ 0 ] += scale * d[ 0 ] * d[ 0 ];
				sum[ 1 ] += scale * d[ 1 ] * d[ 1 ];
				sum[ 2 ] += scale * d[ 2 ] * d[ 2 ];
				sum[ 3 ] += scale * d[ 0 ] * d[ 1 ];
				sum[ 4 ] += scale * d[ 0 ] * d[ 2 ];
				sum[ 5 ] += scale * d[ 1 ] * d[ 2 ];
				sum[ 6 ] += w;

			}

		}

	}

	if ( ! ( sum[ 6 ] > 0 ) ) return [ 0, 0, 0, 0, 0, 0, 0, 0 ];
	return [ ...Array.from( sum.subarray( 0, 6 ), ( s ) => s / sum[ 6 ] ), 0, 0 ];

}
