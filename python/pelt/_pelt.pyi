"""Type stub of the compiled module ``pelt._pelt`` (re-exported by ``pelt``)."""

from collections.abc import Callable
from typing import Literal, TypedDict

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

class BandRow(TypedDict):
    order: int
    coefficients: int
    band_energy: float
    error_directional: float
    error_environment: float
    error: float
    bytes_f16: int
    bytes_u8: int

class TransferResult(TypedDict):
    coefficients: npt.NDArray[np.float32]
    order: int
    tolerance_met: bool | None
    bands: list[BandRow]
    packed_f16: npt.NDArray[np.float16]
    packed_u8: npt.NDArray[np.uint8]
    scale: npt.NDArray[np.float32]
    bias: npt.NDArray[np.float32]
    sidecar: str

def bake_transfer(
    density: npt.ArrayLike,
    tangents: npt.ArrayLike | None = None,
    *,
    layer_spacing: float,
    order: int | None = None,
    tolerance: float = 0.02,
    directions: int = 256,
    phase: Literal["isotropic", "kajiya-kay"] = "isotropic",
    method: Literal["sweep", "brute"] = "sweep",
    sigma: float = 1.0,
    progress: Callable[[float], bool | None] | None = None,
) -> TransferResult:
    """Bake the precomputed radiance transfer of a hair density volume.

    ``density`` is ``[L, R, R]`` (layer 0 is the skin; coverage share per texel, >= 0),
    ``tangents`` ``[L, R, R, 3]`` hair directions (x, y along the skin, z up; zero where there is
    no hair), required for ``phase="kajiya-kay"``. ``layer_spacing`` is the height between layers
    in texel widths; ``sigma`` the optical depth per texel width through full coverage.

    ``order=None`` bakes 8 bands and keeps the smallest order whose relative RMS lighting error
    under the test lights is within ``tolerance`` (``bands`` holds the table and
    ``tolerance_met`` says whether any order met it); an explicit order (1..8) skips the selection
    (``bands`` is empty, ``tolerance_met`` None).

    Returns ``coefficients`` ``[L, R, R, n]`` (n = order²), ``packed_f16`` and ``packed_u8``
    ``[T, L, R, R, 4]`` (T = ceil(n / 4); texture k // 4, channel k % 4 holds coefficient k),
    the 8-bit decode table ``scale`` / ``bias`` (``value = byte / 255 * scale + bias``) and the same
    as a JSON ``sidecar``. ``progress(fraction)`` is called from worker threads; returning False
    cancels with :class:`BakeCancelled`, and an exception it raises is re-raised. Releases the GIL.
    """

def sh_project_equirect(image: npt.ArrayLike, order: int) -> npt.NDArray[np.float32]:
    """Project an equirectangular ``[H, W, 3]`` image (row 0 at +Z, column 0 at azimuth 0 from +X
    toward +Y) onto real SH of ``order`` bands; returns ``[order**2, 3]`` float32."""
