"""Test harness for the real Blender (the ``bpy`` wheel): isolated user folders, a fresh scene per
test, and the add-on registered from the source tree (``addon/``) where a test asks for it."""

import importlib
import os
import shutil
import sys
import tempfile
from pathlib import Path

# Blender reads these when bpy is imported: nothing may touch the real home folder.
_USER_ROOT = Path(tempfile.mkdtemp(prefix="pelt-tests-"))
for _name in ("XDG_CONFIG_HOME", "XDG_CACHE_HOME", "XDG_DATA_HOME", "BLENDER_USER_RESOURCES"):
    os.environ[_name] = str(_USER_ROOT / _name.lower())
os.environ.setdefault("XDG_RUNTIME_DIR", str(_USER_ROOT / "runtime"))
Path(os.environ["XDG_RUNTIME_DIR"]).mkdir(mode=0o700, exist_ok=True)

import bpy  # noqa: E402
import pytest  # noqa: E402

REPO = Path(__file__).resolve().parents[2]


def pytest_sessionfinish(session, exitstatus):
    shutil.rmtree(_USER_ROOT, ignore_errors=True)


@pytest.fixture(autouse=True)
def fresh_scene():
    """An empty factory scene for every test."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield


@pytest.fixture
def addon():
    """The add-on from ``addon/``, registered for one test and unregistered after it."""
    if str(REPO) not in sys.path:
        sys.path.insert(0, str(REPO))
    module = importlib.import_module("addon")
    module.register()
    yield module
    module.unregister()


def add_suzanne():
    """Blender's monkey as the active object."""
    bpy.ops.mesh.primitive_monkey_add()
    return bpy.context.active_object


def small_fur(obj, *, density: int = 3000, tile_size: float = 0.3, fur_depth: float | None = None):
    """Pelt on for ``obj`` with a small, quick bake (8 layers of 64²); its settings."""
    settings = obj.pelt
    settings.enabled = True
    settings.layers = 8
    settings.resolution = "64"
    settings.density = density
    settings.tile_size = tile_size
    if fur_depth is not None:
        settings.fur_depth = fur_depth
    return settings


def datablock_snapshot() -> dict:
    """Every ID datablock by collection, with the attributes, UV maps and coordinates of each mesh
    and the Pelt settings of each object: what an operator that fails must leave exactly as it was."""
    snapshot = {}
    for attr in dir(bpy.data):
        collection = getattr(bpy.data, attr, None)
        if isinstance(collection, bpy.types.bpy_prop_collection) and attr not in ("window_managers",):
            snapshot[attr] = sorted(item.name for item in collection if isinstance(item, bpy.types.ID))
    for mesh in bpy.data.meshes:
        coords = [0.0] * (3 * len(mesh.vertices))
        mesh.vertices.foreach_get("co", coords)
        snapshot[f"mesh:{mesh.name}"] = (
            sorted((a.name, a.domain, a.data_type) for a in mesh.attributes),
            sorted(uv.name for uv in mesh.uv_layers),
            repr(coords),
            len(mesh.polygons),
        )
    for obj in bpy.data.objects:
        if hasattr(obj, "pelt"):
            snapshot[f"object:{obj.name}"] = (obj.pelt.enabled, obj.pelt.last_check)
    return snapshot
