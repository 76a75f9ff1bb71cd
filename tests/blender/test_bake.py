"""The bake operator in the real Blender: what it writes, what a re-bake skips, and that a failed
or cancelled bake leaves the scene exactly as it was."""

import json
import time

import bpy
import numpy as np
import pelt
import pytest
from conftest import add_suzanne, datablock_snapshot, small_fur


def furred_suzanne(*, prt: bool = False):
    obj = add_suzanne()
    settings = small_fur(obj, density=2000, tile_size=0.5)
    settings.lighting = "PRT" if prt else "KAJIYA_KAY"
    settings.prt_auto_order = False
    settings.prt_order = 2
    return obj


def pelt_images(obj) -> dict:
    return {im["pelt_role"]: im for im in bpy.data.images if im.get("pelt_owner") == obj.name}


def last_bake(obj) -> dict:
    return {s["stage"]: s["ran"] for s in json.loads(obj.pelt.last_bake)["stages"]}


def test_bake_writes_uvs_patches_and_tagged_packed_images(addon):
    obj = furred_suzanne(prt=True)
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    mesh = obj.data
    assert "PeltUV" in mesh.uv_layers
    patch = mesh.attributes["pelt_patch"]
    assert (patch.domain, patch.data_type) == ("FACE", "INT")
    ids = np.empty(len(mesh.polygons), np.int32)
    patch.data.foreach_get("value", ids)
    assert ids.min() >= 0, "every face of a fully furred mesh lies in a patch"
    images = pelt_images(obj)
    # Order 2 = 4 coefficients = one transfer texture.
    assert set(images) == {"shells", "tangents", "fin", "transfer_0"}
    for role, image in images.items():
        assert image.name.startswith("Pelt "), image.name
        assert image.packed_file is not None, f"{role} must be packed into the unsaved .blend"
    shells = images["shells"]
    assert tuple(shells.size) == (3 * 64, 3 * 64), "8 layers of 64² in a 3×3 atlas"
    assert shells.colorspace_settings.name == "sRGB"
    assert images["tangents"].colorspace_settings.name == "Non-Color"
    # The atlas's top-left cell (Blender's rows run bottom-up) is the opaque skin.
    pixels = np.empty(shells.size[0] * shells.size[1] * 4, np.float32)
    shells.pixels.foreach_get(pixels)
    top_left = pixels.reshape(shells.size[1], shells.size[0], 4)[-64:, :64]
    assert np.all(top_left[..., 3] == 1.0)
    assert last_bake(obj) == {"patches": True, "volume": True, "transfer": True}
    # The material, fin material and modifier that let EEVEE and Cycles render the fur.
    roles = {m["pelt_role"] for m in bpy.data.materials if m.get("pelt_owner") == obj.name}
    assert roles == {"fur_material", "fin_material"}
    modifier = obj.modifiers["Pelt Fur"]
    assert modifier.type == "NODES" and modifier.node_group.get("pelt_owner") == obj.name
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    assert len(evaluated.polygons) > 8 * len(mesh.polygons), "skin + 7 shells + fins"


def test_rebake_after_a_color_change_skips_every_stage(addon):
    obj = furred_suzanne(prt=True)
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    n = len(obj.data.vertices)
    color = obj.data.attributes.new("pelt_color", "FLOAT_COLOR", "POINT")
    color.data.foreach_set("color", np.tile([0.8, 0.1, 0.1, 1.0], n).astype(np.float32))
    # Painted colors for the first time: the coat's colors become its shading (the volume); the
    # transfer reads the hair's coverage alone.
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert last_bake(obj) == {"patches": False, "volume": True, "transfer": False}
    color.data.foreach_set("color", np.tile([0.1, 0.8, 0.1, 1.0], n).astype(np.float32))
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert last_bake(obj) == {"patches": False, "volume": False, "transfer": False}
    # New hair parameters rerun the volume and the transfer only.
    obj.pelt.density = 2500
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert last_bake(obj) == {"patches": False, "volume": True, "transfer": True}
    # A bigger tile reruns the patches and (the fur depth in tiles changed) the transfer.
    obj.pelt.tile_size = 0.6
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert last_bake(obj) == {"patches": True, "volume": False, "transfer": True}
    assert len([im for im in bpy.data.images if im.get("pelt_owner") == obj.name]) == 4


