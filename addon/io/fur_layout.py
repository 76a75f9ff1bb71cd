# SPDX-License-Identifier: GPL-3.0-or-later
"""The numbers behind Pelt's Blender fur (``blender/materials.py``, ``blender/geonodes.py``), without Blender.

Lengyel et al. 2001, §2.3: the skin (layer 0 of the shell texture, opaque), ``S - 1`` shells lifted
off it along the growth direction, and a fin on every edge. Shell ``j`` of ``1..S-1`` shows layer
``round(j (L - 1) / (S - 1))`` of the ``L`` layers, so fewer shells keep the full fur depth (the
choice of ``crates/pelt-render/src/shells.wgsl``), and sits at ``layer / L × depth × length`` along
``normal + comb - normal (normal · comb)``. The shell atlas holds the layers in a grid of
``columns = ceil(sqrt(L))`` by ``rows = ceil(L / columns)`` cells, layer ``k`` at column
``k % columns``, row ``k // columns`` counted from the top (``pelt.pack_atlas``).

The geometry and shader nodes evaluate the same formulas; the functions here are their reference,
used by the tests and by callers that need the counts.
"""

import math
from dataclasses import dataclass

import numpy as np
import pelt


@dataclass(frozen=True)
class FurSettings:
    """What the Geometry Nodes fur is built from (the node group's inputs)."""

    layers: int = 16
    """Layers of the shell atlas (``L``): shell offsets are multiples of ``depth / layers``."""
    shells: int = 16
    """Surfaces drawn, the skin included (``S <= L``)."""
    depth: float = 0.05
    """Fur depth in object units: how far hair of length multiplier 1 reaches."""
    fins: bool = True
    """Whether to add a fin on every furred edge."""
    tile_size: float = 0.1
    """Object units per texture tile: the fin texture runs ``edge length / tile_size`` tiles."""

    def __post_init__(self):
        checks = (
            ("layers", self.layers >= 1, "must be at least 1"),
            ("shells", 1 <= self.shells <= self.layers, f"must be in 1..layers ({self.layers})"),
            ("depth", math.isfinite(self.depth) and self.depth >= 0.0, "must be finite and >= 0"),
            ("tile_size", math.isfinite(self.tile_size) and self.tile_size > 0.0, "must be > 0"),
        )
        for name, ok, rule in checks:
            if not ok:
                raise pelt.InvalidParameterError(
                    f"invalid parameter `{name}`: {rule}, got {getattr(self, name)}"
                )

    @classmethod
    def for_volume(cls, volume: dict, *, depth: float, shells: int | None = None, **rest) -> "FurSettings":
        """Settings for a ``pelt.bake_volume`` result: ``layers`` is the atlas's kept layers, and
        ``depth`` (the fur depth asked for) shrinks by the trimmed empty top layers, so layer ``k``
        still sits at ``k × layer_spacing × depth``."""
        layers = int(volume["layers"])
        kept_depth = depth * layers * float(volume["layer_spacing"])
        return cls(layers=layers, shells=layers if shells is None else shells, depth=kept_depth, **rest)


def atlas_uv(uv: np.ndarray, layer: np.ndarray, columns: int, rows: int, resolution: int) -> np.ndarray:
    """Where the fur material samples the atlas (Blender image coordinates, ``v`` up) for tile
    coordinates ``uv`` (``PeltUV``, ``[..., 2]``, ``v`` down the tile as Pelt stores it) on
    ``layer``: the fraction of ``uv`` inside the layer's cell, kept half a texel away from the cell's
    border so no sample reads a neighbouring layer."""
    inset = 0.5 / resolution
    inside = np.clip(uv - np.floor(uv), inset, 1.0 - inset)
    layer = np.asarray(layer)
    column, row = layer % columns, layer // columns
    return np.stack([(column + inside[..., 0]) / columns, 1.0 - (row + inside[..., 1]) / rows], axis=-1)
