# SPDX-License-Identifier: GPL-3.0-or-later
"""Whole-mesh comb operators: Comb: Gravity, Comb: Smooth and Comb from Hair Curves."""

import bpy
import numpy as np
import pelt

from ..io import comb_math
from ..io.names import COMB
from . import point_data
from .point_data import TargetError

_ERRORS = (TargetError, pelt.PeltError, RuntimeError)

only_selected_property = bpy.props.BoolProperty(
    name="Only Selected",
    description="Change only the selected vertices (as selected in Edit Mode)",
    default=False,
)


def _comb_target(context):
    obj = point_data.active_mesh_object(context)
    point_data.check_convertible(obj, COMB)
    return obj


def _mask(mesh, only_selected: bool):
    if not only_selected:
        return None
    mask = point_data.selected(mesh)
    if not mask.any():
        raise TargetError(f"no vertex of '{mesh.name}' is selected")
    return mask


def hair_curves_of(obj) -> list:
    """Hair Curves objects grown on ``obj`` (``Curves.surface`` is ``obj``), by name."""
    return sorted(
        (o for o in bpy.data.objects if o.type == "CURVES" and o.data.surface == obj),
        key=lambda o: o.name,
    )


def _strands_in_object_space(curves_obj, obj) -> tuple[np.ndarray, np.ndarray, int]:
    """Roots and root-to-tip vectors of ``curves_obj``'s strands in ``obj``'s object space, and
    the number of its curves."""
    curves = curves_obj.data
    count = len(curves.curves)
    offsets = np.empty(count + 1, dtype=np.int64)
    curves.curve_offset_data.foreach_get("value", offsets)
    positions = np.empty(3 * len(curves.points), dtype=np.float32)
    curves.position_data.foreach_get("vector", positions)
    roots, directions, _ = comb_math.strand_directions(positions.reshape(-1, 3), offsets)
    to_mesh = np.linalg.inv(np.array(obj.matrix_world, dtype=np.float64)) @ np.array(
        curves_obj.matrix_world, dtype=np.float64
    )
    roots = roots @ to_mesh[:3, :3].T + to_mesh[:3, 3]
    return roots, directions @ to_mesh[:3, :3].T, count


class PELT_OT_comb_gravity(bpy.types.Operator):
    """Comb the hair down: blend the comb towards world -Z, projected into each vertex's tangent
    plane (hair on top of a surface stays upright)"""

    bl_idname = "pelt.comb_gravity"
    bl_label = "Comb: Gravity"
    bl_options = {"REGISTER", "UNDO"}

    strength: bpy.props.FloatProperty(
        name="Strength",
        description="How far the comb moves towards gravity: 0 keeps it, 1 replaces it",
        default=1.0,
        min=0.0,
        max=1.0,
        subtype="FACTOR",
    )
    only_selected: only_selected_property

    @classmethod
    def poll(cls, context):
        return context.active_object is not None

    def execute(self, context):
        try:
            obj = _comb_target(context)
            with point_data.object_mode(obj):
                mesh = obj.data
                mask = _mask(mesh, self.only_selected)
                note = point_data.ensure_point_attribute(obj, COMB, "FLOAT_VECTOR", 0.0)
                linear = np.array(obj.matrix_world, dtype=np.float64)[:3, :3]
                pull = comb_math.gravity_pull(point_data.normals(mesh), linear, (0.0, 0.0, -1.0))
                comb = comb_math.blend(point_data.read_point(mesh, COMB), pull, self.strength, mask)
                point_data.write_point(mesh, COMB, comb)
        except (*_ERRORS, np.linalg.LinAlgError) as error:
            self.report({"ERROR"}, f"Pelt: {error}")
            return {"CANCELLED"}
        if note:
            self.report({"WARNING"}, f"Pelt: {obj.name}: {note}")
        changed = len(comb) if mask is None else int(mask.sum())
        self.report({"INFO"}, f"Pelt: {obj.name}: combed {changed} vertices down")
        return {"FINISHED"}


