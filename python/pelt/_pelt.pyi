"""Type stub of the compiled module ``pelt._pelt`` (re-exported by ``pelt``)."""

import os
from collections.abc import Callable, Sequence
from typing import Literal, TypedDict, final, type_check_only

import numpy as np
import numpy.typing as npt

__version__: str
STAGES: tuple[str, ...]
"""The bake's stages in the order they run (``Pipeline.bake``'s report follows it)."""
PRESETS: dict[str, dict[str, str | int | float | list[float]]]
"""The fur presets by name (``SHORT_VELVET``, ``MINK``, ...): ``label``, ``description`` and the
settings each writes (hair parameters, ``fur_depth`` and ``tile_size`` in object units for an
object about 2 units across); the values ``pelt bake --preset`` uses."""

@type_check_only
class ParameterRange(TypedDict):
    min: float
    max: float
    min_open: bool
    min_field: str | None
    unit: str

@type_check_only
class ParameterSet(TypedDict):
    defaults: dict[str, object]
    ranges: dict[str, ParameterRange]

SCHEMA: dict[str, ParameterSet]
"""The parameter sets: ``bake`` (``Pipeline.bake``'s own keywords: ``fur_depth``, one range for
the bake, ``Preview.fur_depth`` and the exports), ``patches``, ``field``, ``hair``, ``volume``,
``transfer`` and ``render`` (``Preview.render``'s keywords): each set's defaults and the range and
unit of each of its numbers, the one statement that its validation checks (``min_open``: the
minimum itself is refused; ``min_field``: the range starts at that field's value, ``min`` being the
lowest it allows)."""

class PeltError(Exception):
    """Base class of every error Pelt raises."""

class InvalidMeshError(PeltError):
    """The mesh or an attribute array is unusable; the message names the element."""

class InvalidParameterError(PeltError):
    """A parameter is outside its allowed range."""

class MemoryLimitError(InvalidParameterError):
    """The parameters ask for more memory than :func:`memory_limit` allows; the message names the
    stage, its estimate, the limit and the parameters to lower."""

class BakeCancelled(PeltError):
    """A bake was cancelled."""

class RenderError(PeltError):
    """The GPU renderer failed."""

@type_check_only
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

@final
class FurMesh:
    """A validated triangle mesh with per-vertex hair attributes.

    ``positions`` is ``[N, 3]``, ``triangles`` ``[M, 3]`` (any integer dtype), ``normals`` and
    ``comb`` ``[N, 3]``, ``color`` ``[N, 4]`` (linear RGBA, the hair's painted color: the coat then
    keeps only its shading, see :class:`Pipeline`), ``length`` ``[N]`` in ``[0, 1000]``,
    ``polygons`` ``[M]`` (the polygon each triangle was cut from; triangles of one polygon stay in
    one lapped patch).
    float32 / uint32 C-contiguous arrays are read in place; others are converted. Raises
    :class:`InvalidMeshError` naming the first bad element. Releases the GIL while it works.
    """

    def __new__(
        cls,
        positions: npt.ArrayLike,
        triangles: npt.ArrayLike,
        *,
        normals: npt.ArrayLike | None = None,
        color: npt.ArrayLike | None = None,
        comb: npt.ArrayLike | None = None,
        length: npt.ArrayLike | None = None,
        polygons: npt.ArrayLike | None = None,
    ) -> FurMesh: ...
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

@type_check_only
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

@final
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
        view: tuple[float, float, float] = ...,
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

def set_thread_count(threads: int) -> None:
    """Use ``threads`` workers (0: one per core) for work started from now on; ``[0, 1024]``."""

def memory_limit() -> int:
    """Bytes a stage may plan to use; above it the stage raises :class:`MemoryLimitError` before
    allocating. Default: half of :func:`physical_memory`, or ``PELT_MEMORY_LIMIT``."""

def set_memory_limit(limit: float | None) -> None:
    """Set :func:`memory_limit` in bytes (at least 64 MiB) for work started from now on; ``None``
    returns to ``PELT_MEMORY_LIMIT`` or the default."""

def physical_memory() -> int:
    """Bytes of physical memory (a container's limit when smaller)."""

@type_check_only
class CoatParams(TypedDict):
    length: list[float]
    width: list[float]

