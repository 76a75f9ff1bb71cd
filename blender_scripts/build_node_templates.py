"""Writes Pelt's node trees, built once, into ``addon/assets/node_templates.blend``.

Usage: python blender_scripts/build_node_templates.py [OUT.blend]

The add-on appends these instead of building the trees node by node on a first bake (see
``addon/blender/templates.py``); ``make`` runs this whenever the code that builds them changes.
"""

import sys
from pathlib import Path

import bpy
from _setup import register_addon


def main() -> None:
    register_addon()
    from addon.blender import fur, templates

    out = Path(sys.argv[1]) if len(sys.argv) > 1 else templates.PATH
    bpy.ops.wm.read_factory_settings(use_empty=True)
    templates.write(out.resolve(), fur.template_builders())
    print(out)


if __name__ == "__main__":
    main()
