//! Integer floors and toroidal wrapping for the texel grids of the bake, without calls.
//!
//! Lengyel et al. 2001, §2.2: the tile repeats, so every position and texel index is taken modulo
//! the tile. The bake does this several times for every strand crossing every layer; on targets
//! without a rounding instruction in their baseline (x86-64 before SSE4.1) `f64::floor` and
//! `rem_euclid` are library calls, and `i64::rem_euclid` is a hardware division. These helpers
//! give the same values with a conversion and a compare.

/// `x.floor() as i64` (saturating, NaN to 0) for any `x`.
#[inline]
pub(crate) fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    // The truncation rounds negative non-integers up; outside i64 it saturates, as the cast of
    // the floor does.
    if (t as f64) > x { t.saturating_sub(1) } else { t }
}

/// `x.floor()` for finite `x`, except that it gives +0 where `floor` gives −0.
#[inline]
pub(crate) fn floor_f64(x: f64) -> f64 {
    // Beyond 2^52 every f64 is an integer.
    if x.abs() < 4_503_599_627_370_496.0 {
        let t = x as i64 as f64;
        if t > x { t - 1.0 } else { t }
    } else {
        x
    }
}

/// `x.rem_euclid(1.0)`, bit for bit.
///
/// Both round the exact `x − ⌊x⌋` once: `fmod` is exact, and the subtraction of an integer from
/// `x` is exact unless `x` is negative, where both add 1 to the exact `x − trunc(x)`. Only a zero
/// result needs care: `fmod` gives it the sign of `x`.
#[inline]
pub(crate) fn fract_wrap(x: f64) -> f64 {
    let f = x - floor_f64(x);
    if f == 0.0 { 0.0f64.copysign(x) } else { f }
}

/// `i.rem_euclid(n)` for `n > 0`, without a division for the `i` in `[−n, 2n)` that the indices
/// of a footprint narrower than the tile around a centre inside it take.
#[inline]
pub(crate) fn wrap_near(i: i64, n: i64) -> usize {
    let w = if i < 0 && i >= -n {
        i + n
    } else if i >= n && i - n < n {
        i - n
    } else if i >= 0 && i < n {
        i
    } else {
        i.rem_euclid(n)
    };
    w as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floors_and_wraps_match_the_library_functions() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            -3.0,
            2.999_999_999_999_999_6,
            -1e-300,
            1e-300,
            -1e-17,
            4_503_599_627_370_495.5,
            -4_503_599_627_370_495.5,
            9e15,
            -9e15,
            1e19,
            -1e19,
            1e300,
            -1e300,
        ];
        // A deterministic spread of magnitudes and signs.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..10_000 {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            let unit = (state >> 11) as f64 / (1u64 << 53) as f64;
            let scale = 10f64.powi((state % 40) as i32 - 20);
            values.push((unit - 0.5) * scale);
        }
        for x in values {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
            assert_eq!(floor_f64(x), x.floor(), "{x}");
            assert_eq!(fract_wrap(x).to_bits(), x.rem_euclid(1.0).to_bits(), "{x}");
        }
        assert_eq!(floor_i64(f64::NAN), 0);
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(fract_wrap(x).is_nan() && x.rem_euclid(1.0).is_nan());
        }
        assert_eq!(floor_i64(f64::INFINITY), i64::MAX);
        assert_eq!(floor_i64(f64::NEG_INFINITY), i64::MIN);
        for n in [1i64, 2, 7, 1024] {
            for i in -3 * n..4 * n {
                assert_eq!(wrap_near(i, n), i.rem_euclid(n) as usize, "{i} mod {n}");
            }
        }
    }
}
