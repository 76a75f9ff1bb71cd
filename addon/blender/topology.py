# SPDX-License-Identifier: GPL-3.0-or-later
"""Modifiers that change the mesh (Mirror, Subdivision, a user's Geometry Nodes…) applied at Bake,
so that the whole mesh, as it shows, gets fur and the preview, the pose and the export all see
the topology that was baked.

Only modifiers at the top of the stack are applied (those before any modifier that only moves
vertices, such as the Armature): the pose keeps deforming the applied mesh, and Blender applies a
modifier as if it came first. The applied mesh is made before the bake from the object evaluated
with those modifiers alone (``applied_mesh``) and adopted only when the bake has succeeded
(``swap_in``, then ``commit`` or ``revert``), so a failed or cancelled bake leaves the object as
it was. Ctrl+Z undoes the adoption with the bake."""

from dataclasses import dataclass

import bpy
import pelt

from . import geonodes
from .pose import DEFORM_ONLY


def _changes_topology(modifier) -> bool:
    return modifier.type not in DEFORM_ONLY


def leading_modifiers(obj) -> list:
    """The shown modifiers at the top of ``obj``'s stack that may change its topology, in order;
    raises ``pelt.InvalidMeshError`` naming one that comes later, before Pelt's fur."""
    fur = geonodes.find_modifier(obj)
    leading, moved_by = [], None
    for modifier in obj.modifiers:
        if modifier == fur:
            break
        if not modifier.show_viewport:
            continue
        if not _changes_topology(modifier):
            moved_by = moved_by or modifier
        elif moved_by is None:
            leading.append(modifier)
        else:
            raise pelt.InvalidMeshError(
                f"the modifier {modifier.name!r} ({modifier.type.title()}) changes the mesh after "
                f"{moved_by.name!r} ({moved_by.type.title()}) deforms it: Pelt applies such modifiers "
                "only at the top of the stack; move it above, or apply it"
            )
    return leading


def applied_mesh(obj, modifiers):
    """A new mesh: ``obj``'s mesh with ``modifiers`` (the leading ones) applied and nothing else.
    The other modifiers are hidden for the evaluation and shown again after it."""
    hidden = [m for m in obj.modifiers if m.show_viewport and m not in modifiers]
    try:
        for modifier in hidden:
            modifier.show_viewport = False
        depsgraph = bpy.context.evaluated_depsgraph_get()
        evaluated = obj.evaluated_get(depsgraph)
        mesh = bpy.data.meshes.new_from_object(evaluated, preserve_all_data_layers=True, depsgraph=depsgraph)
    finally:
        for modifier in hidden:
            modifier.show_viewport = True
    mesh.name = obj.data.name
    return mesh


@dataclass
class Applied:
    """A bake's applied mesh, waiting for the bake to succeed."""

    mesh: object
    names: list[str]
    old: object = None


def prepare(obj) -> Applied | None:
    """``obj``'s mesh with its leading topology modifiers applied, or None without any."""
    modifiers = leading_modifiers(obj)
    if not modifiers:
        return None
    return Applied(applied_mesh(obj, modifiers), [m.name for m in modifiers])


def swap_in(obj, applied: Applied | None) -> None:
    """Gives ``obj`` the applied mesh (the bake writes into it); ``revert`` or ``commit`` next."""
    if applied is not None:
        applied.old = obj.data
        obj.data = applied.mesh


def commit(obj, applied: Applied | None) -> None:
    """Once the bake is written: removes the applied modifiers and the old mesh (Ctrl+Z brings
    both back), and the applied mesh takes the old one's name."""
    if applied is None:
        return
    for name in applied.names:
        modifier = obj.modifiers.get(name)
        if modifier is not None:
            obj.modifiers.remove(modifier)
    old, name = applied.old, applied.old.name
    if old.users == 0:
        bpy.data.meshes.remove(old)
        applied.mesh.name = name


def revert(obj, applied: Applied | None) -> None:
    """The bake failed: ``obj`` gets its mesh back and the applied one is removed."""
    if applied is None:
        return
    if applied.old is not None:
        obj.data = applied.old
    if applied.mesh.users == 0:
        bpy.data.meshes.remove(applied.mesh)
