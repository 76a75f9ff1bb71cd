//! The wgpu smoke test: one frame offscreen on the CPU adapter. It fails (never skips) when no
//! adapter exists, so a machine without Mesa's lavapipe cannot pass `make test` silently.
#![cfg(feature = "render")]

use pelt::render::{AdapterChoice, Renderer, SMOKE_COLOR};

#[test]
fn cpu_adapter_renders_one_frame() {
    let renderer =
        Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe) must exist under make test");
    assert_eq!(renderer.adapter().device_type, "Cpu", "{:?}", renderer.adapter());
    let (w, h) = (100u32, 60u32);
    let pixels = renderer.render_smoke(w, h).unwrap();
    assert_eq!(pixels.len(), (w * h * 4) as usize);
    let at = |x: u32, y: u32| {
        let i = ((y * w + x) * 4) as usize;
        [pixels[i], pixels[i + 1], pixels[i + 2], pixels[i + 3]]
    };
    // centre of the triangle, and the two top corners outside it
    assert_eq!(at(50, 35), SMOKE_COLOR);
    assert_eq!(at(2, 2), [0, 0, 0, 255]);
    assert_eq!(at(97, 2), [0, 0, 0, 255]);
    // coverage: the triangle spans 0.8 * 0.8 * 2 of the 4 NDC units², i.e. 32% of the pixels
    let covered = pixels.chunks_exact(4).filter(|p| *p == SMOKE_COLOR).count() as f64;
    let fraction = covered / f64::from(w * h);
    assert!((fraction - 0.32).abs() < 0.02, "coverage {fraction}");
}
