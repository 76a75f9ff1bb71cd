//! Skinned export read back by the test's GLB reader: linear blend skinning evaluated here from
//! the file alone (node transforms, animation samples, inverse bind matrices, `JOINTS_0` and
//! `WEIGHTS_0`) puts every skin, shell and fin vertex where the object's transform puts it at
//! rest, and where a rotation about the bone's own axis, computed geometrically, puts it in the
//! last frame. Weight reduction and the errors are checked against hand-made cases.

use glam::{Mat4, Quat, Vec3, Vec4};
use serde_json::Value;

use super::fixture::Fixture;
use super::glb_reader::Glb;
use super::parameter_name;
use crate::export::rig::{Animation, Skeleton, SkeletonNode, SkinBinding, Transform};
use crate::export::{GltfMode, GltfOptions, encode_glb};

const QUARTER: f32 = std::f32::consts::FRAC_PI_2;

fn trs(translation: [f32; 3], rotation: Quat, scale: f32) -> Transform {
    Transform {
        translation: Vec3::from(translation),
        rotation,
        scale: Vec3::splat(scale),
    }
}

/// An armature node (turned to Y-up, scaled 2) with a lower and an upper bone; the upper bone
/// turns a quarter about its own z axis between t = 0 and t = 1.
fn skeleton() -> Skeleton {
    let nodes = vec![
        SkeletonNode {
            name: "Armature".into(),
            parent: None,
            rest: trs([0.5, 0.0, -1.0], Quat::from_rotation_x(-QUARTER), 2.0),
        },
        SkeletonNode {
            name: "Lower".into(),
            parent: Some(0),
            rest: trs([0.0, 0.0, -0.5], Quat::IDENTITY, 1.0),
        },
        SkeletonNode {
            name: "Upper".into(),
            parent: Some(1),
            rest: trs([0.0, 0.1, 0.5], Quat::from_rotation_y(0.4), 1.0),
        },
    ];
    let mut poses: Vec<Transform> = nodes.iter().map(|n| n.rest).collect();
    let mut turned = nodes[2].rest;
    turned.rotation *= Quat::from_rotation_z(QUARTER);
    poses.extend([nodes[0].rest, nodes[1].rest, turned]);
    Skeleton {
        nodes,
        animations: vec![Animation {
            name: "Turn".into(),
            times: vec![0.0, 1.0],
            poses,
        }],
    }
}

/// The object's placement at bind time.
fn bind() -> Transform {
    trs([1.0, 2.0, 3.0], Quat::from_rotation_z(0.5), 1.5)
}

/// Per vertex of `fx`: the upper bone above z = 0, the lower one below (two influences each,
/// the second with weight 0, which is ignored).
fn binding(fx: &Fixture) -> (Vec<u32>, Vec<f32>) {
    let mut joints = Vec::new();
    let mut weights = Vec::new();
    for p in fx.mesh.positions() {
        let upper = p[2] > 0.0;
        joints.extend([if upper { 2 } else { 1 }, 0]);
        weights.extend([1.0, 0.0]);
    }
    (joints, weights)
}

fn vec(v: &Value, default: Vec3) -> Vec3 {
    v.as_array()
        .map_or(default, |a| Vec3::new(num(&a[0]), num(&a[1]), num(&a[2])))
}

fn num(v: &Value) -> f32 {
    v.as_f64().unwrap() as f32
}

