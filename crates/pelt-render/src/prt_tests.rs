//! The PRT rotation pass on the CPU adapter against the crate's own SH rotation (the
//! Ivanic–Ruedenberg recurrence in f64, `prt::sh::ShRotation`): the pass takes another route
//! (Euler angles and a fixed 90° matrix), so agreement checks both.

use std::ops::Range;

use super::prt_light::WorldLighting;
use super::prt_rotate::{RotateOutputs, RotatePipeline, RotationUniforms};
use super::readback::read_buffer;
use super::shadow_map::{ShadowFrame, ShadowMap};
use super::{AdapterChoice, Renderer};
use glam::{DVec3, Vec3};
use pelt_core::prt::sh::{self, MAX_ORDER, ShRotation};
use pelt_core::rng::Rng;
use pelt_core::scene::surface_mesh::SurfaceVertex;

fn random_direction(rng: &mut Rng) -> DVec3 {
    loop {
        let v = DVec3::from_array([0; 3].map(|_| 2.0 * rng.next_f64() - 1.0));
        if (0.01..1.0).contains(&v.length_squared()) {
            return v.normalize();
        }
    }
}

/// Vertices with frames of every kind: random (some mirrored), the normal along ±z exactly and
/// nearly (the Euler angles' gimbal), and a dP/du along the normal (no usable tangent).
fn vertices() -> Vec<SurfaceVertex> {
    let mut rng = Rng::new(7);
    let mut frames: Vec<(DVec3, DVec3, bool)> = (0..40)
        .map(|i| (random_direction(&mut rng), random_direction(&mut rng), i % 3 == 0))
        .collect();
    frames.extend(
        [
            ([0.0, 0.0, 1.0], [0.6, 0.8, 0.3], false),
            ([0.0, 0.0, -1.0], [0.6, -0.8, 0.0], false),
            ([1e-6, 0.0, 1.0], [0.0, 1.0, 0.0], true),
            ([0.0, 2e-3, -1.0], [1.0, 0.0, 0.0], false),
            ([0.3, -0.4, 0.5], [0.6, -0.8, 1.0], false),
        ]
        .map(|(n, u, mirrored)| (DVec3::from(n), DVec3::from(u), mirrored)),
    );
    frames
        .into_iter()
        .map(|(n, u, mirrored)| {
            let n = n.normalize();
            // dP/du deliberately off the tangent plane and not unit; dP/dv roughly n × dP/du.
            let dpdu = 1.7 * u;
            let dpdv = n.cross(dpdu) * if mirrored { -0.5 } else { 0.5 };
            SurfaceVertex {
                position: [0.0; 3],
                normal: n.as_vec3().to_array(),
                dpdu: dpdu.as_vec3().to_array(),
                dpdv: dpdv.as_vec3().to_array(),
                uv: [0.0; 2],
                comb: [0.0; 3],
                border: [0.0; 2],
            }
        })
        .collect()
}

/// The tile frame of a vertex as the shader builds it: rows x, y, z (world to tile), and
/// whether y is mirrored.
fn frame_of(v: &SurfaceVertex) -> ([[f64; 3]; 3], bool) {
    let wide = |a: [f32; 3]| Vec3::from(a).as_dvec3();
    let z = wide(v.normal).normalize();
    let dpdu = wide(v.dpdu);
    let mut x = dpdu - z * z.dot(dpdu);
    if x.length_squared() <= 1e-8 * dpdu.length_squared() {
        let a = if z.x.abs() > 0.9 { DVec3::Y } else { DVec3::X };
        x = a - z * z.dot(a);
    }
    let x = x.normalize();
    let y = z.cross(x);
    ([x, y, z].map(|v| v.to_array()), y.dot(wide(v.dpdv)) < 0.0)
}

/// Fur depth of the rotation tests.
const FUR_DEPTH: f32 = 0.2;

/// LOD composites for the pass's hot-spot gains: `layers` level-0 layers, the transfer rows
/// (level 0's layer means, then the members' weighted transfer) and each composite's members.
struct Composites {
    layers: u32,
    means: Vec<f32>,
    ranges: Vec<[u32; 4]>,
}

impl Composites {
    /// None: one layer, no composite.
    fn none(n: usize) -> Self {
        Composites {
            layers: 1,
            means: vec![0.0; n],
            ranges: Vec::new(),
        }
    }
}

