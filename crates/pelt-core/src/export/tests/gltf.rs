//! The GLB export read back by the test's own reader (`glb_reader.rs`): geometry placed where the
//! offset formula (written out here) puts it, images equal to the bake's layers and atlases
//! (built here from their definition), materials, extras, determinism and error naming.

use serde_json::Value;

use super::fixture::{FUR_DEPTH, Fixture, ORDER};
use super::glb_reader::Glb;
use super::{parameter_name, with_threads};
use crate::export::{ExportInput, GltfMode, GltfOptions, encode_glb};

fn options(mode: GltfMode) -> GltfOptions {
    GltfOptions {
        mode,
        ..GltfOptions::default()
    }
}

/// Layer shown by shell `s` of `shells` in `layers`: `s · (L − 1) / shells` rounded half up.
fn layer_of(s: usize, shells: usize, layers: usize) -> usize {
    (s as f64 * (layers - 1) as f64 / shells as f64 + 0.5).floor() as usize
}

/// Layer `l` of a layer-major RGBA8 stack.
fn layer(stack: &[u8], side: usize, l: usize) -> &[u8] {
    &stack[l * side * side * 4..(l + 1) * side * side * 4]
}

/// The atlas of a layer-major RGBA8 stack: `⌈√L⌉` columns, layer `l` at column `l mod c`, row
/// `⌊l / c⌋`, empty cells zero.
fn atlas(stack: &[u8], side: usize, layers: usize) -> (Vec<u8>, usize, usize) {
    let columns = (1..).find(|c| c * c >= layers).unwrap();
    let rows = layers.div_ceil(columns);
    let (w, h) = (columns * side, rows * side);
    let mut out = vec![0u8; w * h * 4];
    for l in 0..layers {
        for y in 0..side {
            for x in 0..side {
                let src = ((l * side + y) * side + x) * 4;
                let dst = (((l / columns) * side + y) * w + (l % columns) * side + x) * 4;
                out[dst..dst + 4].copy_from_slice(&stack[src..src + 4]);
            }
        }
    }
    (out, w, h)
}

fn close(a: &[f32], b: &[f64], tolerance: f64) -> bool {
    a.iter()
        .zip(b)
        .all(|(&x, &y)| (f64::from(x) - y).abs() <= tolerance)
}

fn base_color_image(glb: &Glb, material: &Value) -> usize {
    let texture = material["pbrMetallicRoughness"]["baseColorTexture"]["index"]
        .as_u64()
        .unwrap();
    glb.texture_image(texture as usize)
}

