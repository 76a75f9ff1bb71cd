# SPDX-License-Identifier: GPL-3.0-or-later
"""The geometry side of the Blender fur: a Geometry Nodes modifier ``Pelt Fur`` (node group
``Pelt Fur <object>``) that grows shells and fins on the mesh (Lengyel et al. 2001, §2.3), so
EEVEE and Cycles render Pelt's bake.

The node group outputs, joined in this order:

1. the **skin**: the mesh itself, ``pelt_layer`` = 0, material ``Pelt Fur`` on its furred faces
   (and on its bald faces when the object has no material of its own: otherwise they keep
   theirs, such as the eyes of a head);
2. the **shells** ``1..S-1``: the mesh without its bald faces (length 0 at every corner), turned
   into one instance, duplicated ``S - 1`` times (Duplicate Elements on the instance domain), each
   copy's layer ``round(j (L - 1) / (S - 1))`` and height ``pelt_height = layer / L`` stored on
   its instance, then realized at once, lifted by ``pelt_height × top`` and ``top`` stored as
   ``pelt_top``; each face's area over its skin face's, less 1, as the face attribute
   ``pelt_spread`` (the material thins the hair by it).
   ``top = depth × length × (normal + comb - normal (normal · comb))`` is captured per vertex
   on the whole mesh first, so a shell's border vertices move as the skin's normals say (as
   ``crates/pelt-render/src/shells.wgsl`` does), not as their trimmed copy's would; material
   ``Pelt Fur``;
3. the **fins** (when Fins is on): every edge with some length at either end, duplicated into its
   own two vertices and extruded, each end to its own tip (``top``, as ``crates/pelt-render/src/fins.wgsl``
   lifts them): one quad per edge, with the UV map ``pelt_fin_uv``
   (``u`` from a random start per edge, running ``edge length / tile size`` along the edge; ``v``
   0 at the root, 1 at the tip) and the face attribute ``pelt_fin_normal`` (the unsheared fin's
   normal, for the fade), ``pelt_fin_spread`` (how much wider the fin is at its tip, less 1, for
   the thinning) and the point attribute ``pelt_growth`` (the unit direction of ``top``,
   the hair the fin shows, which its material lights); material ``Pelt Fin``.

Missing attributes read as Pelt's defaults: ``pelt_length`` 1, ``pelt_comb`` 0, ``pelt_color``
white (color and length, at least 0, stored on the output, so the materials always find them).
The inputs Layers, Shells, Depth, Fins and Tile Size show in the modifier panel.
"""

import bpy
import pelt

from ..io.fur_layout import FurSettings
from ..io.names import COLOR, COMB, LENGTH, datablock_name
from ..io.ownership import find_owned, is_owned
from . import templates
from .materials import (
    FIN_NORMAL_ATTRIBUTE,
    FIN_ROLE,
    FIN_SPREAD_ATTRIBUTE,
    FIN_UV_ATTRIBUTE,
    FUR_ROLE,
    GROWTH_ATTRIBUTE,
    HEIGHT_ATTRIBUTE,
    LAYER_ATTRIBUTE,
    SPREAD_ATTRIBUTE,
    TOP_ATTRIBUTE,
)
from .node_graph import NodeGraph, output

NODES_ROLE = "fur_nodes"
MODIFIER_NAME = "Pelt Fur"

# (socket name, socket type, FurSettings field, tooltip, minimum)
INPUTS = (
    ("Layers", "NodeSocketInt", "layers", "Layers of the shell atlas: layer k sits at k/Layers of Depth", 1),
    ("Shells", "NodeSocketInt", "shells", "Surfaces drawn, the skin included (at most Layers)", 1),
    ("Depth", "NodeSocketFloat", "depth", "Fur depth in object units: how far hair of length 1 reaches", 0.0),
    ("Fins", "NodeSocketBool", "fins", "A textured fin on every furred edge (seen near the outline)", None),
    ("Tile Size", "NodeSocketFloat", "tile_size", "Object units per tile of the fin texture", 1e-6),
)
# Set from the object, not the settings (``own_materials``).
BALD_SKIN = (
    "Bald Skin",
    "NodeSocketBool",
    "Pelt's skin material on bald faces too (off when the object has materials of its own, which "
    "bald faces then keep)",
)


