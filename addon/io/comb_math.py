# SPDX-License-Identifier: GPL-3.0-or-later
"""Comb-field math, numpy only (no bpy), shared by the comb operators.

Lengyel et al. 2001, §3 "Hair direction": each vertex stores a comb vector whose tangential part
shears the shells (the renderer offsets layer ``k`` along ``n + comb - n (n · comb)``), so a
tangential comb of length 1 leans the hair by 45°. A zero comb means "not painted": the library
relaxes the field there to "down". The comb functions return vectors in the tangent planes of
the given normals, in the same (object) space as their inputs; ``ScreenView`` and ``screen_dab``
carry the interactive brush from region pixels to object space.
"""

from dataclasses import dataclass

import numpy as np

# Vectors shorter than this have no direction (a zero normal leaves a vector as it is).
_TINY = 1e-12


def unit_rows(vectors: np.ndarray) -> np.ndarray:
    """``vectors`` scaled to unit length row by row; zero rows stay zero."""
    length = np.linalg.norm(vectors, axis=-1, keepdims=True)
    return np.divide(vectors, length, out=np.zeros_like(vectors), where=length > _TINY)


def tangential(vectors: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """The part of each vector in the tangent plane of its normal (``v - n (n · v)``, unit ``n``).

    ``vectors`` is ``[N, 3]`` or one ``[3]`` vector for every normal."""
    n = unit_rows(np.asarray(normals, dtype=np.float64))
    v = np.broadcast_to(np.asarray(vectors, dtype=np.float64), n.shape)
    return v - n * np.einsum("ij,ij->i", v, n)[:, None]


def falloff(distance: np.ndarray, radius: float) -> np.ndarray:
    """Brush weight ``(1 - (d/r)²)²`` inside the radius, 0 on and beyond it: smooth at both ends."""
    if radius <= 0.0:
        return np.zeros_like(distance, dtype=np.float64)
    t = np.clip(1.0 - np.square(np.asarray(distance, dtype=np.float64) / radius), 0.0, None)
    return np.square(t)


def add_tangential(comb, normals, indices, deltas, weights) -> np.ndarray:
    """A copy of ``comb`` with ``weights · tangential(deltas)`` added at ``indices``."""
    out = np.array(comb, dtype=np.float32, copy=True)
    step = tangential(deltas, normals[indices]) * np.asarray(weights, dtype=np.float64)[:, None]
    out[indices] = (out[indices] + step).astype(np.float32)
    return out


def sphere_stroke(comb, positions, normals, center, radius, delta, strength):
    """Lengyel's comb with an object-space brush: vertices closer than ``radius`` to ``center`` get
    ``delta`` projected into their tangent plane, times ``strength`` and the falloff.

    Returns the new comb and the indices of the vertices inside the brush."""
    distance = np.linalg.norm(np.asarray(positions, np.float64) - np.asarray(center, np.float64), axis=1)
    inside = np.flatnonzero(distance < radius)
    weights = falloff(distance[inside], radius) * strength
    return add_tangential(comb, normals, inside, delta, weights), inside


def gravity_pull(normals, linear, down) -> np.ndarray:
    """Per vertex, the object-space comb that hangs along the world direction ``down``: ``down``
    projected into the *world* tangent plane (length ``sin`` of its angle to the normal: 0 where
    hair would stand straight off the surface, so the library picks the direction there), turned
    into object space by the inverse of the object's 3×3 matrix ``linear``. For rotation and
    uniform scale this is the object-space ``down`` projected into the object's tangent planes;
    under non-uniform scale it still points straight down the slope as seen in the world."""
    to_object = np.linalg.inv(np.asarray(linear, dtype=np.float64))
    world_normals = unit_rows(np.asarray(normals, dtype=np.float64) @ to_object)
    world_pull = tangential(unit_rows(np.asarray(down, np.float64)[None])[0], world_normals)
    return unit_rows(world_pull @ to_object.T) * np.linalg.norm(world_pull, axis=1, keepdims=True)


def blend(comb, target, strength: float, mask=None) -> np.ndarray:
    """``comb`` moved by ``strength`` towards ``target``; only rows in ``mask`` change."""
    blended = (1.0 - strength) * np.asarray(comb, np.float64) + strength * np.asarray(target, np.float64)
    out = np.array(comb, dtype=np.float32, copy=True)
    rows = slice(None) if mask is None else mask
    out[rows] = blended[rows]
    return out


def _edge_sums(values: np.ndarray, edges: np.ndarray, count: int) -> np.ndarray:
    """Per vertex, the sum of ``values`` over its edge neighbours (``values`` is ``[N]`` or ``[N, k]``)."""
    i, j = edges[:, 0], edges[:, 1]
    columns = values.reshape(len(values), -1)
    sums = np.empty((count, columns.shape[1]))
    for c in range(columns.shape[1]):
        sums[:, c] = np.bincount(i, columns[j, c], count) + np.bincount(j, columns[i, c], count)
    return sums.reshape((count, *values.shape[1:]))


def degrees(edges: np.ndarray, count: int) -> np.ndarray:
    """Number of edges at each vertex."""
    return np.bincount(edges[:, 0], minlength=count) + np.bincount(edges[:, 1], minlength=count)


def smooth(comb, normals, edges, iterations: int, factor: float, mask=None) -> np.ndarray:
    """Laplacian smoothing of the comb over mesh edges.

    Each iteration moves a vertex's comb by ``factor`` towards the mean of its neighbours',
    projects it into the tangent plane, and gives it the equally smoothed mean *length*: averaging
    vectors that disagree would otherwise shrink them, and projecting would shrink them again.
    Vertices outside ``mask`` and vertices without edges keep their comb (but still pass it on)."""
    count = len(comb)
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    degree = degrees(edges, count)
    update = degree > 0 if mask is None else (degree > 0) & mask
    share = np.divide(1.0, degree, out=np.zeros(count), where=degree > 0)
    current = np.asarray(comb, dtype=np.float64)
    for _ in range(iterations):
        length = np.linalg.norm(current, axis=1)
        mean = _edge_sums(current, edges, count) * share[:, None]
        mean_length = _edge_sums(length, edges, count) * share
        direction = unit_rows(tangential((1.0 - factor) * current + factor * mean, normals))
        smoothed = direction * ((1.0 - factor) * length + factor * mean_length)[:, None]
        current = np.where(update[:, None], smoothed, current)
    return current.astype(np.float32)


def propagate(comb, known, edges, normals, smoothing: int = 10) -> tuple[np.ndarray, np.ndarray]:
    """Fills the rows of ``comb`` not ``known`` from their neighbours, front by front (each new
    vertex takes the mean of its already filled neighbours), then smooths only the filled-in rows
    ``smoothing`` times so the fronts do not show. Components without a known vertex stay as they
    are. Returns the comb and the mask of rows that now hold a value (known or filled)."""
    count = len(comb)
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    current = np.asarray(comb, dtype=np.float64).copy()
    filled = np.asarray(known, dtype=bool).copy()
    while not filled.all():
        source = filled.astype(np.float64)
        reached = _edge_sums(source, edges, count)
        front = (reached > 0) & ~filled
        if not front.any():
            break
        sums = _edge_sums(current * source[:, None], edges, count)
        current[front] = tangential(sums[front] / reached[front, None], normals[front])
        filled |= front
    current = smooth(current, normals, edges, smoothing, 0.5, mask=filled & ~np.asarray(known, bool))
    return current.astype(np.float32), filled


def lean(directions, normals) -> np.ndarray:
    """Comb vectors that lean the shells along ``directions`` (strands, root to tip).

    A strand at angle θ ≤ 45° from the normal gives a tangential comb of length tan θ (the shells
    then follow it exactly); steeper strands, and strands pointing into the surface, give length 1
    (45°), the most the shells show without losing the strands across layers (Lengyel §3)."""
    d = unit_rows(np.asarray(directions, dtype=np.float64))
    n = unit_rows(np.asarray(normals, dtype=np.float64))
    along = np.einsum("ij,ij->i", d, n)
    t = d - n * along[:, None]
    scale = np.maximum(along, np.linalg.norm(t, axis=1))
    return np.divide(t, scale[:, None], out=np.zeros_like(t), where=scale[:, None] > _TINY).astype(np.float32)


def strand_directions(positions, offsets) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Roots and root-to-tip vectors of curves stored Blender's way: ``positions [P, 3]`` and
    ``offsets [C + 1]`` (curve ``c`` owns points ``offsets[c]:offsets[c+1]``).

    Returns ``(roots, directions, used)``; ``used`` marks the curves with two or more points and a
    tip apart from the root (only those are returned)."""
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    offsets = np.asarray(offsets, dtype=np.int64)
    first, end = offsets[:-1], offsets[1:]
    long_enough = end - first >= 2
    roots = positions[first[long_enough]]
    directions = positions[end[long_enough] - 1] - roots
    apart = np.linalg.norm(directions, axis=1) > _TINY
    used = np.zeros(len(first), dtype=bool)
    used[np.flatnonzero(long_enough)[apart]] = True
    return roots[apart], directions[apart], used


def _nearest_brute(points, queries, chunk_bytes: int) -> np.ndarray:
    result = np.empty(len(queries), dtype=np.int64)
    step = max(1, chunk_bytes // (8 * len(points)))
    squared = np.einsum("ij,ij->i", points, points)
    for start in range(0, len(queries), step):
        q = queries[start : start + step]
        # |p - q|² minus the |q|² that every candidate of a row shares
        result[start : start + step] = np.argmin(squared[None, :] - 2.0 * q @ points.T, axis=1)
    return result


def _nearest_in_grid(points, queries, cell: float) -> tuple[np.ndarray, np.ndarray]:
    """Nearest point among the 27 grid cells around each query's cell, and its distance
    (-1 and inf where those cells are empty). Exact wherever that distance is at most ``cell``:
    any point outside the 27 cells is farther than one cell size away."""
    low = points.min(axis=0)
    point_cell = np.floor((points - low) / cell).astype(np.int64)
    dims = point_cell.max(axis=0) + 5  # room for queries outside the points' box and the offsets
    query_cell = np.clip(np.floor((queries - low) / cell).astype(np.int64), -1, dims - 4)

    def key(c):
        return (c[..., 0] + 2) + dims[0] * ((c[..., 1] + 2) + dims[1] * (c[..., 2] + 2))

    order = np.argsort(key(point_cell), kind="stable")
    cells, first, count = np.unique(key(point_cell)[order], return_index=True, return_counts=True)
    offsets = np.stack(np.meshgrid([-1, 0, 1], [-1, 0, 1], [-1, 0, 1], indexing="ij"), -1).reshape(-1, 3)
    keys = key(query_cell[:, None, :] + offsets[None]).ravel()
    slot = np.minimum(np.searchsorted(cells, keys), len(cells) - 1)
    hit = cells[slot] == keys
    owner = np.repeat(np.arange(len(queries)), len(offsets))[hit]
    first, count = first[slot[hit]], count[slot[hit]]
    # one (query, candidate) pair per point in each hit cell
    pair_query = np.repeat(owner, count)
    within = np.arange(len(pair_query)) - np.repeat(np.cumsum(count) - count, count)
    pair_point = order[np.repeat(first, count) + within]
    distance = np.linalg.norm(points[pair_point] - queries[pair_query], axis=1)
    best = np.lexsort((pair_point, distance, pair_query))
    leaders = best[np.r_[True, pair_query[best][1:] != pair_query[best][:-1]]] if len(best) else best
    found = np.full(len(queries), -1, dtype=np.int64)
    found_distance = np.full(len(queries), np.inf)
    found[pair_query[leaders]] = pair_point[leaders]
    found_distance[pair_query[leaders]] = distance[leaders]
    return found, found_distance


def nearest(points, queries, chunk_bytes: int = 1 << 25) -> np.ndarray:
    """Index of the nearest row of ``points`` for each row of ``queries`` (exact; ties go to the
    lower index).

    A uniform grid sized for points spread over a surface answers most queries from the 27 cells
    around them; queries it cannot settle try a grid 4 times coarser, and the last few, or a grid
    as coarse as the whole cloud, are compared with every point in chunks under ``chunk_bytes``."""
    points = np.asarray(points, dtype=np.float64)
    queries = np.asarray(queries, dtype=np.float64)
    if len(points) == 0:
        raise ValueError("no points to search")
    result = np.full(len(queries), -1, dtype=np.int64)
    pending = np.arange(len(queries))
    extent = float(np.ptp(points, axis=0).max()) if len(points) > 1 else 0.0
    cell = 2.0 * extent / np.sqrt(len(points))
    chunk = max(1, chunk_bytes // (64 * 27 * 8))  # queries per grid pass, for bounded pair arrays
    while len(pending) and cell > 0.0 and cell < extent and len(pending) * len(points) > chunk_bytes // 8:
        unsettled = []
        for start in range(0, len(pending), chunk):
            part = pending[start : start + chunk]
            found, distance = _nearest_in_grid(points, queries[part], cell)
            settled = (found >= 0) & (distance <= cell)
            result[part[settled]] = found[settled]
            unsettled.append(part[~settled])
        pending = np.concatenate(unsettled)
        cell *= 4.0
    if len(pending):
        result[pending] = _nearest_brute(points, queries[pending], chunk_bytes)
    return result


def mean_direction_per_vertex(indices, directions, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Per vertex, the normalized sum of the unit ``directions`` assigned to it (``indices``), and
    how many were assigned."""
    unit = unit_rows(np.asarray(directions, dtype=np.float64))
    sums = np.stack([np.bincount(indices, unit[:, c], count) for c in range(3)], axis=1)
    return unit_rows(sums), np.bincount(indices, minlength=count)


@dataclass(frozen=True)
class ScreenView:
    """What the interactive comb needs of a 3D viewport: its projection and size, as numpy.

    ``window`` maps eye to clip space (``RegionView3D.window_matrix``), ``view`` world to eye space
    (``RegionView3D.view_matrix``); region pixels run from the bottom left."""

    window: np.ndarray
    view: np.ndarray
    width: int
    height: int
    is_perspective: bool

    def project(self, world) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Region pixel coordinates ``[N, 2]``, clip-space ``w`` ``[N]`` and a mask of the points in
        front of the eye (the others get meaningless coordinates)."""
        perspective = self.window @ self.view
        world = np.asarray(world, dtype=np.float64)
        clip = world @ perspective[:2, :3].T + perspective[:2, 3]
        w = world @ perspective[3, :3] + perspective[3, 3]
        front = w > _TINY
        ndc = clip / np.where(front, w, 1.0)[:, None]
        half = np.array([self.width, self.height], dtype=np.float64) / 2.0
        return half + half * ndc, w, front

    def drag_at_depth(self, drag, w) -> np.ndarray:
        """World vectors ``[N, 3]`` that move points of clip-space ``w`` by ``drag`` region pixels
        while keeping their depth: the drag in the plane of the view through each point.

        Solved in eye space, where the projection of x and y at one depth is a plain scale (this
        stays exact where the depth buffer has no precision left, unlike unprojecting a depth)."""
        ndc = 2.0 * np.asarray(drag, np.float64) / np.array([self.width, self.height], dtype=np.float64)
        eye = np.zeros((len(w), 3))
        eye[:, 0] = ndc[0] * w / self.window[0, 0]
        eye[:, 1] = ndc[1] * w / self.window[1, 1]
        return eye @ np.linalg.inv(self.view)[:3, :3].T

    def towards_points(self, world) -> np.ndarray:
        """Viewing direction at each world point (not normalized): from the eye for a perspective
        view, the view axis for an orthographic one."""
        eye_to_world = np.linalg.inv(self.view)
        if self.is_perspective:
            return np.asarray(world, np.float64) - eye_to_world[:3, 3]
        return np.broadcast_to(-eye_to_world[:3, 2], np.shape(world))


def screen_dab(view: ScreenView, world, world_normals, world_to_object, mouse, drag, radius_px, front_only):
    """One step of the interactive comb (Lengyel §3): the vertices whose projection lies within
    ``radius_px`` of ``mouse`` and the object-space deltas the screen ``drag`` adds to them
    (``world_to_object`` is the inverse of the object's 3×3 matrix).

    The drag is taken in the view plane through each vertex and scaled so that a drag by one
    brush radius adds a comb of length 1 (45°) before the falloff. With ``front_only``, vertices
    whose normal faces away from the eye are skipped (the brush does not comb the back of the
    mesh; it does not test what other faces hide).

    Returns ``(indices, deltas [K, 3], weights [K])``."""
    pixels, w, in_front = view.project(world)
    distance = np.linalg.norm(pixels - np.asarray(mouse, np.float64), axis=1)
    inside = in_front & (distance < radius_px)
    if front_only:
        inside &= np.einsum("ij,ij->i", view.towards_points(world), world_normals) < 0.0
    indices = np.flatnonzero(inside)
    drag_px = float(np.linalg.norm(drag))
    if drag_px == 0.0 or radius_px <= 0.0 or len(indices) == 0:
        return indices[:0], np.zeros((0, 3)), np.zeros(0)
    moved = view.drag_at_depth(drag, w[indices]) @ np.asarray(world_to_object, np.float64).T
    return indices, unit_rows(moved) * (drag_px / radius_px), falloff(distance[indices], radius_px)
