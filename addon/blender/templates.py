# SPDX-License-Identifier: GPL-3.0-or-later
"""Pelt's node trees, built once and shipped: the fur and fin materials and the fur node group.

Blender 5.0 updates a whole node tree after every edit made from Python, so building a tree node
by node costs time in proportion to its size per edit: about 0.3 ms per edit at 100 nodes, some
200 ms for Pelt's three trees, which would be most of the Blender side of a first bake. But the
trees' shapes depend only on the code that builds them: what differs per object (images, the atlas
layout, materials) sits in a few named nodes that are set afterwards (:func:`set_values`). So the
extension carries the trees built once, in ``assets/node_templates.blend`` (written by
``blender_scripts/build_node_templates.py`` when the extension is packaged), and a bake appends a
copy of the one it needs, which takes milliseconds.

Each template records the :data:`SIGNATURE` of the sources that built it. When the file is missing
or was built by other sources, the tree is built here instead, with the same code, so both ways
give the same tree. Pelt's datablocks record the signature too (``names.BUILT``), so a file
baked with older code gets fresh trees on its next bake.
"""

import hashlib
from contextlib import contextmanager
from pathlib import Path

import bpy

from ..io.ownership import find_owned, mark_built, tag, up_to_date

# Beside the manifest: data that ships with the extension, not code.
PATH = Path(__file__).parents[1] / "assets" / "node_templates.blend"
# A template's custom properties: the signature of the sources that built it, and its role.
TEMPLATE = "pelt_template"
TEMPLATE_ROLE = "pelt_template_role"

# The files whose code decides the trees' shapes (the attribute names they read among them).
_SOURCES = (
    "blender/node_graph.py",
    "blender/materials.py",
    "blender/geonodes.py",
    "blender/templates.py",
    "io/names.py",
)
SIGNATURE = hashlib.sha1(b"".join((Path(__file__).parents[1] / f).read_bytes() for f in _SOURCES)).hexdigest()

# Role (``ownership`` tag) → (the ``bpy.data`` collection, the template's name in the file).
ROLES = {
    "fur_material": ("materials", "Pelt Fur Template"),
    "fin_material": ("materials", "Pelt Fin Template"),
    "fur_nodes": ("node_groups", "Pelt Fur Nodes Template"),
}


def owned_tree(owner_name: str, role: str, name: str, build):
    """Pelt's ``role`` datablock for the object ``owner_name`` with a tree built by this code: the
    one it has when that is up to date, otherwise a fresh one (:func:`fresh`) that takes the
    outdated one's place everywhere it was used. A new datablock is called ``name`` (Blender's
    numbered variant when a user's datablock has that name)."""
    collection = _collection(role)
    current = find_owned(collection, owner_name, role)
    if current is not None and up_to_date(current, SIGNATURE):
        if current.name != name and collection.get(name) is None:
            current.name = name
        return current
    made = fresh(role, name, build)
    if current is not None:
        name = current.name
        current.user_remap(made)
        collection.remove(current)
        made.name = name
    tag(made, owner_name, role)
    return made


def fresh(role: str, name: str, build):
    """A new datablock ``name`` holding the tree of ``role``: a copy of the shipped template when
    it was built by these sources (taken from the :func:`batch` under way, if any), otherwise
    built now by ``build(name)``."""
    made = _batch.pop(role, None) or _append([role]).get(role)
    if made is None:
        made = build(name)
    else:
        made.name = name
    mark_built(made, SIGNATURE)
    return made


@contextmanager
def batch(owner_name: str, roles):
    """Within it, the fresh trees that :func:`owned_tree` will need for these ``roles`` of the
    object ``owner_name`` come from one read of the template file (a read costs about as much
    whether it takes one template or three). Copies left unused are removed on the way out."""
    needed = [role for role in roles if _outdated(owner_name, role)]
    _batch.update(_append(needed))
    try:
        yield
    finally:
        for role in needed:
            leftover = _batch.pop(role, None)
            if leftover is not None:
                _collection(role).remove(leftover)


_batch: dict = {}


def _collection(role: str):
    return getattr(bpy.data, ROLES[role][0])


def _outdated(owner_name: str, role: str) -> bool:
    current = find_owned(_collection(role), owner_name, role)
    return current is None or not up_to_date(current, SIGNATURE)


def _append(roles: list) -> dict:
    """Copies of the templates of ``roles`` from the shipped file, by role; the roles it has no
    current template for are left out."""
    if not roles or not PATH.is_file():
        return {}
    wanted = {role: ROLES[role] for role in roles}
    try:
        with bpy.data.libraries.load(str(PATH), link=False) as (source, target):
            for collection_name in sorted({c for c, _ in wanted.values()}):
                available = set(getattr(source, collection_name))
                names = [name for c, name in wanted.values() if c == collection_name and name in available]
                setattr(target, collection_name, names)
    except (OSError, RuntimeError):
        return {}
    finally:
        _forget_library()
    made = {}
    for collection_name in sorted({c for c, _ in wanted.values()}):
        for block in getattr(target, collection_name):
            if block is None:
                continue
            block.use_fake_user = False
            role = block.get(TEMPLATE_ROLE)
            if role in wanted and block.get(TEMPLATE) == SIGNATURE:
                del block[TEMPLATE], block[TEMPLATE_ROLE]
                made[role] = block
            else:
                getattr(bpy.data, collection_name).remove(block)
    return made


def _forget_library() -> None:
    """Drops the library entry an append may leave behind (the copies are local, and users of
    the file should not see Pelt's template file listed)."""
    for library in list(bpy.data.libraries):
        if Path(bpy.path.abspath(library.filepath)).resolve() == PATH.resolve():
            bpy.data.libraries.remove(library)


def set_values(tree, values: dict) -> None:
    """Sets the named parameter nodes of ``tree``: a number into a Value node, an image into an
    Image Texture node, a material into a Set Material node. Only values that differ are set
    (every edit updates the whole tree and, in EEVEE, recompiles the shader)."""
    for node_name, value in values.items():
        node = tree.nodes[node_name]
        if isinstance(value, bpy.types.Image):
            if node.image != value:
                node.image = value
        elif isinstance(value, bpy.types.Material) or value is None:
            socket = node.inputs["Material"]
            if socket.default_value != value:
                socket.default_value = value
        elif node.outputs[0].default_value != value:
            node.outputs[0].default_value = value


def write(path: Path, builders: dict) -> None:
    """Builds every template (``builders`` maps a role to its ``build(name)``) and writes them,
    with :data:`SIGNATURE`, into the .blend ``path``; removes them from this session again."""
    made = {}
    for role, build in builders.items():
        block = build(ROLES[role][1])
        block[TEMPLATE] = SIGNATURE
        block[TEMPLATE_ROLE] = role
        made[role] = block
    path.parent.mkdir(parents=True, exist_ok=True)
    bpy.data.libraries.write(str(path), set(made.values()), fake_user=True, compress=False)
    for role, block in made.items():
        _collection(role).remove(block)