#[test]
fn geometry_mode_places_shells_and_fins_where_the_offset_formula_says() {
    let fx = Fixture::new();
    let input = fx.input("Sphere");
    let glb = Glb::parse(&encode_glb(&[input], &[], &options(GltfMode::Geometry)).unwrap());
    let json = &glb.json;
    let (mesh, volume) = (&fx.mesh, &fx.volume);
    let (l, r) = (volume.layers, volume.resolution);
    let shells = l - 1;
    let primitives = json["meshes"][0]["primitives"].as_array().unwrap();
    assert_eq!(primitives.len(), 1 + shells + 1, "skin, shells, fins");
    assert_eq!(json["nodes"][0]["name"], "Sphere");
    assert_eq!(json["scenes"][0]["nodes"], serde_json::json!([0]));

    // The skin: every corner at its mesh vertex with its patch UV.
    let skin = &primitives[0];
    let positions = glb.floats(Glb::attribute(skin, "POSITION"));
    let uvs = glb.floats(Glb::attribute(skin, "TEXCOORD_0"));
    let normals = glb.floats(Glb::attribute(skin, "NORMAL"));
    let colors = glb.floats(Glb::attribute(skin, "COLOR_0"));
    let indices = glb.indices(skin["indices"].as_u64().unwrap() as usize);
    let tris = mesh.triangles();
    assert_eq!(indices.len(), 3 * tris.len());
    let length = mesh.length().unwrap();
    let comb = mesh.comb().unwrap();
    let painted = mesh.color().unwrap();
    for (f, tri) in tris.iter().enumerate() {
        for k in 0..3 {
            let (i, v) = (indices[3 * f + k] as usize, tri[k] as usize);
            assert_eq!(positions[i], mesh.positions()[v]);
            assert_eq!(uvs[i], fx.uvs[f][k]);
            assert_eq!(normals[i], mesh.normals()[v]);
            assert_eq!(colors[i], painted[v].map(|c| c.clamp(0.0, 1.0)));
        }
    }
    let materials = json["materials"].as_array().unwrap();
    let skin_material = &materials[skin["material"].as_u64().unwrap() as usize];
    assert_eq!(skin_material["alphaMode"].as_str().unwrap_or("OPAQUE"), "OPAQUE");
    let (pixels, w, h) = glb.image(base_color_image(&glb, skin_material));
    assert_eq!((w as usize, h as usize), (r, r));
    assert_eq!(pixels, layer(&volume.shells, r, 0));

    // Shells: the furred triangles (not bald at all three corners), lifted by
    // layer · spacing · depth · length · (n + c − n (n · c)).
    let furred: Vec<usize> = (0..tris.len())
        .filter(|&f| tris[f].iter().any(|&v| length[v as usize] > 0.0))
        .collect();
    assert!(furred.len() < tris.len(), "the fixture has a bald cap");
    for (s, shell) in (1..=shells).zip(&primitives[1..]) {
        let lifted = glb.floats(Glb::attribute(shell, "POSITION"));
        let idx = glb.indices(shell["indices"].as_u64().unwrap() as usize);
        assert_eq!(idx.len(), 3 * furred.len());
        let height = layer_of(s, shells, l) as f64 * volume.layer_spacing;
        for (j, &f) in furred.iter().enumerate() {
            for k in 0..3 {
                let v = tris[f][k] as usize;
                let (p, n, c) = (
                    mesh.positions()[v].map(f64::from),
                    mesh.normals()[v].map(f64::from),
                    comb[v].map(f64::from),
                );
                let nc = n[0] * c[0] + n[1] * c[1] + n[2] * c[2];
                let scale = height * FUR_DEPTH * f64::from(length[v]);
                let want: Vec<f64> = (0..3).map(|i| p[i] + scale * (n[i] + c[i] - n[i] * nc)).collect();
                let got = &lifted[idx[3 * j + k] as usize];
                assert!(
                    close(got, &want, 1e-6),
                    "shell {s} corner {k} of {f}: {got:?} vs {want:?}"
                );
            }
        }
        let material = &materials[shell["material"].as_u64().unwrap() as usize];
        assert_eq!(material["alphaMode"], "BLEND");
        let (pixels, _, _) = glb.image(base_color_image(&glb, material));
        assert_eq!(pixels, layer(&volume.shells, r, layer_of(s, shells, l)));
    }

    // Fins: one quad per edge with a furred end; bottom on the edge (v = 1), top at full height.
    let mut edges: Vec<[u32; 2]> = tris
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .filter(|e| e.iter().any(|&v| length[v as usize] > 0.0))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let fins = &primitives[shells + 1];
    let fin_material = &materials[fins["material"].as_u64().unwrap() as usize];
    assert_eq!(fin_material["alphaMode"], "BLEND");
    assert_eq!(fin_material["doubleSided"], true);
    let (pixels, w, h) = glb.image(base_color_image(&glb, fin_material));
    assert_eq!([w as usize, h as usize], volume.fin_size);
    assert_eq!(pixels, volume.fin);
    let fin_positions = glb.floats(Glb::attribute(fins, "POSITION"));
    let fin_uvs = glb.floats(Glb::attribute(fins, "TEXCOORD_0"));
    assert_eq!(fin_positions.len(), 4 * edges.len());
    let uv_scale = json["meshes"][0]["extras"]["pelt"]["stack"]["uv_scale"]
        .as_f64()
        .unwrap();
    for (q, edge) in edges.iter().enumerate() {
        let corner = |k: usize| (&fin_positions[4 * q + k], &fin_uvs[4 * q + k]);
        let [a, b] = edge.map(|v| mesh.positions()[v as usize]);
        assert_eq!(*corner(0).0, a);
        assert_eq!(*corner(1).0, b);
        for (bottom, top, v) in [(0, 2, edge[0]), (1, 3, edge[1])] {
            let v = v as usize;
            let (n, c) = (mesh.normals()[v].map(f64::from), comb[v].map(f64::from));
            let nc = n[0] * c[0] + n[1] * c[1] + n[2] * c[2];
            let scale = FUR_DEPTH * f64::from(length[v]);
            let p = mesh.positions()[v].map(f64::from);
            let want: Vec<f64> = (0..3).map(|i| p[i] + scale * (n[i] + c[i] - n[i] * nc)).collect();
            assert!(close(corner(top).0, &want, 1e-6));
            assert_eq!((corner(bottom).1[1], corner(top).1[1]), (1.0, 0.0));
        }
        let len = (0..3).map(|i| f64::from(b[i] - a[i]).powi(2)).sum::<f64>().sqrt();
        let (u0, u1) = (f64::from(corner(0).1[0]), f64::from(corner(1).1[0]));
        assert!((0.0..1.0).contains(&u0));
        assert!((u1 - u0 - len * uv_scale).abs() < 1e-5, "fin {q}");
    }

    // POSITION bounds are stated and exact.
    for p in primitives {
        let a = &json["accessors"][Glb::attribute(p, "POSITION")];
        let data = glb.floats(Glb::attribute(p, "POSITION"));
        for k in 0..3 {
            let lo = data.iter().map(|v| v[k]).fold(f32::INFINITY, f32::min);
            let hi = data.iter().map(|v| v[k]).fold(f32::NEG_INFINITY, f32::max);
            assert_eq!(a["min"][k].as_f64().unwrap() as f32, lo);
            assert_eq!(a["max"][k].as_f64().unwrap() as f32, hi);
        }
    }
}

