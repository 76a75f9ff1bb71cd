"""Bake applies the modifiers that change the mesh at the top of the stack (Mirror, Subdivision),
so the whole mesh gets fur and the armature keeps deforming what was baked; a bake that fails, or
a stack Pelt cannot apply, leaves the object as it was."""

import bmesh
import bpy
import numpy as np
import pytest
from conftest import add_suzanne, datablock_snapshot, small_fur


def mirrored_suzanne():
    """Suzanne's left half, mirrored and subdivided at the top of the stack, then an armature."""
    obj = add_suzanne()
    mesh = obj.data
    # Keep the half with x >= 0 (and the seam): the Mirror makes the other half.
    bm = bmesh.new()
    bm.from_mesh(mesh)
    bmesh.ops.delete(bm, geom=[v for v in bm.verts if v.co.x < -1e-4], context="VERTS")
    bm.to_mesh(mesh)
    bm.free()
    obj.modifiers.new("Mirror", "MIRROR")
    obj.modifiers.new("Subdivision", "SUBSURF").levels = 1
    arm_data = bpy.data.armatures.new("Rig")
    arm = bpy.data.objects.new("Rig", arm_data)
    bpy.context.scene.collection.objects.link(arm)
    obj.modifiers.new("Armature", "ARMATURE").object = arm
    bpy.context.view_layer.objects.active = obj
    return obj


def evaluated_vertex_count(obj) -> int:
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        return len(mesh.vertices)
    finally:
        evaluated.to_mesh_clear()


def test_bake_applies_mirror_and_subdivision_and_keeps_the_armature(addon):
    obj = mirrored_suzanne()
    small_fur(obj)
    half = len(obj.data.vertices)
    # What the viewport shows before the bake (the armature has no bones: it moves nothing).
    shown = evaluated_vertex_count(obj)
    assert shown > 2 * half
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    names = [m.name for m in obj.modifiers]
    assert "Mirror" not in names and "Subdivision" not in names
    assert names[0] == "Armature"
    # The mesh is the one that showed, with the fur's UVs on every corner, mirrored side included.
    assert len(obj.data.vertices) == shown
    uv = obj.data.uv_layers["PeltUV"].data
    values = np.empty(2 * len(uv), np.float32)
    uv.foreach_get("uv", values)
    assert np.isfinite(values).all()
    co = np.empty(3 * len(obj.data.vertices), np.float32)
    obj.data.vertices.foreach_get("co", co)
    assert co.reshape(-1, 3)[:, 0].min() < -0.5  # the mirrored half is real geometry now
    # Pelt's fur modifier reads the mesh as baked: its first rows are the skin.
    assert evaluated_vertex_count(obj) > len(obj.data.vertices)
    # The applied mesh took the old one's name; the old one is gone.
    assert obj.data.name == "Suzanne"
    assert len(bpy.data.meshes) == 1


def test_a_failed_bake_leaves_the_modifiers_and_the_mesh(addon):
    obj = mirrored_suzanne()
    small_fur(obj)
    obj.data.vertices[3].co.z = float("nan")
    before = datablock_snapshot()
    modifiers = [m.name for m in obj.modifiers]
    with pytest.raises(RuntimeError, match="NaN"):
        bpy.ops.pelt.bake()
    assert datablock_snapshot() == before
    assert [m.name for m in obj.modifiers] == modifiers


def test_a_modifier_that_changes_the_mesh_after_the_armature_is_refused(addon):
    obj = mirrored_suzanne()
    small_fur(obj)
    obj.modifiers.new("Late Mirror", "MIRROR")
    before = datablock_snapshot()
    with pytest.raises(RuntimeError, match=r"'Late Mirror' \(Mirror\) changes the mesh after 'Armature'"):
        bpy.ops.pelt.bake()
    assert datablock_snapshot() == before