@final
class HairParams:
    """Parameters of the hair grown in one tile (see ``help(pelt.HairParams)`` for every field
    with its default and range). Keywords set fields; attributes read and write them; a bad value
    raises :class:`InvalidParameterError` naming the field and keeps the old value."""

    seed: int
    density: int
    guard_fraction: float
    undercoat: CoatParams
    overcoat: CoatParams
    segments: int
    taper: float
    curl: float
    helix_radius: float
    helix_frequency: float
    slant: float
    slant_direction: float
    length_jitter: float
    clump_strength: float
    clump_count: int
    root_color: list[float]
    tip_color: list[float]
    color_jitter: float
    def __new__(cls, **fields: object) -> HairParams: ...
    def to_dict(self) -> dict[str, object]: ...
    @staticmethod
    def fields() -> list[str]: ...

@type_check_only
class VolumeStats(TypedDict):
    strands: int
    tallest: float
    layers_requested: int
    layers: int
    trimmed: int
    mean_coverage: list[float]

@type_check_only
class HairVolume(TypedDict):
    """Arrays of a baked hair volume. ``shells``/``tangents`` ``[L, R, R, 4] uint8`` (straight
    alpha, sRGB color; tangent packed ``0.5·d + 0.5``), ``coverage`` (= ``density``)
    ``[L, R, R] float32``, ``fin`` ``[H, W, 4] uint8`` (row 0 = top of the fur), ``lod[k]``
    ``[1 + ceil((L - 1) / 2^(k+1)), R, R, 4]`` (the skin, then groups of hair composited; the
    last level one layer, everything over the skin), ``mips[k]``
    ``[L, R >> (k+1), R >> (k+1), 4]``."""

    resolution: int
    layers: int
    layer_spacing: float
    shells: npt.NDArray[np.uint8]
    coverage: npt.NDArray[np.float32]
    density: npt.NDArray[np.float32]
    tangents: npt.NDArray[np.uint8]
    fin: npt.NDArray[np.uint8]
    lod: list[npt.NDArray[np.uint8]]
    mips: list[npt.NDArray[np.uint8]]
    stats: VolumeStats

def bake_volume(
    params: HairParams | None = None,
    layers: int = 16,
    resolution: int = 128,
    *,
    coverage: str = "exact",
    vertical_filter: float = 0.0,
    fin_size: tuple[int, int] = ...,
    fin_slab: float = 0.1,
    trim: bool = True,
    lod: bool = True,
    mipmaps: bool = True,
    guard_hairs: bool = False,
    guard_share: float = 1.0,
    progress: Callable[[float], bool | None] | None = None,
) -> HairVolume:
    """Grow the hair of ``params`` and bake the hair volume (GIL released). ``coverage`` is
    ``"exact"``, ``"approx"`` or ``"supersample:N"``; ``guard_hairs=True`` leaves out the
    ``guard_share`` of the overcoat that is drawn as strands (:attr:`FurAsset.guard_hairs`);
    ``progress(fraction)`` returning ``False`` cancels with :class:`BakeCancelled`."""

@type_check_only
class AtlasLayout(TypedDict):
    layers: int
    tile: int
    columns: int
    rows: int
    width: int
    height: int

def pack_atlas(layers: npt.NDArray[np.uint8]) -> tuple[npt.NDArray[np.uint8], AtlasLayout]:
    """Lay ``[L, R, R, C]`` layers out in a grid (``ceil(sqrt(L))`` columns, layer 0 top left,
    rows top to bottom); unused cells are zero."""

@type_check_only
class BandRow(TypedDict):
    order: int
    coefficients: int
    band_energy: float
    error_directional: float
    error_environment: float
    error: float
    bytes_f16: int
    bytes_u8: int