# The Set Material nodes, set per object (``templates.set_values``).
SKIN_MATERIAL_NODE = "Pelt Skin Material"
SHELL_MATERIAL_NODE = "Pelt Shell Material"
FIN_MATERIAL_NODE = "Pelt Fin Material"


def node_group_name(obj) -> str:
    return datablock_name("Fur", obj.name)


def build_fur_modifier(obj, settings: FurSettings, *, fur_material=None, fin_material=None):
    """Creates or updates Pelt's Geometry Nodes fur on ``obj`` (a mesh object) with the inputs of
    ``settings``; returns the modifier. The materials default to Pelt's own ``Pelt Fur`` / ``Pelt
    Fin`` materials of ``obj`` (``materials.build_fur_material`` / ``build_fin_material``); without
    them the faces keep no material. Raises ``pelt.PeltError`` (changing nothing) when ``obj`` is
    not a mesh object or ``settings`` is not a ``FurSettings``."""
    check_target(obj, settings)
    fur_material = fur_material or find_owned(bpy.data.materials, obj.name, FUR_ROLE)
    fin_material = fin_material or find_owned(bpy.data.materials, obj.name, FIN_ROLE)
    # The tree is the same for every object (the settings are the modifier's inputs), so a
    # re-bake keeps it and a first bake copies the shipped one.
    group = templates.owned_tree(obj.name, NODES_ROLE, node_group_name(obj), new_node_group)
    shell_materials = {SKIN_MATERIAL_NODE: fur_material, SHELL_MATERIAL_NODE: fur_material}
    templates.set_values(group, {**shell_materials, FIN_MATERIAL_NODE: fin_material})
    modifier = find_modifier(obj)
    if modifier is None:
        modifier = obj.modifiers.new(MODIFIER_NAME, "NODES")
    if modifier.node_group != group:
        modifier.node_group = group
    values = {row[0]: getattr(settings, row[2]) for row in INPUTS}
    values[BALD_SKIN[0]] = not own_materials(obj)
    for item in group.interface.items_tree:
        if item.item_type == "SOCKET" and item.in_out == "INPUT" and item.name in values:
            modifier[item.identifier] = values[item.name]
    obj.update_tag()
    return modifier


def own_materials(obj) -> bool:
    """Whether ``obj`` has a material of its own in some slot (Pelt's are on the modifier's
    output, never in the object's slots)."""
    return any(slot.material is not None for slot in obj.material_slots)


def check_target(obj, settings) -> None:
    """Raises ``pelt.PeltError`` unless ``obj`` is a mesh object and ``settings`` a ``FurSettings``."""
    if obj is None or obj.type != "MESH":
        raise pelt.InvalidMeshError("Pelt fur needs a mesh object")
    if not isinstance(settings, FurSettings):
        raise pelt.InvalidParameterError(
            f"invalid parameter `settings`: must be FurSettings, got {settings!r}"
        )


def find_modifier(obj):
    """The Geometry Nodes modifier of ``obj`` that runs Pelt's fur node group for ``obj``, or None."""
    return next(
        (
            m
            for m in obj.modifiers
            if m.type == "NODES" and m.node_group is not None and is_owned(m.node_group, obj.name, NODES_ROLE)
        ),
        None,
    )


