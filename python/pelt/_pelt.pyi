"""Type stub of the compiled module ``pelt._pelt`` (re-exported by ``pelt``)."""

from collections.abc import Callable
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
    ``comb`` ``[N, 3]``, ``color`` ``[N, 4]`` (linear RGBA), ``length`` ``[N]`` in ``[0, 1000]``,
    ``polygons`` ``[M]`` (the polygon each triangle was cut from; triangles of one polygon stay in
    one lapped patch).
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
        polygons: npt.ArrayLike | None = None,
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

class PatchQuality(TypedDict):
    patch_count: int
    furred_faces: int
    coverage: float
    flipped_faces: int
    mean_alignment_deg: float
    stretch_within_fraction: float
    seam_length_fraction: float
    singularities: int
    face_alignment_deg: npt.NDArray[np.float32]
    face_stretch: npt.NDArray[np.float32]

class Patches:
    """A lapped patch layout (see :func:`build_patches`)."""

    @property
    def uv(self) -> npt.NDArray[np.float32]:
        """Per triangle and corner, the UV in tile units, ``[T, 3, 2]`` (the tile repeats)."""
    @property
    def patch(self) -> npt.NDArray[np.int32]:
        """Per triangle, its patch id ``[T]``; -1 for a bald face."""
    @property
    def direction(self) -> npt.NDArray[np.float32]:
        """Per vertex, the unit hair direction ``[V, 3]`` (object space, tangent)."""
    @property
    def slant(self) -> npt.NDArray[np.float32]:
        """Per vertex, the hair's angle from the normal in radians ``[V]``."""
    @property
    def singularities(self) -> npt.NDArray[np.int32]:
        """Singular faces of the field, ``[S, 2]`` rows ``(face, index)``."""
    @property
    def patch_count(self) -> int: ...
    @property
    def quality(self) -> PatchQuality: ...
    def picture(
        self,
        mesh: FurMesh,
        *,
        width: int = 512,
        height: int = 512,
        view: tuple[float, float, float] = (0.0, 1.0, -0.3),
        hair_length: float = 0.03,
        hair_every: int = 1,
    ) -> npt.NDArray[np.uint8]:
        """An RGBA picture ``[height, width, 4]``: patches in colors, hair directions as lines,
        orthographic along ``view``."""

def build_patches(
    mesh: FurMesh,
    tile_size: float,
    seed: int = 1,
    *,
    max_alignment_deg: float | None = None,
    max_face_alignment_deg: float | None = None,
    stretch_tolerance: float | None = None,
    max_stretched_fraction: float | None = None,
    max_stretch: float | None = None,
    max_patch_faces: int | None = None,
    down: tuple[float, float, float] | None = None,
    blend: float | None = None,
    comb_weight: float | None = None,
    progress: Callable[[float], bool | None] | None = None,
) -> Patches:
    """Builds the comb field and covers the furred faces with lapped patches.

    ``tile_size`` is the world size of one texture tile. Arguments left as ``None`` take the
    defaults: ``max_alignment_deg`` 2.5, ``max_face_alignment_deg`` 30, ``stretch_tolerance``
    1.25, ``max_stretched_fraction`` 0.03, ``max_stretch`` 2.0, ``max_patch_faces`` 4096,
    ``down`` (0, 0, -1), ``blend`` 0.05, ``comb_weight`` 100. ``progress`` receives the covered
    share; returning ``False`` (or raising) cancels with :class:`BakeCancelled`. Raises
    :class:`InvalidParameterError` naming a parameter out of range. Releases the GIL while it
    works.
    """

def thread_count() -> int:
    """Number of worker threads Pelt uses (``PELT_THREADS``, default: all cores)."""