@type_check_only
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
    tolerance: float = ...,
    directions: int = 256,
    phase: Literal["isotropic", "kajiya-kay"] = "isotropic",
    method: Literal["sweep", "brute"] = "sweep",
    sigma: float = ...,
    progress: Callable[[float], bool | None] | None = None,
) -> TransferResult:
    """Bake the precomputed radiance transfer of a hair density volume.

    ``density`` is ``[L, R, R]`` (layer 0 is the skin; coverage share per texel, >= 0),
    ``tangents`` ``[L, R, R, 3]`` hair directions (x, y along the skin, z up; zero where there is
    no hair), required for ``phase="kajiya-kay"``. ``layer_spacing`` is the height between layers
    in texel widths; ``sigma`` the optical depth per texel width through density 1 (a bake from a
    pipeline hands it the coverage over the hair's ``|t_z|``, the hair length per unit height).

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

def save_png(
    path: str | os.PathLike[str], image: npt.NDArray[np.uint8] | npt.NDArray[np.uint16], *, srgb: bool = True
) -> None:
    """Write ``[H, W, C]`` (C in 1..4, rows top to bottom, straight alpha) as an 8- or 16-bit PNG."""

def encode_png(image: npt.NDArray[np.uint8] | npt.NDArray[np.uint16], *, srgb: bool = True) -> bytes:
    """``image`` as the bytes of a PNG file (fast deflate), e.g. to pack into a .blend."""

def save_exr(path: str | os.PathLike[str], image: npt.NDArray[np.float32] | npt.NDArray[np.float16]) -> None:
    """Write ``[H, W, C]`` float32/float16 (C in 1..4: Y, YA, RGB, RGBA) as a ZIP OpenEXR."""

def sh_project_light(
    direction: tuple[float, float, float], order: int, half_angle: float = 0.0
) -> npt.NDArray[np.float32]:
    """SH coefficients ``[order²]`` of a unit-power light from ``direction`` over a cone of
    ``half_angle`` radians (0: directional)."""

def sh_rotate(coefficients: npt.ArrayLike, rotation: npt.ArrayLike) -> npt.NDArray[np.float32]:
    """SH coefficients ``[n²]`` or ``[n², C]`` rotated by ``rotation`` (3×3, mapping a direction
    ``d`` to ``rotation @ d``): a lobe along ``d`` ends up along ``rotation @ d``. Exact (Ivanic &
    Ruedenberg); a rotation that is not orthonormal and proper raises
    :class:`InvalidParameterError` naming ``rotation``."""

@type_check_only
class StageReport(TypedDict):
    stage: Literal["patches", "volume", "guard_hairs", "planes", "transfer"]
    ran: bool
    seconds: float
    summary: str

@type_check_only
class PlaneSlices(TypedDict):
    planes: int
    tilt: tuple[float, float]
    slices: npt.NDArray[np.uint8]

@type_check_only
class GuardHairs(TypedDict):
    """A ``guard_share`` of the overcoat's strands over the mesh, placed where the shells would
    show them (the volume then holds the rest of the coat): every point of every strand, root
    first."""

    positions: npt.NDArray[np.float32]  # (P, 3) object units
    radii: npt.NDArray[np.float32]  # (P,) object units
    counts: npt.NDArray[np.uint32]  # (S,) points per strand
    root_colors: npt.NDArray[np.float32]  # (S, 3) linear
    tip_colors: npt.NDArray[np.float32]  # (S, 3) linear
    root_triangles: npt.NDArray[np.uint32]  # (S,) the mesh triangle each root stands on
    root_weights: npt.NDArray[np.float32]  # (S, 3) its barycentric weights there, by corner

@final
class FurAsset:
    """The result of :meth:`Pipeline.bake`: every stage's output, shared with the pipeline's
    cache (the getters copy arrays out)."""

    @property
    def mesh(self) -> FurMesh: ...
    @property
    def patches(self) -> Patches: ...
    @property
    def volume(self) -> HairVolume: ...
    @property
    def transfer(self) -> TransferResult | None:
        """As :func:`bake_transfer` returns it, plus ``depth_in_tiles``; ``None`` without PRT."""
    @property
    def guard_hairs(self) -> GuardHairs | None:
        """The guard hairs of a bake with ``guard_hairs=True``, else ``None``."""
    @property
    def planes(self) -> PlaneSlices | None:
        """The virtual planes' slices of a bake with ``planes``, else ``None``."""
    @property
    def report(self) -> list[StageReport]:
        """Per stage, in order: whether it ran or was reused, seconds, a summary line."""
    @property
    def tile_size(self) -> float: ...
    @property
    def fur_depth(self) -> float: ...
    @property
    def layers(self) -> int: ...
    @property
    def resolution(self) -> int: ...

