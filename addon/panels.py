# SPDX-License-Identifier: GPL-3.0-or-later
"""The "Pelt" tab of the 3D view sidebar."""

import json

import bpy

from . import comb_tools, point_data

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


class VIEW3D_PT_pelt_paint_comb(bpy.types.Panel):
    bl_label = "Paint & Comb"
    bl_idname = "VIEW3D_PT_pelt_paint_comb"
    bl_parent_id = "VIEW3D_PT_pelt"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Pelt"

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        column = layout.column(align=True)
        column.operator("pelt.paint_color", icon="VPAINT_HLT")
        column.operator("pelt.paint_length", icon="VPAINT_HLT")
        row = column.row(align=True)
        row.enabled = point_data.LENGTH_PAINT in obj.data.attributes
        row.operator("pelt.apply_length_paint", icon="CHECKMARK")
        column = layout.column(align=True)
        column.operator("pelt.comb", icon="CURVE_PATH")
        column.operator("pelt.comb_gravity", icon="SORT_ASC")
        column.operator("pelt.comb_smooth", icon="MOD_SMOOTH")
        row = column.row(align=True)
        row.enabled = bool(comb_tools.hair_curves_of(obj))
        row.operator("pelt.comb_from_curves", icon="OUTLINER_OB_CURVES")


CLASSES = (VIEW3D_PT_pelt, VIEW3D_PT_pelt_paint_comb)