#[test]
fn engine_mode_carries_attributes_atlases_and_the_stack_description() {
    let fx = Fixture::new();
    let glb = Glb::parse(&encode_glb(&[fx.input("Sphere")], &[], &options(GltfMode::Engine)).unwrap());
    let json = &glb.json;
    let (mesh, volume) = (&fx.mesh, &fx.volume);
    let (l, r) = (volume.layers, volume.resolution);
    let primitives = json["meshes"][0]["primitives"].as_array().unwrap();
    let p = &primitives[0];
    let indices = glb.indices(p["indices"].as_u64().unwrap() as usize);
    let uv0 = glb.floats(Glb::attribute(p, "TEXCOORD_0"));
    let uv1 = glb.floats(Glb::attribute(p, "TEXCOORD_1"));
    let lengths = glb.floats(Glb::attribute(p, "_PELT_LENGTH"));
    let combs = glb.floats(Glb::attribute(p, "_PELT_COMB"));
    let dpdu = glb.floats(Glb::attribute(p, "_PELT_DPDU"));
    let dpdv = glb.floats(Glb::attribute(p, "_PELT_DPDV"));
    for (f, tri) in mesh.triangles().iter().enumerate() {
        for k in 0..3 {
            let (i, v) = (indices[3 * f + k] as usize, tri[k] as usize);
            assert_eq!(uv0[i], fx.uvs[f][k]);
            assert_eq!(uv1[i], fx.uvs[f][k]);
            assert_eq!(lengths[i], [mesh.length().unwrap()[v]]);
            assert_eq!(combs[i], mesh.comb().unwrap()[v]);
            // The derivatives lie in the tangent plane.
            let n = mesh.normals()[v];
            for d in [&dpdu[i], &dpdv[i]] {
                let dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
                let size = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                assert!(dn.abs() <= 1e-5 * size.max(1.0), "{d:?} · {n:?}");
            }
        }
    }

    // The fur is described by the extension, used but not required.
    assert_eq!(json["extensionsUsed"], serde_json::json!(["PELT_shell_fur"]));
    assert!(json.get("extensionsRequired").is_none());
    assert!(json["meshes"][0].get("extras").is_none());
    let pelt = &p["extensions"]["PELT_shell_fur"];
    assert_eq!(pelt["version"], 1);
    let stack = &pelt["stack"];
    assert_eq!(stack["layers"], l);
    assert_eq!(stack["resolution"], r);
    assert_eq!(stack["fur_depth"], FUR_DEPTH);
    assert_eq!(stack["layer_spacing"], volume.layer_spacing);
    assert_eq!(stack["shells"], l - 1);
    assert_eq!(
        stack["shell_layers"],
        serde_json::json!((1..l).collect::<Vec<_>>())
    );
    assert_eq!(stack["transfer"]["order"], ORDER);
    let floats = |v: &Value| -> Vec<f32> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap() as f32)
            .collect()
    };
    assert_eq!(floats(&stack["transfer"]["scale"]), fx.u8.sidecar.scale);
    assert_eq!(floats(&stack["transfer"]["bias"]), fx.u8.sidecar.bias);
    assert_eq!(pelt["attributes"]["length"], "_PELT_LENGTH");

    let textures = &pelt["textures"];
    let image = |key: &str| glb.image(glb.texture_image(textures[key].as_u64().unwrap() as usize));
    let (shells, w, h) = atlas(&volume.shells, r, l);
    assert_eq!(stack["atlas"]["width"], w);
    assert_eq!(stack["atlas"]["height"], h);
    assert_eq!(image("shells_atlas"), (shells, w as u32, h as u32));
    let (tangents, _, _) = atlas(&volume.tangents, r, l);
    assert_eq!(image("tangents_atlas").0, tangents);
    assert_eq!(image("fin").0, volume.fin);
    assert_eq!(image("skin").0, layer(&volume.shells, r, 0));
    let transfer = textures["transfer"].as_array().unwrap();
    assert_eq!(transfer.len(), fx.u8.textures);
    for (t, texture) in transfer.iter().enumerate() {
        let size = l * r * r * 4;
        let (want, _, _) = atlas(&fx.u8.texels[t * size..(t + 1) * size], r, l);
        let got = glb.image(glb.texture_image(texture.as_u64().unwrap() as usize)).0;
        assert_eq!(got, want, "transfer texture {t}");
    }
    // The skin material reads the patch UVs from TEXCOORD_1.
    let material = &json["materials"][p["material"].as_u64().unwrap() as usize];
    assert_eq!(
        material["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"],
        1
    );

    // The fallback: four alpha-tested shells showing evenly spaced layers, each lifted by its
    // height along the combed normal, listed by the extension.
    let fallback: Vec<usize> = pelt["fallback"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i.as_u64().unwrap() as usize)
        .collect();
    assert_eq!(fallback, [1, 2, 3, 4]);
    assert_eq!(primitives.len(), 5);
    let skin_positions = glb.floats(Glb::attribute(p, "POSITION"));
    let normals = glb.floats(Glb::attribute(p, "NORMAL"));
    for (s, &k) in fallback.iter().enumerate() {
        let shell = &primitives[k];
        let shown = layer_of(s + 1, 4, l);
        let material = &json["materials"][shell["material"].as_u64().unwrap() as usize];
        assert_eq!(material["alphaMode"], "MASK");
        assert_eq!(
            glb.image(base_color_image(&glb, material)).0,
            layer(&volume.shells, r, shown)
        );
        let lifted = glb.floats(Glb::attribute(shell, "POSITION"));
        let height = shown as f64 * volume.layer_spacing * FUR_DEPTH;
        for (i, q) in lifted.iter().enumerate() {
            let (pos, n, c, len) = (&skin_positions[i], &normals[i], &combs[i], lengths[i][0]);
            let nc: f32 = (0..3).map(|j| n[j] * c[j]).sum();
            let want: Vec<f64> = (0..3)
                .map(|j| f64::from(pos[j]) + height * f64::from(len) * f64::from(n[j] + c[j] - n[j] * nc))
                .collect();
            assert!(close(q, &want, 1e-5), "shell {s} vertex {i}");
        }
    }
}