def new_node_group(name: str):
    """A new node group ``name`` growing the fur (module docs); its Set Material nodes are the
    named ones that ``build_fur_modifier`` sets."""
    group = bpy.data.node_groups.new(name, "GeometryNodeTree")
    group.is_modifier = True
    group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    for socket_name, socket_type, field, tooltip, minimum in INPUTS:
        item = group.interface.new_socket(socket_name, in_out="INPUT", socket_type=socket_type)
        item.description = tooltip
        item.default_value = getattr(FurSettings(), field)
        if minimum is not None:
            item.min_value = minimum
    bald_skin = group.interface.new_socket(BALD_SKIN[0], in_out="INPUT", socket_type=BALD_SKIN[1])
    bald_skin.description = BALD_SKIN[2]
    bald_skin.default_value = True
    group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")

    g = NodeGraph(group)
    inputs = g.node("NodeGroupInput").outputs
    base = _with_default_color(g, inputs["Geometry"])
    base, top, length = _capture_growth(g, base, inputs["Depth"])

    skin = _store(g, base, LAYER_ATTRIBUTE, "FLOAT", "POINT", 0.0)
    skin = g.node(
        "GeometryNodeSetMaterial",
        {"Geometry": skin, "Selection": _skin_faces(g, length, inputs[BALD_SKIN[0]])},
        name=SKIN_MATERIAL_NODE,
    ).outputs[0]
    shells = _shells(g, base, top, length, inputs["Layers"], inputs["Shells"])
    shells = g.node("GeometryNodeSetMaterial", {"Geometry": shells}, name=SHELL_MATERIAL_NODE).outputs[0]
    fins = _fins(g, base, top, length, inputs["Tile Size"])
    fins = g.node("GeometryNodeSetMaterial", {"Geometry": fins}, name=FIN_MATERIAL_NODE).outputs[0]
    fins = g.node("GeometryNodeSwitch", {"Switch": inputs["Fins"], "True": fins}, input_type="GEOMETRY")

    join = g.node("GeometryNodeJoinGeometry")
    # A multi-input socket puts its newest link first: link the last part first.
    for part in (output(fins, "Output"), shells, skin):
        group.links.new(part, join.inputs["Geometry"])
    g.node("NodeGroupOutput", {"Geometry": join.outputs["Geometry"]})
    return group


def _skin_faces(g: NodeGraph, length, bald_skin):
    """The faces that take Pelt's skin material: the furred ones (some corner with length), and
    the bald ones too when ``bald_skin`` (an object without materials of its own)."""
    furred = g.node("FunctionNodeBooleanMath", {("Boolean", 0): _bald(g, length)}, operation="NOT")
    either = g.node(
        "FunctionNodeBooleanMath",
        {("Boolean", 0): furred.outputs[0], ("Boolean", 1): bald_skin},
        operation="OR",
    )
    return either.outputs[0]


def _bald(g: NodeGraph, length):
    """Where the length multiplier is 0: read on faces, those bald at every corner."""
    inputs = {"A": length, "B": 0.0}
    compare = g.node("FunctionNodeCompare", inputs, data_type="FLOAT", operation="LESS_EQUAL")
    return compare.outputs["Result"]


def _named(g: NodeGraph, name: str, data_type: str):
    """A Named Attribute node reading ``name``: outputs Attribute and Exists."""
    return g.node("GeometryNodeInputNamedAttribute", {"Name": name}, data_type=data_type)


def _store(g: NodeGraph, geometry, name: str, data_type: str, domain: str, value):
    node = g.node(
        "GeometryNodeStoreNamedAttribute",
        {"Geometry": geometry, "Name": name, "Value": value},
        data_type=data_type,
        domain=domain,
    )
    return node.outputs["Geometry"]


def _with_default_color(g: NodeGraph, geometry):
    """``geometry`` with ``pelt_color`` as a float color, white where the mesh has none."""
    color = _named(g, COLOR, "FLOAT_COLOR")
    value = g.node(
        "GeometryNodeSwitch",
        {
            "Switch": color.outputs["Exists"],
            "False": (1.0, 1.0, 1.0, 1.0),
            "True": output(color, "Attribute"),
        },
        input_type="RGBA",
    )
    return _store(g, geometry, COLOR, "FLOAT_COLOR", "POINT", output(value, "Output"))


