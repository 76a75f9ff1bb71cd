"""A furred, armature-deformed character through File > Export and back through Blender's own glTF
importer: the animation plays on the imported armature and the fur follows it, each vertex where
Blender put the original skin in the same frame (the shells within the fur's height of it), and
the placement of unskinned objects survives the Y-up turn. Also ``pelt.export_gltf``'s own
checks of skinning arguments."""

import json
import math
import os
import struct
from pathlib import Path

import bpy
import numpy as np
import pelt
import pytest
from conftest import small_fur

RINGS, AROUND, SPACING = 21, 12, 0.1  # a tube 2 units tall
FIRST, LAST = 1, 9


def tube(name: str) -> bpy.types.Object:
    angle = np.arange(AROUND) * (2 * math.pi / AROUND)
    positions = [(0.3 * math.cos(a), 0.3 * math.sin(a), r * SPACING) for r in range(RINGS) for a in angle]
    faces = [
        (
            r * AROUND + k,
            r * AROUND + (k + 1) % AROUND,
            (r + 1) * AROUND + (k + 1) % AROUND,
            (r + 1) * AROUND + k,
        )
        for r in range(RINGS - 1)
        for k in range(AROUND)
    ]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(positions, [], faces)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def character():
    """A tube on a two-bone armature (moved and turned in the world), the upper bone bending
    60 degrees over frames 1 to 9; weights blend across the middle."""
    arm_data = bpy.data.armatures.new("Rig")
    arm = bpy.data.objects.new("Rig", arm_data)
    bpy.context.scene.collection.objects.link(arm)
    bpy.context.view_layer.objects.active = arm
    bpy.ops.object.mode_set(mode="EDIT")
    lower = arm_data.edit_bones.new("Lower")
    lower.head, lower.tail = (0, 0, 0), (0, 0, 1)
    upper = arm_data.edit_bones.new("Upper")
    upper.head, upper.tail = (0, 0, 1), (0, 0, 2)
    upper.parent, upper.use_connect = lower, True
    bpy.ops.object.mode_set(mode="OBJECT")
    arm.location = (1.0, 2.0, 0.5)
    arm.rotation_euler = (0.0, 0.0, math.radians(30))

    body = tube("Body")
    body.parent = arm
    body.modifiers.new("Armature", "ARMATURE").object = arm
    z = np.repeat(np.arange(RINGS) * SPACING, AROUND)
    up = np.clip((z - 0.8) / 0.4, 0.0, 1.0)
    for name, weight in (("Lower", 1.0 - up), ("Upper", up)):
        group = body.vertex_groups.new(name=name)
        for value in np.unique(weight):
            if value > 0:
                group.add(np.flatnonzero(weight == value).tolist(), float(value), "REPLACE")

    bone = arm.pose.bones["Upper"]
    bone.rotation_mode = "QUATERNION"
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = FIRST, LAST
    for frame, angle in ((FIRST, 0.0), (LAST, math.radians(60))):
        bone.rotation_quaternion = (math.cos(angle / 2), math.sin(angle / 2), 0.0, 0.0)
        bone.keyframe_insert("rotation_quaternion", frame=frame)
    scene.frame_set(FIRST)
    return arm, body


def world_vertices(obj) -> np.ndarray:
    """``obj``'s evaluated vertices in the world, (V, 3)."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        co = np.empty(3 * len(mesh.vertices), np.float32)
        mesh.vertices.foreach_get("co", co)
    finally:
        evaluated.to_mesh_clear()
    matrix = np.array(obj.matrix_world)
    return co.reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3]


def nearest(points: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Distance from each point to the nearest target (brute force)."""
    return np.sqrt(((points[:, None, :] - targets[None, :, :]) ** 2).sum(-1).min(axis=1))


