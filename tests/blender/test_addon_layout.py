"""The add-on's layout rule, read from the source (nothing imported): ``addon/io/`` needs no
Blender, so none of its modules imports bpy or Blender's other modules, nor anything from
``addon/blender/``; and the Blender names of DESIGN.md §3 are spelled only in ``io/names.py``."""

import ast

import pytest
from conftest import REPO

ADDON = REPO / "addon"
IO = ADDON / "io"
# Modules that exist only inside Blender.
BLENDER_ONLY = {
    "bpy",
    "bpy_extras",
    "bmesh",
    "mathutils",
    "gpu",
    "gpu_extras",
    "bl_math",
    "bl_ui",
    "blf",
    "aud",
}
# DESIGN.md §3: the names that scripts, exported files and runtimes read.
NAMES = ("pelt_color", "pelt_comb", "pelt_length", "PeltUV", "pelt_patch", "pelt_owner", "pelt_role")


def imported(source: str, package: str) -> set[str]:
    """The absolute names of every module ``source`` imports, nested imports included; relative
    ones are resolved against ``package`` (the dotted package of the file)."""
    parts = package.split(".")
    found = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = parts[: len(parts) - node.level + 1] if node.level else []
            module = ".".join([*base, *([node.module] if node.module else [])])
            # ``from .. import blender`` names the module in its alias.
            found |= {f"{module}.{alias.name}" for alias in node.names}
    return found


@pytest.mark.parametrize("path", sorted(IO.glob("*.py")), ids=lambda p: p.name)
def test_io_needs_no_blender(path):
    for module in sorted(imported(path.read_text(), "addon.io")):
        assert module.split(".")[0] not in BLENDER_ONLY, f"{path.name} imports {module}"
        assert module != "addon.blender" and not module.startswith("addon.blender."), (
            f"{path.name} imports {module}"
        )


def test_io_is_a_flat_package_of_modules():
    """A subfolder would escape the glob above."""
    assert (IO / "__init__.py").is_file()
    assert [p.name for p in IO.iterdir() if p.is_dir() and p.name != "__pycache__"] == []


def test_the_blender_names_are_spelled_in_one_module():
    for path in sorted(ADDON.rglob("*.py")):
        if path == IO / "names.py":
            continue
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value in NAMES:
                pytest.fail(f"{path.relative_to(ADDON)}:{node.lineno} spells {node.value!r}: use io/names.py")


def test_the_resolver_sees_what_the_rule_forbids():
    """The rule would pass vacuously if ``imported`` missed one of these forms."""
    source = (
        "import bpy\nfrom mathutils import Vector\nfrom ..blender import bake\nfrom .. import blender\n"
        "from . import names\ndef f():\n    import gpu\n"
    )
    assert imported(source, "addon.io") == {
        "bpy",
        "mathutils.Vector",
        "addon.blender.bake",
        "addon.blender",
        "addon.io.names",
        "gpu",
    }
