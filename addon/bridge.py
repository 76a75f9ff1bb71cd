# SPDX-License-Identifier: GPL-3.0-or-later
"""bpy <-> numpy <-> pelt transfer, reused by every operator.

Arrays cross with ``foreach_get`` / ``foreach_set`` into preallocated numpy buffers: no per-vertex
Python loop. This module never imports bpy, so its helpers also work on any object that offers the
same ``foreach_get`` interface.
"""

from dataclasses import dataclass

import numpy as np
import pelt

# Point attributes of DESIGN.md §3: name -> (accepted data types, foreach_get property, columns).
POINT_ATTRIBUTES = {
    "pelt_color": ({"FLOAT_COLOR", "BYTE_COLOR"}, "color", 4),
    "pelt_comb": ({"FLOAT_VECTOR"}, "vector", 3),
    "pelt_length": ({"FLOAT"}, "value", 1),
}


@dataclass
class MeshArrays:
    """A Blender mesh as the arrays ``pelt.FurMesh`` takes (triangulated by loop triangles)."""

    positions: np.ndarray
    triangles: np.ndarray
    normals: np.ndarray | None
    triangle_polygons: np.ndarray
    color: np.ndarray | None = None
    comb: np.ndarray | None = None
    length: np.ndarray | None = None

    def fur_mesh(self) -> pelt.FurMesh:
        return pelt.FurMesh(
            self.positions,
            self.triangles,
            normals=self.normals,
            color=self.color,
            comb=self.comb,
            length=self.length,
            polygons=self.triangle_polygons,
        )


def _read(collection, prop: str, count: int, columns: int, dtype) -> np.ndarray:
    flat = np.empty(count * columns, dtype=dtype)
    collection.foreach_get(prop, flat)
    return flat.reshape(count, columns) if columns > 1 else flat


def _point_attribute(mesh, name: str) -> np.ndarray | None:
    attribute = mesh.attributes.get(name)
    if attribute is None:
        return None
    types, prop, columns = POINT_ATTRIBUTES[name]
    vertex_count = len(mesh.vertices)
    if attribute.domain != "POINT":
        raise pelt.InvalidMeshError(
            f"attribute '{name}' is on the {attribute.domain} domain ({len(attribute.data)} values), "
            f"but Pelt needs one value per vertex ({vertex_count} vertices): make it a POINT attribute"
        )
    if attribute.data_type not in types:
        raise pelt.InvalidMeshError(
            f"attribute '{name}' has type {attribute.data_type}, expected {' or '.join(sorted(types))}"
        )
    return _read(attribute.data, prop, vertex_count, columns, np.float32)


def read_mesh(mesh) -> MeshArrays:
    """Reads positions, loop triangles, vertex normals and the Pelt point attributes of ``mesh``."""
    mesh.calc_loop_triangles()
    vertex_count = len(mesh.vertices)
    triangle_count = len(mesh.loop_triangles)
    triangles = _read(mesh.loop_triangles, "vertices", triangle_count, 3, np.uint32)
    # A script can leave a corner naming a vertex that does not exist. Blender would read past the
    # end of its arrays computing normals for such a mesh, so skip them and let pelt name the index.
    indices_valid = triangle_count == 0 or int(triangles.max()) < vertex_count
    return MeshArrays(
        positions=_read(mesh.vertices, "co", vertex_count, 3, np.float32),
        triangles=triangles,
        normals=_read(mesh.vertex_normals, "vector", vertex_count, 3, np.float32) if indices_valid else None,
        triangle_polygons=_read(mesh.loop_triangles, "polygon_index", triangle_count, 1, np.uint32),
        color=_point_attribute(mesh, "pelt_color"),
        comb=_point_attribute(mesh, "pelt_comb"),
        length=_point_attribute(mesh, "pelt_length"),
    )


def fur_mesh_from_object(obj) -> pelt.FurMesh:
    """The object's mesh (as edited, without modifiers) as a ``pelt.FurMesh``.

    Raises ``pelt.PeltError`` (``InvalidMeshError`` for bad geometry or attributes).
    """
    if obj is None or obj.type != "MESH":
        raise pelt.InvalidMeshError("the active object is not a mesh")
    if obj.mode == "EDIT":
        obj.update_from_editmode()
    return read_mesh(obj.data).fur_mesh()