def test_skinned_fur_round_trips_through_blenders_importer(addon, tmp_path):
    _, body = character()
    settings = small_fur(body, tile_size=0.4, fur_depth=0.05)
    prop = tube("Prop")
    prop.location = (-2.0, 0.5, 1.0)
    prop.rotation_euler = (math.radians(40), 0.0, 0.0)
    small_fur(prop, tile_size=0.4, fur_depth=0.05)
    # The prop has an action of its own: it rises and turns.
    prop.keyframe_insert("location", frame=FIRST)
    prop.keyframe_insert("rotation_euler", frame=FIRST)
    prop.location.z += 1.5
    prop.rotation_euler.z = math.radians(70)
    prop.keyframe_insert("location", frame=LAST)
    prop.keyframe_insert("rotation_euler", frame=LAST)
    scene = bpy.context.scene
    posed, prop_world = {}, {}
    for frame in (FIRST, LAST):
        scene.frame_set(frame)
        posed[frame] = world_vertices(body)
        prop_world[frame] = world_vertices(prop)
    scene.frame_set(FIRST)
    reach = 1.5 * settings.fur_depth * 1.5  # length 1 along a combed normal, with margin

    path = tmp_path / "character.glb"
    bpy.ops.object.select_all(action="DESELECT")
    body.select_set(True)
    prop.select_set(True)
    assert bpy.ops.pelt.export(filepath=str(path), mode="GEOMETRY", png=False, ktx2=False) == {"FINISHED"}
    # Exporting moved nothing in the file: the frame and the pose are as they were.
    assert scene.frame_current == FIRST
    assert np.allclose(world_vertices(body), posed[FIRST], atol=1e-6)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    assert bpy.ops.import_scene.gltf(filepath=str(path)) == {"FINISHED"}
    scene = bpy.context.scene
    imported = {o.name: o for o in bpy.data.objects}
    body, prop = imported["Body"], imported["Prop"]
    armatures = [o for o in bpy.data.objects if o.type == "ARMATURE"]
    assert len(armatures) == 1
    action = armatures[0].animation_data.action
    first, last = (round(f) for f in action.frame_range)
    assert last - first == LAST - FIRST

    skin_count = len(posed[FIRST])  # at least: the skin primitive holds the split vertices
    for frame, original in ((first, posed[FIRST]), (last, posed[LAST])):
        scene.frame_set(frame)
        got = world_vertices(body)
        distance = nearest(got, original)
        # The skin primitive comes first: exactly on Blender's own skinned surface.
        assert distance[:skin_count].max() < 1e-3, (frame, distance[:skin_count].max())
        # Shells and fins: within the fur's height of it, so they bent with it.
        assert distance.max() < reach, (frame, distance.max())
    # A control: the last frame is far from the first, so the checks above could fail.
    assert nearest(got[:skin_count], posed[FIRST]).max() > 0.3
    # The prop moves as it moved (skin vertices), turned back from Y-up by the importer; its
    # action may come in as an NLA strip when it is not the file's first animation.
    data = prop.animation_data
    assert data is not None, "the prop's own action was exported"
    if data.action is None:
        data.action = next(s.action for t in data.nla_tracks for s in t.strips)
    for frame, original in prop_world.items():
        scene.frame_set(first + frame - FIRST)
        got = world_vertices(prop)[: len(original)]
        assert nearest(got, original).max() < 1e-3, frame
    assert nearest(prop_world[LAST], prop_world[FIRST]).max() > 1.0