/// Every glTF node's local matrix, with the samples of animation 0 at `key` replacing the
/// animated paths when given.
fn local_matrices(glb: &Glb, key: Option<usize>) -> Vec<Mat4> {
    let nodes = glb.json["nodes"].as_array().unwrap();
    let mut t: Vec<Vec3> = nodes.iter().map(|n| vec(&n["translation"], Vec3::ZERO)).collect();
    let mut s: Vec<Vec3> = nodes.iter().map(|n| vec(&n["scale"], Vec3::ONE)).collect();
    let mut r: Vec<Quat> = nodes
        .iter()
        .map(|n| {
            n["rotation"].as_array().map_or(Quat::IDENTITY, |q| {
                Quat::from_xyzw(num(&q[0]), num(&q[1]), num(&q[2]), num(&q[3]))
            })
        })
        .collect();
    if let Some(key) = key {
        let animation = &glb.json["animations"][0];
        for channel in animation["channels"].as_array().unwrap() {
            let sampler = &animation["samplers"][channel["sampler"].as_u64().unwrap() as usize];
            let out = glb.floats(sampler["output"].as_u64().unwrap() as usize);
            let v = &out[key];
            let node = channel["target"]["node"].as_u64().unwrap() as usize;
            match channel["target"]["path"].as_str().unwrap() {
                "translation" => t[node] = Vec3::new(v[0], v[1], v[2]),
                "rotation" => r[node] = Quat::from_xyzw(v[0], v[1], v[2], v[3]),
                "scale" => s[node] = Vec3::new(v[0], v[1], v[2]),
                other => panic!("path {other}"),
            }
        }
    }
    (0..nodes.len())
        .map(|i| Mat4::from_scale_rotation_translation(s[i], r[i], t[i]))
        .collect()
}

/// Every glTF node's world matrix, through the `children` lists.
fn world_matrices(glb: &Glb, key: Option<usize>) -> Vec<Mat4> {
    let local = local_matrices(glb, key);
    let nodes = glb.json["nodes"].as_array().unwrap();
    let mut parent = vec![None; nodes.len()];
    for (i, n) in nodes.iter().enumerate() {
        for c in n["children"].as_array().into_iter().flatten() {
            parent[c.as_u64().unwrap() as usize] = Some(i);
        }
    }
    (0..nodes.len())
        .map(|mut i| {
            let mut m = local[i];
            while let Some(p) = parent[i] {
                m = local[p] * m;
                i = p;
            }
            m
        })
        .collect()
}

