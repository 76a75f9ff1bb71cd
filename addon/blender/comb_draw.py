# SPDX-License-Identifier: GPL-3.0-or-later
"""What the interactive comb draws over the 3D viewport: the brush circle and the comb vectors.

``gpu`` exists only where Blender draws (not in background mode), so it is imported inside the
draw callbacks; the geometry is made with numpy.
"""

import numpy as np

CIRCLE_SEGMENTS = 64
CIRCLE_COLOR = (1.0, 1.0, 1.0, 0.9)
COMB_COLOR = (1.0, 0.55, 0.1, 0.9)


def circle_points(center, radius: float) -> np.ndarray:
    """``[CIRCLE_SEGMENTS + 1, 3]`` points of a closed circle in region pixels (z = 0)."""
    angle = np.linspace(0.0, 2.0 * np.pi, CIRCLE_SEGMENTS + 1)
    points = np.zeros((CIRCLE_SEGMENTS + 1, 3), dtype=np.float32)
    points[:, 0] = center[0] + radius * np.cos(angle)
    points[:, 1] = center[1] + radius * np.sin(angle)
    return points


def comb_segments(world, world_normals, world_comb, size: float) -> np.ndarray:
    """``[2K, 3]`` line ends showing each nonzero comb: from just above the surface along the
    comb, ``size`` long for a comb of length 1."""
    keep = np.flatnonzero(np.linalg.norm(world_comb, axis=1) > 0.0)
    start = world[keep] + world_normals[keep] * (0.05 * size)
    segments = np.empty((2 * len(keep), 3), dtype=np.float32)
    segments[0::2] = start
    segments[1::2] = start + world_comb[keep] * size
    return segments


def draw_circle(region, center, radius: float) -> None:
    """POST_PIXEL callback body: the brush outline."""
    import gpu
    from gpu_extras.batch import batch_for_shader

    shader = gpu.shader.from_builtin("POLYLINE_UNIFORM_COLOR")
    batch = batch_for_shader(shader, "LINE_STRIP", {"pos": circle_points(center, radius)})
    gpu.state.blend_set("ALPHA")
    shader.uniform_float("viewportSize", (region.width, region.height))
    shader.uniform_float("lineWidth", 1.5)
    shader.uniform_float("color", CIRCLE_COLOR)
    batch.draw(shader)
    gpu.state.blend_set("NONE")


def draw_lines(segments: np.ndarray) -> None:
    """POST_VIEW callback body: the comb vectors, hidden behind the surface like the mesh."""
    if len(segments) == 0:
        return
    import gpu
    from gpu_extras.batch import batch_for_shader

    shader = gpu.shader.from_builtin("UNIFORM_COLOR")
    batch = batch_for_shader(shader, "LINES", {"pos": segments})
    gpu.state.blend_set("ALPHA")
    gpu.state.depth_test_set("LESS_EQUAL")
    shader.uniform_float("color", COMB_COLOR)
    batch.draw(shader)
    gpu.state.depth_test_set("NONE")
    gpu.state.blend_set("NONE")