@final
class Pipeline:
    """A bake cache, one per furred object: keeps the last result of each stage (patches, volume,
    transfer) keyed by exactly the inputs it reads, so a re-bake runs only what changed (a new
    vertex color runs nothing, a new comb the patches, new hair the volume and transfer).

    Over a mesh with colors the coat's ``root_color`` and ``tip_color`` are divided, per channel,
    by the brighter of the two, so the painted color shows as painted at the hair's brightest
    and the coat adds only its shading (adding or removing the colors re-runs the volume)."""

    def __init__(self) -> None: ...
    def clear(self) -> None:
        """Forget every cached stage."""
    def bake(
        self,
        mesh: FurMesh,
        *,
        tile_size: float = 1.0,
        seed: int = 1,
        down: tuple[float, float, float] | None = None,
        hair: HairParams | None = None,
        layers: int = 16,
        resolution: int = 128,
        coverage: str = "exact",
        fin_size: tuple[int, int] = ...,
        fur_depth: float | None = None,
        transfer: bool = True,
        order: int | None = None,
        tolerance: float = ...,
        directions: int = 256,
        phase: Literal["isotropic", "kajiya-kay"] = "kajiya-kay",
        guard_hairs: bool = False,
        guard_share: float = 1.0,
        planes: int = 0,
        progress: Callable[[str, float], bool | None] | None = None,
    ) -> FurAsset:
        """Bake ``mesh`` (GIL released): lapped patches with tiles ``tile_size`` object units wide,
        the hair volume of ``hair``, and (``transfer=True``) its PRT transfer for fur
        ``fur_depth`` object units deep (default: one tile). ``order=None`` picks the SH order by
        band selection within ``tolerance``. ``guard_hairs=True`` draws a ``guard_share`` (in
        ``(0, 1]``) of the overcoat as explicit strands (:attr:`FurAsset.guard_hairs`) and bakes
        the rest of the coat into the volume (and the transfer); it needs a ``guard_fraction``
        and an overcoat width above 0, and at most 1,048,576 guard hairs over the mesh.
        ``planes`` (``[1, 256]``; 0, the default, skips them) bakes that many virtual planes per
        axis for ``Preview.render(shell_method="planes")`` (:attr:`FurAsset.planes`). Every
        parameter is checked before any stage runs. ``progress(stage, fraction)`` returning
        ``False`` cancels with :class:`BakeCancelled`;
        stages finished before the cancel stay cached. Raises :class:`MemoryLimitError` when
        :meth:`peak_bytes` is above :func:`memory_limit`."""
    @staticmethod
    def peak_bytes(
        *,
        tile_size: float = 1.0,
        seed: int = 1,
        down: tuple[float, float, float] | None = None,
        hair: HairParams | None = None,
        layers: int = 16,
        resolution: int = 128,
        coverage: str = "exact",
        fin_size: tuple[int, int] = ...,
        fur_depth: float | None = None,
        transfer: bool = True,
        order: int | None = None,
        tolerance: float = ...,
        directions: int = 256,
        phase: Literal["isotropic", "kajiya-kay"] = "kajiya-kay",
        guard_hairs: bool = False,
        guard_share: float = 1.0,
        planes: int = 0,
    ) -> float:
        """Estimated peak memory in bytes of :meth:`bake` with these arguments (an upper bound;
        the mesh's own share, usually small, is not counted). Checks the arguments as
        :meth:`bake` does, without the memory limit."""

# The wgpu preview renderer.

@type_check_only
class LightingDict(TypedDict, total=False):
    model: Literal["kajiya-kay", "prt"]
    direction: tuple[float, float, float]
    color: tuple[float, float, float]
    self_shadow: float
    ambient: tuple[float, float, float]
    # Kajiya-Kay: the ambient's change per unit of the normal's x, y, z ([3, 3], rows per axis).
    ambient_gradient: npt.ArrayLike
    diffuse: float
    specular: float
    diffuse_power: float
    specular_power: float
    reflect: float
    transmit: float
    # SH radiance [n², 3] (object space): PRT's lighting; under Kajiya-Kay its first two bands
    # set ``ambient`` and ``ambient_gradient`` (the irradiance about each normal over π).
    environment: npt.ArrayLike
    light_radius: float

@type_check_only
class AdapterInfo(TypedDict):
    name: str
    backend: str
    device_type: str