/// Every primitive's vertices skinned from the file: `Σ w · world(joint) · inverse_bind · p`.
fn skinned_primitives(glb: &Glb, key: Option<usize>) -> Vec<Vec<Vec3>> {
    let world = world_matrices(glb, key);
    let node = &glb.json["nodes"][0];
    assert!(node.get("translation").is_none() && node.get("rotation").is_none());
    let skin = &glb.json["skins"][node["skin"].as_u64().unwrap() as usize];
    let joints: Vec<usize> = skin["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j.as_u64().unwrap() as usize)
        .collect();
    let ibm: Vec<Mat4> = glb
        .floats(skin["inverseBindMatrices"].as_u64().unwrap() as usize)
        .iter()
        .map(|m| Mat4::from_cols_slice(m))
        .collect();
    let mesh = &glb.json["meshes"][node["mesh"].as_u64().unwrap() as usize];
    mesh["primitives"]
        .as_array()
        .unwrap()
        .iter()
        .map(|primitive| {
            let positions = glb.floats(Glb::attribute(primitive, "POSITION"));
            let js = glb.joints(Glb::attribute(primitive, "JOINTS_0"));
            let ws = glb.floats(Glb::attribute(primitive, "WEIGHTS_0"));
            positions
                .iter()
                .zip(js.iter().zip(&ws))
                .map(|(p, (j, w))| {
                    assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
                    let p = Vec4::new(p[0], p[1], p[2], 1.0);
                    (0..4)
                        .map(|k| w[k] * (world[joints[j[k] as usize]] * ibm[j[k] as usize] * p))
                        .sum::<Vec4>()
                        .truncate()
                })
                .collect()
        })
        .collect()
}

#[test]
fn skinned_fur_follows_its_bones_in_both_modes() {
    let fx = Fixture::new();
    let skeleton = skeleton();
    let (joints, weights) = binding(&fx);
    let input = crate::export::ExportInput {
        transform: bind(),
        skin: Some(SkinBinding {
            skeleton: 0,
            influences: 2,
            joints: &joints,
            weights: &weights,
        }),
        ..fx.input("Character")
    };
    // The upper bone's pivot and turning axis in the scene at rest, from the skeleton itself.
    let rest = skeleton.world_rest();
    let pivot = rest[2].transform_point3(Vec3::ZERO);
    let axis = rest[2].transform_vector3(Vec3::Z).normalize();
    let turn = Quat::from_axis_angle(axis, QUARTER);
    let bind = bind().matrix();
    for mode in [GltfMode::Geometry, GltfMode::Engine] {
        let options = GltfOptions {
            mode,
            ..GltfOptions::default()
        };
        let glb = Glb::parse(&encode_glb(&[input], std::slice::from_ref(&skeleton), &options).unwrap());
        assert_eq!(glb.json["animations"][0]["name"], "Turn");
        let at_rest = skinned_primitives(&glb, None);
        let first = skinned_primitives(&glb, Some(0));
        let last = skinned_primitives(&glb, Some(1));
        let mesh = &glb.json["meshes"][0]["primitives"];
        let mut checked = 0;
        for (p, primitive) in mesh.as_array().unwrap().iter().enumerate() {
            let written = glb.floats(Glb::attribute(primitive, "POSITION"));
            for (i, q) in written.iter().enumerate() {
                let placed = bind.transform_point3(Vec3::new(q[0], q[1], q[2]));
                assert!(
                    at_rest[p][i].distance(placed) < 1e-4,
                    "{mode:?} primitive {p} vertex {i} at rest"
                );
                assert!(
                    first[p][i].distance(placed) < 1e-4,
                    "{mode:?} primitive {p} vertex {i} at t = 0"
                );
                // Bound wholly to the upper bone: turned about its axis; else unmoved.
                let turned = pivot + turn * (placed - pivot);
                let moved = last[p][i];
                let upper = moved.distance(turned) < 1e-4;
                assert!(
                    upper || moved.distance(placed) < 1e-4,
                    "{mode:?} primitive {p} vertex {i}"
                );
                checked += usize::from(upper);
            }
        }
        assert!(
            checked > 100,
            "{mode:?}: {checked} vertices followed the upper bone"
        );
        // Geometry: skin, shells and fins all carry the weights.
        if mode == GltfMode::Geometry {
            assert!(mesh.as_array().unwrap().len() > 3);
        }
    }
}

#[test]
fn unmoved_nodes_get_no_channels_and_unskinned_objects_keep_their_place() {
    let fx = Fixture::new();
    let skeleton = skeleton();
    let placed = crate::export::ExportInput {
        transform: bind(),
        ..fx.input("Prop")
    };
    let options = GltfOptions::default();
    let glb = Glb::parse(&encode_glb(&[placed], std::slice::from_ref(&skeleton), &options).unwrap());
    let channels = glb.json["animations"][0]["channels"].as_array().unwrap();
    // Only the upper bone (glTF node 1 + 2) turns: one rotation channel.
    assert_eq!(channels.len(), 1);
    assert_eq!(channels[0]["target"]["node"], 3);
    assert_eq!(channels[0]["target"]["path"], "rotation");
    let node = &glb.json["nodes"][0];
    assert!(node.get("skin").is_none());
    let world = world_matrices(&glb, None)[0];
    assert!(world.abs_diff_eq(bind().matrix(), 1e-5));
    // The scene holds the object and the skeleton's root.
    assert_eq!(glb.json["scenes"][0]["nodes"], serde_json::json!([0, 1]));
}

#[test]
fn an_unskinned_object_moves_by_its_own_animation_and_a_skinned_one_may_not_have_one() {
    let fx = Fixture::new();
    // The prop rises by 2 and turns a quarter about y over a second, from where it stands.
    let start = bind();
    let end = Transform {
        translation: start.translation + Vec3::Y * 2.0,
        rotation: Quat::from_rotation_y(std::f32::consts::FRAC_PI_2) * start.rotation,
        ..start
    };
    let animations = [Animation {
        name: "Rise".into(),
        times: vec![0.0, 1.0],
        poses: vec![start, end],
    }];
    let moving = crate::export::ExportInput {
        transform: start,
        animations: &animations,
        ..fx.input("Prop")
    };
    let glb = Glb::parse(&encode_glb(&[moving], &[], &GltfOptions::default()).unwrap());
    let animation = &glb.json["animations"][0];
    assert_eq!(animation["name"], "Rise");
    let paths: Vec<&str> = animation["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            assert_eq!(c["target"]["node"], 0, "the object's own node");
            c["target"]["path"].as_str().unwrap()
        })
        .collect();
    assert_eq!(paths, ["translation", "rotation"]);
    // At each key the node stands where the pose says, as an independent TRS product.
    for (key, pose) in [(0, start), (1, end)] {
        let world = world_matrices(&glb, Some(key))[0];
        assert!(world.abs_diff_eq(pose.matrix(), 1e-5), "key {key}: {world:?}");
    }

    // Refused: an animation on a skinned object, and bad times or poses, by name.
    let skeleton = skeleton();
    let (joints, weights) = binding(&fx);
    let skinned = crate::export::ExportInput {
        skin: Some(SkinBinding {
            skeleton: 0,
            influences: 2,
            joints: &joints,
            weights: &weights,
        }),
        animations: &animations,
        ..fx.input("Character")
    };
    let one = std::slice::from_ref(&skeleton);
    assert_eq!(
        parameter_name(encode_glb(&[skinned], one, &GltfOptions::default())),
        "objects[0].animations"
    );
    let backwards = [Animation {
        times: vec![1.0, 0.5],
        ..animations[0].clone()
    }];
    let short = [Animation {
        poses: vec![start],
        ..animations[0].clone()
    }];
    for (bad, name) in [
        (&backwards, "objects[0].animations[0].times"),
        (&short, "objects[0].animations[0].poses"),
    ] {
        let input = crate::export::ExportInput {
            animations: bad,
            ..fx.input("Prop")
        };
        assert_eq!(
            parameter_name(encode_glb(&[input], &[], &GltfOptions::default())),
            name
        );
    }
}

