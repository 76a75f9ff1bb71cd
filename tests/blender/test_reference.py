"""``pelt.render_reference``: the ground-truth renderer from Python, with the preview's camera
conventions, checked against the preview's own framing and against closed-form light units."""

import math

import numpy as np
import pelt
import pytest
from test_preview import PROJECTION, SIDE, VIEW, look_at, uv_sphere


@pytest.fixture(scope="module")
def asset():
    positions, triangles = uv_sphere()
    mesh = pelt.FurMesh(positions, triangles)
    return pelt.Pipeline().bake(
        mesh, tile_size=0.5, hair=pelt.HairParams(density=512), layers=8, resolution=32, fur_depth=0.1
    )


def test_the_reference_covers_what_the_preview_covers(asset):
    image, info = pelt.render_reference(asset, VIEW, PROJECTION, SIDE, SIDE, samples=4)
    assert image.shape == (SIDE, SIDE, 4) and image.dtype == np.float32
    assert np.isfinite(image).all()
    assert info["samples"] >= 4 and 0 <= info["relative_error"] <= 0.01
    # Same matrices, same framing: the opaque middle and the empty corners agree with the preview.
    preview = pelt.Preview(asset, adapter="cpu").render(VIEW, PROJECTION, SIDE, SIDE)
    assert image[SIDE // 2, SIDE // 2, 3] == 1.0 and preview[SIDE // 2, SIDE // 2, 3] == 255
    assert image[0, 0, 3] == 0.0 and preview[0, 0, 3] == 0
    covered = (image[..., 3] > 0.5).mean()
    assert abs(covered - (preview[..., 3] > 127).mean()) < 0.05


def test_light_strength_scales_the_image_linearly_and_a_bald_asset_is_refused(asset):
    # Every vertex bald: no strand stands anywhere, and the reference says so.
    bald = pelt.Pipeline().bake(
        pelt.FurMesh(*uv_sphere(), length=np.full(len(uv_sphere()[0]), 1e-9, np.float32)),
        tile_size=0.5,
        hair=pelt.HairParams(density=512, color_jitter=0.0),
        layers=8,
        resolution=32,
        fur_depth=0.1,
    )
    with pytest.raises(pelt.InvalidParameterError, match="strands"):
        pelt.render_reference(bald, VIEW, PROJECTION, 8, 8)
    eye = np.array([0.0, -4.0, 1.0])

    def lit_by(strength):
        sun = {"type": "sun", "direction": tuple(eye), "strength": strength}
        image, _ = pelt.render_reference(
            asset, look_at(eye), PROJECTION, SIDE, SIDE, samples=4, lights=[sun], shadows=False
        )
        return image

    image = lit_by(2.0)
    assert image[..., :3].max() > 0
    # Doubling the strength doubles every pixel exactly (the estimator is linear in the light).
    doubled = lit_by(4.0)
    np.testing.assert_allclose(doubled[..., :3], 2 * image[..., :3], rtol=1e-5, atol=1e-7)


def test_bad_input_is_named_and_cancel_returns_nothing(asset):
    with pytest.raises(pelt.InvalidParameterError, match="min_samples"):
        pelt.render_reference(asset, VIEW, PROJECTION, 8, 8, samples=0)
    with pytest.raises(pelt.InvalidParameterError, match=r"camera\.view"):
        pelt.render_reference(asset, look_at((0.1, 0.0, 0.2), (0.0, 1.0, 0.2)), PROJECTION, 8, 8)
    with pytest.raises(pelt.InvalidParameterError, match=r"lights\[0\].type"):
        pelt.render_reference(asset, VIEW, PROJECTION, 8, 8, lights=[{"type": "spot"}])
    with pytest.raises(pelt.BakeCancelled):
        pelt.render_reference(asset, VIEW, PROJECTION, 8, 8, progress=lambda f: False)
    sky = np.zeros((4, 3), np.float32)
    sky[0] = math.sqrt(4 * math.pi)
    image, _ = pelt.render_reference(
        asset, VIEW, PROJECTION, 8, 8, lights=[{"type": "environment", "sh": sky}]
    )
    assert np.isfinite(image).all() and image[..., :3].max() > 0


def test_the_volume_mode_covers_what_the_strands_cover(asset):
    # The hybrid paper's method over the same bake: the density volume ray marched through the
    # prisms reaches the same pixels as the strands, with about their radiance.
    strands, _ = pelt.render_reference(asset, VIEW, PROJECTION, SIDE, SIDE, samples=8)
    volume, info = pelt.render_reference(asset, VIEW, PROJECTION, SIDE, SIDE, samples=8, mode="volume")
    assert volume.shape == strands.shape and np.isfinite(volume).all()
    assert info["samples"] >= 8
    assert abs(volume[..., 3].mean() / strands[..., 3].mean() - 1) < 0.05
    ratio = volume[..., :3].sum() / strands[..., :3].sum()
    assert 0.8 < ratio < 1.25, ratio
    with pytest.raises(pelt.InvalidParameterError, match="mode"):
        pelt.render_reference(asset, VIEW, PROJECTION, 8, 8, mode="voxels")
