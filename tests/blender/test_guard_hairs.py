"""Guard hairs as a hair Curves object in the real Blender: what the bake writes, what a re-bake
replaces, that turning them off removes them, that a failed bake leaves them as they were, and
that Cycles renders them over the shells."""

import json
import shutil
from pathlib import Path

import bpy
import jsonschema
import numpy as np
import pelt
import pytest
from conftest import add_suzanne, datablock_snapshot, small_fur
from test_export_gltf import read_glb
from test_fur_nodes import covered, render, staged_scene

REPO = Path(__file__).resolve().parents[2]


def guard_objects(obj) -> list:
    owned = (o for o in bpy.data.objects if o.get("pelt_owner") == obj.name)
    return [o for o in owned if o.get("pelt_role") == "guard_hairs"]


def pelt_curves() -> list:
    return [c for c in bpy.data.hair_curves if c.get("pelt_role") == "guard_hairs"]


def furred(obj, **fur):
    settings = small_fur(obj, **fur)
    settings.lighting = "KAJIYA_KAY"
    settings.guard_hairs = True
    settings.guard_fraction = 0.1
    return settings


def test_bake_writes_the_guard_hairs_as_curves_on_the_mesh(addon):
    obj = add_suzanne()
    furred(obj, density=1500, tile_size=0.5)
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    [hair] = guard_objects(obj)
    assert hair.type == "CURVES" and hair.parent == obj
    assert hair.matrix_world == obj.matrix_world, "the strands are in the mesh's object space"
    curves = hair.data
    assert curves.surface == obj
    # The same bake in the library gives the strands the object shows.
    options = addon.blender.bake.bake_options(obj)
    mesh = addon.io.bridge.read_object(obj).fur_mesh()
    guard = pelt.Pipeline().bake(mesh, **options).guard_hairs
    assert len(curves.curves) == len(guard["counts"]) > 100
    positions = np.empty(3 * len(curves.points), np.float32)
    curves.position_data.foreach_get("vector", positions)
    np.testing.assert_array_equal(positions.reshape(-1, 3), guard["positions"])
    radii = np.empty(len(curves.points), np.float32)
    curves.attributes["radius"].data.foreach_get("value", radii)
    np.testing.assert_array_equal(radii, guard["radii"])
    assert {"pelt_root_color", "pelt_tip_color"} <= set(curves.attributes.keys())
    [material] = curves.materials
    assert any(n.bl_idname == "ShaderNodeBsdfHairPrincipled" for n in material.node_tree.nodes)
    stages = {s["stage"] for s in json.loads(obj.pelt.last_bake)["stages"]}
    assert "guard_hairs" in stages


def test_a_rebake_replaces_the_strands_and_turning_them_off_removes_them(addon):
    obj = add_suzanne()
    settings = furred(obj, density=1500, tile_size=0.5)
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    [hair] = guard_objects(obj)
    first = len(hair.data.points)
    settings.fur_depth = 2.0 * settings.fur_depth
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert guard_objects(obj) == [hair], "the same object, its strands replaced"
    assert len(pelt_curves()) == 1, "the old strands are gone"
    assert len(hair.data.points) == first
    # Half the strand share draws about half the strands; the rest stay in the shells.
    settings.guard_share = settings.guard_share / 2
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert 0.35 * first < len(hair.data.points) < 0.65 * first
    settings.guard_hairs = False
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert guard_objects(obj) == [] and pelt_curves() == []


def test_a_failed_bake_leaves_the_guard_hairs_as_they_were(addon):
    obj = add_suzanne()
    settings = furred(obj, density=1500, tile_size=0.5)
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    before = datablock_snapshot()
    settings.overcoat_width = (0.0, 0.004)  # a guard hair of width 0 does not show: refused
    with pytest.raises(RuntimeError, match=r"`overcoat.width`: must start above 0 for guard hairs"):
        bpy.ops.pelt.bake()
    assert datablock_snapshot() == before
    assert len(guard_objects(obj)) == 1


