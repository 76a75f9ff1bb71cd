# SPDX-License-Identifier: GPL-3.0-or-later
"""Per-vertex data of a Blender mesh as numpy arrays, and Pelt's point attributes made right.

The paint and comb operators share these: reading positions, normals, edges and selection with
``foreach_get``, creating ``pelt_color`` / ``pelt_comb`` / ``pelt_length`` with their defaults, and
converting an attribute of that name that sits on the wrong domain or has the wrong type.
"""

import contextlib

import bpy
import numpy as np

# data type -> (foreach property, columns)
_LAYOUT = {"FLOAT": ("value", 1), "FLOAT_VECTOR": ("vector", 3), "FLOAT_COLOR": ("color", 4)}


class TargetError(Exception):
    """The operator cannot run on this object (the message says why); nothing was changed."""


def active_mesh_object(context):
    """The active object if Pelt may change its mesh, else ``TargetError``."""
    obj = context.active_object
    if obj is None:
        raise TargetError("no active object")
    if obj.type != "MESH":
        raise TargetError(f"'{obj.name}' is not a mesh (type {obj.type})")
    if obj.data.library is not None or obj.data.override_library is not None:
        raise TargetError(f"the mesh of '{obj.name}' is linked from a library and cannot be changed")
    return obj


def _read(collection, prop: str, count: int, columns: int, dtype=np.float32) -> np.ndarray:
    flat = np.empty(count * columns, dtype=dtype)
    collection.foreach_get(prop, flat)
    return flat.reshape(count, columns) if columns > 1 else flat


def positions(mesh) -> np.ndarray:
    """Vertex coordinates ``[N, 3]``, object space."""
    return _read(mesh.vertices, "co", len(mesh.vertices), 3)


def normals(mesh) -> np.ndarray:
    """Vertex normals ``[N, 3]``, object space."""
    return _read(mesh.vertex_normals, "vector", len(mesh.vertices), 3)


def edges(mesh) -> np.ndarray:
    """Edge vertex pairs ``[E, 2]``."""
    return _read(mesh.edges, "vertices", len(mesh.edges), 2, np.int64)


def selected(mesh) -> np.ndarray:
    """Vertex selection ``[N]`` (as last left by Edit Mode)."""
    return _read(mesh.vertices, "select", len(mesh.vertices), 1, bool)


def read_point(mesh, name: str) -> np.ndarray | None:
    """The POINT attribute ``name`` as ``[N]`` or ``[N, k]`` float32, or None if there is none
    (it must already have the domain and type ``ensure_point_attribute`` gives it)."""
    attribute = mesh.attributes.get(name)
    if attribute is None:
        return None
    prop, columns = _LAYOUT[attribute.data_type]
    return _read(attribute.data, prop, len(mesh.vertices), columns)


def write_point(mesh, name: str, values: np.ndarray) -> None:
    """Writes ``values`` into the existing POINT attribute ``name``."""
    attribute = mesh.attributes[name]
    prop, _ = _LAYOUT[attribute.data_type]
    attribute.data.foreach_set(prop, np.ascontiguousarray(values, dtype=np.float32).ravel())
    mesh.update()


def ensure_point_attribute(obj, name: str, data_type: str, fill) -> str | None:
    """Makes ``name`` a POINT attribute of ``data_type`` on ``obj``'s mesh (Object Mode).

    Missing: created and filled with ``fill`` (one value per vertex, broadcast). On another domain
    or of another type: converted by Blender (values averaged onto the vertices and cast, as
    Mesh > Attributes > Convert does); the return value says so, for the operator's report."""
    mesh = obj.data
    attribute = mesh.attributes.get(name)
    if attribute is None:
        attribute = mesh.attributes.new(name, data_type, "POINT")
        prop, columns = _LAYOUT[data_type]
        values = np.broadcast_to(np.asarray(fill, dtype=np.float32), (len(mesh.vertices), columns))
        attribute.data.foreach_set(prop, np.ascontiguousarray(values).ravel())
        mesh.update()
        return None
    if attribute.domain == "POINT" and attribute.data_type == data_type:
        return None
    before = f"{attribute.domain} {attribute.data_type}"
    previous_active = mesh.attributes.active.name if mesh.attributes.active else None
    mesh.attributes.active = attribute
    with bpy.context.temp_override(object=obj, active_object=obj):
        bpy.ops.geometry.attribute_convert(mode="GENERIC", domain="POINT", data_type=data_type)
    if previous_active is not None and previous_active in mesh.attributes:
        mesh.attributes.active = mesh.attributes[previous_active]
    return f"converted '{name}' from {before} to POINT {data_type}"


def check_convertible(obj, name: str) -> None:
    """``TargetError`` unless the attribute ``name`` (if any) can become a numeric POINT attribute
    (Blender converts no string attributes)."""
    attribute = obj.data.attributes.get(name)
    if attribute is not None and attribute.data_type == "STRING":
        raise TargetError(
            f"'{name}' on '{obj.name}' is a {attribute.domain} {attribute.data_type} attribute that "
            "cannot be converted: rename or remove it"
        )


@contextlib.contextmanager
def object_mode(obj):
    """Object Mode for the duration (mesh attributes are not written back from Edit Mode), then
    the mode it was in."""
    if obj.mode != "EDIT":
        yield
        return
    bpy.ops.object.mode_set(mode="OBJECT")
    try:
        yield
    finally:
        bpy.ops.object.mode_set(mode="EDIT")
