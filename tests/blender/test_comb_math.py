"""The pure comb math (``addon/io/comb_math.py``, ``addon/io/paint_math.py``): no Blender data involved,
each result checked against a direct computation or a known value."""

import sys

import numpy as np
import pytest
from conftest import REPO

if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

from addon.io import comb_math, paint_math


@pytest.fixture
def rng():
    return np.random.default_rng(7)


def random_unit(rng, count):
    v = rng.normal(size=(count, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def test_tangential_removes_the_normal_part(rng):
    normals = random_unit(rng, 50) * rng.uniform(0.5, 2.0, (50, 1))  # not unit: must not matter
    vectors = rng.normal(size=(50, 3))
    t = comb_math.tangential(vectors, normals)
    unit = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    np.testing.assert_allclose(np.einsum("ij,ij->i", t, unit), 0.0, atol=1e-12)
    np.testing.assert_allclose(t + unit * np.einsum("ij,ij->i", vectors, unit)[:, None], vectors, atol=1e-12)


def test_falloff_is_one_at_the_center_and_zero_from_the_rim():
    d = np.array([0.0, 0.5, 1.0, 1.5])
    np.testing.assert_allclose(comb_math.falloff(d, 1.0), [1.0, 0.5625, 0.0, 0.0])
    np.testing.assert_array_equal(comb_math.falloff(d, 0.0), 0.0)


def test_lean_follows_strands_up_to_45_degrees():
    normals = np.tile([0.0, 0.0, 1.0], (4, 1))
    angles = np.radians([10.0, 45.0, 70.0, 120.0])
    directions = np.column_stack([np.sin(angles), np.zeros(4), np.cos(angles)])
    comb = comb_math.lean(directions, normals)
    # tan θ up to 45°, length 1 beyond (and for a strand pointing into the surface)
    np.testing.assert_allclose(comb[:, 0], [np.tan(angles[0]), 1.0, 1.0, 1.0], rtol=1e-6)
    np.testing.assert_allclose(comb[:, 1:], 0.0, atol=1e-7)


@pytest.mark.parametrize("shape", ["cloud", "plane", "line"])
def test_nearest_matches_brute_force(rng, shape):
    count = 2000
    points = {
        "cloud": rng.normal(size=(count, 3)),
        "plane": np.column_stack([rng.uniform(size=(count, 2)), np.zeros(count)]),
        "line": np.column_stack([rng.uniform(size=count), np.zeros((count, 2))]),
    }[shape]
    points = np.round(points, 2)  # duplicates: ties must go to the lower index
    queries = np.concatenate(
        [
            points[rng.integers(0, count, 300)] + rng.normal(scale=0.01, size=(300, 3)),
            rng.normal(scale=3.0, size=(100, 3)),
        ]
    )
    distance = np.linalg.norm(queries[:, None] - points[None], axis=2)
    expected = np.argmin(distance, axis=1)
    # a small chunk budget sends the queries through the grid, then the coarser grids, then brute force
    np.testing.assert_array_equal(comb_math.nearest(points, queries, chunk_bytes=1 << 16), expected)
    np.testing.assert_array_equal(comb_math.nearest(points, queries), expected)


def test_strand_directions_skip_single_points_and_zero_length_strands():
    positions = np.array(
        [[0, 0, 0], [0, 0, 1], [0, 1, 2],  # 3 points: root (0,0,0), tip (0,1,2)
         [5, 5, 5],  # a single point
         [1, 1, 1], [1, 1, 1]],  # tip on the root
        dtype=np.float32,
    )  # fmt: skip
    roots, directions, used = comb_math.strand_directions(positions, [0, 3, 4, 6])
    np.testing.assert_array_equal(used, [True, False, False])
    np.testing.assert_allclose(roots, [[0, 0, 0]])
    np.testing.assert_allclose(directions, [[0, 1, 2]])


def test_propagate_fills_each_reachable_component():
    # a path 0-1-2-3 and an isolated edge 4-5 without any known vertex
    edges = np.array([[0, 1], [1, 2], [2, 3], [4, 5]])
    normals = np.tile([0.0, 0.0, 1.0], (6, 1))
    comb = np.zeros((6, 3), np.float32)
    comb[0] = (0.5, 0.0, 0.0)
    known = np.array([True, False, False, False, False, False])
    filled_comb, filled = comb_math.propagate(comb, known, edges, normals)
    np.testing.assert_array_equal(filled, [True, True, True, True, False, False])
    np.testing.assert_allclose(filled_comb[:4], np.tile([0.5, 0.0, 0.0], (4, 1)), atol=1e-6)
    np.testing.assert_array_equal(filled_comb[4:], 0.0)


def test_smooth_keeps_a_uniform_field_and_leaves_unmasked_vertices(rng):
    edges = np.array([[0, 1], [1, 2], [2, 0], [2, 3]])
    normals = np.tile([0.0, 0.0, 1.0], (4, 1))
    uniform = np.tile([0.3, -0.4, 0.0], (4, 1)).astype(np.float32)
    np.testing.assert_allclose(comb_math.smooth(uniform, normals, edges, 10, 0.5), uniform, atol=1e-6)
    noisy = np.column_stack([rng.normal(size=(4, 2)), np.zeros(4)]).astype(np.float32)
    mask = np.array([True, False, True, False])
    out = comb_math.smooth(noisy, normals, edges, 3, 0.5, mask)
    np.testing.assert_array_equal(out[~mask], noisy[~mask])
    assert not np.allclose(out[mask], noisy[mask])


def test_length_paint_round_trip():
    length = np.linspace(0.0, paint_math.LENGTH_PAINT_MAX, 41)
    rgba = paint_math.length_to_paint(length)
    assert rgba.dtype == np.float32 and rgba.shape == (41, 4)
    np.testing.assert_array_equal(rgba[:, 3], 1.0)
    np.testing.assert_allclose(paint_math.paint_to_length(rgba), length, atol=2e-6)
    # the default length is mid gray as the user sees it: sRGB 0.5, linear 0.2140
    mid = paint_math.length_to_paint(np.array([paint_math.DEFAULT_LENGTH]))[0, 0]
    assert mid == pytest.approx(((0.5 + 0.055) / 1.055) ** 2.4, rel=1e-6)


def perspective_view(width=800, height=600):
    """A perspective view from (0, -10, 0) looking along +y (near 0.01, far 1000, 50° fov)."""
    near, far, f = 0.01, 1000.0, 1.0 / np.tan(np.radians(25.0))
    window = np.array(
        [[f * height / width, 0, 0, 0], [0, f, 0, 0],
         [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)], [0, 0, -1, 0]]
    )  # fmt: skip
    # world -> eye: eye x = world x, eye y = world z, eye z = -(world y + 10)
    view = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, -10], [0, 0, 0, 1]], dtype=np.float64)
    return comb_math.ScreenView(window, view, width, height, True)


