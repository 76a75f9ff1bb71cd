# SPDX-License-Identifier: GPL-3.0-or-later
"""The "Pelt" tab of the 3D view sidebar."""

import json

import bpy

# Statistics rows shown after a check: (key, label).
STAT_ROWS = (
    ("vertices", "Vertices"),
    ("faces", "Triangles"),
    ("edges", "Edges"),
    ("boundary_edges", "Boundary Edges"),
    ("non_manifold_edges", "Non-Manifold Edges"),
    ("degenerate_faces", "Degenerate Triangles"),
    ("components", "Components"),
    ("loose_vertices", "Loose Vertices"),
)


class VIEW3D_PT_pelt(bpy.types.Panel):
    bl_label = "Pelt"
    bl_idname = "VIEW3D_PT_pelt"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Pelt"

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"

    def draw_header(self, context):
        self.layout.prop(context.active_object.pelt, "enabled", text="")

    def draw(self, context):
        layout = self.layout
        settings = context.active_object.pelt
        layout.operator("pelt.check_mesh", icon="CHECKMARK")
        if not settings.last_check:
            return
        try:
            stats = json.loads(settings.last_check)
        except ValueError:
            return
        box = layout.box()
        grid = box.grid_flow(columns=2, even_columns=True)
        for key, label in STAT_ROWS:
            grid.label(text=label)
            grid.label(text=str(stats.get(key, "?")))
        box.label(text=f"Area: {stats.get('surface_area', 0.0):.4g}")


CLASSES = (VIEW3D_PT_pelt,)
