"""Pelt: real-time fur on any mesh.

The compiled core lives in ``pelt._pelt``; this package re-exports it. Arrays go in and come out as
numpy (float32 / uint32, C-contiguous; other numeric dtypes are converted). Every error is a
``pelt.PeltError``.
"""

from ._pelt import (
    BakeCancelled,
    FurAsset,
    FurMesh,
    HairParams,
    InvalidMeshError,
    InvalidParameterError,
    Patches,
    PeltError,
    Pipeline,
    Preview,
    RenderError,
    __version__,
    bake_transfer,
    bake_volume,
    build_patches,
    encode_png,
    export_gltf,
    pack_atlas,
    save_exr,
    save_png,
    set_thread_count,
    sh_project_equirect,
    sh_project_light,
    thread_count,
    write_asset,
    write_texture_set,
)

__all__ = [
    "BakeCancelled",
    "FurAsset",
    "FurMesh",
    "HairParams",
    "InvalidMeshError",
    "InvalidParameterError",
    "Patches",
    "PeltError",
    "Pipeline",
    "Preview",
    "RenderError",
    "__version__",
    "bake_transfer",
    "bake_volume",
    "build_patches",
    "encode_png",
    "export_gltf",
    "pack_atlas",
    "save_exr",
    "save_png",
    "set_thread_count",
    "sh_project_equirect",
    "sh_project_light",
    "thread_count",
    "write_asset",
    "write_texture_set",
]
