# SPDX-License-Identifier: GPL-3.0-or-later
"""Paint Color and Paint Length: Blender's Vertex Paint on Pelt's point attributes.

Vertex Paint paints color attributes only, so the length is painted as the gray of the helper
color attribute ``pelt_length_paint`` (black bald, mid gray the default length 1, white 2; see
``paint_math``) and copied into ``pelt_length`` by "Apply Length Paint". The helper is made from
``pelt_length`` when missing and kept afterwards, so leaving Vertex Paint loses no strokes.
"""

import bpy
import numpy as np
import pelt

from ..io import paint_math
from ..io.names import COLOR, LENGTH, LENGTH_PAINT
from . import point_data
from .point_data import TargetError


def _paintable_mesh_object(context):
    obj = point_data.active_mesh_object(context)
    if not obj.visible_get():
        raise TargetError(f"'{obj.name}' is hidden: Vertex Paint needs it visible")
    return obj


def _enter_vertex_paint(operator, context, names: tuple[str, ...], prepare) -> set[str]:
    """The body of the paint operators: check the active object and the attributes ``names``,
    leave Edit Mode, run ``prepare(obj) -> (notes, attribute to paint)``, make that attribute the
    active color and enter Vertex Paint. A failure puts the mode back and reports."""
    try:
        obj = _paintable_mesh_object(context)
        for name in names:
            point_data.check_convertible(obj, name)
    except TargetError as error:
        operator.report({"ERROR"}, f"Pelt: {error}")
        return {"CANCELLED"}
    mode = obj.mode
    try:
        if mode == "EDIT":
            bpy.ops.object.mode_set(mode="OBJECT")
        notes, painted = prepare(obj)
        obj.data.attributes.active_color_name = painted
        if obj.mode != "VERTEX_PAINT":
            bpy.ops.object.mode_set(mode="VERTEX_PAINT")
    except (pelt.PeltError, RuntimeError) as error:
        if obj.mode != mode:
            bpy.ops.object.mode_set(mode=mode)
        operator.report({"ERROR"}, f"Pelt: {obj.name}: {error}")
        return {"CANCELLED"}
    for note in filter(None, notes):
        operator.report({"WARNING"}, f"Pelt: {obj.name}: {note}")
    return {"FINISHED"}


def _ensure_color(obj) -> tuple[list, str]:
    fill = paint_math.starting_color(obj.pelt.root_color, obj.pelt.tip_color)
    return [point_data.ensure_point_attribute(obj, COLOR, "FLOAT_COLOR", fill)], COLOR


def _ensure_length_paint(obj) -> tuple[list, str]:
    """``pelt_length`` and its paint helper on ``obj`` (Object Mode); returns the notes for the
    report and the helper's name."""
    notes = [point_data.ensure_point_attribute(obj, LENGTH, "FLOAT", paint_math.DEFAULT_LENGTH)]
    mesh = obj.data
    if LENGTH_PAINT in mesh.attributes:
        notes.append(point_data.ensure_point_attribute(obj, LENGTH_PAINT, "FLOAT_COLOR", 1.0))
        return notes, LENGTH_PAINT
    length = point_data.read_point(mesh, LENGTH)
    longest = float(length.max(initial=0.0))
    if longest > paint_math.LENGTH_PAINT_MAX:
        notes.append(
            f"lengths above {paint_math.LENGTH_PAINT_MAX:g} (up to {longest:.3g}) paint as white "
            f"and become {paint_math.LENGTH_PAINT_MAX:g} when the paint is applied"
        )
    point_data.ensure_point_attribute(obj, LENGTH_PAINT, "FLOAT_COLOR", paint_math.length_to_paint(length))
    return notes, LENGTH_PAINT


def apply_length_paint(obj) -> tuple[np.ndarray, list]:
    """Copies the grays of ``pelt_length_paint`` into ``pelt_length`` (creating or converting
    either where needed; Object Mode). Returns the lengths and notes for a report. A bake that
    wants the painted length without the button can call this first."""
    mesh = obj.data
    notes = [
        point_data.ensure_point_attribute(obj, LENGTH_PAINT, "FLOAT_COLOR", 1.0),
        point_data.ensure_point_attribute(obj, LENGTH, "FLOAT", paint_math.DEFAULT_LENGTH),
    ]
    length = paint_math.paint_to_length(point_data.read_point(mesh, LENGTH_PAINT))
    point_data.write_point(mesh, LENGTH, length)
    return length, notes


class PELT_OT_paint_color(bpy.types.Operator):
    """Paint the fur color: Vertex Paint on the pelt_color attribute, whose colors the fur then
    shows as painted (created in the coat's own color when missing, converted to a per-vertex
    color when it is another kind of attribute)"""

    bl_idname = "pelt.paint_color"
    bl_label = "Paint Color"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        return _enter_vertex_paint(self, context, (COLOR,), _ensure_color)


class PELT_OT_paint_length(bpy.types.Operator):
    """Paint the fur length: Vertex Paint on the gray helper pelt_length_paint (black bald, mid
    gray length 1, white length 2); Apply Length Paint copies it into pelt_length"""

    bl_idname = "pelt.paint_length"
    bl_label = "Paint Length"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        return _enter_vertex_paint(self, context, (LENGTH, LENGTH_PAINT), _ensure_length_paint)


class PELT_OT_apply_length_paint(bpy.types.Operator):
    """Copy the painted grays of pelt_length_paint into the fur length pelt_length (black bald,
    mid gray 1, white 2)"""

    bl_idname = "pelt.apply_length_paint"
    bl_label = "Apply Length Paint"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        try:
            obj = point_data.active_mesh_object(context)
            if LENGTH_PAINT not in obj.data.attributes:
                raise TargetError(f"'{obj.name}' has no painted length: use Paint Length first")
            point_data.check_convertible(obj, LENGTH)
            point_data.check_convertible(obj, LENGTH_PAINT)
            with point_data.object_mode(obj):
                length, notes = apply_length_paint(obj)
        except (TargetError, pelt.PeltError, RuntimeError) as error:
            self.report({"ERROR"}, f"Pelt: {error}")
            return {"CANCELLED"}
        for note in filter(None, notes):
            self.report({"WARNING"}, f"Pelt: {obj.name}: {note}")
        low, high = (float(length.min()), float(length.max())) if len(length) else (0.0, 0.0)
        bald = int(np.count_nonzero(length == 0.0))
        self.report({"INFO"}, f"Pelt: {obj.name}: length {low:.3g} to {high:.3g}, {bald} bald vertices")
        return {"FINISHED"}


CLASSES = (PELT_OT_paint_color, PELT_OT_paint_length, PELT_OT_apply_length_paint)
