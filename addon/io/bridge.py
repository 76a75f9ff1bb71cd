# SPDX-License-Identifier: GPL-3.0-or-later
"""bpy <-> numpy <-> pelt transfer, reused by every operator.

Arrays cross with ``foreach_get`` / ``foreach_set`` into preallocated numpy buffers: no per-vertex
Python loop. This module never imports bpy, so its helpers also work on any object that offers the
same ``foreach_get`` interface.
"""

import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
import pelt

from .names import COLOR, COMB, LENGTH, PATCH_ATTRIBUTE, UV_MAP

# Point attributes of DESIGN.md §3: name -> (accepted data types, foreach_get property, columns).
POINT_ATTRIBUTES = {
    COLOR: ({"FLOAT_COLOR", "BYTE_COLOR"}, "color", 4),
    COMB: ({"FLOAT_VECTOR"}, "vector", 3),
    LENGTH: ({"FLOAT"}, "value", 1),
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


def corner_vertices(mesh) -> np.ndarray:
    """The vertex of every corner (loop), uint32. The ``.corner_vert`` attribute is Blender's own
    storage (since 3.6) and reads in one copy; ``loops`` converts item by item (100× slower)."""
    corner_vert = mesh.attributes.get(".corner_vert")
    if corner_vert is not None:
        return _read(corner_vert.data, "value", len(mesh.loops), 1, np.int32).view(np.uint32)
    return _read(mesh.loops, "vertex_index", len(mesh.loops), 1, np.uint32)


def read_positions(mesh) -> np.ndarray:
    """Vertex positions ``[N, 3]`` float32 (the ``position`` attribute reads in one copy; a mesh
    without vertices has none)."""
    position = mesh.attributes.get("position")
    data = position.data if position is not None else mesh.vertices
    return _read(data, "vector" if position is not None else "co", len(mesh.vertices), 3, np.float32)


def loop_triangles(mesh) -> tuple[np.ndarray, np.ndarray]:
    """``(loops [T, 3] uint32, polygon [T] int32)`` of the loop triangles, each read in one copy
    (``foreach_get`` is a copy only when the numpy dtype is the property's own)."""
    mesh.calc_loop_triangles()
    count = len(mesh.loop_triangles)
    loops = _read(mesh.loop_triangles, "loops", count, 3, np.uint32)
    polygons = _read(mesh.loop_triangle_polygons, "value", count, 1, np.int32)
    return loops, polygons


def read_mesh(mesh) -> MeshArrays:
    """Reads positions, loop triangles, vertex normals and the Pelt point attributes of ``mesh``."""
    vertex_count = len(mesh.vertices)
    loops, polygons = loop_triangles(mesh)
    triangles = corner_vertices(mesh)[loops]
    # A script can leave a corner naming a vertex that does not exist. Blender would read past the
    # end of its arrays computing normals for such a mesh, so skip them and let pelt name the index.
    indices_valid = len(triangles) == 0 or int(triangles.max()) < vertex_count
    return MeshArrays(
        positions=read_positions(mesh),
        triangles=triangles,
        normals=_read(mesh.vertex_normals, "vector", vertex_count, 3, np.float32) if indices_valid else None,
        triangle_polygons=polygons.view(np.uint32),
        color=_point_attribute(mesh, COLOR),
        comb=_point_attribute(mesh, COMB),
        length=_point_attribute(mesh, LENGTH),
    )


def read_object(obj) -> MeshArrays:
    """The object's mesh (as edited, without modifiers) as arrays.

    Raises ``pelt.InvalidMeshError`` when ``obj`` is not a mesh or an attribute is unusable.
    """
    if obj is None or obj.type != "MESH":
        raise pelt.InvalidMeshError("the active object is not a mesh")
    if obj.mode == "EDIT":
        obj.update_from_editmode()
    return read_mesh(obj.data)


def fur_mesh_from_object(obj) -> pelt.FurMesh:
    """The object's mesh as a validated ``pelt.FurMesh``.

    Raises ``pelt.PeltError`` (``InvalidMeshError`` for bad geometry or attributes).
    """
    return read_object(obj).fur_mesh()


def _check_rgba(rgba: np.ndarray) -> None:
    if rgba.ndim != 3 or rgba.shape[2] != 4 or rgba.dtype != np.uint8:
        raise pelt.InvalidParameterError(
            f"invalid parameter `rgba`: must be [H, W, 4] uint8, got {rgba.shape} {rgba.dtype}"
        )


def write_image(images, name: str, rgba: np.ndarray, *, color: bool = True, image=None, path=None, png=None):
    """Makes ``image`` (or a new image ``name`` in ``images``, i.e. ``bpy.data.images``) show
    ``[H, W, 4] uint8`` straight-alpha pixels, rows top to bottom.

    Pelt encodes the pixels as PNG (fast, GIL released) and Blender loads them when first shown,
    so nothing is converted pixel by pixel here: with ``path`` (a file path and the ``filepath``
    Blender should store, e.g. relative ``//…``) the PNG is written there; otherwise it is packed
    into the .blend. ``color`` marks the bytes as sRGB-encoded color; otherwise they are data
    (tangents, transfer) and tagged Non-Color. An existing image is never looked up by name: the
    caller says which one is its own. ``png``: the pixels already encoded (``encode_pngs``), for
    the packed case."""
    _check_rgba(rgba)
    height, width = rgba.shape[:2]
    if image is None:
        image = images.new(name, width, height, alpha=True, float_buffer=False)
    if image.packed_file is not None:
        image.unpack(method="REMOVE")
    image.source = "FILE"
    if path is None:
        data = png if png is not None else pelt.encode_png(rgba, srgb=color)
        # The name a packed image would be unpacked to; no file is read or written.
        image.filepath_raw = "//" + "".join(c if c.isalnum() or c in "-_." else "_" for c in name) + ".png"
        image.pack(data=data, data_len=len(data))
    else:
        file, filepath = path
        pelt.save_png(file, rgba, srgb=color)
        image.filepath_raw = filepath
    image.colorspace_settings.name = "sRGB" if color else "Non-Color"
    image.alpha_mode = "STRAIGHT"
    # Drop pixels loaded from the previous bake; Blender decodes the new file when next shown
    # (``reload`` would look for the packed image's file on disk).
    image.buffers_free()
    return image


def write_linear_image(images, name: str, rgba: np.ndarray, *, image=None):
    """Makes ``image`` (or a new image ``name``) a float image holding ``[H, W, 4] float32``
    scene-linear, straight-alpha pixels (rows top to bottom), so that Blender displays it
    through the scene's view transform as it does its own renders. A byte image or one of
    another size is replaced by a new one of the same name. Returns the image."""
    if rgba.ndim != 3 or rgba.shape[2] != 4 or rgba.dtype != np.float32:
        raise pelt.InvalidParameterError(
            f"invalid parameter `rgba`: must be [H, W, 4] float32, got {rgba.dtype} {rgba.shape}"
        )
    height, width = rgba.shape[:2]
    if image is not None and (not image.is_float or tuple(image.size) != (width, height)):
        name = image.name
        images.remove(image)
        image = None
    if image is None:
        image = images.new(name, width, height, alpha=True, float_buffer=True)
    image.colorspace_settings.is_data = False
    image.alpha_mode = "STRAIGHT"
    # Blender stores rows bottom-up.
    image.pixels.foreach_set(np.ascontiguousarray(rgba[::-1]).ravel())
    image.update()
    return image


def encode_pngs(images: list) -> list:
    """``[(rgba, color?), ...]`` as PNG bytes, encoded side by side (``pelt.encode_png`` releases
    the GIL, so threads run it in parallel)."""
    if len(images) < 2:
        return [pelt.encode_png(rgba, srgb=color) for rgba, color in images]
    with ThreadPoolExecutor(max_workers=min(len(images), os.cpu_count() or 1)) as pool:
        return list(pool.map(lambda item: pelt.encode_png(item[0], srgb=item[1]), images))


def write_patches(mesh, patches) -> None:
    """Writes ``patches`` (from ``pelt.build_patches`` on ``read_mesh(mesh)``) into ``mesh``: the UV
    map ``PeltUV`` (one UV per loop, tile units) and the INT face attribute ``pelt_patch`` (-1 on
    bald faces). Every triangle of a polygon lies in one patch, so each loop gets one UV.

    Checks the sizes before touching the mesh, so a mismatch raises ``pelt.InvalidMeshError`` and
    changes nothing."""
    loops, polygons = loop_triangles(mesh)
    triangle_count = len(loops)
    uv = np.asarray(patches.uv, dtype=np.float32)
    patch = np.asarray(patches.patch, dtype=np.int32)
    if uv.shape != (triangle_count, 3, 2) or patch.shape != (triangle_count,):
        raise pelt.InvalidMeshError(
            f"patches are for {patch.shape[0]} triangles, the mesh has {triangle_count}: bake them again"
        )
    # Each (u, v) pair moved as one 8-byte item: numpy scatters single items 4-5 times faster than rows.
    loop_uv = np.zeros(len(mesh.loops), np.uint64)
    loop_uv[loops.ravel()] = np.ascontiguousarray(uv).reshape(-1, 2).view(np.uint64).ravel()
    loop_uv = loop_uv.view(np.float32)
    polygon_patch = np.full(len(mesh.polygons), -1, np.int32)
    polygon_patch[polygons] = patch

    layer = mesh.uv_layers.get(UV_MAP) or mesh.uv_layers.new(name=UV_MAP)
    # A UV map is a FLOAT2 corner attribute; its "vector" reads in one copy ("uv" item by item).
    mesh.attributes[layer.name].data.foreach_set("vector", loop_uv.ravel())
    attribute = mesh.attributes.get(PATCH_ATTRIBUTE)
    if attribute is not None and (attribute.domain != "FACE" or attribute.data_type != "INT"):
        mesh.attributes.remove(attribute)
        attribute = None
    if attribute is None:
        attribute = mesh.attributes.new(PATCH_ATTRIBUTE, "INT", "FACE")
    attribute.data.foreach_set("value", polygon_patch)
    mesh.update()
