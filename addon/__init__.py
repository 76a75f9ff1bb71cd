# SPDX-License-Identifier: GPL-3.0-or-later
"""Pelt: real-time fur on any mesh.

Registration follows one pattern: each module exports ``CLASSES``; ``register()`` registers them in
order and attaches ``bpy.types.Object.pelt``; ``unregister()`` undoes it in reverse.
"""

import bpy

from . import bake, comb, comb_tools, export, live_preview, ops, paint, panels, preferences, preview, props

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
