"""Bad input through the operator: CANCELLED, a report that names the problem, and every datablock
left exactly as it was. (bpy turns an operator's ERROR report into a RuntimeError carrying the
report text; the unchanged snapshot shows nothing was written, unlike a FINISHED run, which stores
the statistics.)"""

import math

import bpy
import numpy as np
import pytest
from conftest import add_suzanne, datablock_snapshot


def make_active(obj):
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)


def expect_cancelled(fragment):
    before = datablock_snapshot()
    with pytest.raises(RuntimeError, match=fragment):
        bpy.ops.pelt.check_mesh()
    assert datablock_snapshot() == before


def test_nan_vertex(addon):
    obj = add_suzanne()
    obj.data.vertices[17].co = (0.0, math.nan, 0.0)
    expect_cancelled(r"`positions` row 17 component 1 is NaN")


def test_out_of_range_index(addon):
    # Blender lets a script store a corner that names a vertex the mesh does not have (an invalid
    # mesh, as broken importers make); Pelt must refuse it before anything reads past the end.
    mesh = bpy.data.meshes.new("broken")
    mesh.vertices.add(3)
    mesh.vertices.foreach_set("co", np.array([0, 0, 0, 1, 0, 0, 0, 1, 0], np.float32))
    mesh.loops.add(3)
    mesh.loops.foreach_set("vertex_index", np.array([0, 1, 7], np.int32))
    mesh.polygons.add(1)
    mesh.polygons.foreach_set("loop_start", np.array([0], np.int32))
    obj = bpy.data.objects.new("broken", mesh)
    bpy.context.collection.objects.link(obj)
    make_active(obj)
    expect_cancelled(r"triangle 0 corner 2 refers to vertex 7, but the mesh has 3 vertices")


def test_attribute_of_the_wrong_length(addon):
    obj = add_suzanne()
    # one value per face corner instead of one per vertex
    obj.data.attributes.new("pelt_length", "FLOAT", "CORNER")
    expect_cancelled(r"'pelt_length'.*CORNER.*1968 values.*507 vertices")


def test_attribute_of_the_wrong_type(addon):
    obj = add_suzanne()
    obj.data.attributes.new("pelt_comb", "FLOAT", "POINT")
    expect_cancelled(r"'pelt_comb'.*FLOAT_VECTOR")


def test_empty_mesh(addon):
    obj = bpy.data.objects.new("empty", bpy.data.meshes.new("empty"))
    bpy.context.collection.objects.link(obj)
    make_active(obj)
    expect_cancelled(r"the mesh has no vertices")


def test_mesh_without_faces(addon):
    mesh = bpy.data.meshes.new("points")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0)], [(0, 1)], [])
    obj = bpy.data.objects.new("points", mesh)
    bpy.context.collection.objects.link(obj)
    make_active(obj)
    expect_cancelled(r"the mesh has no triangles")
