// Real spherical harmonics as Pelt stores precomputed radiance transfer (crates/pelt-core/src/prt/sh.rs: index
// l² + l + m, orthonormal, no Condon–Shortley phase, θ from +Z, φ from +X toward +Y), the
// directional light as a uniform cap (sh.rs `cap_zonal`, crates/pelt-render/src/prt_light.rs) and the 8-bit
// transfer decoding (docs/export.md, "Conventions": Transfer). The fragment shaders evaluate the
// basis with the same recurrence (glsl/prt.js `peltShEval`).

/** The band l of coefficient index k. */
export function bandOf( k ) {

	return Math.floor( Math.sqrt( k ) );

}

/**
 * All order² basis functions at the unit direction d (sh.rs `eval_unit`): Y_l^m = √2 Q_l^m(z)
 * Re((x + iy)^m) (Im for m < 0), Q by the normalized three-term recurrence in l.
 */
export function shEval( order, d ) {

	const [ x, y, z ] = d;
	const out = new Float64Array( order * order );
	let qmm = 0.5 / Math.sqrt( Math.PI );
	let c = 1;
	let s = 0;
	for ( let m = 0; m < order; m ++ ) {

		if ( m > 0 ) {

			qmm *= Math.sqrt( ( 2 * m + 1 ) / ( 2 * m ) );
			[ c, s ] = [ x * c - y * s, x * s + y * c ];

		}

		let qPrev = 0;
		let q = qmm;
		for ( let l = m; l < order; l ++ ) {

			if ( l > m ) {

				const a = Math.sqrt( ( 4 * l * l - 1 ) / ( l * l - m * m ) );
				const b = Math.sqrt( ( ( l - 1 ) * ( l - 1 ) - m * m ) / ( 4 * ( l - 1 ) * ( l - 1 ) - 1 ) );
				[ qPrev, q ] = [ q, a * ( z * q - b * qPrev ) ];

			}

			const center = l * l + l;
			if ( m === 0 ) {

				out[ center ] = q;

			} else {

				out[ center + m ] = Math.SQRT2 * q * c;
				out[ center - m ] = Math.SQRT2 * q * s;

			}

		}

	}

	return out;

}

/**
 * Zonal coefficients z_l of a uniform cap of `halfAngle` radians about +Z with unit total power
 * (sh.rs `cap_zonal`: the mean of P_l over the cap as a polynomial in s = 1 − cos α, accurate
 * down to α = 0).
 */
export function capZonal( order, halfAngle ) {

	const s = 2 * Math.sin( 0.5 * halfAngle ) ** 2;
	const out = [];
	for ( let l = 0; l < order; l ++ ) {

		let term = 1;
		let mean = 1;
		for ( let k = 1; k <= l; k ++ ) {

			term *= ( l - k + 1 ) * ( l + k ) / ( k * k ) * ( - 0.5 * s );
			mean += term / ( k + 1 );

		}

		out.push( Math.sqrt( ( 2 * l + 1 ) / ( 4 * Math.PI ) ) * mean );

	}

	return out;

}

/**
 * Per band, what multiplies Y_l^m(d) in the coefficients of the cap turned toward d (sh.rs
 * `zonal_to_direction`: c_l^m = √(4π / (2l + 1)) z_l Y_l^m(d)).
 */
export function capBandWeights( order, halfAngle ) {

	return capZonal( order, halfAngle ).map( ( z, l ) => Math.sqrt( 4 * Math.PI / ( 2 * l + 1 ) ) * z );

}

/** The SH coefficients of the cap around unit direction d (sh.rs `project_cap`). */
export function projectCap( order, d, halfAngle ) {

	const weights = capBandWeights( order, halfAngle );
	return Array.from( shEval( order, d ), ( y, k ) => weights[ bandOf( k ) ] * y );

}

/** Coefficient k of an 8-bit transfer texel: byte / 255 · scale[k] + bias[k]. */
export function decodeTransfer( byte, k, transfer ) {

	return byte / 255 * transfer.scale[ k ] + transfer.bias[ k ];

}

/** Texture and channel of transfer coefficient k: texture k / 4, channel k % 4. */
export function transferSlot( k ) {

	return [ Math.floor( k / 4 ), k % 4 ];

}

/**
 * The hair's mean transfer per layer, `[layer · n² + k]`, for the fins, which have no transfer
 * of their own (crates/pelt-render/src/transfer.rs `layer_means`): each coefficient's mean over the layer's
 * atlas cell weighted by the shell texel's opacity, or the plain mean where the cell is empty.
 * `transferTexels[t]` and `shellTexels` are RGBA bytes of the atlases, rows from the top.
 */
export function layerMeans( transferTexels, shellTexels, stack ) {

	const { atlas, transfer, layers } = stack;
	const n = transfer.coefficients;
	const out = new Float32Array( layers * n );
	for ( let layer = 0; layer < layers; layer ++ ) {

		const x0 = ( layer % atlas.columns ) * atlas.tile;
		const y0 = Math.floor( layer / atlas.columns ) * atlas.tile;
		for ( let k = 0; k < n; k ++ ) {

			const [ t, channel ] = transferSlot( k );
			const texels = transferTexels[ t ];
			let sum = 0;
			let weight = 0;
			let plain = 0;
			for ( let y = y0; y < y0 + atlas.tile; y ++ ) {

				for ( let x = x0; x < x0 + atlas.tile; x ++ ) {

					const at = 4 * ( y * atlas.width + x );
					const v = decodeTransfer( texels[ at + channel ], k, transfer );
					const a = shellTexels[ at + 3 ];
					sum += a * v;
					weight += a;
					plain += v;

				}

			}

			out[ layer * n + k ] = weight > 0 ? sum / weight : plain / ( atlas.tile * atlas.tile );

		}

	}

	return out;

}