def test_nan_vertex_cancels_and_changes_nothing(addon):
    obj = furred_suzanne()
    obj.data.vertices[7].co.x = float("nan")
    before = datablock_snapshot()
    # An operator that reports an error and returns CANCELLED raises in scripts.
    with pytest.raises(RuntimeError, match=r"Suzanne: invalid mesh: `positions` row 7 .* NaN"):
        bpy.ops.pelt.bake()
    assert datablock_snapshot() == before


def test_bad_setting_cancels_and_changes_nothing(addon):
    obj = furred_suzanne()
    obj.pelt.undercoat_length = (0.9, 0.2)  # min > max
    before = datablock_snapshot()
    with pytest.raises(RuntimeError, match="undercoat"):
        bpy.ops.pelt.bake()
    assert datablock_snapshot() == before


def test_cancel_mid_bake_writes_nothing(addon):
    from addon.blender import bake

    obj = furred_suzanne()
    obj.pelt.resolution = "512"
    obj.pelt.layers = 32
    obj.pelt.density = 30000
    before = datablock_snapshot()
    job = bake.start_job(obj).start()
    deadline = time.monotonic() + 60
    while job.stage != "volume" and not job.done and time.monotonic() < deadline:
        time.sleep(0.005)
    assert not job.done, "the bake ended before it could be cancelled: make it bigger"
    job.cancel()
    assert job.wait(60)
    assert isinstance(job.error, pelt.BakeCancelled)
    with pytest.raises(pelt.BakeCancelled):
        bake.finish(obj, job)
    assert datablock_snapshot() == before


def test_users_datablocks_with_pelt_names_are_never_touched(addon):
    obj = furred_suzanne()
    mine = bpy.data.images.new(f"Pelt Shells {obj.name}", 4, 4)
    mine.pixels.foreach_set(np.full(64, 0.25, np.float32))
    expected = np.empty(64, np.float32)
    mine.pixels.foreach_get(expected)
    material = bpy.data.materials.new(f"Pelt Fur {obj.name}")
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    pixels = np.empty(64, np.float32)
    mine.pixels.foreach_get(pixels)
    assert tuple(mine.size) == (4, 4) and np.array_equal(pixels, expected)
    assert "pelt_owner" not in mine and "pelt_owner" not in material
    assert material.name == f"Pelt Fur {obj.name}" and material.users == 0
    assert pelt_images(obj)["shells"] != mine


def test_rebake_after_switching_prt_off_removes_the_transfer_images(addon):
    obj = furred_suzanne(prt=True)
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    obj.pelt.lighting = "KAJIYA_KAY"
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert set(pelt_images(obj)) == {"shells", "tangents", "fin"}


def test_images_are_saved_beside_a_saved_blend(addon, tmp_path):
    obj = furred_suzanne()
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "fur.blend"))
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    for image in pelt_images(obj).values():
        assert image.packed_file is None
        assert (tmp_path / "pelt_textures").is_dir()
        assert bpy.path.abspath(image.filepath).startswith(str(tmp_path / "pelt_textures"))


