# SPDX-License-Identifier: GPL-3.0-or-later
"""The shader side of the Blender fur: materials ``Pelt Fur <object>`` (skin and shells) and
``Pelt Fin <object>`` (fins), for EEVEE and Cycles (Lengyel et al. 2001, §2.3).

``Pelt Fur`` samples the shell atlas at the layer of each face's shell: the geometry nodes
(``geonodes.py``) store that layer in the point attribute ``pelt_layer``, and the material reads
``atlas_uv = (cell(layer) + fract(PeltUV)) / (columns, rows)``, flipped to Blender's bottom-up rows
(``fur_layout.atlas_uv`` is the same formula in numpy). The layer cells sit side by side in one
image, so the sample must never blend two cells: the image is read with Closest interpolation
(no filtering across a border, and no mipmaps whose texels would straddle two layers) and the
in-cell coordinate is kept half a texel inside the cell, so even a coordinate landing exactly on a
border reads its own layer. Color = texel × ``pelt_color`` (× ``HAIR_DIFFUSE`` on the skin, the
preview's Lambertian ``Kd``); alpha = texel alpha × the color's alpha, 1 on the skin (layer 0),
thinned where the shell is wider than its skin face (``pelt_spread``, ``_thinned``).

``Pelt Fin`` samples the fin texture at ``pelt_fin_uv`` (``u`` along the edge, repeating; ``v`` 0 at
the root, 1 at the tip, kept half a texel inside so the tip never wraps to the root) and fades the
fin by ``max(0, 2|p| - 1)``, ``p`` = fin normal · view direction, so only fins near the silhouette
show. The fin normal is the unsheared fin's (``pelt_fin_normal``, object space), as in
``crates/pelt-render/src/fins.wgsl``. Its alpha thins as the fin widens toward the tip
(``pelt_fin_spread``: ``1 + v × spread`` times the edge's width at height ``v``).

Both shade as the preview does (``crates/pelt-render/src/lighting.wgsl``), so that a render agrees
with it:

- **The fur's shadow on itself is the preview's Banks term** (Lengyel §2.4): the color is darkened
  by ``SELF_SHADOW`` at the skin under hair of length 1, ``1 - (1 - SELF_SHADOW)^length`` under
  the painted ``pelt_length`` (none on bald skin), fading to none at the tips (``pelt_height`` on
  the shells, ``v`` on the fins). Shadow and diffuse rays pass the fins, and the shells within
  ``SELF_REACH`` fur depths of where they started (``pelt_top``, Light Path's Ray Length): the
  skin, as the preview's body shadow, and shells further away, as the fur's shadow on other
  things, stop them. A shadow ray through the shells met each layer's
  coverage as if it were independent of the next, whereas a hair's cross-sections line up along
  it: a slanted light was dimmed again at every layer, so the more shells, the darker (Cycles at
  0.24–0.72 of the reference renderer's strands on a furred sphere at 16 layers).
- **Fins are lit as the hair they show:** a Lambertian and a translucent lobe about the normal
  of the hair's cylinder that faces the eye (``pelt_growth`` is the hair's direction), so a light
  from the eye lights it fully and a light along the hair not at all, as Kajiya–Kay's diffuse
  term does. The fin quad's own normal had lit the fringe black under a light from above.

Both render with EEVEE's DITHERED method: it writes depth and needs no sorting, so the many
overlapping shells and fins of one object composite correctly (BLENDED sorts per object only).
Cycles takes the alpha as transparency; it needs as many transparent bounces as surfaces a ray
crosses (``fur.prepare_scene``).
"""

import bpy
import pelt

from ..io.names import COLOR, LENGTH, UV_MAP, datablock_name
from . import templates
from .node_graph import NodeGraph, output