def _capture_growth(g: NodeGraph, geometry, depth):
    """Captures, per vertex of the whole mesh, the length multiplier (1 where ``pelt_length`` is
    missing, never below 0; stored as ``pelt_length`` for the materials' self-shadowing) and
    ``top``, the offset of the fur's tips; returns the geometry and the two fields."""
    length_attribute = _named(g, LENGTH, "FLOAT")
    length = g.node(
        "GeometryNodeSwitch",
        {
            "Switch": length_attribute.outputs["Exists"],
            "False": 1.0,
            "True": output(length_attribute, "Attribute"),
        },
        input_type="FLOAT",
    )
    length = g.math("MAXIMUM", output(length, "Output"), 0.0)
    normal = g.node("GeometryNodeInputNormal").outputs["Normal"]
    comb = output(_named(g, COMB, "FLOAT_VECTOR"), "Attribute")
    along_normal = g.vector_math("SCALE", normal, scale=g.vector_math("DOT_PRODUCT", normal, comb))
    growth = g.vector_math("SUBTRACT", g.vector_math("ADD", normal, comb), along_normal)
    top = g.vector_math("SCALE", growth, scale=g.math("MULTIPLY", depth, length))

    capture = g.node("GeometryNodeCaptureAttribute", domain="POINT")
    capture.capture_items.new("VECTOR", "Top")
    capture.capture_items.new("FLOAT", "Length")
    g.set(capture.inputs["Geometry"], _store(g, geometry, LENGTH, "FLOAT", "POINT", length))
    g.set(capture.inputs["Top"], top)
    g.set(capture.inputs["Length"], length)
    return capture.outputs["Geometry"], capture.outputs["Top"], capture.outputs["Length"]


def _shells(g: NodeGraph, base, top, length, layers, shells):
    """Shells ``1..S-1``: the furred faces, once per shell, each lifted to its layer (``S`` at
    most ``L``, whatever the modifier panel says)."""
    shells = g.math("MINIMUM", shells, layers)
    furred = g.node(
        "GeometryNodeDeleteGeometry",
        {"Geometry": base, "Selection": _bald(g, length)},
        domain="FACE",
        mode="ALL",
    ).outputs[0]
    skin_area = g.node("GeometryNodeCaptureAttribute", domain="FACE")
    skin_area.capture_items.new("FLOAT", "Area")
    g.set(skin_area.inputs["Geometry"], furred)
    g.set(skin_area.inputs["Area"], g.node("GeometryNodeInputMeshFaceArea").outputs["Area"])
    instance = g.node("GeometryNodeGeometryToInstance", {"Geometry": skin_area.outputs["Geometry"]})
    instance = instance.outputs[0]
    copies = g.node(
        "GeometryNodeDuplicateElements",
        {"Geometry": instance, "Amount": g.math("SUBTRACT", shells, 1.0)},
        domain="INSTANCE",
    )
    # Shell j = duplicate + 1 shows layer round(j (L - 1) / (S - 1)), halves up, as shells.wgsl
    # does in integers: a quotient ending in .5 is exact in floats, and any other lies at least
    # 1 / (S - 1) away from a half, far beyond the rounding error.
    j = g.math("ADD", copies.outputs["Duplicate Index"], 1.0)
    spread = g.math(
        "DIVIDE", g.math("MULTIPLY", j, g.math("SUBTRACT", layers, 1.0)), g.math("SUBTRACT", shells, 1.0)
    )
    layer = g.math("FLOOR", g.math("ADD", spread, 0.5))
    tagged = _store(g, copies.outputs["Geometry"], LAYER_ATTRIBUTE, "FLOAT", "INSTANCE", layer)
    # The shell's height as a share of the fur depth, for the material's self-shadowing.
    tagged = _store(g, tagged, HEIGHT_ATTRIBUTE, "FLOAT", "INSTANCE", g.math("DIVIDE", layer, layers))
    realized = g.node("GeometryNodeRealizeInstances", {"Geometry": tagged}).outputs[0]
    height = output(_named(g, HEIGHT_ATTRIBUTE, "FLOAT"), "Attribute")
    lifted = g.node(
        "GeometryNodeSetPosition", {"Geometry": realized, "Offset": g.vector_math("SCALE", top, scale=height)}
    )
    # How much wider each face is than its skin face: the hair there stands that much further
    # apart (its number and width are the skin's), which the material thins the coverage by.
    area = g.node("GeometryNodeInputMeshFaceArea").outputs["Area"]
    spread = g.math("SUBTRACT", g.math("DIVIDE", area, skin_area.outputs["Area"]), 1.0)
    shells = _store(g, lifted.outputs[0], SPREAD_ATTRIBUTE, "FLOAT", "FACE", spread)
    # The fur's height here, which tells the material how far a ray is from its own fur.
    return _store(g, shells, TOP_ATTRIBUTE, "FLOAT_VECTOR", "POINT", top)