def test_undo_restores_the_scene_before_the_bake(addon):
    obj = furred_suzanne()
    scene = bpy.context.scene
    scene.cycles.transparent_max_bounces = 8  # Blender's default
    bpy.ops.ed.undo_push(message="before bake")
    # As from the UI: the operator's own undo step (scripts skip it unless asked).
    assert bpy.ops.pelt.bake("EXEC_DEFAULT", True) == {"FINISHED"}
    assert "PeltUV" in bpy.data.objects[obj.name].data.uv_layers
    # Cycles stops a ray, black, after 8 transparent surfaces: the bake raised them for its 8
    # shells and fins (a ray crosses each shell and a fin twice) and recorded it for the panel.
    assert bpy.context.scene.cycles.transparent_max_bounces == 4 * 8 + 4
    changes = json.loads(bpy.data.objects[obj.name].pelt.last_bake)["scene_changes"]
    assert changes == ["Cycles transparent bounces 8 → 36"]
    # Headless Blender keeps its window in the data but not in the operator's context.
    with bpy.context.temp_override(window=bpy.context.window_manager.windows[0]):
        assert bpy.ops.ed.undo() == {"FINISHED"}
    assert "PeltUV" not in bpy.data.objects["Suzanne"].data.uv_layers
    assert not [im for im in bpy.data.images if im.get("pelt_owner")]
    assert bpy.context.scene.cycles.transparent_max_bounces == 8


def test_presets_set_every_preset_field(addon):
    from addon.io.presets import PRESET_KEYS, PRESETS

    obj = add_suzanne()
    for key, preset in PRESETS.items():
        assert bpy.ops.pelt.apply_preset(preset=key) == {"FINISHED"}
        for name in PRESET_KEYS:
            assert np.allclose(np.asarray(getattr(obj.pelt, name)), preset[name], atol=1e-6), (key, name)
    # Every preset bakes.
    for key in PRESETS:
        bpy.ops.pelt.apply_preset(preset=key)
        obj.pelt.resolution = "64"
        obj.pelt.layers = 8
        assert bpy.ops.pelt.bake() == {"FINISHED"}, key


def test_thread_count_preference_reaches_the_library():
    try:
        pelt.set_thread_count(1)
        assert pelt.thread_count() == 1
        with pytest.raises(pelt.InvalidParameterError, match="threads"):
            pelt.set_thread_count(-1)
    finally:
        pelt.set_thread_count(0)


def test_rebake_refreshes_the_pixels_blender_already_loaded(addon):
    obj = furred_suzanne()
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    shells = pelt_images(obj)["shells"]
    before = np.empty(shells.size[0] * shells.size[1] * 4, np.float32)
    shells.pixels.foreach_get(before)  # loads the packed PNG
    obj.pelt.root_color = (0.9, 0.1, 0.1)
    obj.pelt.tip_color = (0.9, 0.1, 0.1)
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert pelt_images(obj)["shells"] == shells
    after = np.empty_like(before)
    shells.pixels.foreach_get(after)
    skin = after.reshape(shells.size[1], shells.size[0], 4)[-64:, :64]
    # Layer 0 (the skin) takes the root color: red now, brown before.
    assert skin[..., 0].mean() > 2 * skin[..., 1].mean()
    assert not np.array_equal(before, after)


def test_a_bake_above_the_memory_limit_is_refused_and_the_panel_warns_first(addon):
    from types import SimpleNamespace

    obj = furred_suzanne(prt=True)
    obj.pelt.resolution = "1024"
    obj.pelt.layers = 128
    # The preference's own update: 0.5 GiB, then back to the default (half the memory).
    addon.blender.preferences._apply_memory(SimpleNamespace(memory_limit_gib=0.5))
    try:
        peak, limit = addon.blender.bake.memory_estimate(obj)
        assert limit == 2**29 and peak > 128 * 1024**2 * 12
        before = datablock_snapshot()
        with pytest.raises(
            RuntimeError, match=r"above the memory limit of 512\.0 MiB.*`resolution` \(1024\)"
        ):
            bpy.ops.pelt.bake()
        assert datablock_snapshot() == before
    finally:
        addon.blender.preferences._apply_memory(SimpleNamespace(memory_limit_gib=0.0))
    assert pelt.memory_limit() > 2**29
    obj.pelt.resolution = "64"
    obj.pelt.layers = 8
    peak, limit = addon.blender.bake.memory_estimate(obj)
    assert peak < 2**28 < limit