@type_check_only
class UploadStats(TypedDict):
    texture_bytes: int
    geometry_bytes: int
    attribute_bytes: int
    transfer_bytes: int
    pose_bytes: int

@type_check_only
class FrameInfo(TypedDict):
    shells: int
    level: int
    blend: float
    target_shells: float
    radius_pixels: float | None
    fur_pixels: float | None
    mesh_level: int
    triangles: int

@final
class Preview:
    """The real-time preview of one baked asset: a wgpu device (hardware first, or Mesa's CPU
    adapter) with the asset's mesh, patches, hair volume, transfer and guard hairs (drawn as
    strands over the shells) uploaded once."""

    def __new__(cls, asset: FurAsset, *, adapter: Literal["auto", "cpu", "gpu"] = "auto") -> Preview:
        """Open a device (``"auto"``: a GPU when there is one, else the CPU adapter; ``"cpu"``,
        ``"gpu"``: only that kind, :class:`RenderError` when there is none) and upload ``asset``
        (GIL released)."""
    def render(
        self,
        view_matrix: npt.ArrayLike,
        projection_matrix: npt.ArrayLike,
        width: int,
        height: int,
        *,
        lighting: Literal["kajiya-kay", "prt"] | LightingDict | None = None,
        shells: int | None = None,
        fins: bool = True,
        body_shadow: bool = True,
        lod: bool = False,
        linear: bool = False,
        texture: bool = False,
        background: tuple[float, float, float, float] = ...,
        min_shells: int = 4,
        max_shells: int = 64,
        shells_per_pixel: float = 1.0,
        shell_method: Literal["instanced", "marched", "planes", "auto"] = "instanced",
        mesh_error: float = 1.0,
        guard_hairs: bool = True,
        strand_order: Literal["stochastic", "depth", "banded", "sorted"] = "stochastic",
        strand_bands: int = 4,
        strand_pixels: float = 1.0,
        plane_loop_limit: int = 16,
        occluders: npt.ArrayLike | None = None,
        occluder_bias: float | None = None,
    ) -> npt.NDArray[np.uint8] | npt.NDArray[np.float32]:
        """One frame (GIL released): ``[height, width, 4]`` uint8 sRGB, or float32 linear with
        ``linear=True``; straight alpha, top row first. ``texture=True`` returns it as an
        OpenGL-style texture takes it (Blender's ``gpu.types.GPUTexture``): float32 (the sRGB
        bytes over 255, or linear), bottom row first, converted on Pelt's threads.

        ``view_matrix`` maps the mesh's object space to view space and ``projection_matrix`` is
        an OpenGL projection (clip depth -1..1), both 4×4 in the math convention (``M @ v``), as
        ``np.array(region_3d.view_matrix @ obj.matrix_world)`` and
        ``np.array(region_3d.window_matrix)`` give them. ``lighting``: ``None`` is PRT when the
        asset has a transfer, else Kajiya-Kay; a dict sets fields over the model's defaults
        (``color``: the directional light's irradiance × color, Blender's sun strength, so a
        white surface facing it shows ``color / π``, default π; ``environment`` ``[n², 3]`` SH
        radiance for PRT). ``body_shadow``: one part of the mesh shadows the directional light
        on the fur of another (``False``: the fur's own lighting model alone, as a runtime that
        casts no shadows draws it). ``shells``: how many of the volume's
        shells to draw (``None``: all); ``lod=True`` chooses the count from the projected fur
        depth (``shells_per_pixel`` per pixel, within ``min_shells``..``max_shells``) and
        cross-fades LOD levels (``shells`` must be ``None`` then). ``shell_method="marched"``
        draws the shells as one hull whose pixels march down through the layers: one mesh of
        triangles whatever the shell count, several times faster on a CPU adapter, lit once per
        pixel; ``"planes"`` traces each pixel's ray through the asset's virtual planes (a bake
        with ``planes``; raycast paper), crossing at most ``plane_loop_limit`` (``[1, 256]``) of
        them, the shell count and LOD not applying; ``"auto"`` marches (faster on every adapter
        measured). ``mesh_error``: the
        most pixels a simplified version of the mesh, drawn instead of the full one where the
        object is small on screen, may stray from it (0 always draws the full mesh; after
        :meth:`update`, a simplified version that would smear the new colors or lengths, such
        as a bald spot narrower than its triangles, is no longer drawn). The fur is
        :attr:`fur_depth` deep. ``guard_hairs``: draw the asset's guard hairs as strands over
        the shells (``False``: the shells alone); ``strand_order``: how they are composited
        among the shells: ``"stochastic"`` (a thin strand's coverage as a per-pixel random
        choice, opaque, exact on average), ``"depth"`` (coverage as opacity, one draw under the
        shells), ``"banded"`` (``strand_bands`` height bands between the shells), ``"sorted"``
        (a band per shell: the reference, slowest); ``strand_pixels``: the strand LOD keeps a
        share of the strands thinner than this many pixels, drawn that wide (0: every strand).
        ``occluders``: another renderer's depth of the same view, ``[height, width]`` window
        depths in ``[0, 1]`` (OpenGL's depth buffer; 1 where nothing is), rows top first, for
        compositing the fur into its picture (Blender's viewport): the fur behind those surfaces
        is hidden, unless it is within ``occluder_bias`` object units behind them (default three
        fur depths: the fur's own skin and shells in that picture do not hide it).
        Bad input raises :class:`InvalidParameterError` naming it; the
        preview stays usable."""
    def update(
        self,
        *,
        color: npt.ArrayLike | None = None,
        length: npt.ArrayLike | None = None,
        comb: npt.ArrayLike | None = None,
    ) -> None:
        """Rewrite the per-vertex colors (``[V, 4]`` or ``[V, 3]``, linear), length multipliers
        (``[V]``, 0..1000) and/or comb vectors (``[V, 3]``, object space at rest: the shells and
        fins lean with them, in the current pose; the patches keep the bake's orientation) in
        place; nothing else is uploaded (see :attr:`uploads`). A bad array raises
        :class:`InvalidParameterError` naming it and changes nothing."""
    def deform(self, positions: npt.ArrayLike, normals: npt.ArrayLike | None = None) -> None:
        """Pose the fur: the bake's mesh with its vertices at ``positions`` (``[V, 3]``, object
        space; an armature's or shape keys' result, the same vertices and triangles) and unit
        ``normals`` (``[V, 3]``; computed from the posed triangles when omitted). Only the skin,
        shell and fin vertices are re-sent (:attr:`uploads` ``pose_bytes``): no bake, no
        texture upload; the fur keeps its place on the skin and the comb turns with it. Each
        pose is taken from the rest shape. A wrong row count or a non-finite value raises
        :class:`InvalidMeshError` naming ``positions`` or ``normals``; the preview is unchanged."""
    @property
    def levels_dropped(self) -> bool:
        """Whether a repaint (:meth:`update`) left the mesh's coarser levels of detail undrawn
        (they would smear it), so far-away frames draw the full mesh until :meth:`remake_levels`."""
    def remake_levels(self) -> bool:
        """Simplify the mesh again under the current colors and lengths when :attr:`levels_dropped`
        and upload the new levels (GIL released; about as long as the upload's simplification, a
        tenth of a second on 60k triangles): frames far away draw a coarse level again. Returns
        whether it made them."""
    def set_transfer(self, transfer: FurAsset | TransferResult) -> None:
        """Replace the PRT transfer textures with another bake's of the same hair volume (same
        layers and resolution, else :class:`InvalidParameterError`)."""
    @property
    def fur_depth(self) -> float:
        """The fur depth in object units that frames draw with (the height of the volume's top at
        length 1): the asset's at first. Setting it changes the next frame without a re-upload or a
        bake (the shells and fins stretch to it; the guard hairs and a PRT transfer keep the depth
        they were baked for). A NaN, negative or too large value raises
        :class:`InvalidParameterError` naming ``fur_depth`` and keeps the depth set."""
    @fur_depth.setter
    def fur_depth(self, value: float) -> None: ...
    @property
    def adapter(self) -> AdapterInfo: ...
    @property
    def uploads(self) -> UploadStats:
        """Bytes sent to the GPU so far, by kind."""
    @property
    def transfer_order(self) -> int | None: ...
    @property
    def guard_strands(self) -> int:
        """Guard hairs drawn as strands (the asset's; 0 without)."""
    @property
    def last_frame(self) -> FrameInfo | None:
        """What the last frame drew (shell count, LOD level and blend, projected sizes)."""

