# SPDX-License-Identifier: GPL-3.0-or-later
"""The "Pelt" tab of the 3D view sidebar: the main panel (check, bake, last report) and one
sub-panel per group of settings."""

import json

import bpy

from ..io.names import LENGTH_PAINT
from . import bake, comb_tools, live_preview, pose, preferences

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


def _json(text: str):
    try:
        return json.loads(text) if text else None
    except ValueError:
        return None


class _PeltPanel:
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Pelt"

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"


class VIEW3D_PT_pelt(_PeltPanel, bpy.types.Panel):
    bl_label = "Pelt"
    bl_idname = "VIEW3D_PT_pelt"

    def draw_header(self, context):
        self.layout.prop(context.active_object.pelt, "enabled", text="")

    def draw(self, context):
        layout = self.layout
        settings = context.active_object.pelt
        row = layout.row(align=True)
        row.scale_y = 1.4
        row.operator("pelt.bake", icon="RENDER_STILL")
        estimate = bake.memory_estimate(context.active_object)
        if estimate is not None:
            peak, limit = estimate
            row = layout.row()
            row.alert = peak > limit
            text = f"Memory: about {preferences.format_bytes(peak)} of {preferences.format_bytes(limit)}"
            row.label(text=text + (": lower Resolution or Layers" if peak > limit else ""),
                      icon="ERROR" if peak > limit else "MEMORY")  # fmt: skip
        note = pose.NOTES.get(context.active_object.session_uid)
        if note is not None:
            row = layout.row()
            row.alert = True
            row.label(text=f"Pose: {note}", icon="ERROR")
        layout.operator("pelt.check_mesh", icon="CHECKMARK")
        last_bake = _json(settings.last_bake)
        if last_bake:
            box = layout.box()
            box.label(text="Last Bake", icon="INFO")
            for stage in last_bake.get("stages", []):
                text = f"{stage['seconds']:.2f} s" if stage["ran"] else "skipped (unchanged)"
                box.label(text=f"{stage['stage'].title()}: {text}")
            for change in last_bake.get("scene_changes", []):
                box.label(text=f"Set for the fur: {change}", icon="SCENE_DATA")
        stats = _json(settings.last_check)
        if stats:
            box = layout.box()
            grid = box.grid_flow(columns=2, even_columns=True)
            for key, label in STAT_ROWS:
                grid.label(text=label)
                grid.label(text=str(stats.get(key, "?")))
            box.label(text=f"Area: {stats.get('surface_area', 0.0):.4g}")


class VIEW3D_PT_pelt_paint_comb(_PeltPanel, bpy.types.Panel):
    bl_label = "Paint & Comb"
    bl_idname = "VIEW3D_PT_pelt_paint_comb"
    bl_parent_id = "VIEW3D_PT_pelt"

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        column = layout.column(align=True)
        column.operator("pelt.paint_color", icon="VPAINT_HLT")
        column.operator("pelt.paint_length", icon="VPAINT_HLT")
        row = column.row(align=True)
        row.enabled = LENGTH_PAINT in obj.data.attributes
        row.operator("pelt.apply_length_paint", icon="CHECKMARK")
        column = layout.column(align=True)
        column.operator("pelt.comb", icon="CURVE_PATH")
        column.operator("pelt.comb_gravity", icon="SORT_ASC")
        column.operator("pelt.comb_smooth", icon="MOD_SMOOTH")
        row = column.row(align=True)
        row.enabled = bool(comb_tools.hair_curves_of(obj))
        row.operator("pelt.comb_from_curves", icon="OUTLINER_OB_CURVES")


class _SubPanel(_PeltPanel):
    bl_parent_id = "VIEW3D_PT_pelt"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        self.draw_settings(layout, context.active_object.pelt)


class VIEW3D_PT_pelt_hair(_SubPanel, bpy.types.Panel):
    bl_label = "Hair"
    bl_idname = "VIEW3D_PT_pelt_hair"
    bl_options = set()

    def draw_settings(self, layout, settings):
        layout.menu("PELT_MT_presets", icon="PRESET")
        for name in ("density", "guard_fraction", "undercoat_length", "undercoat_width", "overcoat_length",
                     "overcoat_width", "taper", "curl", "helix_radius", "helix_frequency", "slant",
                     "length_jitter", "clump_strength", "clump_count", "root_color", "tip_color",
                     "color_jitter", "seed"):  # fmt: skip
            layout.prop(settings, name)
        layout.prop(settings, "guard_hairs")
        row = layout.row()
        row.active = settings.guard_hairs
        row.prop(settings, "guard_share")


class VIEW3D_PT_pelt_shells(_SubPanel, bpy.types.Panel):
    bl_label = "Shells & Textures"
    bl_idname = "VIEW3D_PT_pelt_shells"

    def draw_settings(self, layout, settings):
        for name in ("fur_depth", "tile_size", "layers", "resolution", "coverage", "patch_seed"):
            layout.prop(settings, name)


class VIEW3D_PT_pelt_display(_SubPanel, bpy.types.Panel):
    bl_label = "Fins & Level of Detail"
    bl_idname = "VIEW3D_PT_pelt_display"

    def draw_settings(self, layout, settings):
        layout.prop(settings, "fins")
        layout.prop(settings, "shell_method")
        if settings.shell_method == "PLANES":
            column = layout.column(align=True)
            column.prop(settings, "planes")
            column.prop(settings, "plane_loop_limit")
        layout.prop(settings, "lod")
        column = layout.column(align=True)
        column.active = settings.lod
        column.prop(settings, "min_shells")
        column.prop(settings, "max_shells")


class VIEW3D_PT_pelt_lighting(_SubPanel, bpy.types.Panel):
    bl_label = "Lighting"
    bl_idname = "VIEW3D_PT_pelt_lighting"

    def draw_settings(self, layout, settings):
        layout.prop(settings, "lighting")
        column = layout.column()
        column.active = settings.lighting == "PRT"
        column.prop(settings, "prt_auto_order")
        if settings.prt_auto_order:
            column.prop(settings, "prt_tolerance")
        else:
            column.prop(settings, "prt_order")


class VIEW3D_PT_pelt_preview(_SubPanel, bpy.types.Panel):
    bl_label = "Preview"
    bl_idname = "VIEW3D_PT_pelt_preview"
    bl_options = set()

    def draw_settings(self, layout, settings):
        row = layout.row(align=True)
        live = live_preview.is_on()
        row.operator("pelt.live_preview", icon="HIDE_ON" if live else "HIDE_OFF", depress=live)
        row.operator("pelt.render_preview", icon="RENDER_STILL")
        session = live_preview.session_of(bpy.context.active_object) if live else None
        for line in session.status() if session is not None else ():
            icon = "ERROR" if line.startswith("Out of date") else "NONE"
            layout.label(text=line, icon=icon)


class VIEW3D_PT_pelt_export(_SubPanel, bpy.types.Panel):
    bl_label = "Export"
    bl_idname = "VIEW3D_PT_pelt_export"

    def draw_settings(self, layout, settings):
        layout.label(text="glTF for engines and viewers, with textures")
        layout.operator("pelt.export", icon="EXPORT")


CLASSES = (
    VIEW3D_PT_pelt,
    VIEW3D_PT_pelt_paint_comb,
    VIEW3D_PT_pelt_hair,
    VIEW3D_PT_pelt_shells,
    VIEW3D_PT_pelt_display,
    VIEW3D_PT_pelt_lighting,
    VIEW3D_PT_pelt_preview,
    VIEW3D_PT_pelt_export,
)
