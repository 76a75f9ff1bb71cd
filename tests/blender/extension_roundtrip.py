"""Installs the built extension zip into a fresh Blender, checks and bakes Suzanne, uninstalls;
prints JSON.

Run by ``test_extension_install.py`` in its own process, with the user folders of that test, so
that the ``pelt`` module imported is the one unpacked from the zip's wheel, not the development
copy in the virtual environment.
"""

import json
import sys
from pathlib import Path

import bpy

zip_path = sys.argv[1]
# hide the development copy of pelt: only the extension's own wheel may serve the add-on
sys.path[:] = [p for p in sys.path if not p.endswith("site-packages") or "extensions" in p]
sys.modules.pop("pelt", None)

bpy.ops.wm.read_factory_settings(use_empty=True)
result = {}
result["install"] = sorted(
    bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default", enable_on_install=True)
)
result["enabled"] = "bl_ext.user_default.pelt" in bpy.context.preferences.addons
pelt = sys.modules.get("pelt")
result["pelt_file"] = getattr(pelt, "__file__", None)
result["pelt_version"] = getattr(pelt, "__version__", None)

bpy.ops.mesh.primitive_monkey_add()
obj = bpy.context.active_object
obj.data.calc_loop_triangles()
result["check"] = sorted(bpy.ops.pelt.check_mesh())
result["stats"] = json.loads(obj.pelt.last_check)
result["blender_counts"] = {"vertices": len(obj.data.vertices), "faces": len(obj.data.loop_triangles)}

# The extension's preferences are registered under its package name.
prefs = bpy.context.preferences.addons["bl_ext.user_default.pelt"].preferences
result["preferences"] = {"threads": prefs.threads, "cache_size": prefs.cache_size, "adapter": prefs.adapter}
obj.pelt.enabled = True
obj.pelt.layers = 8
obj.pelt.resolution = "64"
obj.pelt.lighting = "PRT"
result["bake"] = sorted(bpy.ops.pelt.bake())
result["baked_stages"] = [s["stage"] for s in json.loads(obj.pelt.last_bake)["stages"] if s["ran"]]
result["uv"] = "PeltUV" in obj.data.uv_layers
result["images"] = sorted(im["pelt_role"] for im in bpy.data.images if im.get("pelt_owner") == obj.name)
# The packaged node trees are current for the packaged sources (so a first bake appends them).
templates = sys.modules["bl_ext.user_default.pelt.blender.templates"]
copies = templates._append(list(templates.ROLES))
result["templates_current"] = sorted(copies)
for role, block in copies.items():
    getattr(bpy.data, templates.ROLES[role][0]).remove(block)

repos = bpy.context.preferences.extensions.repos
index = next(i for i, repo in enumerate(repos) if repo.module == "user_default")
package_dir = Path(bpy.utils.user_resource("EXTENSIONS")) / "user_default" / "pelt"
result["installed_dir_existed"] = package_dir.is_dir()
result["uninstall"] = sorted(bpy.ops.extensions.package_uninstall(repo_index=index, pkg_id="pelt"))
result["enabled_after"] = "bl_ext.user_default.pelt" in bpy.context.preferences.addons
result["property_after"] = hasattr(bpy.types.Object, "pelt")
result["operator_after"] = hasattr(bpy.types, "PELT_OT_check_mesh")
result["installed_dir_after"] = package_dir.exists()
print("RESULT " + json.dumps(result))