class PELT_OT_comb_smooth(bpy.types.Operator):
    """Smooth the comb: average each vertex's comb with its neighbours' (directions kept in the
    tangent planes, lengths averaged separately so they do not shrink)"""

    bl_idname = "pelt.comb_smooth"
    bl_label = "Comb: Smooth"
    bl_options = {"REGISTER", "UNDO"}

    iterations: bpy.props.IntProperty(
        name="Iterations",
        description="Smoothing passes over the mesh edges",
        default=5,
        min=1,
        soft_max=50,
        max=1000,
    )
    factor: bpy.props.FloatProperty(
        name="Factor",
        description="Share of the neighbours' mean a vertex takes per pass",
        default=0.5,
        min=0.0,
        max=1.0,
        subtype="FACTOR",
    )
    only_selected: only_selected_property

    @classmethod
    def poll(cls, context):
        return context.active_object is not None

    def execute(self, context):
        try:
            obj = _comb_target(context)
            with point_data.object_mode(obj):
                mesh = obj.data
                mask = _mask(mesh, self.only_selected)
                if COMB not in mesh.attributes:
                    raise TargetError(f"'{obj.name}' has no comb to smooth: comb it first")
                note = point_data.ensure_point_attribute(obj, COMB, "FLOAT_VECTOR", 0.0)
                comb = comb_math.smooth(
                    point_data.read_point(mesh, COMB),
                    point_data.normals(mesh),
                    point_data.edges(mesh),
                    self.iterations,
                    self.factor,
                    mask,
                )
                point_data.write_point(mesh, COMB, comb)
        except _ERRORS as error:
            self.report({"ERROR"}, f"Pelt: {error}")
            return {"CANCELLED"}
        if note:
            self.report({"WARNING"}, f"Pelt: {obj.name}: {note}")
        self.report({"INFO"}, f"Pelt: {obj.name}: comb smoothed {self.iterations} times")
        return {"FINISHED"}


class PELT_OT_comb_from_curves(bpy.types.Operator):
    """Comb along hair curves: each strand's root-to-tip direction combs the vertex nearest its
    root; vertices without a strand take their neighbours' comb"""

    bl_idname = "pelt.comb_from_curves"
    bl_label = "Comb from Hair Curves"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return context.active_object is not None

    def execute(self, context):
        try:
            obj = _comb_target(context)
            sources = hair_curves_of(obj)
            if not sources:
                raise TargetError(f"no hair Curves object has '{obj.name}' as its surface")
            strands = [_strands_in_object_space(curves_obj, obj) for curves_obj in sources]
            roots = np.concatenate([s[0] for s in strands])
            directions = np.concatenate([s[1] for s in strands])
            curve_count = sum(s[2] for s in strands)
            if len(roots) == 0:
                raise TargetError(f"the hair curves on '{obj.name}' have no strand with two points")
            if len(obj.data.vertices) == 0:
                raise TargetError(f"'{obj.name}' has no vertices")
            with point_data.object_mode(obj):
                mesh = obj.data
                positions = point_data.positions(mesh)
                normals = point_data.normals(mesh)
                nearest = comb_math.nearest(positions, roots)
                direction, count = comb_math.mean_direction_per_vertex(nearest, directions, len(positions))
                known = count > 0
                comb = np.zeros_like(positions)
                comb[known] = comb_math.lean(direction[known], normals[known])
                comb, filled = comb_math.propagate(comb, known, point_data.edges(mesh), normals)
                note = point_data.ensure_point_attribute(obj, COMB, "FLOAT_VECTOR", 0.0)
                old = point_data.read_point(mesh, COMB)
                # vertices no strand reaches, even through neighbours, keep their comb
                comb[~filled] = old[~filled]
                point_data.write_point(mesh, COMB, comb)
        except _ERRORS as error:
            self.report({"ERROR"}, f"Pelt: {error}")
            return {"CANCELLED"}
        if note:
            self.report({"WARNING"}, f"Pelt: {obj.name}: {note}")
        self.report(
            {"INFO"},
            f"Pelt: {obj.name}: combed from {len(roots)} of {curve_count} strands "
            f"({', '.join(o.name for o in sources)}) at {int(known.sum())} vertices, "
            f"{int((filled & ~known).sum())} filled in",
        )
        return {"FINISHED"}


CLASSES = (PELT_OT_comb_gravity, PELT_OT_comb_smooth, PELT_OT_comb_from_curves)
