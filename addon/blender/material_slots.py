# SPDX-License-Identifier: GPL-3.0-or-later
"""An object's own materials for ``pelt.export_gltf``'s ``materials``: its slots as plain glTF
materials and each triangle's slot, so the faces the fur leaves bald keep them in the file (a
head's eyes stay eyes), as they do in Blender's renders (``geonodes.py``)."""

import numpy as np

from ..io import bridge
from ..io.names import OWNER

# Principled BSDF inputs read into the glTF material, with the defaults of a material without nodes.
PRINCIPLED = "BSDF_PRINCIPLED"


def own_material(material) -> dict | None:
    """``material`` as glTF's metallic-roughness factors (a Principled BSDF's inputs, else the
    viewport display color); ``None`` for an empty slot or a material of Pelt's."""
    if material is None or material.get(OWNER) is not None:
        return None
    color = list(material.diffuse_color)
    metallic, roughness = material.metallic, material.roughness
    tree = material.node_tree
    principled = next((n for n in tree.nodes if n.type == PRINCIPLED), None) if tree else None
    if principled is not None:
        color = [*principled.inputs["Base Color"].default_value[:3], principled.inputs["Alpha"].default_value]
        metallic = principled.inputs["Metallic"].default_value
        roughness = principled.inputs["Roughness"].default_value
    clamp = lambda v: min(max(float(v), 0.0), 1.0)  # noqa: E731
    return {
        "name": material.name[:64],
        "base_color": [clamp(c) for c in color],
        "metallic": clamp(metallic),
        "roughness": clamp(roughness),
    }


def material_slots(obj, triangles: int) -> dict | None:
    """The slots of ``obj`` and the slot of each of its mesh's loop triangles (the bake's
    triangles), or ``None`` when it has no material of its own or the mesh no longer has the
    bake's ``triangles``."""
    slots = [own_material(slot.material) for slot in obj.material_slots]
    if not any(slots):
        return None
    _, polygons = bridge.loop_triangles(obj.data)
    if len(polygons) != triangles:
        return None
    polygon_slot = np.empty(len(obj.data.polygons), np.int32)
    obj.data.polygons.foreach_get("material_index", polygon_slot)
    # Blender draws a face whose index is past the last slot with the last slot's material.
    slot = np.clip(polygon_slot[polygons], 0, len(slots) - 1).astype(np.uint32)
    return {"slots": slots, "triangle_slot": slot}
