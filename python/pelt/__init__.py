"""Pelt: real-time fur on any mesh.

The compiled core lives in ``pelt._pelt``; this package re-exports it. Arrays go in and come out as
numpy (float32 / uint32, C-contiguous; other numeric dtypes are converted). Every error is a
``pelt.PeltError``.
"""

from ._pelt import (
    BakeCancelled,
    FurMesh,
    InvalidMeshError,
    InvalidParameterError,
    Patches,
    PeltError,
    RenderError,
    __version__,
    build_patches,
    thread_count,
)

__all__ = [
    "BakeCancelled",
    "FurMesh",
    "InvalidMeshError",
    "InvalidParameterError",
    "Patches",
    "PeltError",
    "RenderError",
    "__version__",
    "build_patches",
    "thread_count",
]
