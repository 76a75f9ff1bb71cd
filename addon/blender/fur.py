# SPDX-License-Identifier: GPL-3.0-or-later
"""Pelt's Blender fur of one object as a whole: build it (materials + Geometry Nodes), remove it,
and set up a scene to render it. Only datablocks tagged as Pelt's for the object are touched
(``io/ownership.py``)."""

import bpy

from ..io.fur_layout import FurSettings
from ..io.ownership import all_owned
from . import geonodes, materials, templates


def build_fur(
    obj,
    images: dict,
    layout: dict,
    settings: FurSettings,
    *,
    render_method: str = "DITHERED",
    fin_height: int | None = None,
):
    """Builds (or rebuilds) the materials ``Pelt Fur <obj>`` and ``Pelt Fin <obj>`` and the
    modifier ``Pelt Fur``; returns the modifier. ``images`` holds the ``"shells"`` atlas and the
    ``"fin"`` image (``fin_height`` texels tall, when the caller knows), ``layout`` the atlas
    layout of ``pelt.pack_atlas``. Raises ``pelt.PeltError``
    when an input is invalid; the checks all run before anything is created."""
    geonodes.check_target(obj, settings)
    materials.check_inputs(images, layout, render_method)
    with templates.batch(obj.name, template_builders()):
        fur = materials.build_fur_material(obj, images, layout, render_method=render_method)
        fin = materials.build_fin_material(obj, images, render_method=render_method, fin_height=fin_height)
        return geonodes.build_fur_modifier(obj, settings, fur_material=fur, fin_material=fin)


def template_builders() -> dict:
    """The builders of Pelt's shipped node trees by role (``templates.write``)."""
    return {
        materials.FUR_ROLE: materials.new_fur_material,
        materials.FIN_ROLE: materials.new_fin_material,
        geonodes.NODES_ROLE: geonodes.new_node_group,
    }


def remove_fur(obj, *, images: bool = False) -> list[str]:
    """Removes Pelt's fur from ``obj``: its ``Pelt Fur`` modifier and every material and node
    group tagged as Pelt's for ``obj`` (and, with ``images``, Pelt's images for ``obj``). Returns
    the names of what it removed; a user's datablock, whatever its name, stays."""
    removed = []
    modifier = geonodes.find_modifier(obj)
    while modifier is not None:
        removed.append(f"modifier {modifier.name}")
        obj.modifiers.remove(modifier)
        modifier = geonodes.find_modifier(obj)
    collections = [bpy.data.node_groups, bpy.data.materials]
    if images:
        collections.append(bpy.data.images)
    for collection in collections:
        for datablock in all_owned(collection, obj.name):
            removed.append(datablock.name)
            collection.remove(datablock)
    return removed


def prepare_scene(scene, settings: FurSettings) -> list[str]:
    """Lets ``scene`` render the fur: Cycles' transparent bounces raised (never lowered) to what
    a ray through every shell and a fin on both sides of the object needs (otherwise rays stop,
    black, after the default 8 surfaces). Returns a line per setting it changed, for the report
    (the bake's undo step takes them back)."""
    needed = 4 * settings.shells + 4
    before = scene.cycles.transparent_max_bounces
    if before >= needed:
        return []
    scene.cycles.transparent_max_bounces = needed
    return [f"Cycles transparent bounces {before} → {needed}"]
