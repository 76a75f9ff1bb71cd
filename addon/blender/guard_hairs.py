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

The strands follow the mesh's deformation (an armature, shape keys, modifiers): each curve keeps
its root's triangle (its three vertices, weights and rest positions), and a Geometry Nodes
modifier on the curves moves and turns every strand as that triangle moved and turned in the
mesh's evaluated geometry. Blender's own Deform Curves on Surface node cannot serve: it needs the
evaluated surface to keep the mesh's topology, and Pelt's fur modifier adds the shells and fins
(after the skin, whose vertices keep their indices, so they can be sampled by index).
"""

import bpy
import numpy as np

from ..io import bridge
from ..io.names import datablock_name
from ..io.ownership import find_owned, tag
from .node_graph import NodeGraph

ROLE = "guard_hairs"
MATERIAL_ROLE = "guard_hair_material"
DEFORM_ROLE = "guard_hair_deform"
ROOT_COLOR = "pelt_root_color"
TIP_COLOR = "pelt_tip_color"
DEFORM_MODIFIER = "Pelt Follow Surface"
# Per curve: the root triangle's vertices, the root's weights there, and the corners at rest.
ROOT_VERTICES = ("pelt_root_v0", "pelt_root_v1", "pelt_root_v2")
ROOT_WEIGHTS = "pelt_root_weights"
REST_CORNERS = ("pelt_rest_p0", "pelt_rest_p1", "pelt_rest_p2")


def find(obj):
    """Pelt's guard-hair object of ``obj``, or None."""
    return find_owned(bpy.data.objects, obj.name, ROLE)


def prepare(obj, guard: dict | None):
    """The new strands of ``obj`` as a Curves datablock, not yet shown (``None`` when the bake has
    no guard hairs); ``commit`` puts them in place. Raises with nothing left behind."""
    if guard is None or len(guard["counts"]) == 0:
        return None
    counts = np.asarray(guard["counts"], np.int64)
    corners = root_corners(obj.data, guard["root_triangles"])
    curves = bpy.data.hair_curves.new(datablock_name("Guard Hairs", obj.name))
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
        for name, vertices in zip(ROOT_VERTICES, corners.T, strict=True):
            curves.attributes.new(name, "INT", "CURVE").data.foreach_set("value", vertices)
        weights = np.ascontiguousarray(guard["root_weights"], np.float32)
        curves.attributes.new(ROOT_WEIGHTS, "FLOAT_VECTOR", "CURVE").data.foreach_set(
            "vector", weights.ravel()
        )
        rest = bridge.read_positions(obj.data)[corners]
        for k, name in enumerate(REST_CORNERS):
            attribute = curves.attributes.new(name, "FLOAT_VECTOR", "CURVE")
            attribute.data.foreach_set("vector", np.ascontiguousarray(rest[:, k]).ravel())
        curves.materials.append(_material(obj))
        curves.surface = obj
    except BaseException:
        bpy.data.hair_curves.remove(curves)
        raise
    return curves


def root_corners(mesh, triangles) -> np.ndarray:
    """``[S, 3]`` int32: the vertices of each root's loop triangle (the triangles Pelt read,
    ``bridge.loop_triangles``), in the order of its weights."""
    loops, _ = bridge.loop_triangles(mesh)
    corners = bridge.corner_vertices(mesh)[loops[np.asarray(triangles, np.int64)]]
    return np.ascontiguousarray(corners.view(np.int32))


def commit(obj, curves) -> None:
    """Shows the strands from ``prepare`` as ``obj``'s guard hairs, replacing those of its
    guard-hair object (which keeps its collections and visibility) or making one; ``None``
    removes the object. Nothing here can fail on valid datablocks, so the writer calls it last."""
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
    else:
        hair = bpy.data.objects.new(curves.name, curves)
        tag(hair, obj.name, ROLE)
        for collection in obj.users_collection:
            collection.objects.link(hair)
        hair.parent = obj
        hair.matrix_parent_inverse.identity()
    modifier = hair.modifiers.get(DEFORM_MODIFIER) or hair.modifiers.new(DEFORM_MODIFIER, "NODES")
    group = _follow_group(obj)
    modifier.node_group = group
    modifier[group.interface.items_tree["Surface"].identifier] = obj


def _follow_group(obj):
    """Pelt's node group of ``obj`` that moves and turns each strand as its root triangle moved
    and turned from rest to the surface's evaluated skin (its first vertices, by index)."""
    group = find_owned(bpy.data.node_groups, obj.name, DEFORM_ROLE)
    if group is not None:
        return group
    group = bpy.data.node_groups.new(datablock_name("Follow Surface", obj.name), "GeometryNodeTree")
    tag(group, obj.name, DEFORM_ROLE)
    group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    group.interface.new_socket("Surface", in_out="INPUT", socket_type="NodeSocketObject")
    group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    g = NodeGraph(group)
    inputs = g.node("NodeGroupInput").outputs
    surface = g.node("GeometryNodeObjectInfo", {"Object": inputs["Surface"]}, transform_space="ORIGINAL")
    position = g.node("GeometryNodeInputPosition").outputs[0]

    def named(name, data_type):
        return g.node("GeometryNodeInputNamedAttribute", {"Name": name}, data_type=data_type).outputs[0]

    now = [
        g.node(
            "GeometryNodeSampleIndex",
            {"Geometry": surface.outputs["Geometry"], "Value": position, "Index": named(v, "INT")},
            data_type="FLOAT_VECTOR",
            domain="POINT",
        ).outputs[0]
        for v in ROOT_VERTICES
    ]
    rest = [named(p, "FLOAT_VECTOR") for p in REST_CORNERS]
    weights = g.node("ShaderNodeSeparateXYZ", {"Vector": named(ROOT_WEIGHTS, "FLOAT_VECTOR")}).outputs

    def point(corners):
        scaled = [g.vector_math("SCALE", c, scale=w) for c, w in zip(corners, weights, strict=True)]
        return g.vector_math("ADD", g.vector_math("ADD", scaled[0], scaled[1]), scaled[2])

    def frame(corners):
        edge = g.vector_math("SUBTRACT", corners[1], corners[0])
        normal = g.vector_math("CROSS_PRODUCT", edge, g.vector_math("SUBTRACT", corners[2], corners[0]))
        return g.node("FunctionNodeAxesToRotation", {"Primary Axis": normal, "Secondary Axis": edge}).outputs[
            0
        ]

    undo_rest = g.node("FunctionNodeInvertRotation", {"Rotation": frame(rest)}).outputs[0]
    turn = g.node(
        "FunctionNodeRotateRotation",
        {"Rotation": undo_rest, "Rotate By": frame(now)},
        rotation_space="GLOBAL",
    ).outputs[0]
    offset = g.vector_math("SUBTRACT", position, point(rest))
    turned = g.node("FunctionNodeRotateVector", {"Vector": offset, "Rotation": turn}).outputs[0]
    moved = g.node(
        "GeometryNodeSetPosition",
        {"Geometry": inputs["Geometry"], "Position": g.vector_math("ADD", point(now), turned)},
    )
    g.node("NodeGroupOutput", {"Geometry": moved.outputs[0]})
    return group


def _material(obj):
    """Pelt's guard-hair material of ``obj``: a Principled Hair BSDF colored directly, root color
    to tip color along the strand."""
    material = find_owned(bpy.data.materials, obj.name, MATERIAL_ROLE)
    if material is not None:
        return material
    material = bpy.data.materials.new(datablock_name("Guard Hairs", obj.name))
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