def test_export_gltf_checks_its_skinning_and_material_arguments(tmp_path):
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.2]], np.float32)
    triangles = np.array([[0, 1, 2], [1, 3, 2]], np.uint32)
    asset = pelt.Pipeline().bake(
        pelt.FurMesh(positions, triangles), tile_size=0.5, layers=3, resolution=16, fin_size=(16, 8)
    )
    skeleton = {"names": ["Root"], "parents": [-1], "rest": np.eye(4)[None]}
    skin = {"skeleton": 0, "joints": np.zeros((4, 1), np.uint32), "weights": np.ones((4, 1), np.float32)}
    path = tmp_path / "x.glb"
    eyes, both = {"name": "Eyes", "base_color": [0.1, 0.1, 0.1, 1.0]}, [0, 0]
    half_turn = np.diag([1.0, -1.0, -1.0, 1.0])
    turn = {"name": "Turn", "times": [0.0, 1.0], "poses": np.stack([np.eye(4), half_turn])}
    assert pelt.export_gltf(asset, path, animations=turn) == [None]
    assert pelt.export_gltf(asset, path, skin=skin, skeletons=[skeleton]) == [
        {"vertices": 4, "reduced": 0, "renormalized": 0}
    ]
    bad = [
        ({"skin": {**skin, "joints": np.ones((4, 1), np.uint32)}}, "joints"),
        ({"skin": {**skin, "weights": np.zeros((4, 1))}}, "weights"),
        ({"skin": {**skin, "weights": np.ones((3, 1))}}, "weights"),
        ({"skin": {**skin, "joints": -np.ones((4, 1), np.int64)}}, "joints"),
        ({"skin": skin, "skeletons": [{**skeleton, "parents": [3]}]}, "parent"),
        ({"skin": skin, "skeletons": [{**skeleton, "rest": np.zeros((1, 4, 4))}]}, "rest"),
        ({"skin": skin, "skeletons": []}, "skeleton"),
        ({"transform": np.full((4, 4), np.nan)}, "transform"),
        ({"transform": [np.eye(4), np.eye(4)]}, "transform"),
        ({"materials": {"slots": [eyes], "triangle_slot": [0]}}, r"materials\.triangle_slot"),
        ({"materials": {"slots": [eyes], "triangle_slot": [0, 1]}}, r"materials\.triangle_slot\[1\]"),
        ({"materials": {"slots": [{**eyes, "base_color": [2, 0, 0]}], "triangle_slot": both}}, "base_color"),
        ({"materials": {"slots": [{**eyes, "base_color": [2, 0, 0, 1]}], "triangle_slot": both}}, "base"),
        ({"materials": {"slots": [{**eyes, "roughness": -1}], "triangle_slot": both}}, "roughness"),
        ({"materials": {"slots": [{"name": ""}], "triangle_slot": both}}, r"slots\[0\]\.name"),
        ({"materials": {"slots": [eyes]}}, "triangle_slot"),
        # Found by the fuzz: a number where a sequence goes raised an unnamed TypeError.
        ({"materials": {"slots": 0.0, "triangle_slot": both}}, r"materials\.slots"),
        ({"animations": [5.0]}, r"animations\[0\]"),
        ({"skeletons": 1.5, "skin": None}, "skeletons"),
        ({"animations": {**turn, "times": [1.0, 0.5]}}, r"animations\[0\]\.times"),
        ({"animations": [{**turn, "poses": np.eye(4)[None]}]}, r"animations\[0\]\.poses"),
        ({"animations": turn, "skin": skin}, "animations"),
    ]
    for arguments, name in bad:
        arguments.setdefault("skeletons", [skeleton])
        with pytest.raises(pelt.InvalidParameterError, match=name):
            pelt.export_gltf(asset, path, **arguments)
    # A failed export leaves the earlier file as it was.
    assert path.read_bytes()[:4] == b"glTF"