/// The pass's output for `vertices` (surface curving at `curvature[i]`) under `light`: `n²`
/// rows per vertex, and the gains of `composites` per vertex (RGB; 1 where not written), those
/// in `gains` written.
fn run_pass(
    renderer: &Renderer,
    vertices: &[SurfaceVertex],
    curvature: &[f32],
    order: usize,
    light: &WorldLighting,
    (composites, gains): (&Composites, Range<u32>),
) -> (Vec<[f32; 4]>, Vec<[f32; 3]>) {
    use wgpu::util::DeviceExt;
    let device = &renderer.device;
    let rotate = RotatePipeline::new(device).unwrap();
    let n = sh::coeff_count(order);
    let count = composites.ranges.len();
    let geometry = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(vertices),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let uniforms = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::bytes_of(&RotationUniforms::new(
            vertices.len() as u32,
            order,
            light,
            FUR_DEPTH,
            (composites.layers, count as u32),
            gains,
            &ShadowFrame::NONE,
        )),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let storage = |values: &[u8]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: values,
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let output = |size: usize| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: size.max(16) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        })
    };
    let curvature = storage(bytemuck::cast_slice(curvature));
    let means = storage(bytemuck::cast_slice(&composites.means));
    let ranges = storage(bytemuck::cast_slice(if count == 0 {
        &[[0u32; 4]][..]
    } else {
        &composites.ranges
    }));
    let rotated = output(vertices.len() * n * 16);
    let gains = output(vertices.len() * count * 8);
    let group = rotate.bind_group(
        device,
        &uniforms,
        &geometry,
        &RotateOutputs {
            rotated: &rotated,
            curvature: &curvature,
            means: &means,
            composites: &ranges,
            gains: &gains,
        },
        // No map is read (`ShadowFrame::NONE`): every vertex sees the light.
        (
            &ShadowMap::new(device).view,
            &renderer.fur_layouts().unwrap().shadow_sampler,
        ),
    );
    let mut encoder = device.create_command_encoder(&Default::default());
    rotate
        .dispatch(&mut encoder, &group, vertices.len() as u32, 65535)
        .unwrap();
    renderer.queue.submit([encoder.finish()]);
    let bytes = read_buffer(device, &renderer.queue, &rotated).unwrap();
    let gain_bytes = read_buffer(device, &renderer.queue, &gains).unwrap();
    // 16-bit fixed point over [1, 20] (`hot_spot.wgsl` `pack_gain`).
    let gains = bytemuck::cast_slice::<u8, [u16; 4]>(&gain_bytes)
        .iter()
        .take(vertices.len() * count)
        .map(|g| [g[0], g[1], g[2]].map(|v| 1.0 + f32::from(v) / 65535.0 * 19.0))
        .collect();
    (bytemuck::cast_slice(&bytes).to_vec(), gains)
}

/// `n` random RGB coefficients.
fn random_coefficients(rng: &mut Rng, n: usize) -> Vec<[f32; 4]> {
    (0..n)
        .map(|_| [0; 4].map(|_| 2.0 * rng.next_f64() as f32 - 1.0))
        .map(|[r, g, b, _]| [r, g, b, 0.0])
        .collect()
}

/// `coefficients` rotated into `v`'s tile frame by the crate's own rotation, channel `c`.
fn expected_in_frame(v: &SurfaceVertex, order: usize, coefficients: &[[f32; 4]], c: usize) -> Vec<f64> {
    let (r, mirrored) = frame_of(v);
    let rotation = ShRotation::new(order, r).unwrap();
    let world: Vec<f64> = coefficients.iter().map(|row| f64::from(row[c])).collect();
    let mut want = rotation.apply(&world).unwrap();
    if mirrored {
        for (k, w) in want.iter_mut().enumerate() {
            if sh::band_of(k).1 < 0 {
                *w = -*w;
            }
        }
    }
    want
}

#[test]
fn rotation_pass_matches_the_sh_rotation_for_every_order() {
    let renderer = Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe)");
    let vertices = vertices();
    let mut rng = Rng::new(11);
    for order in 1..=MAX_ORDER {
        let n = sh::coeff_count(order);
        let light = random_coefficients(&mut rng, n);
        let world = WorldLighting {
            environment: light.clone(),
            sun: vec![[0.0; 4]; n],
            sun_direction: [0.0, 0.0, 1.0],
        };
        let none = Composites::none(n);
        let curvature = vec![0.0; vertices.len()];
        let (got, _) = run_pass(&renderer, &vertices, &curvature, order, &world, (&none, 0..0));
        for (i, v) in vertices.iter().enumerate() {
            for c in 0..3 {
                let want = expected_in_frame(v, order, &light, c);
                let norm = light.iter().map(|w| f64::from(w[c]).powi(2)).sum::<f64>().sqrt();
                for (k, w) in want.iter().enumerate() {
                    let g = f64::from(got[i * n + k][c]);
                    // f32 trigonometry and sums, and the gimbal branch (sin β below 1e-4) cost a
                    // few 1e-5 of the lighting's norm at order 8.
                    assert!(
                        (g - w).abs() <= 2e-4 * norm,
                        "order {order}, vertex {i}, channel {c}, coefficient {k}: {g} vs {w}"
                    );
                }
            }
        }
    }
}