FUR_ROLE = "fur_material"
FIN_ROLE = "fin_material"
LAYER_ATTRIBUTE = "pelt_layer"
FIN_UV_ATTRIBUTE = "pelt_fin_uv"
FIN_NORMAL_ATTRIBUTE = "pelt_fin_normal"
HEIGHT_ATTRIBUTE = "pelt_height"
GROWTH_ATTRIBUTE = "pelt_growth"
TOP_ATTRIBUTE = "pelt_top"
# A shell face's area over its skin face's, less 1 (face attribute); a fin's width at its tip
# over its edge's, less 1 (face attribute): how far the hair there stands apart (`_thinned`).
SPREAD_ATTRIBUTE = "pelt_spread"
FIN_SPREAD_ATTRIBUTE = "pelt_fin_spread"
# How far the hair may thin out or crowd: the preview's bound (`MIN_SPREAD` in
# crates/pelt-render/src/common.wgsl), where a hollow's focus leaves a lifted face no area.
MIN_SPREAD = 0.25
# Fur depths a shadow or diffuse ray may run through its own fur's shells (the Banks term stands
# for that shadow) before a shell stops it: a light 75° off the normal crosses the fur within 4.
SELF_REACH = 4.0
# The preview's Kajiya-Kay diffuse coefficient and Banks self-shadowing (the library's defaults,
# which ``preview.object_lighting`` passes explicitly): the materials shade with the same values.
HAIR_DIFFUSE = 0.9
SELF_SHADOW = 0.15
RENDER_METHODS = ("DITHERED", "BLENDED")
# The nodes that hold what differs per object (``templates.set_values``).
ATLAS_NODE = "Pelt Atlas"
COLUMNS_NODE = "Pelt Atlas Columns"
ROWS_NODE = "Pelt Atlas Rows"
INSET_NODE = "Pelt Atlas Inset"
FIN_NODE = "Pelt Fin Texture"
FIN_INSET_NODE = "Pelt Fin Inset"


def fur_material_name(obj) -> str:
    return datablock_name("Fur", obj.name)


def fin_material_name(obj) -> str:
    return datablock_name("Fin", obj.name)


def build_fur_material(obj, images: dict, layout: dict, *, render_method: str = "DITHERED"):
    """Creates or updates Pelt's skin-and-shell material for ``obj`` from ``images["shells"]``
    (the shell atlas image) and ``layout`` (the atlas layout of ``pelt.pack_atlas``: ``columns``,
    ``rows``, ``tile``); returns it. Raises ``pelt.InvalidParameterError`` (changing nothing) when
    an input is missing or malformed."""
    atlas = _image(images, "shells")
    columns, rows, tile = (_positive_int(layout, key) for key in ("columns", "rows", "tile"))
    _check_render_method(render_method)
    material = _material(obj, FUR_ROLE, fur_material_name(obj), render_method, new_fur_material)
    templates.set_values(
        material.node_tree,
        {ATLAS_NODE: atlas, COLUMNS_NODE: float(columns), ROWS_NODE: float(rows), INSET_NODE: 0.5 / tile},
    )
    return material


def new_fur_material(name: str):
    """A new material ``name`` with the skin-and-shell tree; the atlas and its layout are the
    named nodes that ``build_fur_material`` sets."""
    material, g = _new_material(name)
    u, v, _ = g.separate(g.node("ShaderNodeUVMap", uv_map=UV_MAP).outputs["UV"])
    columns, rows, inset = (g.value(node, 1.0) for node in (COLUMNS_NODE, ROWS_NODE, INSET_NODE))
    layer_node = g.node("ShaderNodeAttribute", attribute_type="GEOMETRY", attribute_name=LAYER_ATTRIBUTE)
    layer = g.math("ROUND", layer_node.outputs["Fac"])
    column = g.math("FLOORED_MODULO", layer, columns)
    row = g.math("FLOOR", g.math("DIVIDE", layer, columns))
    bounds = (inset, g.math("SUBTRACT", 1.0, inset))
    atlas_u = g.math("DIVIDE", g.math("ADD", column, _inside(g, g.math("FRACT", u), *bounds)), columns)
    atlas_v = g.math(
        "SUBTRACT", 1.0, g.math("DIVIDE", g.math("ADD", row, _inside(g, g.math("FRACT", v), *bounds)), rows)
    )
    texel = g.node(
        "ShaderNodeTexImage",
        {"Vector": g.combine(atlas_u, atlas_v)},
        name=ATLAS_NODE,
        interpolation="Closest",
        extension="EXTEND",
    )
    color = _color_attribute(g)
    coverage = g.math("MULTIPLY", texel.outputs["Alpha"], color.outputs["Alpha"])
    spread = g.node("ShaderNodeAttribute", attribute_type="GEOMETRY", attribute_name=SPREAD_ATTRIBUTE)
    coverage = _thinned(g, coverage, g.math("ADD", spread.outputs["Fac"], 1.0))
    skin = g.math("LESS_THAN", layer, 0.5)
    reach = g.vector_math("LENGTH", _world_vector(g, TOP_ATTRIBUTE))
    path = g.node("ShaderNodeLightPath").outputs
    away = g.math("GREATER_THAN", path["Ray Length"], g.math("MULTIPLY", reach, SELF_REACH))
    alpha = _seen_alpha(g, path, g.math("MAXIMUM", coverage, skin), casts=g.math("MAXIMUM", skin, away))
    height = g.node("ShaderNodeAttribute", attribute_type="GEOMETRY", attribute_name=HEIGHT_ATTRIBUTE)
    base = _self_shadowed(g, _skin_weighted(g, _tinted(g, texel, color), skin), height.outputs["Fac"])
    _shade(g, base, alpha)
    return material