def test_cycles_renders_the_guard_hairs_over_the_shells(addon, tmp_path):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=1.0)
    obj = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    settings = furred(obj, density=800, tile_size=0.6, fur_depth=0.3)
    settings.guard_fraction = 0.25
    settings.guard_share = 1.0
    settings.overcoat_width = (0.02, 0.03)
    settings.root_color = (0.05, 0.05, 0.05)
    settings.tip_color = (0.9, 0.9, 0.9)
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    [hair] = guard_objects(obj)
    scene = staged_scene("CYCLES", 96, 4)
    hair.hide_render = True
    shells = render(scene, tmp_path / "shells.png")
    hair.hide_render = False
    hybrid = render(scene, tmp_path / "hybrid.png")
    # The guard hairs stand above the undercoat: more of the frame is covered, and inside the
    # shells' silhouette they change the picture.
    assert np.count_nonzero(covered(hybrid)) > np.count_nonzero(covered(shells))
    inside = covered(shells)
    changed = np.abs(hybrid[..., :3] - shells[..., :3]).max(axis=2) > 0.05
    assert np.count_nonzero(changed & inside) > 0.02 * np.count_nonzero(inside)
    out = REPO / "out"
    out.mkdir(exist_ok=True)
    shutil.copyfile(tmp_path / "hybrid.png", out / "guard_hairs_cycles.png")
    shutil.copyfile(tmp_path / "shells.png", out / "guard_hairs_cycles_without.png")


def test_the_library_returns_the_guard_hairs_and_an_undercoat_volume():
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=1.0)
    mesh = bpy.context.active_object.data
    positions = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", positions)
    mesh.calc_loop_triangles()
    triangles = np.empty(3 * len(mesh.loop_triangles), np.int32)
    mesh.loop_triangles.foreach_get("vertices", triangles)
    triangles = triangles.reshape(-1, 3).astype(np.uint32)
    fur_mesh = pelt.FurMesh(positions.reshape(-1, 3), triangles)
    hair = pelt.HairParams(density=600, guard_fraction=0.2)
    options = {"tile_size": 0.5, "hair": hair, "layers": 8, "resolution": 32, "transfer": False}
    plain = pelt.Pipeline().bake(fur_mesh, **options)
    assert plain.guard_hairs is None
    hybrid = pelt.Pipeline().bake(fur_mesh, guard_hairs=True, **options)
    guard = hybrid.guard_hairs
    counts = guard["counts"]
    assert counts.dtype == np.uint32 and guard["positions"].shape == (int(counts.sum()), 3)
    assert guard["radii"].shape == (int(counts.sum()),) and np.all(guard["radii"] > 0)
    assert guard["root_colors"].shape == guard["tip_colors"].shape == (len(counts), 3)
    assert np.isfinite(guard["positions"]).all()
    # The shells hold the undercoat alone: a fifth of the hair fewer.
    strands = plain.volume["stats"]["strands"], hybrid.volume["stats"]["strands"]
    assert 0.7 * strands[0] < strands[1] < 0.9 * strands[0]
    assert pelt.Pipeline.peak_bytes(guard_hairs=True, **options) > 0
    export_both_modes(hybrid, guard)
    with pytest.raises(pelt.InvalidParameterError, match="`guard_fraction`: is 0"):
        pelt.Pipeline().bake(
            fur_mesh, guard_hairs=True, **{**options, "hair": pelt.HairParams(guard_fraction=0.0)}
        )


def test_the_guard_hairs_follow_the_deformed_surface(addon):
    # A modifier that lifts the whole surface along its normals by 0.3: every root must land on
    # the deformed sphere (radius 1.3), with its strand moved along.
    obj, hair = furred_sphere()
    rest = curve_points(hair)
    roots = curve_roots(hair)
    displace = obj.modifiers.new("Lift", "DISPLACE")
    displace.strength = 0.3
    displace.mid_level = 0.0
    moved = curve_points(hair)
    rest_radius = np.linalg.norm(rest[roots], axis=1)
    moved_radius = np.linalg.norm(moved[roots], axis=1)
    # Roots on the faceted sphere sit within 0.035 of radius 1; lifted by 0.3 along the normals.
    assert np.all(np.abs(moved_radius - rest_radius - 0.3) < 0.03), (moved_radius - rest_radius).min()
    # The whole strand moves with its root: its shape relative to the root is kept.
    tips = np.r_[roots[1:], len(rest)] - 1
    lengths_before = np.linalg.norm(rest[tips] - rest[roots], axis=1)
    lengths_after = np.linalg.norm(moved[tips] - moved[roots], axis=1)
    np.testing.assert_allclose(lengths_after, lengths_before, rtol=1e-3, atol=1e-5)
    obj.modifiers.remove(displace)
    np.testing.assert_allclose(curve_points(hair), rest, atol=1e-6)


