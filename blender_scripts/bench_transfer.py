"""Benchmark: moving a 100k-face Blender mesh into ``pelt.FurMesh``.

Builds a grid of 317 × 317 quads (100,489 faces, 200,978 triangles) with the three Pelt point
attributes, then times ``bridge.read_mesh`` (foreach_get into numpy, loop triangles, normals,
attributes) and ``MeshArrays.fur_mesh`` (validation, edge map, frames in Rust). Writes the figures
as ``pelt bench`` JSON cases (``--json``) and prints them.
"""

import argparse
import json
import statistics
import time
from pathlib import Path

import bpy
import numpy as np
from _setup import register_addon

REPEATS = 9


def median_seconds(work, repeats=REPEATS):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        work()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()

    addon = register_addon()
    bridge = addon.bridge
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
    for case in cases:
        case.update(peak_bytes=None, error=None, error_metric=None, baseline=None, speedup=None)
        print(f"{case['name']:<30} {case['seconds'] * 1000:9.2f} ms  {case['size']}")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"cases": cases}, indent=2) + "\n")


if __name__ == "__main__":
    main()
