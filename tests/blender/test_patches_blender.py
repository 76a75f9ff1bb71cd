"""Lapped patches written into real Blender meshes: ``PeltUV`` and ``pelt_patch``."""

import bpy
import numpy as np
import pelt
import pytest
from conftest import add_suzanne


def loop_uvs(mesh, name="PeltUV"):
    layer = mesh.uv_layers[name]
    uv = np.empty(2 * len(mesh.loops), np.float32)
    layer.data.foreach_get("uv", uv)
    return uv.reshape(-1, 2)


def face_patches(mesh):
    values = np.empty(len(mesh.polygons), np.int32)
    mesh.attributes["pelt_patch"].data.foreach_get("value", values)
    return values


def test_quad_mesh_gets_one_uv_per_loop_and_a_patch_per_face(addon):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=12, y_subdivisions=9, size=2.0)
    mesh = bpy.context.active_object.data
    arrays = addon.io.bridge.read_mesh(mesh)
    patches = pelt.build_patches(arrays.fur_mesh(), tile_size=0.5, seed=3)
    addon.io.bridge.write_patches(mesh, patches)

    assert mesh.uv_layers.get("PeltUV") is not None
    uv = loop_uvs(mesh)
    assert uv.shape == (len(mesh.loops), 2) and np.isfinite(uv).all()
    attribute = mesh.attributes["pelt_patch"]
    assert (attribute.domain, attribute.data_type) == ("FACE", "INT")
    ids = face_patches(mesh)
    assert ids.min() >= 0 and len(np.unique(ids)) == patches.patch_count
    # Each loop's UV is the one Pelt gave the corner of the triangle holding that loop.
    mesh.calc_loop_triangles()
    loops = np.empty(3 * len(mesh.loop_triangles), np.int64)
    mesh.loop_triangles.foreach_get("loops", loops)
    assert np.allclose(uv[loops], np.asarray(patches.uv).reshape(-1, 2))
    # A tile is 0.5 units: the flat 2 by 2 grid spans about four tiles of UV along the hair.
    extent = uv.max(axis=0) - uv.min(axis=0)
    assert 3.0 < extent.max() < 5.0


def test_suzanne_is_fully_covered_without_flips(addon):
    obj = add_suzanne()
    arrays = addon.io.bridge.read_mesh(obj.data)
    patches = pelt.build_patches(arrays.fur_mesh(), tile_size=0.1, seed=1)
    quality = patches.quality
    assert quality["coverage"] == pytest.approx(1.0)
    assert quality["flipped_faces"] == 0
    # The quality bar on Suzanne: hair within 3° of the field, little stretch.
    assert quality["mean_alignment_deg"] <= 3.0
    assert quality["stretch_within_fraction"] >= 0.95
    addon.io.bridge.write_patches(obj.data, patches)
    assert np.isfinite(loop_uvs(obj.data)).all()
    assert (face_patches(obj.data) >= 0).all()


def test_patches_of_another_mesh_change_nothing(addon):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=4, y_subdivisions=4)
    small = bpy.context.active_object.data
    patches = pelt.build_patches(addon.io.bridge.read_mesh(small).fur_mesh(), tile_size=0.5)
    obj = add_suzanne()
    with pytest.raises(pelt.InvalidMeshError, match="bake them again"):
        addon.io.bridge.write_patches(obj.data, patches)
    assert obj.data.uv_layers.get("PeltUV") is None
    assert obj.data.attributes.get("pelt_patch") is None


def test_subdivided_suzanne_over_100k_triangles(addon):
    obj = add_suzanne()
    modifier = obj.modifiers.new("Subdivision", "SUBSURF")
    modifier.levels = 4
    bpy.ops.object.modifier_apply(modifier=modifier.name)
    arrays = addon.io.bridge.read_mesh(obj.data)
    assert len(arrays.triangles) >= 100_000
    patches = pelt.build_patches(arrays.fur_mesh(), tile_size=0.05, seed=1)
    quality = patches.quality
    print(
        f"subdivided Suzanne: {len(arrays.triangles)} triangles, {quality['patch_count']} patches, "
        f"seams {quality['seam_length_fraction']:.3f}, alignment {quality['mean_alignment_deg']:.2f} deg"
    )
    assert quality["coverage"] == pytest.approx(1.0)
    assert quality["flipped_faces"] == 0
    assert np.isfinite(np.asarray(patches.uv)).all()
