"""Export from Blender: the File > Export operator and the headless batch script."""

import json
import subprocess
import sys

import bpy
import pytest
from conftest import REPO, add_suzanne


def small_fur(obj):
    obj.pelt.enabled = True
    obj.pelt.layers = 6
    obj.pelt.resolution = "64"
    obj.pelt.density = 1500
    obj.pelt.tile_size = 0.5
    return obj


def test_export_operator_writes_the_glb_and_its_texture_set(addon, tmp_path):
    small_fur(add_suzanne())
    path = tmp_path / "fur" / "suzanne.glb"
    assert bpy.ops.pelt.export(filepath=str(path), mode="GEOMETRY", png=True, ktx2=True) == {"FINISHED"}
    assert path.read_bytes()[:4] == b"glTF"
    manifest = json.loads((path.parent / "pelt.json").read_text())
    listed = json.dumps(manifest)
    assert ".ktx2" in listed and ".png" in listed
    # Blender's own importer reads it back, with Pelt's alpha-blended materials.
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=str(path))
    assert bpy.data.meshes and bpy.data.materials
    assert any(m.surface_render_method == "BLENDED" for m in bpy.data.materials)


def test_export_of_a_broken_mesh_writes_nothing(addon, tmp_path):
    obj = small_fur(add_suzanne())
    obj.data.vertices[3].co.z = float("nan")
    path = tmp_path / "broken.glb"
    with pytest.raises(RuntimeError, match=r"nothing written.*NaN"):
        bpy.ops.pelt.export(filepath=str(path))
    assert not any(tmp_path.iterdir())


def test_bake_batch_exports_the_good_object_and_names_the_broken_one(addon, tmp_path):
    good = small_fur(add_suzanne())
    good.name = "Good"
    broken = small_fur(add_suzanne())
    broken.name = "Broken"
    broken.data.vertices[0].co.x = float("nan")
    bald = add_suzanne()
    bald.name = "NoFur"
    blend = tmp_path / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    out = tmp_path / "out"
    done = subprocess.run(
        [sys.executable, str(REPO / "blender_scripts" / "bake_batch.py"), str(blend), "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 1, done.stdout + done.stderr
    assert "scene.blend: Broken:" in done.stderr and "NaN" in done.stderr
    assert "Good" not in done.stderr
    assert "scene.blend: Good: ok" in done.stdout
    folder = out / "scene" / "Good"
    assert (folder / "Good_engine.glb").is_file() and (folder / "Good_geometry.glb").is_file()
    assert (folder / "pelt.json").is_file()
    assert not (out / "scene" / "Broken").exists() or not any((out / "scene" / "Broken").iterdir())
    assert not (out / "scene" / "NoFur").exists()