def build_fin_material(obj, images: dict, *, render_method: str = "DITHERED", fin_height: int | None = None):
    """Creates or updates Pelt's fin material for ``obj`` from ``images["fin"]`` (the fin
    texture: row 0, the top of the Pelt image, is the tip of the hair); returns it. ``fin_height``
    is the fin texture's height in texels when the caller knows it (reading ``image.size`` makes
    Blender decode a packed image). Raises ``pelt.InvalidParameterError`` (changing nothing) when
    the image is missing."""
    fin = _image(images, "fin")
    _check_render_method(render_method)
    height = max(int(fin_height if fin_height is not None else fin.size[1]), 1)
    material = _material(obj, FIN_ROLE, fin_material_name(obj), render_method, new_fin_material)
    templates.set_values(material.node_tree, {FIN_NODE: fin, FIN_INSET_NODE: 0.5 / height})
    return material


def new_fin_material(name: str):
    """A new material ``name`` with the fin tree; the fin texture and its inset are the named
    nodes that ``build_fin_material`` sets."""
    material, g = _new_material(name)
    uv_node = g.node("ShaderNodeAttribute", attribute_type="GEOMETRY", attribute_name=FIN_UV_ATTRIBUTE)
    u, height, _ = g.separate(uv_node.outputs["Vector"])
    inset = g.value(FIN_INSET_NODE, 0.0)
    v = _inside(g, height, inset, g.math("SUBTRACT", 1.0, inset))
    texel = g.node(
        "ShaderNodeTexImage",
        {"Vector": g.combine(u, v)},
        name=FIN_NODE,
        interpolation="Linear",
        extension="REPEAT",
    )
    fin_normal = g.node(
        "ShaderNodeVectorTransform",
        {
            "Vector": g.node(
                "ShaderNodeAttribute", attribute_type="GEOMETRY", attribute_name=FIN_NORMAL_ATTRIBUTE
            ).outputs["Vector"]
        },
        vector_type="NORMAL",
        convert_from="OBJECT",
        convert_to="WORLD",
    ).outputs["Vector"]
    geometry = g.node("ShaderNodeNewGeometry").outputs
    p = g.vector_math("DOT_PRODUCT", g.vector_math("NORMALIZE", fin_normal), geometry["Incoming"])
    fade = g.math("MAXIMUM", g.math("MULTIPLY_ADD", g.math("ABSOLUTE", p), 2.0, -1.0), 0.0)
    color = _color_attribute(g)
    tip_spread = g.node("ShaderNodeAttribute", attribute_type="GEOMETRY", attribute_name=FIN_SPREAD_ATTRIBUTE)
    width = g.math("MULTIPLY_ADD", height, tip_spread.outputs["Fac"], 1.0)
    alpha = g.math("MULTIPLY", _thinned(g, texel.outputs["Alpha"], width), color.outputs["Alpha"])
    alpha = g.math("MULTIPLY", alpha, fade)
    hair = _world_attribute(g, GROWTH_ATTRIBUTE)
    lit = _hair_lobes(g, _self_shadowed(g, _tinted(g, texel, color), v), hair, geometry)
    _output(g, lit, _seen_alpha(g, g.node("ShaderNodeLightPath").outputs, alpha, casts=0.0))
    return material


