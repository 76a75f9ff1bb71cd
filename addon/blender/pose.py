# SPDX-License-Identifier: GPL-3.0-or-later
"""The fur in the object's pose: Pelt bakes the mesh as edited (the rest shape, without
modifiers), and the preview follows the evaluated mesh (an armature, shape keys, any modifier
that keeps the vertices), re-sending only its positions and normals (``pelt.Preview.deform``, no
bake). Bake applies the modifiers at the top of the stack that change the topology (``topology``);
where one was added after the bake (Mirror, Subdivision), the preview keeps the rest
shape and the panel says why.

Pelt's own Geometry Nodes fur (``geonodes.py``, added by Bake) joins the skin first, its vertices
in their order, then shells and fins: under it the pose is the evaluated mesh's first rows, when
every modifier before it only moves vertices."""

import ctypes
from contextlib import contextmanager

import bpy
import numpy as np
import pelt

from ..io import bridge
from . import geonodes

# session_uid -> why the object's preview shows the rest shape instead of its pose
NOTES: dict[int, str] = {}
# id(pelt.Preview) of the previews drawn in a pose (to return to the rest shape)
_POSED: set[int] = set()
# Modifier types that move vertices and keep the mesh's vertices and faces as they are.
DEFORM_ONLY = frozenset(
    {
        "ARMATURE", "CAST", "CLOTH", "CORRECTIVE_SMOOTH", "CURVE", "DISPLACE", "HOOK",
        "LAPLACIANDEFORM", "LAPLACIANSMOOTH", "LATTICE", "MESH_CACHE", "MESH_DEFORM",
        "SHRINKWRAP", "SIMPLE_DEFORM", "SMOOTH", "SOFT_BODY", "SURFACE_DEFORM", "WARP", "WAVE",
    }
)  # fmt: skip


def _under_fur_modifier(obj) -> bool:
    """Whether Pelt's fur modifier is shown, so that the posed skin is the evaluated mesh's
    first rows. Raises ``pelt.InvalidMeshError`` when a modifier before it may change the
    topology."""
    fur = geonodes.find_modifier(obj)
    if fur is None or not fur.show_viewport:
        return False
    for modifier in obj.modifiers:
        if modifier == fur:
            break
        if modifier.show_viewport and modifier.type not in DEFORM_ONLY:
            raise pelt.InvalidMeshError(
                f"the modifier {modifier.name!r} ({modifier.type.title()}) before Pelt's fur may change "
                "the topology: the preview shows the mesh without it (Bake applies it)"
            )
    return True


@contextmanager
def _evaluated_mesh(obj, depsgraph):
    """``obj``'s evaluated mesh: the depsgraph's own when it is a mesh (no copy: under Pelt's fur
    it has every shell's vertices too), else a copy freed on leaving."""
    evaluated = obj.evaluated_get(depsgraph)
    if isinstance(evaluated.data, bpy.types.Mesh):
        yield evaluated.data
        return
    try:
        yield evaluated.to_mesh()
    finally:
        evaluated.to_mesh_clear()


def moved(obj) -> bool:
    """Whether anything evaluated may move the mesh's vertices: a modifier shown in the
    viewport other than Pelt's fur (which keeps the skin's rows as they are), or shape keys."""
    fur = geonodes.find_modifier(obj)
    shown = (m for m in obj.modifiers if m.show_viewport and m != fur)
    return any(True for _ in shown) or obj.data.shape_keys is not None


def first_positions(mesh, rows: int) -> np.ndarray:
    """The first ``rows`` vertex positions ``[rows, 3]`` float32 of ``mesh``. Under Pelt's fur the
    evaluated mesh holds every shell's and fin's vertices after the skin's (24 times as many on a
    sphere), and reading them all cost 6 to 10 ms of a redraw while frames render; the position
    attribute is one float3 array, so its first rows are copied straight from it."""
    position = mesh.attributes.get("position")
    if (
        not 0 < rows < len(mesh.vertices)
        or position is None
        or (position.data_type, position.domain) != ("FLOAT_VECTOR", "POINT")
    ):
        return bridge.read_positions(mesh)[:rows]
    block = (ctypes.c_float * (3 * rows)).from_address(position.data[0].as_pointer())
    return np.frombuffer(block, np.float32).reshape(rows, 3).copy()


def evaluated_pose(obj, depsgraph, vertex_count: int, *, normals: bool = True) -> tuple:
    """Positions and vertex normals ``[V, 3]`` float32 of ``obj``'s evaluated mesh (object
    space); with ``normals=False`` the normals are None (``pelt.Preview.deform`` then computes
    them on its own thread). Raises ``pelt.InvalidMeshError`` when its vertices are not the
    ``vertex_count`` baked."""
    under_fur = _under_fur_modifier(obj)
    with _evaluated_mesh(obj, depsgraph) as mesh:
        count = len(mesh.vertices)
        if count != vertex_count and not (under_fur and count > vertex_count):
            raise pelt.InvalidMeshError(
                f"the modifiers change the topology ({count} vertices evaluated, {vertex_count} baked): "
                "the preview shows the mesh without them (Bake applies those at the top of the stack)"
            )
        rows = slice(0, vertex_count)
        positions = first_positions(mesh, vertex_count)
        if not normals:
            return positions, None
        values = np.empty(count * 3, np.float32)
        mesh.vertex_normals.foreach_get("vector", values)
        return positions, values.reshape(count, 3)[rows]


def target(asset: pelt.FurAsset, obj, depsgraph, *, normals: bool = True) -> tuple | None:
    """Positions and normals (``evaluated_pose``) that pose ``obj``'s bake ``asset`` as
    ``depsgraph`` evaluates ``obj``; None for the rest shape (nothing moves it, or the pose cannot
    be applied: the reason is then in ``NOTES``)."""
    NOTES.pop(obj.session_uid, None)
    if not moved(obj):
        return None
    try:
        return evaluated_pose(obj, depsgraph, asset.mesh.vertex_count, normals=normals)
    except pelt.PeltError as error:
        NOTES[obj.session_uid] = str(error)
        return None


def apply(preview: pelt.Preview, asset: pelt.FurAsset, obj, depsgraph) -> None:
    """Poses ``preview`` (of ``obj``'s bake ``asset``) as ``depsgraph`` evaluates ``obj``. A pose
    that cannot be applied leaves the rest shape drawn and its reason in ``NOTES``."""
    pose = target(asset, obj, depsgraph)
    if pose is not None:
        preview.deform(*pose)
        _POSED.add(id(preview))
    elif id(preview) in _POSED:
        mesh = asset.mesh
        preview.deform(mesh.positions, mesh.normals)
        _POSED.discard(id(preview))
