# SPDX-License-Identifier: GPL-3.0-or-later
"""Per-object Pelt settings (``Object.pelt``)."""

import bpy


class PeltObjectSettings(bpy.types.PropertyGroup):
    enabled: bpy.props.BoolProperty(
        name="Fur",
        description="Grow Pelt fur on this object",
        default=False,
    )
    last_check: bpy.props.StringProperty(
        name="Last Check",
        description="Statistics of the last mesh check, as JSON (shown in the Pelt panel)",
        default="",
        options={"HIDDEN"},
    )


CLASSES = (PeltObjectSettings,)
