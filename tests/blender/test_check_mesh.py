"""``pelt.check_mesh`` on real Blender meshes, checked against Blender's own counts (bmesh)."""

import json

import bmesh
import bpy
import numpy as np
import pytest
from conftest import add_suzanne, datablock_snapshot


def triangulated_reference(mesh):
    """Counts of the mesh triangulated by its loop triangles, computed by Blender itself (a new
    mesh built from the triangles, read through bmesh), independent of Pelt."""
    mesh.calc_loop_triangles()
    coords = [tuple(v.co) for v in mesh.vertices]
    triangles = [tuple(t.vertices) for t in mesh.loop_triangles]
    triangulated = bpy.data.meshes.new("reference")
    triangulated.from_pydata(coords, [], triangles)
    bm = bmesh.new()
    bm.from_mesh(triangulated)
    bpy.data.meshes.remove(triangulated)
    bm.verts.ensure_lookup_table()
    # connected components by flood fill over edges
    seen, components = set(), 0
    for start in bm.verts:
        if start.index in seen or not start.link_faces:
            continue
        components += 1
        stack = [start]
        seen.add(start.index)
        while stack:
            v = stack.pop()
            for e in v.link_edges:
                w = e.other_vert(v)
                if w.index not in seen:
                    seen.add(w.index)
                    stack.append(w)
    reference = {
        "vertices": len(bm.verts),
        "faces": len(bm.faces),
        "edges": len(bm.edges),
        "boundary_edges": sum(e.is_boundary for e in bm.edges),
        "non_manifold_edges": sum(len(e.link_faces) > 2 for e in bm.edges),
        "components": components,
        "surface_area": sum(f.calc_area() for f in bm.faces),
    }
    bm.free()
    return reference


def test_suzanne_statistics_match_blender(addon):
    obj = add_suzanne()
    mesh = obj.data
    assert bpy.ops.pelt.check_mesh() == {"FINISHED"}
    stats = json.loads(obj.pelt.last_check)
    reference = triangulated_reference(mesh)
    mesh.calc_loop_triangles()
    assert stats["vertices"] == len(mesh.vertices) == reference["vertices"]
    assert stats["faces"] == len(mesh.loop_triangles) == reference["faces"]
    assert stats["edges"] == reference["edges"]
    assert stats["boundary_edges"] == reference["boundary_edges"]
    assert stats["non_manifold_edges"] == reference["non_manifold_edges"]
    assert stats["components"] == reference["components"] == 3  # head and two eyes
    assert stats["loose_vertices"] == 0
    # Suzanne's quads are not planar, so compare with the area of the triangles, not the polygons
    assert stats["surface_area"] == pytest.approx(reference["surface_area"], rel=1e-5)
    coords = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", coords)
    coords = coords.reshape(-1, 3)
    np.testing.assert_allclose(stats["bbox_min"], coords.min(0))
    np.testing.assert_allclose(stats["bbox_max"], coords.max(0))


def test_check_reads_pelt_point_attributes(addon):
    obj = add_suzanne()
    mesh = obj.data
    n = len(mesh.vertices)
    mesh.attributes.new("pelt_color", "FLOAT_COLOR", "POINT").data.foreach_set("color", np.ones(4 * n))
    mesh.attributes.new("pelt_comb", "FLOAT_VECTOR", "POINT").data.foreach_set("vector", np.zeros(3 * n))
    length = np.linspace(0, 2, n)
    mesh.attributes.new("pelt_length", "FLOAT", "POINT").data.foreach_set("value", length)
    from addon.io import bridge

    fur = bridge.fur_mesh_from_object(obj)
    np.testing.assert_allclose(fur.length, length, rtol=1e-6)
    assert fur.color.shape == (n, 4) and fur.comb.shape == (n, 3) and fur.normals_given
    normals = np.empty(3 * n, np.float32)
    mesh.vertex_normals.foreach_get("vector", normals)
    np.testing.assert_allclose(fur.normals, normals.reshape(-1, 3), atol=1e-6)
    assert bpy.ops.pelt.check_mesh() == {"FINISHED"}


def test_check_in_edit_mode_sees_the_edits(addon):
    obj = add_suzanne()
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.delete(type="VERT")
    bpy.ops.mesh.primitive_cube_add()
    assert bpy.ops.pelt.check_mesh() == {"FINISHED"}
    assert json.loads(obj.pelt.last_check)["vertices"] == 8
    bpy.ops.object.mode_set(mode="OBJECT")


def test_successful_check_changes_only_the_pelt_settings(addon):
    obj = add_suzanne()
    before = datablock_snapshot()
    assert bpy.ops.pelt.check_mesh() == {"FINISHED"}
    after = datablock_snapshot()
    changed = {key for key in before if before[key] != after.get(key)}
    assert changed == {f"object:{obj.name}"}


def test_panel_and_properties_are_registered(addon):
    assert hasattr(bpy.types, "VIEW3D_PT_pelt")
    assert bpy.types.VIEW3D_PT_pelt.bl_category == "Pelt"
    obj = add_suzanne()
    assert obj.pelt.enabled is False
    obj.pelt.enabled = True
    assert obj.pelt.enabled is True
