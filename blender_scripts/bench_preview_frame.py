# SPDX-License-Identifier: GPL-3.0-or-later
"""The live preview's frame without Blender: render, read back and convert as the worker does.

``bench_preview.py`` beside it times the add-on's preview inside Blender on the CPU adapter;
this times the same worker step (``pelt.Preview.render`` with the add-on's default settings and
``texture=True``, the floats Blender's texture takes) on whichever adapter is asked for, at
960×540 and 1920×1080, so a machine with a GPU but no Blender gives the figure too (it imports no
bpy). The 8-bit frame alone is timed too: the difference is the conversion. The scene is the
Blender bench's: a UV sphere of 192 segments and 80 rings (30,336 triangles), tiles 0.3 wide,
fur 0.08 deep, Kajiya–Kay.
"""

import argparse
import statistics
import time
from pathlib import Path

import numpy as np
import pelt
from _setup import write_cases

SIZES = ((960, 540), (1920, 1080))
FRAMES = 30


def uv_sphere(segments: int, rings: int) -> tuple[np.ndarray, np.ndarray]:
    """Blender's UV sphere of radius 1: poles, rings of quads split in two, fans at the poles."""
    theta = np.pi * np.arange(1, rings) / rings
    phi = 2 * np.pi * np.arange(segments) / segments
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1).reshape(-1, 3)
    positions = np.vstack([[0, 0, 1], ring, [0, 0, -1]]).astype(np.float32)
    index = np.arange(ring.shape[0]).reshape(rings - 1, segments) + 1
    right = np.roll(index, -1, axis=1)
    quads = np.stack([index[:-1], index[1:], right[1:], right[:-1]], -1).reshape(-1, 4)
    bottom = len(positions) - 1
    top_fan = np.stack([np.zeros(segments, int), index[0], right[0]], -1)
    bottom_fan = np.stack([index[-1], np.full(segments, bottom), right[-1]], -1)
    triangles = np.vstack([top_fan, quads[:, [0, 1, 2]], quads[:, [0, 2, 3]], bottom_fan])
    return positions, triangles.astype(np.uint32)


def view_matrix(turn: float) -> np.ndarray:
    """The camera 3.2 units out along −y, orbiting about z by ``turn`` radians (world to view)."""
    eye = np.array([3.2 * np.sin(turn), -3.2 * np.cos(turn), 0.0])
    forward = -eye / np.linalg.norm(eye)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    rotation = np.stack([right, up, -forward])
    view = np.eye(4)
    view[:3, :3] = rotation
    view[:3, 3] = -rotation @ eye
    return view.astype(np.float32)


def projection(width: int, height: int) -> np.ndarray:
    """The lens of both preview benches (this and ``bench_preview.py``), as OpenGL clip space."""
    near, far, focal = 0.1, 100.0, 1.8
    return np.array(
        [
            [focal * height / width, 0, 0, 0],
            [0, focal, 0, 0],
            [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
            [0, 0, -1, 0],
        ],
        np.float32,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--adapter", choices=("auto", "cpu", "gpu"), default="auto")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()

    positions, triangles = uv_sphere(192, 80)
    asset = pelt.Pipeline().bake(
        pelt.FurMesh(positions, triangles), tile_size=0.3, fur_depth=0.08, layers=16, transfer=False
    )
    preview = pelt.Preview(asset, adapter=args.adapter)
    adapter = dict(preview.adapter)
    # The add-on's defaults (addon/blender/props.py): auto method, fins, LOD from 4 to 32 shells.
    options = {"shell_method": "auto", "fins": True, "lod": True, "min_shells": 4, "max_shells": 32}
    cases = []
    for width, height in SIZES:
        proj = projection(width, height)
        preview.render(view_matrix(0.0), proj, width, height, **options)
        rendered, textures = [], []
        for i in range(FRAMES):
            for texture, seconds in ((False, rendered), (True, textures)):
                start = time.perf_counter()
                preview.render(view_matrix(0.05 * i), proj, width, height, texture=texture, **options)
                seconds.append(time.perf_counter() - start)
        cases.append(
            {
                "name": f"preview.frame.{height}p",
                "size": (
                    f"{len(triangles)} triangles, {width}×{height}, "
                    f"{adapter['name']} ({adapter['device_type']}): "
                    f"the 8-bit frame alone {statistics.median(rendered) * 1e3:.2f} ms"
                ),
                "seconds": statistics.median(textures),
            }
        )
    write_cases(cases, args.json)


if __name__ == "__main__":
    main()
