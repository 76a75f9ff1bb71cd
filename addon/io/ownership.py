# SPDX-License-Identifier: GPL-3.0-or-later
"""Which datablocks Pelt made for which object (DESIGN.md §3).

Every datablock Pelt creates carries two custom properties: ``pelt_owner`` (the owning object's
name) and ``pelt_role`` (what it is for that object: ``"fur_material"``, ``"fin_material"``,
``"fur_nodes"``, ``"shells"``, ...). Pelt finds its own datablocks by these tags, never by name, so
a user's datablock that merely looks like Pelt's ("Pelt Fur Sphere" without the tags) is never
reused, changed or removed. This module never imports bpy: it works on any ID collection.
"""

from .names import BUILT, OWNER, ROLE


def tag(datablock, owner_name: str, role: str) -> None:
    """Marks ``datablock`` as Pelt's ``role`` datablock for the object named ``owner_name``."""
    datablock[OWNER] = owner_name
    datablock[ROLE] = role


def is_owned(datablock, owner_name: str, role: str | None = None) -> bool:
    """Whether ``datablock`` is Pelt's (for ``role``, or any role) for the object ``owner_name``."""
    if datablock.get(OWNER) != owner_name:
        return False
    return role is None or datablock.get(ROLE) == role


def find_owned(collection, owner_name: str, role: str):
    """Pelt's ``role`` datablock for ``owner_name`` in ``collection`` (``bpy.data.materials``, ...),
    or None."""
    return next((item for item in collection if is_owned(item, owner_name, role)), None)


def all_owned(collection, owner_name: str) -> list:
    """Every datablock of ``collection`` that Pelt made for ``owner_name``."""
    return [item for item in collection if is_owned(item, owner_name)]


def up_to_date(datablock, signature: str) -> bool:
    """Whether ``datablock`` was last built from inputs with this ``signature`` (so a re-bake can
    keep its node tree instead of building the same one again)."""
    return datablock.get(BUILT) == signature


def mark_built(datablock, signature: str) -> None:
    """Records the ``signature`` of the inputs ``datablock`` was just built from."""
    datablock[BUILT] = signature