# Exports of baked assets (glTF 2.0 binaries, texture sets, asset folders; schema in docs/export.md).

_GltfMode = Literal["engine", "geometry"]

@type_check_only
class SkinBinding(TypedDict):
    """One object's binding to ``skeletons[skeleton]``: ``joints`` ``[V, K]`` node indices and
    ``weights`` ``[V, K]`` (non-negative; zero weights are ignored; every vertex needs one)."""

    skeleton: int
    joints: npt.ArrayLike
    weights: npt.ArrayLike

@type_check_only
class OwnMaterialDict(TypedDict, total=False):
    """One of the object's own materials: ``name`` (required, 1 to 64 characters), ``base_color``
    linear RGBA in ``[0, 1]`` (default 0.8 grey, opaque), ``metallic`` (0) and ``roughness`` (0.5)."""

    name: str
    base_color: Sequence[float]
    metallic: float
    roughness: float

@type_check_only
class MaterialSlotsDict(TypedDict):
    """An object's material slots (``None`` for an empty one) and the slot of each triangle
    ``[T]``: a triangle bald at its three corners keeps its slot's material, as Pelt's Blender fur
    does."""

    slots: Sequence[OwnMaterialDict | None]
    triangle_slot: npt.ArrayLike

@type_check_only
class AnimationDict(TypedDict):
    """Sampled animation: ``times`` ``[T]`` seconds (increasing), ``poses`` ``[T, N, 4, 4]``
    every node's matrix relative to its parent, row-major."""

    name: str
    times: npt.ArrayLike
    poses: npt.ArrayLike

