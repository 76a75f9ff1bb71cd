"""The preview in the object's pose (real bpy, CPU adapter): an armature or a shape key moves the
fur without a bake, checked against a bake of the posed mesh applied as a mesh of its own; a
modifier that changes the topology leaves the rest shape drawn, and the panel says why."""

import math

import bpy
import numpy as np
import pytest
from conftest import small_fur

RINGS, AROUND = 13, 16


def tube() -> bpy.types.Object:
    """An open tube of radius 0.35 from z = -1 to 1, standing at the origin."""
    z = np.linspace(-1.0, 1.0, RINGS)
    angle = np.linspace(0.0, 2 * math.pi, AROUND, endpoint=False)
    positions = [(0.35 * math.cos(a), 0.35 * math.sin(a), h) for h in z for a in angle]

    def at(ring, k):
        return ring * AROUND + k % AROUND

    cells = [(r, k) for r in range(RINGS - 1) for k in range(AROUND)]
    faces = [(at(r, k), at(r, k + 1), at(r + 1, k + 1), at(r + 1, k)) for r, k in cells]
    mesh = bpy.data.meshes.new("Tube")
    mesh.from_pydata(positions, [], faces)
    obj = bpy.data.objects.new("Tube", mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def furred(obj) -> bpy.types.Object:
    small_fur(obj, fur_depth=0.12)
    bpy.context.view_layer.objects.active = obj
    return obj


def side_camera():
    scene = bpy.context.scene
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (7.0, 0.0, 0.0)
    camera.rotation_euler = (math.pi / 2, 0.0, math.pi / 2)
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 64, 80, 100


def bend_with_armature(obj):
    """Two bones up the tube, the upper half weighted to the upper bone, bent 70° about x."""
    armature = bpy.data.objects.new("Rig", bpy.data.armatures.new("Rig"))
    bpy.context.scene.collection.objects.link(armature)
    bpy.context.view_layer.objects.active = armature
    bpy.ops.object.mode_set(mode="EDIT")
    lower = armature.data.edit_bones.new("Lower")
    lower.head, lower.tail = (0.0, 0.0, -1.0), (0.0, 0.0, 0.0)
    upper = armature.data.edit_bones.new("Upper")
    upper.head, upper.tail, upper.parent = (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), lower
    bpy.ops.object.mode_set(mode="OBJECT")
    heights = np.array([v.co.z for v in obj.data.vertices])
    for name, chosen in (("Lower", heights <= 0.0), ("Upper", heights > 0.0)):
        group = obj.vertex_groups.new(name=name)
        group.add([int(i) for i in np.flatnonzero(chosen)], 1.0, "REPLACE")
    modifier = obj.modifiers.new("Armature", "ARMATURE")
    modifier.object = armature
    armature.pose.bones["Upper"].rotation_mode = "XYZ"
    armature.pose.bones["Upper"].rotation_euler = (math.radians(70.0), 0.0, 0.0)
    bpy.context.view_layer.objects.active = obj
    return armature


def lean_with_shape_key(obj):
    """A shape key that leans the tube sideways, growing with height, at full value."""
    obj.shape_key_add(name="Basis")
    key = obj.shape_key_add(name="Lean")
    for point in key.data:
        point.co.y += 0.3 * (point.co.z + 1.0) ** 2
    key.value = 1.0


def render() -> np.ndarray:
    assert bpy.ops.pelt.render_preview() == {"FINISHED"}
    image = next(im for im in bpy.data.images if im.get("pelt_role") == "preview")
    pixels = np.empty(image.size[0] * image.size[1] * 4, np.float32)
    image.pixels.foreach_get(pixels)
    return pixels.reshape(image.size[1], image.size[0], 4)


def overlap(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of the covered pixels."""
    a, b = a[..., 3] > 0.5, b[..., 3] > 0.5
    return float((a & b).sum() / (a | b).sum())


@pytest.mark.parametrize("deformer", ["armature", "shape_key"])
def test_preview_follows_the_pose_without_a_bake(addon, deformer):
    from addon.blender import preview

    side_camera()
    obj = furred(tube())
    rest = render()
    cached = preview._PREVIEWS[obj.session_uid]
    before = cached[0].uploads
    if deformer == "armature":
        bend_with_armature(obj)
    else:
        lean_with_shape_key(obj)
    posed = render()

    # The same preview, re-sent its vertices only: no bake ran, no texture went up again.
    assert preview._PREVIEWS[obj.session_uid] == cached
    after = cached[0].uploads
    assert after["pose_bytes"] > before["pose_bytes"]
    assert after["texture_bytes"] == before["texture_bytes"]

    # The posed mesh applied and baked as an object of its own: the same silhouette.
    depsgraph = bpy.context.evaluated_depsgraph_get()
    applied = bpy.data.objects.new("Applied", bpy.data.meshes.new_from_object(obj.evaluated_get(depsgraph)))
    bpy.context.scene.collection.objects.link(applied)
    reference = render_of(furred(applied))
    assert overlap(posed, reference) > 0.9, overlap(posed, reference)
    assert overlap(rest, reference) < 0.8, overlap(rest, reference)
    assert np.isfinite(posed).all()


def render_of(obj) -> np.ndarray:
    bpy.context.view_layer.objects.active = obj
    return render()


def test_after_bake_the_pose_is_read_under_pelts_own_fur_modifier(addon):
    # Bake adds Pelt's Geometry Nodes fur (skin, shells, fins) after the armature: the evaluated
    # mesh has more vertices than the bake, the skin's first.
    from addon.blender import geonodes, pose

    side_camera()
    obj = furred(tube())
    bend_with_armature(obj)
    obj.modifiers["Armature"].show_viewport = False
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert geonodes.find_modifier(obj) is not None
    rest = render()
    obj.modifiers["Armature"].show_viewport = True
    posed = render()
    assert obj.session_uid not in pose.NOTES
    assert overlap(posed, rest) < 0.8
    # The skin's rows read alone are those of the whole evaluated mesh's read.
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    skin = len(obj.data.vertices)
    assert len(evaluated.vertices) > 2 * skin
    whole = addon.io.bridge.read_positions(evaluated)
    assert np.array_equal(pose.first_positions(evaluated, skin), whole[:skin])
    assert np.array_equal(pose.first_positions(evaluated, 7), whole[:7])
    # A Subdivision before Pelt's fur may change the topology: the rest shape, and why.
    subdivision = obj.modifiers.new("Subdivision", "SUBSURF")
    bpy.ops.object.modifier_move_to_index(modifier=subdivision.name, index=0)
    assert np.array_equal(render(), rest)
    assert "Subdivision" in pose.NOTES[obj.session_uid]


def test_a_modifier_that_changes_the_topology_keeps_the_rest_shape_and_says_why(addon):
    from addon.blender import panels, pose

    side_camera()
    obj = furred(tube())
    rest = render()
    obj.modifiers.new("Subdivision", "SUBSURF")
    assert np.array_equal(render(), rest)
    note = pose.NOTES[obj.session_uid]
    assert "topology" in note and "vertices evaluated" in note
    assert panels.pose.NOTES is pose.NOTES
    # A pose after it applies again, and the note goes.
    obj.modifiers.clear()
    assert not pose.moved(obj)
    lean_with_shape_key(obj)
    assert overlap(render(), rest) < 0.9
    assert obj.session_uid not in pose.NOTES
    # Back at the basis, the rest shape.
    obj.data.shape_keys.key_blocks["Lean"].value = 0.0
    assert np.allclose(render(), rest, atol=2e-3)