def test_user_flow_mirrored_armature_character_baked_posed_exported_and_reimported(addon, tmp_path):
    """Half a character with a Mirror at the top of its stack, an armature after it and a second
    material: Bake applies the Mirror, Render Preview draws the pose, the export carries the
    skeleton and the action, and Blender's importer plays it back with the fur on both halves."""
    import bmesh

    _, body = character()
    bm = bmesh.new()
    bm.from_mesh(body.data)
    bmesh.ops.delete(bm, geom=[v for v in bm.verts if v.co.x < -1e-4], context="VERTS")
    bm.to_mesh(body.data)
    bm.free()
    mirror = body.modifiers.new("Mirror", "MIRROR")
    bpy.context.view_layer.objects.active = body
    bpy.ops.object.modifier_move_to_index(modifier=mirror.name, index=0)
    body.data.materials.append(bpy.data.materials.new("Skin"))
    eyes = bpy.data.materials.new("Eyes")
    eye_color = (0.02, 0.03, 0.2, 1.0)
    eyes.diffuse_color = eye_color
    nodes = eyes.node_tree.nodes if eyes.node_tree else []
    principled = next((n for n in nodes if n.type == "BSDF_PRINCIPLED"), None)
    if principled is not None:
        principled.inputs["Base Color"].default_value = eye_color
    body.data.materials.append(eyes)
    # The top two rows are the "eyes": their own material, painted bald, so they keep it.
    top = np.array([p.center.z > 1.8 for p in body.data.polygons], np.int32)
    body.data.polygons.foreach_set("material_index", top)
    z = np.array([v.co.z for v in body.data.vertices])
    length = body.data.attributes.new("pelt_length", "FLOAT", "POINT")
    length.data.foreach_set("value", np.where(z > 1.75, 0.0, 1.0).astype(np.float32))
    small_fur(body, tile_size=0.4, fur_depth=0.05)
    half = len(body.data.vertices)

    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert body.modifiers[0].type == "ARMATURE"
    assert len(body.data.vertices) > 1.6 * half  # the seam's vertices merge
    assert [m.name for m in body.data.materials] == ["Skin", "Eyes"]
    eye_triangles = sum(len(p.vertices) - 2 for p in body.data.polygons if p.material_index == 1)
    assert eye_triangles == 2 * 2 * AROUND  # both rows, both halves, two triangles a quad

    camera_data = bpy.data.cameras.new("Camera")
    camera = bpy.data.objects.new("Camera", camera_data)
    bpy.context.scene.collection.objects.link(camera)
    camera.location = (1.0, -4.0, 1.5)
    camera.rotation_euler = (math.radians(85), 0.0, 0.0)
    scene = bpy.context.scene
    scene.camera = camera
    scene.render.resolution_x = scene.render.resolution_y = 96
    frames = {}
    for frame in (FIRST, LAST):
        scene.frame_set(frame)
        assert bpy.ops.pelt.render_preview() == {"FINISHED"}
        image = bpy.data.images["Pelt Preview"]
        pixels = np.empty(4 * image.size[0] * image.size[1], np.float32)
        image.pixels.foreach_get(pixels)
        frames[frame] = pixels.reshape(image.size[1], image.size[0], 4)
    from addon.blender import pose

    assert body.session_uid not in pose.NOTES
    covered = [f[..., 3] > 0.5 for f in frames.values()]
    # The pose moved the fur in the preview.
    assert (covered[0] != covered[1]).sum() > 50

    # Pelt's fur modifier joins the skin first: its rows are the mesh's.
    posed = {}
    for frame in (FIRST, LAST):
        scene.frame_set(frame)
        posed[frame] = world_vertices(body)[: len(body.data.vertices)]
    scene.frame_set(FIRST)
    path = tmp_path / "character.glb"
    bpy.ops.object.select_all(action="DESELECT")
    body.select_set(True)
    assert bpy.ops.pelt.export(filepath=str(path), mode="GEOMETRY", png=False, ktx2=False) == {"FINISHED"}
    # The engine file the three.js runtime's browser test draws (make check-three).
    engine = Path(os.environ.get("PELT_THREE_OUT") or tmp_path) / "blender_character.glb"
    assert bpy.ops.pelt.export(filepath=str(engine), mode="ENGINE", png=False, ktx2=False) == {"FINISHED"}
    data = engine.read_bytes()
    document = json.loads(data[20 : 20 + struct.unpack_from("<I", data, 12)[0]])
    assert "PELT_shell_fur" in document["extensionsUsed"]
    assert "Eyes" in [m["name"] for m in document["materials"]]

    bpy.ops.wm.read_factory_settings(use_empty=True)
    assert bpy.ops.import_scene.gltf(filepath=str(path)) == {"FINISHED"}
    imported = bpy.data.objects["Body"]
    # The eyes came back as eyes: their own material on their triangles, with its color.
    slots = [m.name for m in imported.data.materials]
    assert "Eyes" in slots, slots
    eye_slot = slots.index("Eyes")
    assert sum(1 for p in imported.data.polygons if p.material_index == eye_slot) == eye_triangles
    node = next(n for n in imported.data.materials[eye_slot].node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    np.testing.assert_allclose(node.inputs["Base Color"].default_value[:], eye_color, atol=1e-3)
    action = next(o for o in bpy.data.objects if o.type == "ARMATURE").animation_data.action
    first, last = (round(f) for f in action.frame_range)
    # The skin primitive's vertices (the mesh split at patch seams) come first.
    data = path.read_bytes()
    document = json.loads(data[20 : 20 + struct.unpack_from("<I", data, 12)[0]])
    position = document["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
    skin_count = document["accessors"][position]["count"]
    for frame, original in ((first, posed[FIRST]), (last, posed[LAST])):
        bpy.context.scene.frame_set(frame)
        got = world_vertices(imported)[:skin_count]
        assert nearest(got, original).max() < 1e-3, frame
        # Every vertex of both halves came back.
        assert nearest(original, got).max() < 1e-3, frame