def _fins(g: NodeGraph, base, top, length, tile_size):
    """One quad per furred edge, from the edge to its ends' tips, with the UV map ``pelt_fin_uv``."""
    edge = g.node("GeometryNodeInputMeshEdgeVertices").outputs
    span = g.math(
        "DIVIDE",
        g.vector_math("DISTANCE", edge["Position 1"], edge["Position 2"]),
        tile_size,
    )
    start = g.node(
        "FunctionNodeRandomValue",
        {("Min", 0): 0.0, ("Max", 0): 1.0, "ID": g.node("GeometryNodeInputIndex").outputs[0]},
        data_type="FLOAT",
    )
    per_edge = g.node("GeometryNodeCaptureAttribute", domain="EDGE")
    per_edge.capture_items.new("FLOAT", "Start")
    per_edge.capture_items.new("FLOAT", "Span")
    per_edge.capture_items.new("VECTOR", "Fin Normal")
    per_edge.capture_items.new("FLOAT", "Tip Spread")
    g.set(per_edge.inputs["Geometry"], base)
    g.set(per_edge.inputs["Start"], output(start, "Value"))
    g.set(per_edge.inputs["Span"], span)
    g.set(per_edge.inputs["Fin Normal"], _fin_normal(g, edge))
    g.set(per_edge.inputs["Tip Spread"], _tip_spread(g, edge, top))

    # An edge's length multiplier is the mean of its ends': > 0 when either end has fur.
    furred = g.node(
        "FunctionNodeCompare", {"A": length, "B": 0.0}, data_type="FLOAT", operation="GREATER_THAN"
    )
    edges = g.node(
        "GeometryNodeDuplicateElements",
        {"Geometry": per_edge.outputs["Geometry"], "Selection": furred.outputs["Result"]},
        domain="EDGE",
    ).outputs["Geometry"]

    # Each duplicated edge has its own two vertices: the second end runs `span` further along u.
    # (Edge Vertices is read on the edges, then carried to each edge's two vertices.)
    second_end = g.node(
        "GeometryNodeFieldOnDomain",
        {"Value": edge["Vertex Index 2"]},
        domain="EDGE",
        data_type="INT",
    )
    is_second = g.node(
        "FunctionNodeCompare",
        {"A": g.node("GeometryNodeInputIndex").outputs[0], "B": output(second_end, "Value")},
        data_type="INT",
        operation="EQUAL",
    )
    u = g.math(
        "MULTIPLY_ADD", is_second.outputs["Result"], per_edge.outputs["Span"], per_edge.outputs["Start"]
    )
    per_point = g.node("GeometryNodeCaptureAttribute", domain="POINT")
    per_point.capture_items.new("FLOAT", "U")
    per_point.capture_items.new("VECTOR", "Fin Normal")
    per_point.capture_items.new("FLOAT", "Tip Spread")
    g.set(per_point.inputs["Geometry"], edges)
    g.set(per_point.inputs["U"], u)
    g.set(per_point.inputs["Fin Normal"], per_edge.outputs["Fin Normal"])
    g.set(per_point.inputs["Tip Spread"], per_edge.outputs["Tip Spread"])
    roots = per_point.outputs["Geometry"]

    root_count = g.node("GeometryNodeAttributeDomainSize", {"Geometry": roots}, component="MESH")
    # Extrusion appends the tip vertices after the roots, each a copy of its root with its `top`.
    # They are lifted after the extrusion, each by its own `top` (the node would move both ends of
    # an edge by their mean), so a fin's tips meet the tips of the hair around it.
    extruded = g.node(
        "GeometryNodeExtrudeMesh",
        {"Mesh": roots, "Offset": (0.0, 0.0, 0.0), "Offset Scale": 0.0},
        mode="EDGES",
    ).outputs["Mesh"]
    is_tip = g.node(
        "FunctionNodeCompare",
        {"A": g.node("GeometryNodeInputIndex").outputs[0], "B": root_count.outputs["Point Count"]},
        data_type="INT",
        operation="GREATER_EQUAL",
    )
    extruded = g.node(
        "GeometryNodeSetPosition",
        {"Geometry": extruded, "Selection": is_tip.outputs["Result"], "Offset": top},
    ).outputs[0]
    uv = g.node(
        "GeometryNodeFieldOnDomain",
        {"Value": g.combine(per_point.outputs["U"], is_tip.outputs["Result"])},
        domain="POINT",
        data_type="FLOAT_VECTOR",
    )
    fins = _store(g, extruded, FIN_UV_ATTRIBUTE, "FLOAT2", "CORNER", output(uv, "Value"))
    # The hair's direction, which the fin material lights (the fin's own plane is not the hair's).
    fins = _store(g, fins, GROWTH_ATTRIBUTE, "FLOAT_VECTOR", "POINT", g.vector_math("NORMALIZE", top))
    fins = _store(g, fins, FIN_SPREAD_ATTRIBUTE, "FLOAT", "FACE", per_point.outputs["Tip Spread"])
    return _store(g, fins, FIN_NORMAL_ATTRIBUTE, "FLOAT_VECTOR", "FACE", per_point.outputs["Fin Normal"])


