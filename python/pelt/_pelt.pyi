"""Type stub of the compiled module ``pelt._pelt`` (re-exported by ``pelt``)."""

from typing import TypedDict

import numpy as np
import numpy.typing as npt

__version__: str

class PeltError(Exception):
    """Base class of every error Pelt raises."""

class InvalidMeshError(PeltError):
    """The mesh or an attribute array is unusable; the message names the element."""

class InvalidParameterError(PeltError):
    """A parameter is outside its allowed range."""

class BakeCancelled(PeltError):
    """A bake was cancelled."""

class RenderError(PeltError):
    """The GPU renderer failed."""

class MeshStats(TypedDict):
    vertices: int
    faces: int
    edges: int
    boundary_edges: int
    non_manifold_edges: int
    degenerate_faces: int
    components: int
    loose_vertices: int
    surface_area: float
    bbox_min: list[float]
    bbox_max: list[float]

class FurMesh:
    """A validated triangle mesh with per-vertex hair attributes.

    ``positions`` is ``[N, 3]``, ``triangles`` ``[M, 3]`` (any integer dtype), ``normals`` and
    ``comb`` ``[N, 3]``, ``color`` ``[N, 4]`` (linear RGBA), ``length`` ``[N]`` in ``[0, 1000]``.
    float32 / uint32 C-contiguous arrays are read in place; others are converted. Raises
    :class:`InvalidMeshError` naming the first bad element. Releases the GIL while it works.
    """

    def __init__(
        self,
        positions: npt.ArrayLike,
        triangles: npt.ArrayLike,
        *,
        normals: npt.ArrayLike | None = None,
        color: npt.ArrayLike | None = None,
        comb: npt.ArrayLike | None = None,
        length: npt.ArrayLike | None = None,
    ) -> None: ...
    def stats(self) -> MeshStats: ...
    @property
    def vertex_count(self) -> int: ...
    @property
    def face_count(self) -> int: ...
    @property
    def normals_given(self) -> bool: ...
    @property
    def positions(self) -> npt.NDArray[np.float32]: ...
    @property
    def triangles(self) -> npt.NDArray[np.uint32]: ...
    @property
    def normals(self) -> npt.NDArray[np.float32]: ...
    @property
    def tangents(self) -> npt.NDArray[np.float32]: ...
    @property
    def bitangents(self) -> npt.NDArray[np.float32]: ...
    @property
    def color(self) -> npt.NDArray[np.float32] | None: ...
    @property
    def comb(self) -> npt.NDArray[np.float32] | None: ...
    @property
    def length(self) -> npt.NDArray[np.float32] | None: ...
    @property
    def edges(self) -> npt.NDArray[np.uint32]: ...

def thread_count() -> int:
    """Number of worker threads Pelt uses (``PELT_THREADS``, default: all cores)."""
