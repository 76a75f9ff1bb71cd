# SPDX-License-Identifier: GPL-3.0-or-later
"""The guard hairs of a bake as a hair Curves object over the furred mesh, so that EEVEE and
Cycles render them with the shells (the hybrid paper: explicit strands for the coarse guard
hairs, the volume for the undercoat).

One Curves object per furred object, tagged ``pelt_owner``/``pelt_role = "guard_hairs"``, parented
to it with an identity transform (the strands are in the mesh's object space), its surface set to
the mesh. A re-bake replaces the strands of that object only; a bake without guard hairs removes
it. The strands are prepared with the images (a failure leaves nothing) and put in place last.
Per point: ``position`` and ``radius``; per curve: ``pelt_root_color`` and ``pelt_tip_color``,
which the material blends along the strand (Curves Info's intercept) into a Principled Hair
BSDF's direct color.
"""

import bpy
import numpy as np

from .node_graph import NodeGraph
from .ownership import find_owned, tag

ROLE = "guard_hairs"
MATERIAL_ROLE = "guard_hair_material"
ROOT_COLOR = "pelt_root_color"
TIP_COLOR = "pelt_tip_color"


def find(obj):
    """Pelt's guard-hair object of ``obj``, or None."""
    return find_owned(bpy.data.objects, obj.name, ROLE)


def prepare(obj, guard: dict | None):
    """The new strands of ``obj`` as a Curves datablock, not yet shown (``None`` when the bake has
    no guard hairs); ``commit`` puts them in place. Raises with nothing left behind."""
    if guard is None or len(guard["counts"]) == 0:
        return None
    counts = np.asarray(guard["counts"], np.int64)
    curves = bpy.data.hair_curves.new(f"Pelt Guard Hairs {obj.name}")
    tag(curves, obj.name, ROLE)
    try:
        curves.add_curves(counts.tolist())
        positions = np.ascontiguousarray(guard["positions"], np.float32).ravel()
        curves.position_data.foreach_set("vector", positions)
        radius = curves.attributes.new("radius", "FLOAT", "POINT")
        radius.data.foreach_set("value", np.ascontiguousarray(guard["radii"], np.float32))
        for name, key in ((ROOT_COLOR, "root_colors"), (TIP_COLOR, "tip_colors")):
            rgb = np.asarray(guard[key], np.float32)
            rgba = np.concatenate([rgb, np.ones((len(rgb), 1), np.float32)], axis=1)
            curves.attributes.new(name, "FLOAT_COLOR", "CURVE").data.foreach_set("color", rgba.ravel())
        curves.materials.append(_material(obj))
        curves.surface = obj
    except BaseException:
        bpy.data.hair_curves.remove(curves)
        raise
    return curves


def commit(obj, curves) -> None:
    """Shows ``curves`` (from ``prepare``) as ``obj``'s guard hairs, replacing the strands of its
    guard-hair object (which keeps its collections and visibility) or making one; ``None`` removes
    the object. Nothing here can fail on valid datablocks, so the writer calls it last."""
    hair = find(obj)
    if curves is None:
        if hair is not None:
            _remove_object(hair)
        return
    if hair is not None:
        old = hair.data
        hair.data = curves
        if old is not None and old.users == 0:
            bpy.data.hair_curves.remove(old)
        return
    hair = bpy.data.objects.new(curves.name, curves)
    tag(hair, obj.name, ROLE)
    for collection in obj.users_collection:
        collection.objects.link(hair)
    hair.parent = obj
    hair.matrix_parent_inverse.identity()


def _material(obj):
    """Pelt's guard-hair material of ``obj``: a Principled Hair BSDF colored directly, root color
    to tip color along the strand."""
    material = find_owned(bpy.data.materials, obj.name, MATERIAL_ROLE)
    if material is not None:
        return material
    material = bpy.data.materials.new(f"Pelt Guard Hairs {obj.name}")
    tag(material, obj.name, MATERIAL_ROLE)
    tree = material.node_tree
    tree.nodes.clear()
    g = NodeGraph(tree)
    info = g.node("ShaderNodeHairInfo")
    root = g.node("ShaderNodeAttribute", attribute_type="GEOMETRY", attribute_name=ROOT_COLOR)
    tip = g.node("ShaderNodeAttribute", attribute_type="GEOMETRY", attribute_name=TIP_COLOR)
    mix = g.node(
        "ShaderNodeMix",
        {"Factor": info.outputs["Intercept"], "A": root.outputs["Color"], "B": tip.outputs["Color"]},
        data_type="RGBA",
    )
    bsdf = g.node(
        "ShaderNodeBsdfHairPrincipled",
        {"Color": mix.outputs["Result"]},
        parametrization="COLOR",
    )
    output = g.node("ShaderNodeOutputMaterial")
    g.set(output.inputs["Surface"], bsdf.outputs[0])
    return material


def _remove_object(hair) -> None:
    data = hair.data
    bpy.data.objects.remove(hair)
    if data is not None and data.users == 0:
        bpy.data.hair_curves.remove(data)