def orthographic_view(width=800, height=600):
    view = perspective_view(width, height).view
    window = np.diag([2.0 / 8.0, 2.0 / 6.0, -2.0 / 100.0, 1.0])
    return comb_math.ScreenView(window, view, width, height, False)


@pytest.mark.parametrize("make_view", [perspective_view, orthographic_view])
def test_a_drag_moves_the_projection_by_the_drag_at_the_same_depth(rng, make_view):
    view = make_view()
    points = rng.uniform(-2.0, 2.0, (30, 3))
    pixels, w, front = view.project(points)
    assert front.all()
    drag = np.array([17.0, -6.0])
    moved = points + view.drag_at_depth(drag, w)
    np.testing.assert_allclose(view.project(moved)[0], pixels + drag, atol=1e-7)
    eye_depth = lambda p: p @ view.view[2, :3] + view.view[2, 3]  # noqa: E731
    np.testing.assert_allclose(eye_depth(moved), eye_depth(points), atol=1e-12)


def test_screen_dab_picks_front_facing_vertices_inside_the_circle():
    view = perspective_view()
    # a row of points along x at y = 0, half facing the eye (normal -y), half away
    world = np.column_stack([np.linspace(-1, 1, 21), np.zeros(21), np.zeros(21)])
    normals = np.tile([0.0, -1.0, 0.0], (21, 1))
    normals[::2] = (0.0, 1.0, 0.0)
    center = view.project(np.zeros((1, 3)))[0][0]
    radius = float(np.abs(view.project(world[[15]])[0][0, 0] - center[0])) + 0.5  # reaches |x| <= 0.5
    indices, deltas, weights = comb_math.screen_dab(
        view, world, normals, np.eye(3), center, (radius, 0.0), radius, True
    )
    np.testing.assert_array_equal(indices, [5, 7, 9, 11, 13, 15])
    # a drag by one radius to the right: unit length along +x before the falloff
    np.testing.assert_allclose(deltas, np.tile([1.0, 0.0, 0.0], (6, 1)), atol=1e-12)
    # symmetric about the center, rising towards it
    assert 0.0 < weights[0] < weights[1] < weights[2] < 1.0
    assert weights[2] == pytest.approx(weights[3])
    everything = comb_math.screen_dab(view, world, normals, np.eye(3), center, (1.0, 0.0), radius, False)[0]
    np.testing.assert_array_equal(everything, np.arange(5, 16))
