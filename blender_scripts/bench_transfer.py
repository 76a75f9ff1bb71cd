"""Benchmark: the Blender side of a bake on a 100k-face mesh.

Builds a grid of 317 × 317 quads (100,489 faces, 200,978 triangles) with the three Pelt point
attributes, then times ``bridge.read_mesh`` (foreach_get into numpy, loop triangles, normals,
attributes) and ``MeshArrays.fur_mesh`` (validation, edge map, frames in Rust); then a whole bake
of that mesh as the bake operator runs it: the pipeline on its worker thread (patches, hair
volume; Kajiya-Kay lighting, so no transfer) against Blender's overhead around it (reading the
mesh, writing ``PeltUV``, ``pelt_patch``, the images and the material). Writes the figures as
``pelt bench`` JSON cases (``--json``) and prints them.
"""

import argparse
import statistics
import time
from pathlib import Path

import bpy
import numpy as np
from _setup import register_addon, write_cases

REPEATS = 9


def median_seconds(work, repeats=REPEATS):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        work()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def bake_overhead(addon, obj, size: str) -> list:
    """The pipeline's time against the Blender-side time of the same bake: the first bake of the
    object (Pelt's materials and node tree built from nothing) and the median of three more
    with fresh pipelines (every stage runs again; the node trees are kept, their inputs being
    unchanged)."""
    bake, writer = addon.blender.bake, addon.blender.writer
    obj.pelt.tile_size = 0.05
    pipeline_times, overhead_times = [], []
    for _ in range(4):
        addon.blender.preferences.CACHE.clear()
        start = time.perf_counter()
        job = bake.start_job(obj)
        read = time.perf_counter() - start
        job.start().wait()
        if job.error is not None:
            raise job.error
        start = time.perf_counter()
        writer.write_asset(obj, job.asset, build_material=bake.build_material)
        overhead_times.append(read + time.perf_counter() - start)
        pipeline_times.append(job.seconds)
    pipeline, overhead = statistics.median(pipeline_times[1:]), statistics.median(overhead_times[1:])
    first = overhead_times[0]
    return [
        {
            "name": "blender.bake.pipeline",
            "size": size + ", 16 layers of 128², no transfer",
            "seconds": pipeline,
        },
        {
            "name": "blender.bake.overhead",
            "size": f"read + write of a re-bake: {overhead / pipeline:.1%} of the pipeline's time",
            "seconds": overhead,
        },
        {
            "name": "blender.bake.overhead.first",
            "size": f"read + write of the first bake: {first / pipeline_times[0]:.1%} of its pipeline's time",
            "seconds": first,
        },
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()

    addon = register_addon()
    bridge = addon.io.bridge
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=317, y_subdivisions=317, size=2.0)
    mesh = bpy.context.active_object.data
    n = len(mesh.vertices)
    mesh.attributes.new("pelt_color", "FLOAT_COLOR", "POINT").data.foreach_set("color", np.ones(4 * n))
    mesh.attributes.new("pelt_comb", "FLOAT_VECTOR", "POINT").data.foreach_set("vector", np.ones(3 * n))
    mesh.attributes.new("pelt_length", "FLOAT", "POINT").data.foreach_set("value", np.ones(n))
    mesh.calc_loop_triangles()
    size = f"{len(mesh.polygons)} faces, {len(mesh.loop_triangles)} triangles, {n} vertices, 3 attributes"

    def transfer():
        return bridge.read_mesh(mesh).fur_mesh()

    first_start = time.perf_counter()
    fur = transfer()
    first = time.perf_counter() - first_start
    assert fur.stats()["faces"] == len(mesh.loop_triangles)
    arrays = bridge.read_mesh(mesh)
    cases = [
        {"name": "blender.transfer", "size": size, "seconds": median_seconds(transfer)},
        {
            "name": "blender.transfer.read",
            "size": size,
            "seconds": median_seconds(lambda: bridge.read_mesh(mesh)),
        },
        {"name": "blender.transfer.build", "size": size, "seconds": median_seconds(arrays.fur_mesh)},
        {"name": "blender.transfer.first_call", "size": size, "seconds": first},
    ]
    cases += bake_overhead(addon, bpy.context.active_object, size)
    write_cases(cases, args.json)


if __name__ == "__main__":
    main()