#[test]
fn the_directional_light_fades_out_past_each_vertex_terminator() {
    // The body shadows a sun behind the terminator; its few bands must not light the fur there.
    // Hair h tall on a surface curving at κ sees a band of √(2hκ) in N·L past it, at most 0.3:
    // at N·L ≥ 0.3 − band the vertex gets the sun's rotated coefficients whole, at N·L ≤ −band
    // nothing, and in between a linear share. A flat surface has no band.
    let renderer = Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe)");
    let vertices = vertices();
    let order = 4;
    let n = sh::coeff_count(order);
    let mut rng = Rng::new(5);
    let sun = random_coefficients(&mut rng, n);
    let sun_direction = [0.36f32, -0.48, 0.8];
    let world = WorldLighting {
        environment: vec![[0.0; 4]; n],
        sun: sun.clone(),
        sun_direction,
    };
    // Flat, bands of 0.2 and 0.14, and one that the cap holds at 0.3.
    let curvatures = [0.0f32, 0.1, 0.05, 1e6];
    let curvature: Vec<f32> = (0..vertices.len()).map(|i| curvatures[i % 4]).collect();
    let none = Composites::none(n);
    let (got, _) = run_pass(&renderer, &vertices, &curvature, order, &world, (&none, 0..0));
    let (mut lit, mut dark) = (0, 0);
    for (i, v) in vertices.iter().enumerate() {
        let facing = Vec3::from(v.normal)
            .as_dvec3()
            .normalize()
            .dot(Vec3::from(sun_direction).as_dvec3());
        let band = (2.0 * f64::from(FUR_DEPTH) * f64::from(curvature[i]))
            .sqrt()
            .min(0.3);
        let share = ((facing + band) / 0.3).clamp(0.0, 1.0);
        lit += usize::from(share == 1.0);
        dark += usize::from(share == 0.0);
        let want = expected_in_frame(v, order, &sun, 0);
        for (k, w) in want.iter().enumerate() {
            let g = f64::from(got[i * n + k][0]);
            assert!(
                (g - share * w).abs() <= 1e-4 * (1.0 + w.abs()),
                "vertex {i} (N·L {facing:.3}), coefficient {k}: {g} vs {}",
                share * w
            );
        }
    }
    assert!(
        lit > 5 && dark > 5,
        "{lit} vertices facing the sun, {dark} past its terminator"
    );
}

#[test]
fn the_hot_spot_gain_of_a_composite_weighs_its_members_own_factors() {
    // All shells raise level-0 layer i by g_i = max(top / max(m_i, 0.05·top), 1), its mean
    // radiance m_i against the top layer's; a composite showing light R_i of member i gets
    // Σ R_i g_i / Σ R_i (R_i clamped at 0, 1 where it shows none), per vertex and channel.
    let renderer = Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe)");
    let vertices = vertices();
    let order = 3;
    let n = sh::coeff_count(order);
    let mut rng = Rng::new(17);
    let world = WorldLighting {
        environment: random_coefficients(&mut rng, n),
        sun: vec![[0.0; 4]; n],
        sun_direction: [0.0, 0.0, 1.0],
    };
    // Four level-0 layers, brighter outward, then the rows of three composites' members: two
    // pairs and all four.
    let layers = 4usize;
    let mut means: Vec<f32> = (0..layers * n)
        .map(|i| (i / n + 1) as f32 * (0.2 + rng.next_f64() as f32))
        .collect();
    means.extend((0..8 * n).map(|_| 2.0 * rng.next_f64() as f32 - 0.5));
    let ranges = vec![[0, 2, 4, 0], [2, 4, 6, 0], [0, 4, 8, 0]];
    let composites = Composites {
        layers: layers as u32,
        means,
        ranges,
    };
    let curvature = vec![0.0; vertices.len()];
    let (lighting, gains) = run_pass(
        &renderer,
        &vertices,
        &curvature,
        order,
        &world,
        (&composites, 0..3),
    );
    let dot = |v: usize, row: usize, c: usize| -> f64 {
        (0..n)
            .map(|k| f64::from(lighting[v * n + k][c]) * f64::from(composites.means[row * n + k]))
            .sum()
    };
    let (mut raised, mut unlit) = (0, 0);
    for v in 0..vertices.len() {
        for (j, &[first, end, row, _]) in composites.ranges.iter().enumerate() {
            for (c, &got) in gains[v * 3 + j].iter().enumerate() {
                let top = dot(v, layers - 1, c).max(0.0);
                let (mut lifted, mut shown) = (0.0, 0.0);
                for i in first as usize..end as usize {
                    let r = dot(v, row as usize + i - first as usize, c).max(0.0);
                    let g = (top / dot(v, i, c).max(0.05 * top).max(1e-6)).max(1.0);
                    lifted += r * g;
                    shown += r;
                }
                let want = if shown > 0.0 { lifted / shown } else { 1.0 };
                let got = f64::from(got);
                // Stored in steps of 19 / 65535.
                assert!(
                    (got - want).abs() <= 1e-3 * want,
                    "vertex {v}, composite {j}, channel {c}: {got} vs {want}"
                );
                raised += usize::from(want > 1.01);
                unlit += usize::from(shown == 0.0);
            }
        }
    }
    assert!(raised > 20 && unlit > 5, "{raised} gains above 1, {unlit} unlit");
    // A frame drawing only the second composite weighs only its gain (the others stay 1).
    let (_, some) = run_pass(
        &renderer,
        &vertices,
        &curvature,
        order,
        &world,
        (&composites, 1..2),
    );
    for (i, (got, all)) in some.iter().zip(&gains).enumerate() {
        let want = if i % 3 == 1 { *all } else { [1.0; 3] };
        assert_eq!(*got, want, "vertex {}, composite {}", i / 3, i % 3);
    }
}