#[test]
fn more_than_four_influences_keep_the_strongest_normalized() {
    let joints = [
        1, 2, 3, 4, 5, 2, /* */ 0, 0, 0, 0, 0, 0, /* */ 3, 1, 0, 0, 0, 0,
    ];
    let weights = [
        0.125, 0.25, 0.375, 0.0625, 0.5, 0.125, /* */ 2.0, 0.0, 0.0, 0.0, 0.0, 0.0, /* */ 0.25,
        0.25, 0.5, 0.0, 0.0, 0.0,
    ];
    let binding = SkinBinding {
        skeleton: 0,
        influences: 6,
        joints: &joints,
        weights: &weights,
    };
    let skeletons = [Skeleton {
        nodes: (0..6)
            .map(|j| SkeletonNode {
                name: format!("n{j}"),
                parent: None,
                rest: Transform::IDENTITY,
            })
            .collect(),
        animations: Vec::new(),
    }];
    binding.validate(3, &skeletons).unwrap();
    let reduced = binding.reduce();
    // Joint 2 appears twice (0.25 + 0.125, tied with joint 3: the lower index first); the
    // weakest (joint 4) goes and the kept four are scaled to sum 1.
    assert_eq!(reduced.joints[0], [5, 2, 3, 1]);
    let kept = 0.5 + 0.375 + 0.375 + 0.125;
    for (got, want) in reduced.weights[0].iter().zip([0.5, 0.375, 0.375, 0.125]) {
        assert!((got - want / kept).abs() < 1e-6);
    }
    assert_eq!(
        (reduced.joints[1], reduced.weights[1]),
        ([0, 0, 0, 0], [1.0, 0.0, 0.0, 0.0])
    );
    assert_eq!(reduced.joints[2], [0, 1, 3, 0]);
    assert_eq!(reduced.report.vertices, 3);
    assert_eq!(reduced.report.reduced, 1);
    // Vertex 0 summed 1.4375 and vertex 1 summed 2; vertex 2 summed 1.
    assert_eq!(reduced.report.renormalized, 2);
}

