"""Inputs that used to abort, hang or blur their error, through the Python module (the regression
cases of the reliability work): each now ends quickly in a named ``PeltError`` or a sound result,
and Blender's process survives."""

import os
import subprocess
import sys

import numpy as np
import pelt
import pytest


@pytest.fixture
def memory_limit():
    """A 1 GiB budget for the test, so a refusal never depends on this machine's memory."""
    pelt.set_memory_limit(1 << 30)
    yield 1 << 30
    pelt.set_memory_limit(None)


def quad_mesh():
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    return pelt.FurMesh(positions, np.array([[0, 1, 2], [0, 2, 3]], np.uint32))


def test_volume_larger_than_the_budget_is_refused_before_allocating(memory_limit):
    with pytest.raises(pelt.MemoryLimitError, match=r"`resolution` \(4096\), `layers` \(256\)") as error:
        pelt.bake_volume(layers=256, resolution=4096)
    assert "above the memory limit of 1.0 GiB" in str(error.value)
    assert isinstance(error.value, pelt.InvalidParameterError)
    with pytest.raises(pelt.MemoryLimitError):
        pelt.Pipeline().bake(quad_mesh(), layers=64, resolution=4096)


def test_transfer_larger_than_the_budget_is_refused_before_allocating(memory_limit):
    # 64 GiB of coefficients; np.zeros maps its pages lazily, so the input itself costs nothing.
    density = np.zeros((256, 1024, 1024), np.float32)
    with pytest.raises(pelt.MemoryLimitError, match=r"`order` \(8\)"):
        pelt.bake_transfer(density, layer_spacing=1.0, order=8)


def test_long_shifts_on_a_one_texel_volume_bake_at_once():
    # The gap kernel of a 1e4-texel shift was a dense grid of up to 1e14 bytes.
    result = pelt.bake_transfer(np.zeros((2, 1, 1), np.float32), layer_spacing=1e4, order=1, directions=16)
    assert np.isfinite(result["coefficients"]).all()
    asset = pelt.Pipeline().bake(
        quad_mesh(), tile_size=0.01, fur_depth=1000, resolution=1, layers=2, order=1, directions=16
    )
    assert np.isfinite(asset.transfer["coefficients"]).all()


def test_bake_estimate_and_limit_are_visible():
    assert pelt.memory_limit() == pytest.approx(pelt.physical_memory() / 2, rel=1e-6) or os.environ.get(
        "PELT_MEMORY_LIMIT"
    )
    small = pelt.Pipeline.peak_bytes()
    big = pelt.Pipeline.peak_bytes(layers=64, resolution=4096)
    assert 0 < small < 1 << 30 and big > 64 * 4096**2 * 12
    with pytest.raises(pelt.InvalidParameterError, match="resolution"):
        pelt.Pipeline.peak_bytes(resolution=0)
    for bad in (-1.0, 1.0, float("nan"), 1e300):
        with pytest.raises(pelt.InvalidParameterError, match="memory_limit"):
            pelt.set_memory_limit(bad)


def test_parameters_the_transfer_needs_are_checked_before_any_stage():
    # The layer spacing (fur depth in texels per layer) named by the parameter the user set.
    with pytest.raises(pelt.InvalidParameterError, match=r"`fur_depth`.*keep fur_depth \(here 1000000\)"):
        pelt.Pipeline().bake(quad_mesh(), fur_depth=1e6, tile_size=1e-3)
    with pytest.raises(pelt.InvalidParameterError, match=r"`tile_size`.*fur_depth.*not given.*got 1e30"):
        pelt.Pipeline().bake(quad_mesh(), tile_size=1e30)
    with pytest.raises(pelt.InvalidParameterError, match=r"`layers`.*\[2, 4096\].*got 1"):
        pelt.Pipeline().bake(quad_mesh(), layers=1)
    # Zero-length hair trims to the skin and one empty layer, which the transfer bakes.
    bald = pelt.HairParams(density=0)
    asset = pelt.Pipeline().bake(quad_mesh(), hair=bald, order=1, directions=16)
    assert asset.layers == 2