def _tip_spread(g: NodeGraph, edge, top):
    """Per edge, how much wider its fin is at the tip than at the root, less 1: the ends' ``top``
    difference along the edge over its squared length, as ``fin_density`` in
    ``crates/pelt-render/src/fins.wgsl`` measures it."""
    tops = _at_ends(g, edge, top)
    along = g.vector_math("SUBTRACT", edge["Position 2"], edge["Position 1"])
    lift = g.vector_math("SUBTRACT", tops[1], tops[0])
    return g.math(
        "DIVIDE", g.vector_math("DOT_PRODUCT", lift, along), g.vector_math("DOT_PRODUCT", along, along)
    )


def _fin_normal(g: NodeGraph, edge):
    """Per edge, the unit normal of its unsheared fin: edge × (sum of its ends' normals), as
    ``crates/pelt-render/src/fin_mesh.rs`` computes it. The fade uses this plane, not the quad's own (which
    the comb tilts toward the viewer), so a combed fin shows no more than an upright one."""
    ends = _at_ends(g, edge, g.node("GeometryNodeInputNormal").outputs["Normal"])
    along = g.vector_math("SUBTRACT", edge["Position 2"], edge["Position 1"])
    return g.vector_math("NORMALIZE", g.vector_math("CROSS_PRODUCT", along, g.vector_math("ADD", *ends)))


def _at_ends(g: NodeGraph, edge, vector):
    """The point field ``vector`` at an edge's two ends (``edge``: an Edge Vertices node's outputs)."""
    return [
        output(
            g.node(
                "GeometryNodeFieldAtIndex",
                {"Value": vector, "Index": edge[f"Vertex Index {k}"]},
                domain="POINT",
                data_type="FLOAT_VECTOR",
            ),
            "Value",
        )
        for k in (1, 2)
    ]
