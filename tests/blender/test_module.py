"""The ``pelt`` Python module: arrays in and out, conversions, the exception tree, the panic guard
and the released GIL."""

import threading
import time
import tomllib

import numpy as np
import pelt
import pytest
from conftest import REPO


def octahedron():
    positions = np.array(
        [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float32
    )
    triangles = np.array(
        [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]],
        dtype=np.uint32,
    )
    return positions, triangles


def grid(n):
    """An n×n grid of quads in the XY plane, 2n² triangles."""
    ys, xs = np.mgrid[0 : n + 1, 0 : n + 1]
    positions = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], axis=1).astype(np.float32)
    i = (np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]).ravel()
    a, b, c, d = i, i + 1, i + n + 2, i + n + 1
    triangles = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.uint32)
    return positions, triangles


def test_version_matches_the_crate():
    cargo = tomllib.loads((REPO / "Cargo.toml").read_text())
    assert pelt.__version__ == cargo["workspace"]["package"]["version"]


def test_exception_tree():
    for cls in (pelt.InvalidMeshError, pelt.InvalidParameterError, pelt.BakeCancelled, pelt.RenderError):
        assert issubclass(cls, pelt.PeltError)
    assert issubclass(pelt.PeltError, Exception)
    assert pelt.PeltError.__module__ == "pelt"


def test_octahedron_stats_and_arrays():
    positions, triangles = octahedron()
    mesh = pelt.FurMesh(positions, triangles)
    stats = mesh.stats()
    assert (stats["vertices"], stats["faces"], stats["edges"]) == (6, 8, 12)
    assert stats["boundary_edges"] == 0 and stats["components"] == 1
    assert stats["surface_area"] == pytest.approx(4 * np.sqrt(3), rel=1e-6)
    assert stats["bbox_min"] == [-1, -1, -1] and stats["bbox_max"] == [1, 1, 1]
    np.testing.assert_array_equal(mesh.positions, positions)
    np.testing.assert_array_equal(mesh.triangles, triangles)
    assert mesh.positions.dtype == np.float32 and mesh.triangles.dtype == np.uint32
    # area-weighted normals of a regular octahedron point along the vertex directions
    np.testing.assert_allclose(mesh.normals, positions, atol=1e-6)
    frame = np.stack([mesh.tangents, mesh.bitangents, mesh.normals], axis=1)
    np.testing.assert_allclose(
        frame @ frame.transpose(0, 2, 1), np.broadcast_to(np.eye(3), (6, 3, 3)), atol=1e-5
    )
    assert mesh.edges.shape == (12, 2) and (mesh.edges[:, 0] < mesh.edges[:, 1]).all()
    assert mesh.color is None and mesh.comb is None and mesh.length is None


def test_other_dtypes_and_sequences_are_converted():
    positions, triangles = octahedron()
    reference = pelt.FurMesh(positions, triangles).stats()
    for p, t in [
        (positions.astype(np.float64), triangles.astype(np.int64)),
        (positions.tolist(), triangles.tolist()),
        (np.asfortranarray(positions), triangles.astype(np.int32)),
        (positions.astype(np.int16), triangles.astype(np.uint8)),
    ]:
        assert pelt.FurMesh(p, t).stats() == reference
    length = np.ones(6, dtype=np.float64)
    mesh = pelt.FurMesh(positions, triangles, length=length, color=np.ones((6, 4)), comb=np.zeros((6, 3)))
    assert mesh.length.dtype == np.float32 and mesh.color.shape == (6, 4) and mesh.comb.shape == (6, 3)


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"positions": np.zeros((6, 2), np.float32)}, "`positions` must have shape [N, 3], got [6, 2]"),
        ({"triangles": np.zeros((8, 4), np.uint32)}, "`triangles` must have shape [N, 3], got [8, 4]"),
        ({"triangles": np.zeros((8, 3), np.float32)}, "`triangles` has dtype float32"),
        ({"positions": np.full((6, 3), "a")}, "`positions` has dtype <U1"),
        ({"color": np.ones((6, 3))}, "`color` must have shape [N, 4], got [6, 3]"),
        ({"length": np.ones((6, 1))}, "`length` must have shape [N], got [6, 1]"),
        ({"comb": np.ones((5, 3))}, "`comb` has 5 rows but the mesh has 6 vertices"),
        ({"length": np.array([1, 1, 2e3, 1, 1, 1])}, "`length` of vertex 2 is 2000"),
        ({"positions": [[0, 0], [1]]}, "`positions` must have shape [N, 3], got something numpy cannot read"),
    ],
)
def test_bad_arrays_raise_invalid_mesh_error(kwargs, fragment):
    positions, triangles = octahedron()
    args = {"positions": positions, "triangles": triangles, **kwargs}
    with pytest.raises(pelt.InvalidMeshError) as info:
        pelt.FurMesh(args.pop("positions"), args.pop("triangles"), **args)
    assert fragment in str(info.value)


