//! The peak memory of a transfer bake from its sizes alone, checked against the budget
//! ([`crate::memory`]) before anything is allocated.
//!
//! With `V = L·R²` voxels and `N = order²` coefficients (64 for the automatic order, which bakes
//! order 8 and then cuts a copy), what is alive at once is: the coefficients (`4NV`), the
//! Kajiya–Kay phase field (`12V`), the packed textures when the caller packs (`12⌈N/4⌉V`), and
//! the method's working set. The sweep holds a group of rays (about 64 MiB, at least one ray of
//! `16R²`, for at most half the directions), two layer pyramids (`8R²` per level), separable temporaries (`8R²`), a row
//! accumulator per worker (`4R(N + 66)`) and a segment kernel per worker (at most `16R²`, and
//! `16(s + 3)²` for a kernel `s = sweep_step · sweep_max_samples` texels long).

use super::accumulate::Phase;
use super::params::{Method, TransferParams};
use crate::error::Result;
use crate::memory;

/// Test lights of the automatic order's band table (extra channels per sampled row).
const TEST_LIGHT_CHANNELS: f64 = 65.0;

/// The estimated peak bytes of baking (and, with `packed`, packing) the transfer of a
/// `layers × resolution²` volume with `params`; `auto` for the automatic order.
pub fn transfer_peak_bytes(
    layers: usize,
    resolution: usize,
    params: &TransferParams,
    auto: bool,
    packed: bool,
) -> f64 {
    let (l, r) = (layers as f64, resolution as f64);
    let v = l * r * r;
    let order = if auto { super::sh::MAX_ORDER } else { params.order };
    let n = (order * order) as f64;
    // The automatic order cuts a copy at the chosen order while the order-8 bake is alive.
    let coefficients = if auto { 8.0 * n * v } else { 4.0 * n * v };
    let phase = if params.phase == Phase::KajiyaKay {
        12.0 * v
    } else {
        0.0
    };
    let packing = if packed { 12.0 * (n / 4.0).ceil() * v } else { 0.0 };
    let workers = crate::threads::thread_count() as f64;
    let extra = if auto { TEST_LIGHT_CHANNELS } else { 0.0 };
    let working = match params.method {
        Method::Brute => workers * 4.0 * r * (n + extra + 1.0),
        Method::Sweep => {
            // Directions above the horizon in groups of about 64 MiB of rays, one ray at least.
            let group = (64.0 * 1024.0 * 1024.0 / (16.0 * r * r)).floor().max(1.0);
            let rays = group.min((params.directions as f64 / 2.0).ceil().max(1.0)) * 16.0 * r * r;
            let levels = (r.log2().ceil() + 2.0).max(1.0);
            let kernel_side =
                (f64::from(params.sweep_step) * f64::from(params.sweep_max_samples) + 3.0).min(r);
            rays + 8.0 * levels * r * r
                + 8.0 * r * r
                + workers * (4.0 * r * (n + extra + 1.0) + 16.0 * kernel_side * kernel_side)
        }
    };
    coefficients + phase + packing + working
}

/// `Ok` when [`transfer_peak_bytes`] fits the memory limit; otherwise
/// [`crate::PeltError::MemoryLimit`] naming the sizes to lower.
pub fn check_transfer_memory(
    layers: usize,
    resolution: usize,
    params: &TransferParams,
    auto: bool,
    packed: bool,
) -> Result<()> {
    let bytes = transfer_peak_bytes(layers, resolution, params, auto, packed);
    memory::check("bake_transfer", bytes, || {
        let order = if auto {
            "the automatic order (bakes 8)".to_string()
        } else {
            format!("`order` ({})", params.order)
        };
        format!("`resolution` ({resolution}), `layers` ({layers}) or {order}")
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_estimate_grows_with_every_size_and_refuses_the_64_gib_bake() {
        let params = TransferParams {
            order: 8,
            ..TransferParams::default()
        };
        let big = transfer_peak_bytes(256, 1024, &params, false, true);
        // Coefficients alone: 256·1024²·64·4 bytes = 64 GiB.
        assert!(big >= 64.0 * (1u64 << 30) as f64, "{big}");
        assert!(transfer_peak_bytes(256, 1024, &params, true, true) > big);
        let small = transfer_peak_bytes(16, 128, &params, false, false);
        assert!(small < 200.0 * (1u64 << 20) as f64, "{small}");
        // Above any limit this machine allows (half its memory, and it has less than 128 GiB·2).
        if memory::limit() < 64 << 30 {
            let error = check_transfer_memory(256, 1024, &params, false, true)
                .unwrap_err()
                .to_string();
            assert!(
                error.contains("`resolution` (1024), `layers` (256) or `order` (8)"),
                "{error}"
            );
        }
    }
}