def test_thread_counts_are_capped_and_named():
    with pytest.raises(pelt.InvalidParameterError, match=r"`threads`.*\[0, 1024\].*got -1"):
        pelt.set_thread_count(-1)
    with pytest.raises(pelt.InvalidParameterError, match=r"`threads`.*got 100000"):
        pelt.set_thread_count(100_000)
    # An environment asking for 100,000 threads would take minutes to start: one per core instead.
    code = "import pelt; pelt.bake_volume(layers=2, resolution=8); print(pelt.thread_count())"

    def run(threads):
        env = dict(os.environ, PELT_THREADS=threads)
        return subprocess.run(
            [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120
        )

    capped, default = run("100000"), run("")
    assert capped.returncode == 0, capped.stderr
    assert int(capped.stdout) == int(default.stdout)
    assert "PELT_THREADS" in capped.stderr and "[1, 1024]" in capped.stderr


def test_messages_name_the_argument_its_value_and_range():
    mesh = quad_mesh()
    cases = [
        (lambda: pelt.bake_volume(layers=-1), r"`layers`.*\[0, .*got -1"),
        (lambda: pelt.bake_volume(resolution=-3), r"`resolution`.*got -3"),
        (lambda: pelt.Pipeline().bake(mesh, seed=-1), r"`seed`.*got -1"),
        (lambda: pelt.Pipeline().bake(mesh, order=-2), r"`order`.*got -2"),
        (lambda: pelt.Pipeline().bake(mesh, fin_size=(64, -1)), r"`fin_size\[1\]`.*got -1"),
        (lambda: pelt.sh_project_light((0, 0, 1), -1), r"`order`.*got -1"),
        (lambda: pelt.build_patches(mesh, 1.0, seed=-5), r"`seed`.*got -5"),
        (lambda: pelt.HairParams(curl=float("nan")), r"`curl`.*not a finite number"),
        # Huge and tiny numbers in exponent form, not hundreds of digits.
        (lambda: pelt.HairParams(curl=1e300), r"`curl`.*got 1e300$"),
        (lambda: pelt.set_memory_limit(1e300), r"`memory_limit`.*got 1e300$"),
        (lambda: pelt.FurMesh(None, np.zeros((1, 3), np.uint32)), r"`positions`.*got None"),
        (
            lambda: pelt.FurMesh(mesh.positions, np.array([[0, 1, 2**64 - 1]], np.uint64)),
            r"`triangles`.*refers to vertex 18446744073709551615",
        ),
        (
            lambda: pelt.sh_project_equirect(np.full((4, 8, 3), 3e38, np.float32), 2),
            r"`image`.*beyond float32",
        ),
    ]
    for call, pattern in cases:
        with pytest.raises(pelt.PeltError, match=pattern):
            call()
    patches = pelt.build_patches(mesh, 1.0)
    with pytest.raises(pelt.InvalidParameterError, match=r"`height`.*got -1"):
        patches.picture(mesh, height=-1)


def octahedron(scale=1.0, normals=None):
    positions = np.array(
        [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], np.float32
    ) * np.float32(scale)
    triangles = np.array(
        [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]], np.uint32
    )
    return pelt.FurMesh(positions, triangles, normals=normals)


def test_geometry_is_scale_free_from_1e_minus_20_to_1e30():
    unit = octahedron()
    patches = pelt.build_patches(unit, 0.3)
    for scale in (1e-30, 1e-20, 1e-12, 1e12, 1e20, 1e30):
        mesh = octahedron(scale)
        stats = mesh.stats()
        # The area was inf at 1e12 and NaN at 1e30 (squares of f32 lengths), 0 below 1e-11.
        assert stats["surface_area"] / scale**2 == pytest.approx(4 * np.sqrt(3), rel=1e-6), scale
        np.testing.assert_allclose(mesh.normals, unit.normals, atol=1e-6)
        scaled = pelt.build_patches(mesh, 0.3 * scale)
        assert scaled.quality["patch_count"] == patches.quality["patch_count"], scale
        assert np.isfinite(scaled.quality["mean_alignment_deg"])
        assert np.isfinite(scaled.uv).all()
    # Given normals of any finite length keep their direction (they became +Z at 1e19 and 1e-23).
    for magnitude in (1e-30, 1e-19, 1e19, 1e30):
        mesh = octahedron(normals=unit.normals * np.float32(magnitude))
        np.testing.assert_allclose(mesh.normals, unit.normals, atol=1e-6)
    # A tile so small against the mesh that float32 UVs cannot place it: named, not inf UVs.
    with pytest.raises(pelt.InvalidParameterError, match=r"`tile_size`.*tiles across"):
        pelt.build_patches(octahedron(1.7e38), 1.0)


def test_a_failed_export_leaves_the_folder_as_it_was(tmp_path):
    asset = pelt.Pipeline().bake(
        quad_mesh(), layers=4, resolution=16, fin_size=(16, 8), order=1, directions=16
    )
    folder = tmp_path / "out"
    pelt.write_asset(asset, folder, formats="png")
    before = {p.name: p.read_bytes() for p in folder.iterdir()}
    # A folder where the GLB goes (the last file written): 14 to 17 files used to stay behind.
    (folder / "pelt_geometry.glb").unlink()
    (folder / "pelt_geometry.glb").mkdir()
    for write in (
        lambda: pelt.write_asset(asset, folder, formats="png,exr"),
        lambda: pelt.write_texture_set(asset, folder / "pelt.json"),  # a file where the folder goes
    ):
        with pytest.raises(pelt.PeltError):
            write()
    after = {p.name: (p.read_bytes() if p.is_file() else None) for p in folder.iterdir()}
    assert after == {**before, "pelt_geometry.glb": None}
    assert [p.name for p in tmp_path.iterdir()] == ["out"], "no temporary folder is left"


def test_frames_larger_than_the_budget_are_refused_before_allocating(memory_limit):
    asset = pelt.Pipeline().bake(quad_mesh(), layers=4, resolution=16, fin_size=(16, 8), transfer=False)
    view = np.eye(4)
    view[2, 3] = -5.0
    near, far = 0.5, 20.0
    projection = np.array(
        [
            [2, 0, 0, 0],
            [0, 2, 0, 0],
            [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
            [0, 0, -1, 0],
        ]
    )
    # 2^26 pixels at 88 bytes: 5.5 GiB of sums and image.
    with pytest.raises(pelt.MemoryLimitError, match=r"`render_reference`.*`width` \(8192\)"):
        pelt.render_reference(asset, view, projection, 8192, 8192)
    preview = pelt.Preview(asset, adapter="cpu")
    with pytest.raises(pelt.MemoryLimitError, match=r"`render`.*`width` \(16384\)"):
        preview.render(view, projection, 16384, 16384)
    assert preview.render(view, projection, 32, 32).shape == (32, 32, 4)