#[test]
fn several_objects_become_nodes_and_share_identical_images() {
    let fx = Fixture::new();
    let (a, mut b) = (fx.input("Left"), fx.input("Right"));
    b.shells = Some(2);
    for mode in [GltfMode::Engine, GltfMode::Geometry] {
        let one = Glb::parse(&encode_glb(&[a], &[], &options(mode)).unwrap());
        let two = Glb::parse(&encode_glb(&[a, b], &[], &options(mode)).unwrap());
        let json = &two.json;
        assert_eq!(json["scenes"][0]["nodes"], serde_json::json!([0, 1]));
        assert_eq!(json["nodes"][0]["name"], "Left");
        assert_eq!(json["nodes"][1]["name"], "Right");
        assert_eq!(json["nodes"][1]["mesh"], 1);
        // Both objects share the volume, so no image is stored twice.
        assert_eq!(
            json["images"].as_array().unwrap().len(),
            one.json["images"].as_array().unwrap().len()
        );
        if mode == GltfMode::Geometry {
            let layers = fx.volume.layers;
            assert_eq!(
                json["meshes"][1]["primitives"].as_array().unwrap().len(),
                1 + 2 + 1
            );
            assert_eq!(
                json["meshes"][1]["extras"]["pelt"]["stack"]["shell_layers"],
                serde_json::json!([layer_of(1, 2, layers), layer_of(2, 2, layers)])
            );
        }
    }
}