def test_negative_and_too_large_indices_are_reported_as_given():
    positions, triangles = octahedron()
    bad = triangles.astype(np.int64)
    bad[3, 1] = -1
    with pytest.raises(pelt.InvalidMeshError, match="triangle 3 corner 1 refers to vertex -1"):
        pelt.FurMesh(positions, bad)
    bad = triangles.copy()
    bad[7, 2] = 6
    with pytest.raises(
        pelt.InvalidMeshError, match="triangle 7 corner 2 refers to vertex 6, but the mesh has 6"
    ):
        pelt.FurMesh(positions, bad)


def test_nan_is_rejected_with_its_row():
    positions, triangles = octahedron()
    positions[4, 2] = np.nan
    with pytest.raises(pelt.InvalidMeshError, match="`positions` row 4 component 2 is NaN"):
        pelt.FurMesh(positions, triangles)


def test_empty_mesh_is_rejected():
    with pytest.raises(pelt.InvalidMeshError, match="no vertices"):
        pelt.FurMesh(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32))


def test_input_arrays_are_not_modified_and_results_are_copies():
    positions, triangles = octahedron()
    before = positions.copy()
    mesh = pelt.FurMesh(positions, triangles)
    out = mesh.positions
    out[:] = 0
    np.testing.assert_array_equal(positions, before)
    np.testing.assert_array_equal(mesh.positions, before)


def test_panic_inside_rust_surfaces_as_pelt_error():
    with pytest.raises(pelt.PeltError, match=r"internal error: deliberate panic.*bug in Pelt"):
        pelt._pelt._panic_for_test("deliberate panic")


def test_building_a_mesh_releases_the_gil():
    positions, triangles = grid(700)  # ~1M triangles: long enough to observe
    window = {"inside": False, "ticks": 0}

    def build():
        window["inside"] = True
        pelt.FurMesh(positions, triangles)
        window["inside"] = False

    worker = threading.Thread(target=build)
    worker.start()
    while worker.is_alive():
        if window["inside"]:
            window["ticks"] += 1
        time.sleep(0.001)
    worker.join()
    # with the GIL held during the whole call this thread could not run while inside the call
    assert window["ticks"] >= 5, window


def test_sh_rotate_turns_a_light_exactly_where_the_rotation_sends_it():
    # Independent answer: the same light projected from the rotated direction (the basis
    # evaluated there, no rotation involved).
    rng = np.random.default_rng(3)
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q @ np.diag(np.sign(np.diag(r)))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    d = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    for order in (1, 2, 5, 8):
        light = pelt.sh_project_light(tuple(d), order, 0.2)
        expected = pelt.sh_project_light(tuple(q @ d), order, 0.2)
        assert np.allclose(pelt.sh_rotate(light, q), expected, atol=1e-5), order
    # Columns (colour channels) turn independently and keep their shape.
    rgb = np.stack([light, 2.0 * light, -light], axis=1)
    turned = pelt.sh_rotate(rgb, q)
    assert turned.shape == rgb.shape and turned.dtype == np.float32
    assert np.allclose(turned[:, 1], 2.0 * expected, atol=1e-5)
    with pytest.raises(pelt.InvalidParameterError, match="rotation"):
        pelt.sh_rotate(light, 2.0 * np.eye(3))
    with pytest.raises(pelt.InvalidParameterError, match="rotation"):
        pelt.sh_rotate(light, np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(pelt.InvalidParameterError, match="coefficients"):
        pelt.sh_rotate(np.ones(5, np.float32), np.eye(3))


def test_stages_are_the_pipelines_in_the_order_a_bake_reports_them():
    # Every stage a bake runs is named in pelt.STAGES, in its order (the add-on's progress bar
    # counts through the same tuple).
    positions, triangles = octahedron()
    asset = pelt.Pipeline().bake(
        pelt.FurMesh(positions, triangles),
        hair=pelt.HairParams(density=64),
        layers=4,
        resolution=16,
        fin_size=(16, 8),
        order=2,
        directions=32,
        planes=2,
    )
    reported = [s["stage"] for s in asset.report]
    assert reported == [s for s in pelt.STAGES if s in reported]
    assert reported == ["patches", "volume", "planes", "transfer"]


def test_presets_are_hair_parameters_with_their_sizes():
    assert list(pelt.PRESETS) == ["SHORT_VELVET", "MINK", "LONG_SHAGGY", "CURLY"]
    for name, preset in pelt.PRESETS.items():
        assert preset["label"] and preset["description"], name
        assert preset["fur_depth"] > 0 and preset["tile_size"] > 0, name
        # Everything else is a HairParams field, which takes it as it is.
        hair = {
            key: value
            for key, value in preset.items()
            if key not in ("label", "description", "fur_depth", "tile_size")
        }
        for coat in ("undercoat", "overcoat"):
            hair[coat] = {"length": hair.pop(f"{coat}_length"), "width": hair.pop(f"{coat}_width")}
        params = pelt.HairParams(**hair)
        assert params.density == preset["density"] and params.curl == pytest.approx(preset["curl"]), name