@type_check_only
class SkeletonDict(TypedDict, total=False):
    """A node hierarchy: ``names`` ``[N]``, ``parents`` ``[N]`` (-1 for a root), ``rest``
    ``[N, 4, 4]`` matrices relative to the parent, row-major; optional ``animations``."""

    names: Sequence[str]
    parents: npt.ArrayLike
    rest: npt.ArrayLike
    animations: Sequence[AnimationDict]

@type_check_only
class WeightReport(TypedDict):
    """What binding an object changed: ``vertices`` bound, ``reduced`` (more than four joints,
    the strongest four kept), ``renormalized`` (weights that did not sum to 1)."""

    vertices: int
    reduced: int
    renormalized: int

_TextureFormat = Literal["png", "ktx2", "exr"]

@type_check_only
class ManifestFile(TypedDict, total=False):
    path: str
    kind: str
    format: str
    pixel_format: str
    color_space: Literal["srgb", "linear"]
    width: int
    height: int
    layers: int
    layer: int
    texture: int
    levels: int
    layout: str
    mode: _GltfMode
    bytes: int
    meaning: str

@type_check_only
class ManifestObject(TypedDict):
    name: str
    stack: dict[str, object]
    files: list[ManifestFile]

@type_check_only
class Manifest(TypedDict):
    format: Literal["pelt-asset"]
    version: int
    generator: str
    objects: list[ManifestObject]
    files: list[ManifestFile]

def export_gltf(
    asset: FurAsset | Sequence[FurAsset],
    path: str | os.PathLike[str],
    *,
    mode: _GltfMode = "engine",
    name: str | Sequence[str] | None = None,
    fins: bool = True,
    shells: int | None = None,
    transform: npt.ArrayLike | Sequence[npt.ArrayLike | None] | None = None,
    skin: SkinBinding | Sequence[SkinBinding | None] | None = None,
    skeletons: Sequence[SkeletonDict] | None = None,
    materials: MaterialSlotsDict | Sequence[MaterialSlotsDict | None] | None = None,
    animations: AnimationDict | Sequence[AnimationDict | Sequence[AnimationDict] | None] | None = None,
) -> list[WeightReport | None]:
    """Write ``asset`` (one, or several as one node each, named by ``name``; default ``Object``,
    ``Object.1``, ...) as a glTF binary (GIL released). ``mode="geometry"`` bakes the shells (one
    primitive each, ``shells`` of them, default every layer above the skin) and the fins
    (``fins``) into alpha-blended meshes any viewer shows; ``"engine"`` writes the base mesh with
    ``TEXCOORD_1`` = PeltUV, ``COLOR_0``, ``_PELT_LENGTH``, ``_PELT_COMB``, ``_PELT_DPDU``,
    ``_PELT_DPDV``, the atlases and the stack description in the ``PELT_shell_fur`` extension of
    its first primitive, and four alpha-tested fallback shells for viewers without it.

    ``transform`` places each object (a 4×4 row-major matrix, translation in the last column, or
    one per object). ``skeletons`` are node hierarchies with sampled animations; ``skin`` binds an
    object to one of them (per vertex ``K`` joints and weights; the four strongest are kept and
    normalized). A skinned object's shells and fins carry the weights of the skin vertex they
    stand on. ``materials`` keeps an object's own materials on its bald faces, as plain
    primitives without fur. ``animations`` moves an unskinned object's node (``poses``
    ``[T, 4, 4]``: its transform at each time). Returns per object what binding it changed
    (``None`` for an unskinned object)."""