#[test]
fn output_is_byte_identical_across_runs_and_thread_counts() {
    let fx = Fixture::new();
    let objects = [fx.input("A"), fx.input("B")];
    for mode in [GltfMode::Engine, GltfMode::Geometry] {
        let once = encode_glb(&objects, &[], &options(mode)).unwrap();
        assert_eq!(once, encode_glb(&objects, &[], &options(mode)).unwrap());
        let one = with_threads(1, || encode_glb(&objects, &[], &options(mode)).unwrap());
        let two = with_threads(2, || encode_glb(&objects, &[], &options(mode)).unwrap());
        assert_eq!(one, once);
        assert_eq!(two, once);
    }
}

#[test]
fn bad_objects_are_named() {
    let fx = Fixture::new();
    let good = fx.input("Good");
    let engine = options(GltfMode::Engine);
    assert_eq!(parameter_name(encode_glb(&[], &[], &engine)), "objects");
    let short = ExportInput {
        corner_uvs: &fx.uvs[1..],
        ..good
    };
    assert_eq!(
        parameter_name(encode_glb(&[good, short], &[], &engine)),
        "objects[1].corner_uvs"
    );
    for (input, name) in [
        (
            ExportInput {
                fur_depth: f64::NAN,
                ..good
            },
            "objects[0].fur_depth",
        ),
        (
            ExportInput {
                shells: Some(0),
                ..good
            },
            "objects[0].shells",
        ),
        (ExportInput { name: "", ..good }, "objects[0].name"),
    ] {
        assert_eq!(parameter_name(encode_glb(&[input], &[], &engine)), name);
    }
    let mut volume = fx.volume.clone();
    volume.fin.pop();
    let broken = ExportInput {
        volume: &volume,
        transfer: None,
        ..good
    };
    assert_eq!(
        parameter_name(encode_glb(&[broken], &[], &engine)),
        "objects[0].volume.fin"
    );
    let mut other = fx.u8.clone();
    other.texels.truncate(8);
    let mut transfer = good.transfer.unwrap();
    transfer.u8 = &other;
    let mismatched = ExportInput {
        transfer: Some(transfer),
        ..good
    };
    assert_eq!(
        parameter_name(encode_glb(&[mismatched], &[], &engine)),
        "objects[0].transfer.u8"
    );
}

#[test]
fn offsets_beyond_f32_are_refused_naming_the_comb() {
    let fx = Fixture::new();
    let mesh = &fx.mesh;
    let comb = vec![[1e38f32, 0.0, 0.0]; mesh.vertex_count()];
    let huge = crate::FurMesh::new(
        crate::MeshInput::new(mesh.positions(), mesh.triangles())
            .with_comb(&comb)
            .with_length(mesh.length().unwrap()),
    )
    .unwrap();
    let input = ExportInput {
        mesh: &huge,
        fur_depth: 1e5,
        ..fx.input("Huge")
    };
    // Both modes lift shells (the engine mode its fallback shells).
    for mode in [GltfMode::Geometry, GltfMode::Engine] {
        let name = parameter_name(encode_glb(&[input], &[], &options(mode)));
        assert!(name.starts_with("objects[0].comb["), "{name}");
    }
}
