"""``pelt.build_patches``: array shapes and dtypes, polygons kept whole, bald faces, parameter
errors, progress and cancellation, and the picture helper."""

import numpy as np
import pelt
import pytest


def uv_sphere(segments, rings):
    """A UV sphere with pole fans and quads split in two; returns positions, triangles, polygons."""
    theta = np.pi * np.arange(1, rings) / rings
    phi = 2 * np.pi * np.arange(segments) / segments
    ring = np.stack(
        [
            np.outer(np.sin(theta), np.cos(phi)).ravel(),
            np.outer(np.sin(theta), np.sin(phi)).ravel(),
            np.repeat(np.cos(theta), segments),
        ],
        axis=1,
    )
    positions = np.concatenate([[[0, 0, 1]], ring, [[0, 0, -1]]]).astype(np.float32)
    south = len(positions) - 1
    s = np.arange(segments)
    at = lambda r, k: 1 + (r - 1) * segments + k % segments  # noqa: E731
    triangles, polygons = [], []
    for k in s:
        triangles.append([0, at(1, k), at(1, k + 1)])
        polygons.append(len(polygons))
    quad = len(polygons)
    for r in range(1, rings - 1):
        for k in s:
            a, b, c, d = at(r, k), at(r + 1, k), at(r + 1, k + 1), at(r, k + 1)
            triangles += [[a, b, c], [a, c, d]]
            polygons += [quad, quad]
            quad += 1
    for k in s:
        triangles.append([south, at(rings - 1, k + 1), at(rings - 1, k)])
        polygons.append(quad)
        quad += 1
    return positions, np.array(triangles, dtype=np.uint32), np.array(polygons, dtype=np.uint32)


def test_arrays_have_the_documented_shapes_and_polygons_stay_whole():
    positions, triangles, polygons = uv_sphere(32, 16)
    mesh = pelt.FurMesh(positions, triangles, polygons=polygons)
    patches = pelt.build_patches(mesh, 0.25, seed=3)
    t, v = len(triangles), len(positions)
    assert patches.uv.shape == (t, 3, 2) and patches.uv.dtype == np.float32
    assert patches.patch.shape == (t,) and patches.patch.dtype == np.int32
    assert patches.direction.shape == (v, 3) and patches.slant.shape == (v,)
    assert np.isfinite(patches.uv).all() and np.isfinite(patches.direction).all()
    np.testing.assert_allclose(np.linalg.norm(patches.direction, axis=1), 1.0, atol=1e-5)
    q = patches.quality
    assert q["coverage"] == 1.0 and q["flipped_faces"] == 0
    assert q["patch_count"] == patches.patch_count == patches.patch.max() + 1
    assert q["face_stretch"].shape == (t, 2) and q["face_alignment_deg"].shape == (t,)
    for polygon in np.unique(polygons):
        assert len(np.unique(patches.patch[polygons == polygon])) == 1
    # Within a patch every vertex has one UV: corners of a vertex in one patch agree.
    for p in range(patches.patch_count):
        faces = patches.patch == p
        corners = triangles[faces].ravel()
        uvs = patches.uv[faces].reshape(-1, 2)
        for vertex in np.unique(corners):
            assert np.ptp(uvs[corners == vertex], axis=0).max() == 0.0


def test_bald_faces_get_id_minus_one():
    positions, triangles, _ = uv_sphere(16, 8)
    length = np.where(positions[:, 2] < -0.01, 0.0, 1.0).astype(np.float32)
    mesh = pelt.FurMesh(positions, triangles, length=length)
    patches = pelt.build_patches(mesh, 0.25)
    bald = (length[triangles] == 0).all(axis=1)
    assert (patches.patch[bald] == -1).all() and (patches.patch[~bald] >= 0).all()


def test_bad_parameters_raise_invalid_parameter_naming_them():
    positions, triangles, _ = uv_sphere(8, 4)
    mesh = pelt.FurMesh(positions, triangles)
    with pytest.raises(pelt.InvalidParameterError, match="tile_size"):
        pelt.build_patches(mesh, 0.0)
    with pytest.raises(pelt.InvalidParameterError, match="max_stretch"):
        pelt.build_patches(mesh, 1.0, max_stretch=1.0)
    with pytest.raises(pelt.InvalidParameterError, match="down"):
        pelt.build_patches(mesh, 1.0, down=(0, 0, 0))
    with pytest.raises(pelt.InvalidMeshError, match="polygons"):
        pelt.FurMesh(positions, triangles, polygons=np.zeros(3, dtype=np.uint32))
    with pytest.raises(pelt.InvalidParameterError, match="polygons"):
        pelt.FurMesh(positions, triangles, polygons=-np.ones(len(triangles), dtype=np.int64))


def test_progress_reports_and_cancels():
    positions, triangles, _ = uv_sphere(32, 16)
    mesh = pelt.FurMesh(positions, triangles)
    seen = []
    pelt.build_patches(mesh, 0.25, progress=lambda f: seen.append(f))
    assert seen and seen[-1] == pytest.approx(1.0) and seen == sorted(seen)
    with pytest.raises(pelt.BakeCancelled):
        pelt.build_patches(mesh, 0.25, progress=lambda f: False)


def test_picture_is_rgba_with_patch_colors_and_background():
    positions, triangles, _ = uv_sphere(32, 16)
    mesh = pelt.FurMesh(positions, triangles)
    patches = pelt.build_patches(mesh, 0.25)
    image = patches.picture(mesh, width=64, height=48, view=(0, 1, 0))
    assert image.shape == (48, 64, 4) and image.dtype == np.uint8
    assert image[0, 0, 3] == 0, "corner is background"
    assert image[24, 32, 3] == 255, "centre shows the sphere"
    with pytest.raises(pelt.InvalidParameterError, match="size"):
        patches.picture(mesh, width=0)
