"""The skin of an armature-deformed mesh (``addon/blender/rig.py``), checked against Blender itself: linear
blend skinning computed here from the gathered arrays alone must put every vertex where the
Armature modifier does, at every frame of the action, in glTF's Y-up world."""

import importlib.util
import math
import sys

import bpy
import numpy as np
import pytest
from conftest import REPO, datablock_snapshot
from mathutils import Quaternion

# Loaded as a file of its own: the module must not need the add-on's package.
_spec = importlib.util.spec_from_file_location("pelt_addon_rig", REPO / "addon" / "blender" / "rig.py")
rig = importlib.util.module_from_spec(_spec)
sys.modules[_spec.name] = rig
_spec.loader.exec_module(rig)

RINGS, AROUND = 31, 16  # 496 vertices, rings 0.1 apart from z = 0 to 3
FIRST, LAST = 1, 11
FPS, FPS_BASE = 30, 1.001
GROUPS = ("Root", "Mid", "Tip", "Helper", "Extra")  # Helper: a bone that does not deform; Extra: no bone
Z_UP_TO_Y_UP = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, 0], [0, 0, 0, 1]], float)


def tube() -> bpy.types.Object:
    z = np.arange(RINGS) * 0.1
    angle = np.arange(AROUND) * (2 * math.pi / AROUND)
    positions = [(0.3 * math.cos(a), 0.3 * math.sin(a), h) for h in z for a in angle]
    cells = [(r, k) for r in range(RINGS - 1) for k in range(AROUND)]
    faces = [
        (
            r * AROUND + k,
            r * AROUND + (k + 1) % AROUND,
            (r + 1) * AROUND + (k + 1) % AROUND,
            (r + 1) * AROUND + k,
        )
        for r, k in cells
    ]
    mesh = bpy.data.meshes.new("Tube")
    mesh.from_pydata(positions, [], faces)
    obj = bpy.data.objects.new("Tube", mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def written_weights() -> np.ndarray:
    """The weights the test writes, (V, 5) in ``GROUPS`` order: smooth falloffs along the tube and
    rings of special cases."""
    ring = np.repeat(np.arange(RINGS), AROUND)
    side = np.tile(np.arange(AROUND), RINGS)
    z = ring * 0.1
    w = np.zeros((RINGS * AROUND, len(GROUPS)))
    w[:, 0] = np.clip(1.5 - z, 0.0, 1.0)
    w[:, 1] = np.clip(1.0 - np.abs(z - 1.5), 0.0, 1.0)
    w[:, 2] = np.clip(z - 1.5, 0.0, 1.0)
    w = np.round(w, 2)
    w[ring == 4] = 0.0  # unweighted
    w[ring == 7] = (0.0, 0.0, 0.0, 1.0, 0.0)  # a non-deforming bone only: unmoved
    w[ring == 10] *= 0.5  # total 0.5: Blender normalizes
    five = (ring == 16) & (side % 2 == 0)
    w[five] = (0.2, 0.5, 0.3, 0.7, 0.9)  # five groups, two of them ignored by the armature
    w[ring == 22] = (0.0, 4e-5, 4e-5, 0.0, 0.0)  # too little to move: unmoved
    w[ring == 25, 4] = 0.6  # a group naming no bone beside real weights
    return w


def skinned_tube():
    """The tube skinned to a chain of three bones (and a non-deforming helper) of an armature
    moved, rotated and scaled in the world, with an action over frames 1–11 on its bones and on
    the armature object; the tube is the armature's child."""
    obj = tube()
    arm = bpy.data.objects.new("Rig", bpy.data.armatures.new("Rig"))
    bpy.context.scene.collection.objects.link(arm)
    bpy.context.view_layer.objects.active = arm
    bpy.ops.object.mode_set(mode="EDIT")
    bones = arm.data.edit_bones
    root = bones.new("Root")
    root.head, root.tail = (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)
    mid = bones.new("Mid")
    mid.head, mid.tail, mid.roll, mid.parent = (0.0, 0.0, 1.0), (0.2, 0.0, 2.0), 0.6, root
    mid.use_connect = True
    tip = bones.new("Tip")
    tip.head, tip.tail, tip.roll, tip.parent = (0.2, 0.0, 2.0), (0.0, 0.1, 3.0), -0.4, mid
    helper = bones.new("Helper")
    helper.head, helper.tail, helper.parent = (0.5, 0.0, 1.0), (0.5, 0.0, 1.5), root
    helper.use_deform = False
    bpy.ops.object.mode_set(mode="OBJECT")

    arm.location, arm.rotation_euler, arm.scale = (0.4, -0.7, 0.25), (0.3, -0.2, 0.9), (1.7, 1.7, 1.7)
    obj.parent = arm
    obj.location, obj.rotation_euler = (0.05, 0.1, -0.1), (0.1, 0.0, 0.2)
    modifier = obj.modifiers.new("Armature", "ARMATURE")
    modifier.object = arm

    weights = written_weights()
    for column, name in enumerate(GROUPS):
        group = obj.vertex_groups.new(name=name)
        for value in np.unique(weights[:, column]):
            if value > 0.0:
                group.add(np.flatnonzero(weights[:, column] == value).tolist(), float(value), "REPLACE")

    pose = arm.pose.bones
    keys = {
        "Root": {FIRST: ((1, 0, 0), 0.0), LAST: ((1, 0, 0), 0.5)},
        "Mid": {FIRST: ((0, 1, 0), 0.0), 6: ((0, 1, 0), 0.8), LAST: ((1, 1, 0), -0.6)},
    }
    for name, frames in keys.items():
        for frame, (axis, angle) in frames.items():
            pose[name].rotation_quaternion = Quaternion(axis, angle)
            pose[name].keyframe_insert("rotation_quaternion", frame=frame)
    for frame, offset in ((FIRST, (0.0, 0.0, 0.0)), (6, (0.1, 0.0, 0.2))):
        pose["Root"].location = offset
        pose["Root"].keyframe_insert("location", frame=frame)
    pose["Tip"].rotation_mode = "XYZ"
    for frame, euler, size in ((FIRST, (0.0, 0.0, 0.0), 1.0), (LAST, (0.4, 0.3, -0.5), 1.2)):
        pose["Tip"].rotation_euler, pose["Tip"].scale = euler, (size, size, size)
        pose["Tip"].keyframe_insert("rotation_euler", frame=frame)
        pose["Tip"].keyframe_insert("scale", frame=frame)
    for frame, x, turn in ((FIRST, 0.4, 0.9), (LAST, 0.9, 1.3)):
        arm.location.x, arm.rotation_euler.z = x, turn
        arm.keyframe_insert("location", frame=frame)
        arm.keyframe_insert("rotation_euler", frame=frame)
    arm.animation_data.action.name = "Wave"

    scene = bpy.context.scene
    scene.render.fps, scene.render.fps_base = FPS, FPS_BASE
    scene.frame_set(4, subframe=0.25)
    return obj, arm


def evaluated_world(obj) -> np.ndarray:
    """The evaluated vertices in glTF's world, float64 (V, 3)."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        co = np.empty(len(mesh.vertices) * 3, np.float32)
        mesh.vertices.foreach_get("co", co)
        world = Z_UP_TO_Y_UP @ np.array(evaluated.matrix_world)
    finally:
        evaluated.to_mesh_clear()
    return co.reshape(-1, 3).astype(float) @ world[:3, :3].T + world[:3, 3]


def rest_positions(obj) -> np.ndarray:
    co = np.empty(len(obj.data.vertices) * 3, np.float32)
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(float)


def world_matrices(local: np.ndarray, parents: np.ndarray) -> np.ndarray:
    """Every node's world matrix: the product of local matrices down its parent chain."""
    world = np.empty(local.shape)
    for node in range(len(parents)):
        matrix, parent = local[node].astype(float), parents[node]
        while parent >= 0:
            matrix = local[parent].astype(float) @ matrix
            parent = parents[parent]
        world[node] = matrix
    return world


def linear_blend(skin, poses: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Vertices skinned by the local ``poses`` (N, 4, 4), as a glTF viewer does: weights
    normalized, joint matrices ``world @ inverse(rest world) @ bind``."""
    joint = (
        world_matrices(poses, skin.parents)
        @ np.linalg.inv(world_matrices(skin.rest, skin.parents))
        @ skin.bind.astype(float)
    )
    weights = skin.weights / skin.weights.sum(axis=1, keepdims=True)
    blended = np.einsum("vk,vkij->vij", weights, joint[skin.joints])
    return np.einsum("vij,vj->vi", blended[:, :3, :3], vertices) + blended[:, :3, 3]


def node(skin, name: str) -> int:
    return skin.names.index(name)


def test_y_up_and_object_transform():
    assert rig.Y_UP.dtype == np.float64 and rig.Y_UP.shape == (4, 4)
    assert np.array_equal(rig.Y_UP @ (1.0, 2.0, 3.0, 1.0), (1.0, 3.0, -2.0, 1.0))
    obj = tube()
    obj.location, obj.rotation_euler, obj.scale = (1.0, 2.0, 3.0), (0.0, 0.0, math.pi / 2), (2.0, 2.0, 2.0)
    bpy.context.view_layer.update()
    transform = rig.object_transform(obj)
    assert transform.dtype == np.float32 and transform.shape == (4, 4)
    # (1, 0, 0) turns to (0, 2, 0) + (1, 2, 3) = (1, 4, 3) in Blender, (1, 3, -4) Y-up.
    assert np.allclose(transform @ (1.0, 0.0, 0.0, 1.0), (1.0, 3.0, -4.0, 1.0), atol=1e-6)


def test_no_armature_gives_none():
    obj = tube()
    assert rig.armature_modifier(obj) is None and rig.gather(obj, bpy.context.scene) is None
    unset = obj.modifiers.new("No object", "ARMATURE")
    assert rig.gather(obj, bpy.context.scene) is None
    unset.object = bpy.data.objects.new("Rig", bpy.data.armatures.new("Rig"))
    unset.show_viewport = False
    assert rig.armature_modifier(obj) is None and rig.gather(obj, bpy.context.scene) is None
    unset.show_viewport = True
    assert rig.armature_modifier(obj) == unset


def test_skin_follows_blender_at_every_frame():
    obj, arm = skinned_tube()
    scene = bpy.context.scene
    # An unkeyed edit of animated channels, which sampling the action would overwrite.
    arm.pose.bones["Mid"].rotation_quaternion = Quaternion((0.0, 0.0, 1.0), 0.3)
    arm.location.y = -0.5
    bpy.context.view_layer.update()
    posed = evaluated_world(obj)
    before = datablock_snapshot()
    arm_world, mesh_world = np.array(arm.matrix_world), np.array(obj.matrix_world)

    skin = rig.gather(obj, scene)

    # Nothing changed: datablocks, frame, the unkeyed edit and so the evaluated pose.
    assert datablock_snapshot() == before
    assert (scene.frame_current, scene.frame_subframe) == (4, 0.25)
    assert tuple(arm.pose.bones["Mid"].rotation_quaternion) == pytest.approx(
        tuple(Quaternion((0, 0, 1), 0.3))
    )
    assert arm.location.y == pytest.approx(-0.5)
    assert np.abs(evaluated_world(obj) - posed).max() < 1e-6

    # The nodes: the armature object, then its bones in their order, parented as the bones are.
    bones = list(arm.data.bones)
    assert skin.armature == "Rig" and skin.names == ["Rig"] + [b.name for b in bones]
    assert skin.parents.dtype == np.int32
    expected_parents = [-1] + [1 + bones.index(b.parent) if b.parent else 0 for b in bones]
    assert skin.parents.tolist() == expected_parents
    assert skin.rest.dtype == np.float32 and skin.rest.shape == (5, 4, 4)
    rest_world = world_matrices(skin.rest, skin.parents)
    assert np.allclose(rest_world[0], Z_UP_TO_Y_UP @ arm_world, atol=1e-5)
    for i, bone in enumerate(bones):
        expected = Z_UP_TO_Y_UP @ arm_world @ np.array(bone.matrix_local)
        assert np.allclose(rest_world[1 + i], expected, atol=1e-5), bone.name
    assert skin.bind.dtype == np.float32
    assert np.allclose(skin.bind, Z_UP_TO_Y_UP @ mesh_world, atol=1e-6)

    # The weights as written: deforming bones only, not normalized; node 0 for unmoved vertices.
    written = written_weights()
    vertex_count = len(obj.data.vertices)
    assert skin.weights.dtype == np.float32 and skin.joints.dtype == np.uint32
    assert skin.weights.shape == skin.joints.shape == (vertex_count, 4)
    assert (skin.joints == skin.joints[0]).all()
    columns = {int(j): k for k, j in enumerate(skin.joints[0])}
    deforming = ("Root", "Mid", "Tip")
    assert sorted(columns) == sorted([0] + [node(skin, name) for name in deforming])
    unmoved = written[:, :3].sum(axis=1) <= 1e-4
    assert unmoved.sum() == 3 * AROUND  # rings 4, 7 and 22
    assert np.array_equal(skin.weights[:, columns[0]], unmoved.astype(np.float32))
    for g, name in enumerate(deforming):
        got = skin.weights[:, columns[node(skin, name)]]
        assert np.allclose(got, np.where(unmoved, 0.0, written[:, g]), atol=1e-6), name
    ring = np.repeat(np.arange(RINGS), AROUND)
    assert np.allclose(skin.weights[ring == 10].sum(axis=1), 0.5)  # not normalized
    ignored = [note for note in skin.notes if "'Extra'" in note]
    assert len(ignored) == 1 and "'Helper'" in ignored[0] and "'Root'" not in ignored[0]
    assert len(skin.notes) == 1, skin.notes

    # The action, sampled at every frame.
    assert len(skin.animations) == 1
    animation = skin.animations[0]
    frames = np.arange(FIRST, LAST + 1)
    assert animation.name == "Wave"
    assert animation.times.dtype == np.float32 and animation.poses.dtype == np.float32
    assert np.allclose(animation.times, (frames - FIRST) * FPS_BASE / FPS, rtol=0, atol=1e-7)
    assert animation.poses.shape == (len(frames), 5, 4, 4)

    vertices = rest_positions(obj)
    for t, frame in enumerate(frames):
        scene.frame_set(int(frame))
        world = world_matrices(animation.poses[t], skin.parents)
        arm_now = Z_UP_TO_Y_UP @ np.array(arm.matrix_world)
        assert np.allclose(world[0], arm_now, atol=1e-5), frame
        for i, bone in enumerate(bones):
            expected = arm_now @ np.array(arm.pose.bones[bone.name].matrix)
            assert np.allclose(world[1 + i], expected, atol=1e-5), (frame, bone.name)
        blender = evaluated_world(obj)
        size = np.ptp(blender, axis=0).max()
        error = np.abs(linear_blend(skin, animation.poses[t], vertices) - blender).max()
        assert error < 1e-4 * size, (frame, error, size)
    # The pose changes: a skin stuck at rest would not pass.
    assert np.abs(evaluated_world(obj) - linear_blend(skin, skin.rest, vertices)).max() > 0.1


def test_notes_what_the_file_cannot_carry():
    obj, arm = skinned_tube()
    scene = bpy.context.scene

    def notes() -> list[str]:
        return rig.gather(obj, scene).notes

    def added() -> list[str]:
        return [note for note in notes() if note not in base]

    base = notes()
    modifier = rig.armature_modifier(obj)
    bones = arm.data.bones
    changes = [
        (modifier, "use_bone_envelopes", True, "envelopes"),
        (modifier, "use_deform_preserve_volume", True, "dual quaternions"),
        (modifier, "vertex_group", "Extra", "'Extra'"),
        (modifier, "use_multi_modifier", True, "Multi Modifier"),
        (arm.data, "pose_position", "REST", "rest position"),
        (bones["Tip"], "bbone_segments", 4, "B-Bones"),
        (bones["Mid"], "use_envelope_multiply", True, "'Mid'"),
        # Tip keeps its own scale under Mid stretched across it: sheared in Mid's space.
        (bones["Tip"], "inherit_scale", "NONE", None),
    ]
    for owner, option, value, words in changes:
        before = getattr(owner, option)
        setattr(owner, option, value)
        if words is None:
            arm.pose.bones["Mid"].scale = (1.0, 2.0, 1.0)
            new = added()
            arm.pose.bones["Mid"].scale = (1.0, 1.0, 1.0)
            words = "'Tip'"
        else:
            new = added()
        setattr(owner, option, before)
        assert len(new) == 1 and words in new[0], (option, new)
    assert notes() == base

    second = obj.modifiers.new("Second", "ARMATURE")
    second.object = arm
    new = added()
    assert len(new) == 1 and "'Second'" in new[0], new
    obj.modifiers.remove(second)

    track = arm.animation_data.nla_tracks.new()
    new = added()
    assert len(new) == 1 and "NLA" in new[0], new
    arm.animation_data.nla_tracks.remove(track)

    # Not the armature's child: the armature moves in its action, the mesh stays.
    matrix = obj.matrix_world.copy()
    obj.parent = None
    obj.matrix_world = matrix
    new = added()
    assert len(new) == 1 and "'Tube'" in new[0] and "'Wave'" in new[0], new
    assert notes() == [*base, *new]  # the same again: gathering changed nothing

    # Unanimated and not the child: nothing to say.
    arm.animation_data.action = None
    assert notes() == base
