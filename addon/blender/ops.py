# SPDX-License-Identifier: GPL-3.0-or-later
"""Operators. Each catches ``pelt.PeltError``, reports it and returns CANCELLED, changing nothing."""

import json

import bpy
import pelt

from ..io import bridge


class PELT_OT_check_mesh(bpy.types.Operator):
    """Read the active mesh into Pelt, validate it and show its statistics"""

    bl_idname = "pelt.check_mesh"
    bl_label = "Check Mesh"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"

    def execute(self, context):
        obj = context.active_object
        try:
            stats = bridge.fur_mesh_from_object(obj).stats()
        except pelt.PeltError as error:
            self.report({"ERROR"}, f"Pelt: {obj.name}: {error}")
            return {"CANCELLED"}
        obj.pelt.last_check = json.dumps(stats)
        self.report(
            {"INFO"},
            f"Pelt: {obj.name}: {stats['vertices']} vertices, {stats['faces']} triangles, "
            f"{stats['components']} components",
        )
        return {"FINISHED"}


CLASSES = (PELT_OT_check_mesh,)