#[test]
fn bad_skins_and_skeletons_name_the_field() {
    let fx = Fixture::new();
    let skeleton = skeleton();
    let (joints, weights) = binding(&fx);
    let skin = SkinBinding {
        skeleton: 0,
        influences: 2,
        joints: &joints,
        weights: &weights,
    };
    let skinned = |skin: SkinBinding<'_>, skeletons: &[Skeleton]| {
        let input = crate::export::ExportInput {
            skin: Some(skin),
            ..fx.input("Character")
        };
        parameter_name(encode_glb(&[input], skeletons, &GltfOptions::default()))
    };
    let one = std::slice::from_ref(&skeleton);
    assert_eq!(skinned(skin, &[]), "objects[0].skin.skeleton");
    let mut missing = joints.clone();
    missing[4] = 3;
    assert_eq!(
        skinned(
            SkinBinding {
                joints: &missing,
                ..skin
            },
            one
        ),
        "objects[0].skin.joints"
    );
    let mut negative = weights.clone();
    negative[0] = -0.5;
    assert_eq!(
        skinned(
            SkinBinding {
                weights: &negative,
                ..skin
            },
            one
        ),
        "objects[0].skin.weights"
    );
    let mut unweighted = weights.clone();
    unweighted[6] = 0.0;
    assert_eq!(
        skinned(
            SkinBinding {
                weights: &unweighted,
                ..skin
            },
            one
        ),
        "objects[0].skin.weights"
    );
    assert_eq!(
        skinned(
            SkinBinding {
                joints: &joints[2..],
                ..skin
            },
            one
        ),
        "objects[0].skin.joints"
    );

    let mut cycle = skeleton.clone();
    cycle.nodes[0].parent = Some(2);
    assert_eq!(skinned(skin, &[cycle]), "skeletons[0].nodes[0].parent");
    let mut orphan = skeleton.clone();
    orphan.nodes[1].parent = Some(9);
    assert_eq!(skinned(skin, &[orphan]), "skeletons[0].nodes[1].parent");
    let mut flat = skeleton.clone();
    flat.nodes[2].rest.scale = Vec3::new(1.0, 0.0, 1.0);
    assert_eq!(skinned(skin, &[flat]), "skeletons[0].nodes[2].rest");
    let mut backwards = skeleton.clone();
    backwards.animations[0].times = vec![1.0, 1.0];
    assert_eq!(skinned(skin, &[backwards]), "skeletons[0].animations[0].times");
    let mut short = skeleton.clone();
    short.animations[0].poses.pop();
    assert_eq!(skinned(skin, &[short]), "skeletons[0].animations[0].poses");
    let mut nan = skeleton.clone();
    nan.animations[0].poses[4].translation.x = f32::NAN;
    assert_eq!(skinned(skin, &[nan]), "skeletons[0].animations[0].poses[4]");

    let input = crate::export::ExportInput {
        transform: trs([0.0; 3], Quat::from_xyzw(0.0, 0.0, 0.0, 2.0), 1.0),
        ..fx.input("Prop")
    };
    assert_eq!(
        parameter_name(encode_glb(&[input], &[], &GltfOptions::default())),
        "objects[0].transform"
    );
    // A matrix with a zero column has no transform.
    let mut rows = Mat4::IDENTITY.transpose().to_cols_array_2d();
    rows[1][1] = 0.0;
    assert!(Transform::from_rows(rows).is_none());
    let rows = bind().matrix().transpose().to_cols_array_2d();
    let back = Transform::from_rows(rows).unwrap();
    assert!(back.matrix().abs_diff_eq(bind().matrix(), 1e-5));
}

#[test]
fn a_long_chain_of_nodes_is_checked_and_placed() {
    // 65535 nodes, each the child of the next: a walk from every node to the root would take
    // 2·10⁹ steps (minutes here); each chain is walked once.
    let n = crate::export::rig::MAX_NODES;
    let node = |j: usize| SkeletonNode {
        name: format!("n{j}"),
        parent: (j + 1 < n).then_some(j + 1),
        rest: Transform::IDENTITY,
    };
    let mut chain = Skeleton {
        nodes: (0..n).map(node).collect(),
        animations: Vec::new(),
    };
    chain.validate().unwrap();
    assert_eq!(chain.world_rest().len(), n);
    // Closed into a ring, the lowest node is named.
    chain.nodes[n - 1].parent = Some(0);
    assert_eq!(parameter_name(chain.validate()), "nodes[0].parent");
}