def furred_sphere():
    """A unit sphere baked with guard hairs; the sphere and its guard-hair object."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12, radius=1.0)
    obj = bpy.context.active_object
    furred(obj, density=600, tile_size=0.6, fur_depth=0.2)
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    [hair] = guard_objects(obj)
    return obj, hair


def curve_points(hair) -> np.ndarray:
    evaluated = hair.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    points = np.empty(3 * len(evaluated.points), np.float32)
    evaluated.position_data.foreach_get("vector", points)
    return points.reshape(-1, 3)


def curve_roots(hair) -> np.ndarray:
    offsets = np.empty(len(hair.data.curves) + 1, np.int32)
    hair.data.curve_offset_data.foreach_get("value", offsets)
    return offsets[:-1]


def test_the_guard_hairs_turn_with_an_armature(addon):
    # The whole sphere bound to one bone turned 90° about x: every strand turns with it.
    obj, hair = furred_sphere()
    rest = curve_points(hair)
    rig = one_bone_rig()
    group = obj.vertex_groups.new(name="Root")
    group.add(list(range(len(obj.data.vertices))), 1.0, "REPLACE")
    modifier = obj.modifiers.new("Armature", "ARMATURE")
    modifier.object = rig
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.modifier_move_to_index(modifier="Armature", index=0)
    pose = rig.pose.bones["Root"]
    pose.rotation_mode = "XYZ"
    pose.rotation_euler = (np.pi / 2, 0.0, 0.0)
    bpy.context.view_layer.update()
    turned = curve_points(hair)
    # The bone's x axis is the world's: a quarter turn about x takes (x, y, z) to (x, -z, y).
    expected = rest @ np.array([[1, 0, 0], [0, 0, 1], [0, -1, 0]], np.float32)
    np.testing.assert_allclose(turned, expected, atol=2e-3)


def one_bone_rig():
    """An armature of one bone, ``Root``, from the origin up +z."""
    armature = bpy.data.armatures.new("Rig")
    rig = bpy.data.objects.new("Rig", armature)
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    armature.edit_bones.new("Root").tail = (0.0, 0.0, 1.0)
    bpy.ops.object.mode_set(mode="OBJECT")
    return rig


def export_both_modes(asset, guard):
    """The engine file's extension conforms to the published schema and names the strands'
    lines; the geometry file's ribbons import into Blender."""
    out = REPO / "out"
    out.mkdir(exist_ok=True)
    engine, geometry = out / "guard_hairs_engine.glb", out / "guard_hairs_geometry.glb"
    pelt.export_gltf(asset, engine, name="Guarded")
    document, _ = read_glb(engine)
    primitives = document["meshes"][0]["primitives"]
    fur = primitives[0]["extensions"]["PELT_shell_fur"]
    schema = json.loads((REPO / "docs" / "schema" / "PELT_shell_fur.schema.json").read_text())
    jsonschema.validate(fur, schema, cls=jsonschema.Draft202012Validator)
    lines = primitives[fur["guardHairs"]["primitive"]]
    assert lines["mode"] == 1 and document["accessors"][lines["attributes"]["POSITION"]]["count"] == len(
        guard["positions"]
    )
    pelt.export_gltf(asset, geometry, name="Guarded", mode="geometry")
    before = set(bpy.data.meshes)
    assert bpy.ops.import_scene.gltf(filepath=str(geometry)) == {"FINISHED"}
    [mesh] = [m for m in bpy.data.meshes if m not in before]
    # The skin's, the shells' and the fins' vertices, and four a point for the crossed ribbons.
    assert len(mesh.vertices) > 4 * len(guard["positions"])