def write_texture_set(
    asset: FurAsset | Sequence[FurAsset],
    folder: str | os.PathLike[str],
    *,
    formats: str | Sequence[_TextureFormat] | None = None,
    name: str | Sequence[str] | None = None,
) -> Manifest:
    """Write every texture of ``asset`` into ``folder`` in ``formats`` (``"png,ktx2,exr"`` or a
    list; default all): per-layer and atlas PNGs, EXR density and float16 transfer, KTX2 arrays
    with mipmaps; plus ``pelt.json``. Returns the manifest (GIL released)."""

def write_asset(
    asset: FurAsset | Sequence[FurAsset],
    folder: str | os.PathLike[str],
    *,
    formats: str | Sequence[_TextureFormat] | None = None,
    modes: Sequence[_GltfMode] | None = None,
    name: str | Sequence[str] | None = None,
    fins: bool = True,
    glb_stem: str = ...,
) -> Manifest:
    """:func:`write_texture_set` plus one ``<glb_stem>_<mode>.glb`` per mode (default engine and
    geometry), all listed in ``pelt.json``. Returns the manifest (GIL released)."""

@type_check_only
class SunLight(TypedDict, total=False):
    type: Literal["sun"]
    direction: tuple[float, float, float]
    strength: float
    color: tuple[float, float, float]

@type_check_only
class EnvironmentLight(TypedDict):
    type: Literal["environment"]
    sh: npt.ArrayLike

@type_check_only
class ReferenceInfo(TypedDict):
    samples: int
    relative_error: float
    pixel_error: float
    seconds: float

def render_reference(
    asset: FurAsset,
    view_matrix: npt.ArrayLike,
    projection_matrix: npt.ArrayLike,
    width: int,
    height: int,
    *,
    lights: Sequence[SunLight | EnvironmentLight] | None = None,
    samples: int = 16,
    max_samples: int = 1024,
    target_error: float = 0.01,
    seed: int = 0,
    shadows: bool = True,
    mode: Literal["strands", "volume"] = "strands",
    progress: Callable[[float], bool | None] | None = None,
) -> tuple[npt.NDArray[np.float32], ReferenceInfo]:
    """A ground-truth image of ``asset`` (GIL released): the tile's strands placed over the mesh
    as the shells imply and ray traced with exact shadows. The camera is as in
    :meth:`Preview.render`. Returns ``[height, width, 4]`` float32 linear RGB premultiplied by
    coverage, and coverage (top row first, no tone mapping), with the samples per pixel taken,
    the achieved relative standard error of the mean radiance and of single pixels, and seconds.

    ``lights``: suns (``direction`` toward the light, ``strength`` in Blender's units, so a white
    surface facing a sun of strength E has radiance E/π; ``color`` linear) and SH environments
    (``sh`` ``[n², 3]`` radiance); default one sun of strength π from the upper right. Samples
    per pixel: at least ``samples``, more until the mean radiance is within ``target_error``,
    at most ``max_samples``. ``progress(fraction)`` returning ``False`` cancels
    (:class:`BakeCancelled`); nothing is returned then. ``mode="volume"`` ray marches the baked
    density volume through the triangles' prisms instead of tracing the strands (the hybrid
    paper's method: single scattering, attenuation toward light and eye). Bad input (a camera
    inside the mesh, zero samples, an asset without strands) raises
    :class:`InvalidParameterError` naming it."""

def _panic_for_test(message: str) -> None:
    """Panics inside the library on purpose; raises :class:`PeltError` (tests check no panic
    crosses into Python)."""
