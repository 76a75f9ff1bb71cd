//! The reader against GLB files assembled byte by byte here (interleaved and normalized
//! attributes, node transforms, strips, welding) and against broken files.

use std::path::Path;

use super::{parse_gltf, read_gltf};
use crate::error::PeltError;

/// A GLB of `json` and `bin` laid out as the glTF 2.0 specification §4 says.
fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    crate::export::gltf::glb_container(json.as_bytes(), bin).unwrap()
}

fn f32s(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// Six vertices of a unit quad as two separate triangles (as exporters split at UV seams),
/// interleaved: position (12 bytes) then RGBA8 normalized color (4 bytes); then u16 indices;
/// then three positions of a strip.
fn scene_bin() -> (Vec<u8>, usize, usize) {
    let corners = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [-0.0, 0.0, 0.0], // the same position as vertex 0 (−0 welds with +0)
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let mut bin = Vec::new();
    for (k, p) in corners.iter().enumerate() {
        bin.extend(f32s(p));
        bin.extend([51 * k as u8, 255, 0, 255]);
    }
    let indices_at = bin.len();
    for i in [0u16, 1, 2, 3, 4, 5] {
        bin.extend(i.to_le_bytes());
    }
    let strip_at = bin.len();
    bin.extend(f32s(&[
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0,
    ]));
    (bin, indices_at, strip_at)
}

fn scene_json(bin_len: usize, indices_at: usize, strip_at: usize) -> String {
    format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "buffers": [{{"byteLength": {bin_len}}}],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 96, "byteStride": 16}},
    {{"buffer": 0, "byteOffset": {indices_at}, "byteLength": 12}},
    {{"buffer": 0, "byteOffset": {strip_at}, "byteLength": 48}}
  ],
  "accessors": [
    {{"bufferView": 0, "byteOffset": 0, "count": 6, "componentType": 5126, "type": "VEC3",
      "min": [0, 0, 0], "max": [1, 1, 0]}},
    {{"bufferView": 0, "byteOffset": 12, "count": 6, "componentType": 5121, "normalized": true,
      "type": "VEC4"}},
    {{"bufferView": 1, "count": 6, "componentType": 5123, "type": "SCALAR"}},
    {{"bufferView": 2, "count": 4, "componentType": 5126, "type": "VEC3",
      "min": [0, 0, 0], "max": [1, 1, 0]}}
  ],
  "meshes": [
    {{"name": "QuadMesh", "primitives": [{{"attributes": {{"POSITION": 0, "COLOR_0": 1}}, "indices": 2}}]}},
    {{"name": "Strip", "primitives": [{{"attributes": {{"POSITION": 3}}, "mode": 5}},
                                      {{"attributes": {{"POSITION": 3}}, "mode": 1}}]}}
  ],
  "nodes": [
    {{"name": "Quad", "mesh": 0, "translation": [1, 2, 3], "scale": [2, 2, 2]}},
    {{"mesh": 1}},
    {{"children": [1], "matrix": [0,1,0,0, -1,0,0,0, 0,0,1,0, 5,0,0,1]}}
  ],
  "scenes": [{{"nodes": [0, 2]}}],
  "scene": 0
}}"#
    )
}

#[test]
fn nodes_are_read_in_world_space_welded_with_their_colors() {
    let (bin, indices_at, strip_at) = scene_bin();
    let bytes = glb(&scene_json(bin.len(), indices_at, strip_at), &bin);
    let objects = parse_gltf(Path::new("scene.glb"), &bytes, "scene").unwrap();
    assert_eq!(objects.len(), 2);

    let quad = &objects[0];
    assert_eq!(quad.name, "Quad");
    // Vertices 3 and 4 repeat 0 and 2: four remain, in file order; scale 2 then translate.
    assert_eq!(
        quad.mesh.positions,
        [[1.0, 2.0, 3.0], [3.0, 2.0, 3.0], [3.0, 4.0, 3.0], [1.0, 4.0, 3.0]]
    );
    assert_eq!(quad.mesh.triangles, [[0, 1, 2], [0, 2, 3]]);
    assert_eq!(quad.mesh.polygons, [0, 1]);
    // Normalized bytes: red = 51 k / 255 of the first vertex of each group.
    let color = quad.mesh.color.as_ref().unwrap();
    let red: Vec<f32> = color.iter().map(|c| c[0]).collect();
    assert_eq!(red, [0.0, 51.0 / 255.0, 102.0 / 255.0, 255.0 / 255.0]);
    assert!(color.iter().all(|c| c[1] == 1.0 && c[2] == 0.0 && c[3] == 1.0));

    // The unnamed node takes its mesh's name; its parent turns +x into +y and moves by 5 in x.
    // A strip of 4 vertices is 2 triangles, the second reversed; the line primitive is skipped.
    let strip = &objects[1];
    assert_eq!(strip.name, "Strip");
    assert_eq!(
        strip.mesh.positions,
        [[5.0, 0.0, 0.0], [5.0, 1.0, 0.0], [4.0, 0.0, 0.0], [4.0, 1.0, 0.0]]
    );
    assert_eq!(strip.mesh.triangles, [[0, 1, 2], [2, 1, 3]]);
    assert_eq!(strip.mesh.color, None);
}

