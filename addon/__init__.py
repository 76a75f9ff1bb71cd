# SPDX-License-Identifier: GPL-3.0-or-later
"""Pelt: real-time fur on any mesh.

Layout:
- ``io/``: no bpy. Plain data and numpy: the Blender names of DESIGN.md §3 (``names``), the mesh
  transfer (``bridge``), comb and paint math, the atlas layout, bake and preview worker threads.
- ``blender/``: the glue. Operators, panels, properties, preferences, materials and geometry
  nodes, the preview, comb and paint tools, export; it imports ``io``, never the other way round.
- ``assets/``: the node trees built once by ``make setup`` and shipped (``blender/templates.py``).

Registration follows one pattern: each glue module below exports ``CLASSES``; ``register()``
registers them in order and attaches ``bpy.types.Object.pelt``; ``unregister()`` undoes it in
reverse.
"""

import bpy

from .blender import (
    bake,
    comb,
    comb_tools,
    export,
    live_preview,
    ops,
    paint,
    panels,
    preferences,
    preview,
    props,
)

_MODULES = (preferences, props, ops, paint, comb, comb_tools, bake, preview, live_preview, export, panels)


def register() -> None:
    for module in _MODULES:
        for cls in module.CLASSES:
            bpy.utils.register_class(cls)
    bpy.types.Object.pelt = bpy.props.PointerProperty(type=props.PeltObjectSettings)
    preferences.apply()
    export.register_menus()


def unregister() -> None:
    export.unregister_menus()
    live_preview.stop()
    bake.RECORDS.clear()
    preview.forget_previews()
    del bpy.types.Object.pelt
    preferences.CACHE.clear()
    for module in reversed(_MODULES):
        for cls in reversed(module.CLASSES):
            bpy.utils.unregister_class(cls)