def check_inputs(images: dict, layout: dict, render_method: str = "DITHERED") -> None:
    """Raises ``pelt.InvalidParameterError`` unless both materials can be built from these."""
    _image(images, "shells")
    _image(images, "fin")
    for key in ("columns", "rows", "tile"):
        _positive_int(layout, key)
    _check_render_method(render_method)


def _image(images: dict, key: str):
    image = images.get(key) if hasattr(images, "get") else None
    if not isinstance(image, bpy.types.Image):
        raise pelt.InvalidParameterError(
            f"invalid parameter `images`: needs the {key!r} image, got {image!r}"
        )
    return image


def _positive_int(layout: dict, key: str) -> int:
    value = layout.get(key) if hasattr(layout, "get") else None
    if not isinstance(value, int) or value < 1:
        raise pelt.InvalidParameterError(
            f"invalid parameter `layout`: {key!r} must be a positive integer (pelt.pack_atlas's layout), "
            f"got {value!r}"
        )
    return value


def _check_render_method(render_method: str) -> None:
    if render_method not in RENDER_METHODS:
        raise pelt.InvalidParameterError(
            f"invalid parameter `render_method`: must be one of {RENDER_METHODS}, got {render_method!r}"
        )


def _material(obj, role: str, name: str, render_method: str, new):
    """Pelt's ``role`` material of ``obj`` with an up-to-date tree (``templates.owned_tree``) and
    the fur's render settings."""
    material = templates.owned_tree(obj.name, role, name, new)
    if material.surface_render_method != render_method:
        material.surface_render_method = render_method
    material.use_transparent_shadow = True
    material.use_backface_culling = False
    return material


def _new_material(name: str):
    """A new material ``name`` with an empty node tree, and a graph to build into it."""
    material = bpy.data.materials.new(name)
    material.node_tree.nodes.clear()
    return material, NodeGraph(material.node_tree)


def _inside(g: NodeGraph, coordinate, low, high):
    """``coordinate`` kept within ``[low, high]``."""
    return g.math("MAXIMUM", g.math("MINIMUM", coordinate, high), low)


def _color_attribute(g: NodeGraph):
    return g.node("ShaderNodeAttribute", attribute_type="GEOMETRY", attribute_name=COLOR)


def _thinned(g: NodeGraph, alpha, grown):
    """``alpha`` of the tile's hair standing ``grown`` times as far apart (the shells and fins lift
    the mesh along diverging growth directions; their hairs keep their count and width): the
    optical depth ``-ln(1 - alpha)`` over ``grown``, held within the preview's bounds
    (``spread_out`` and ``density_of_growth`` in ``crates/pelt-render/src/common.wgsl``)."""
    grown = g.math("MAXIMUM", g.math("MINIMUM", grown, 1.0 / MIN_SPREAD), MIN_SPREAD)
    clear = g.math("POWER", g.math("SUBTRACT", 1.0, alpha), g.math("DIVIDE", 1.0, grown))
    return g.math("SUBTRACT", 1.0, clear)


def _tinted(g: NodeGraph, texel, color):
    """The texel's color × the painted ``pelt_color``."""
    mix = g.node(
        "ShaderNodeMix",
        {"Factor": 1.0, "A": texel.outputs["Color"], "B": color.outputs["Color"]},
        data_type="RGBA",
        blend_type="MULTIPLY",
    )
    return output(mix, "Result")


def _skin_weighted(g: NodeGraph, color, skin):
    """``color`` × ``HAIR_DIFFUSE`` on the skin (``skin`` 1 there, 0 on the shells): the
    preview's and the reference's skin is Lambertian with that ``Kd`` under every light."""
    return g.vector_math("SCALE", color, scale=g.math("MULTIPLY_ADD", skin, HAIR_DIFFUSE - 1.0, 1.0))