fn reason(result: Result<Vec<super::NamedMesh>, String>) -> String {
    match result {
        Err(reason) => reason,
        Ok(objects) => panic!("expected an error, got {} objects", objects.len()),
    }
}

#[test]
fn broken_files_are_refused_with_a_reason() {
    let (bin, indices_at, strip_at) = scene_bin();
    let json = scene_json(bin.len(), indices_at, strip_at);
    let parse = |bytes: &[u8]| reason(parse_gltf(Path::new("x.glb"), bytes, "x"));

    let good = glb(&json, &bin);
    assert!(parse(&good[..good.len() - 8]).contains("states"));
    assert!(parse(b"not a gltf").contains("not a glTF 2.0 document"));
    let bad_index = {
        let mut b = bin.clone();
        b[indices_at..indices_at + 2].copy_from_slice(&9u16.to_le_bytes());
        glb(&json, &b)
    };
    assert!(parse(&bad_index).contains("refers to vertex 9"));
    let no_position = json.replace(r#""POSITION": 0, "COLOR_0": 1"#, r#""COLOR_0": 1"#);
    let m = parse(&glb(&no_position, &bin));
    assert!(m.contains("POSITION"), "{m}");
    let nan_position = {
        let mut b = bin.clone();
        b[16..20].copy_from_slice(&f32::NAN.to_le_bytes());
        glb(&json, &b)
    };
    let m = parse(&nan_position);
    assert!(
        m.contains("POSITION element 1") && m.contains("not finite"),
        "{m}"
    );
    // Two transforms of 1e30 carry the strip to 1e60, past float32.
    let huge_scale = json
        .replace(r#"{"mesh": 1}"#, r#"{"mesh": 1, "scale": [1e30, 1e30, 1e30]}"#)
        .replace("[0,1,0,0, -1,0,0,0,", "[0,1e30,0,0, -1e30,0,0,0,");
    let m = parse(&glb(&huge_scale, &bin));
    assert!(
        m.contains("mesh 1 primitive 0 POSITION") && m.contains("not finite"),
        "{m}"
    );
    let past_end = json.replace(r#""byteLength": 48"#, r#""byteLength": 4800"#);
    assert!(parse(&glb(&past_end, &bin)).contains("runs past its buffer"));
    let bad_type = json.replace(r#""componentType": 5123"#, r#""componentType": 5126"#);
    assert!(parse(&glb(&bad_type, &bin)).contains("does not allow"));
    let dangling = json.replace(r#""indices": 2"#, r#""indices": 7"#);
    assert!(parse(&glb(&dangling, &bin)).contains("invalid glTF"));
    let viewless = json.replace(r#"{"bufferView": 2, "count": 4"#, r#"{"count": 4"#);
    let m = parse(&glb(&viewless, &bin));
    assert!(m.contains("bufferView") || m.contains("buffer view"), "{m}");
    let cycle = json.replace(r#""children": [1]"#, r#""children": [2]"#);
    assert!(parse(&glb(&cycle, &bin)).contains("child of node 2"));
    let missing_position = json.replace(r#""POSITION": 0, "COLOR_0": 1"#, r#""POSITION": 9"#);
    let m = parse(&glb(&missing_position, &bin));
    assert!(m.contains("POSITION names accessor 9"), "{m}");
    let data_uri = json.replace(
        &format!(r#""byteLength": {}}}]"#, bin.len()),
        &format!(
            r#""byteLength": {}, "uri": "data:application/octet-stream;base64,AAAA"}}]"#,
            bin.len()
        ),
    );
    assert!(parse(&glb(&data_uri, &bin)).contains("data URI"));
    let lines_only = json
        .replace(r#""indices": 2}"#, r#""indices": 2, "mode": 1}"#)
        .replace(r#""mode": 5"#, r#""mode": 3"#);
    assert!(parse(&glb(&lines_only, &bin)).contains("no triangle mesh"));
}

#[test]
fn errors_name_the_file() {
    let dir = std::env::temp_dir().join(format!("pelt-gltf-read-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("broken.glb");
    std::fs::write(&path, b"glTF\x02\0\0\0").unwrap();
    match read_gltf(&path) {
        Err(PeltError::InvalidParameter { name, reason }) => {
            assert_eq!(name, path.display().to_string());
            assert!(reason.contains("truncated"), "{reason}");
        }
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
    assert!(matches!(
        read_gltf(&dir.join("missing.glb")),
        Err(PeltError::Io { .. })
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A node graph where node i has children [i+1, i+1] names 2^n instances in n nodes; a scene
/// listing one node many times repeats its bake. glTF hierarchies are trees: both are refused.
#[test]
fn shared_children_and_repeated_roots_cannot_multiply_instances() {
    let (bin, indices_at, strip_at) = scene_bin();
    let json = scene_json(bin.len(), indices_at, strip_at);
    let parse = |json: &str| reason(parse_gltf(Path::new("x.glb"), &glb(json, &bin), "x"));
    // `json` with its node list and scene roots replaced.
    let graph = |nodes: &[String], roots: &[String]| {
        let (from, to) = (
            json.find(r#""nodes": ["#).unwrap(),
            json.find(r#""scenes""#).unwrap(),
        );
        let scene = format!(r#""scenes": [{{"nodes": [{}]}}]"#, roots.join(","));
        json.replace(&json[from..to], &format!("\"nodes\": [{}],\n  ", nodes.join(",")))
            .replace(r#""scenes": [{"nodes": [0, 2]}]"#, &scene)
    };
    let doubling: Vec<String> = (0..24)
        .map(|i| format!(r#"{{"mesh": 0, "children": [{0}, {0}]}}"#, i + 1))
        .chain(std::iter::once(r#"{"mesh": 0}"#.to_string()))
        .collect();
    let m = parse(&graph(&doubling, &["0".into()]));
    assert!(m.contains("node 0 lists child 1 twice"), "{m}");
    let two_parents = json.replace(
        r#""scale": [2, 2, 2]}"#,
        r#""scale": [2, 2, 2], "children": [1]}"#,
    );
    let m = parse(&two_parents);
    assert!(m.contains("node 1 is a child of both node 0 and node 2"), "{m}");
    let repeated: Vec<String> = vec!["0".to_string(); 10_000];
    let m = parse(&json.replace(
        r#""nodes": [0, 2]"#,
        &format!(r#""nodes": [{}]"#, repeated.join(",")),
    ));
    assert!(m.contains("lists node 0 twice"), "{m}");
    // Many distinct objects: each one a bake, so the file is capped.
    let many = vec![r#"{"mesh": 0}"#.to_string(); super::MAX_OBJECTS + 1];
    let roots: Vec<String> = (0..=super::MAX_OBJECTS).map(|i| i.to_string()).collect();
    let wide = graph(&many, &roots);
    let m = parse(&wide);
    assert!(m.contains("more than 1024 mesh instances"), "{m}");
}

/// A `.gltf` in a fresh folder whose one buffer has `uri`, and the quad mesh of [`scene_bin`].
fn gltf_with_uri(dir: &Path, uri: &str) -> std::path::PathBuf {
    let (bin, indices_at, strip_at) = scene_bin();
    let json = scene_json(bin.len(), indices_at, strip_at).replace(
        &format!(r#""byteLength": {}}}]"#, bin.len()),
        &format!(r#""byteLength": {}, "uri": {uri:?}}}]"#, bin.len()),
    );
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("scene.bin"), &bin).unwrap();
    let path = dir.join("scene.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

/// Buffer URIs name files inside the glTF's folder only: an absolute path, a `file:` URI, `..`
/// that climbs out (also %-escaped) or a link that leads out are refused, as Khronos's loader does.
#[test]
fn buffer_uris_cannot_leave_the_files_folder() {
    let root = std::env::temp_dir().join(format!("pelt-gltf-uri-{}", std::process::id()));
    let dir = root.join("asset");
    let inside = gltf_with_uri(&dir, "sub/../scene%2Ebin");
    assert_eq!(read_gltf(&inside).unwrap().len(), 2);
    std::fs::write(root.join("secret.bin"), vec![7u8; 400]).unwrap();
    let outside = root.join("secret.bin").display().to_string();
    for uri in [
        outside.as_str(),
        "/etc/passwd",
        "file:///etc/passwd",
        "../secret.bin",
        "%2E%2E/secret.bin",
        "sub/../../secret.bin",
        "..\\secret.bin",
    ] {
        let path = gltf_with_uri(&dir, uri);
        match read_gltf(&path) {
            Err(PeltError::InvalidParameter { reason, .. }) => {
                assert!(reason.contains("buffer 0 uri"), "{uri}: {reason}")
            }
            other => panic!("{uri}: expected a refusal, got {other:?}"),
        }
    }
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(root.join("secret.bin"), dir.join("link.bin")).unwrap();
        let path = gltf_with_uri(&dir, "link.bin");
        let error = read_gltf(&path).unwrap_err().to_string();
        assert!(error.contains("through a link"), "{error}");
    }
    std::fs::remove_dir_all(&root).unwrap();
}