def _self_shadowed(g: NodeGraph, color, height):
    """``color`` darkened as the preview's Banks term does at ``height`` (0 at the skin, 1 at the
    tips) under hair of the painted length ``l`` (``pelt_length``, which the fur's node group
    stores): by ``b = 1 - (1 - SELF_SHADOW)^l`` at the skin, none at the tips; the factor
    ``height × b + 1 - b``."""
    length = g.node("ShaderNodeAttribute", attribute_type="GEOMETRY", attribute_name=LENGTH).outputs["Fac"]
    clear = g.math("POWER", 1.0 - SELF_SHADOW, length)
    return g.vector_math(
        "SCALE", color, scale=g.math("MULTIPLY_ADD", height, g.math("SUBTRACT", 1.0, clear), clear)
    )


def _seen_alpha(g: NodeGraph, path, alpha, *, casts):
    """``alpha`` for the rays that see the fur; ``alpha × casts`` for shadow and diffuse rays (the
    fur's shadow on itself is ``_self_shadowed``'s; ``casts`` is 1 where the surface stops them).
    ``path``: the outputs of the tree's Light Path node."""
    lighting = g.math("MAXIMUM", path["Is Shadow Ray"], path["Is Diffuse Ray"])
    passes = g.math("MULTIPLY", lighting, g.math("SUBTRACT", 1.0, casts))
    return g.math("MULTIPLY", alpha, g.math("SUBTRACT", 1.0, passes))


def _world_vector(g: NodeGraph, name: str):
    """The object-space vector attribute ``name``, in world space."""
    attribute = g.node("ShaderNodeAttribute", attribute_type="GEOMETRY", attribute_name=name)
    world = g.node(
        "ShaderNodeVectorTransform",
        {"Vector": attribute.outputs["Vector"]},
        vector_type="VECTOR",
        convert_from="OBJECT",
        convert_to="WORLD",
    )
    return world.outputs["Vector"]


def _world_attribute(g: NodeGraph, name: str):
    """The object-space direction attribute ``name``, in world space, unit."""
    return g.vector_math("NORMALIZE", _world_vector(g, name))


def _hair_lobes(g: NodeGraph, color, hair, geometry):
    """Hair of direction ``hair`` lit as a cylinder seen from the eye: Lambertian and translucent
    lobes (``HAIR_DIFFUSE`` × ``color``) about the normal of the hair that faces the eye, so that
    the light reaching it is ``|κ| sin(hair, light)`` (Kajiya–Kay's diffuse term, weighed by
    Goldman's azimuth cosine κ). A hair pointing at the eye has no such normal: a hundredth of the
    surface's keeps it defined."""
    incoming = geometry["Incoming"]
    across = g.vector_math(
        "SUBTRACT", incoming, g.vector_math("SCALE", hair, scale=g.vector_math("DOT_PRODUCT", incoming, hair))
    )
    normal = g.vector_math(
        "NORMALIZE", g.vector_math("ADD", across, g.vector_math("SCALE", geometry["Normal"], scale=0.01))
    )
    weighted = g.vector_math("SCALE", color, scale=HAIR_DIFFUSE)
    diffuse = g.node("ShaderNodeBsdfDiffuse", {"Color": weighted, "Normal": normal})
    translucent = g.node("ShaderNodeBsdfTranslucent", {"Color": weighted, "Normal": normal})
    lobes = {("Shader", 0): diffuse.outputs["BSDF"], ("Shader", 1): translucent.outputs["BSDF"]}
    both = g.node("ShaderNodeAddShader", lobes)
    return both.outputs["Shader"]


def _output(g: NodeGraph, shader, alpha) -> None:
    """``shader`` over transparency by ``alpha`` into the material output."""
    clear = g.node("ShaderNodeBsdfTransparent").outputs["BSDF"]
    mix = g.node("ShaderNodeMixShader", {"Factor": alpha, ("Shader", 0): clear, ("Shader", 1): shader})
    g.node("ShaderNodeOutputMaterial", {"Surface": mix.outputs["Shader"]}, target="ALL")


def _shade(g: NodeGraph, base_color, alpha) -> None:
    """A Principled BSDF (soft, low specular: hair seen as a surface) into the material output."""
    bsdf = g.node(
        "ShaderNodeBsdfPrincipled",
        {"Base Color": base_color, "Alpha": alpha, "Roughness": 0.6, "Specular IOR Level": 0.3},
    )
    g.node("ShaderNodeOutputMaterial", {"Surface": bsdf.outputs["BSDF"]}, target="ALL")
