"""The PRT preview against the ground truth: the reference renderer's strands, traced with exact
shadows, are the independent answer the preview's transfer must agree with on average."""

import math

import numpy as np
import pelt
import pytest
from test_preview import PROJECTION, look_at, uv_sphere

SIDE = 96
EYE = np.array([0.0, -4.0, 1.0])
VIEW = look_at(EYE)
# A sun of strength π: a white surface facing it has radiance 1.
STRENGTH = math.pi


@pytest.fixture(scope="module")
def long_fur():
    """The image benchmark's long-furred sphere: its mesh, tile 0.3, fur depth 0.2, default hair,
    64 shells, PRT order 4, and 32 virtual planes per axis."""
    positions, triangles = uv_sphere(128, 64)
    return pelt.Pipeline().bake(
        pelt.FurMesh(positions, triangles),
        tile_size=0.3,
        fur_depth=0.2,
        layers=65,
        order=4,
        planes=32,
    )


def mean_fur_luminance(image: np.ndarray) -> float:
    """Mean Rec. 709 luminance over the covered pixels, straight (not premultiplied) color."""
    covered = image[..., 3] > 0.5
    rgb = image[..., :3]
    return float((rgb[covered] @ np.array([0.2126, 0.7152, 0.0722])).mean())


def prt_preview(asset, toward_sun) -> float:
    lighting = {
        "model": "prt",
        "direction": tuple(toward_sun),
        "color": (STRENGTH,) * 3,
        "environment": np.zeros((0, 3), np.float32),
    }
    image = pelt.Preview(asset, adapter="cpu").render(
        VIEW, PROJECTION, SIDE, SIDE, lighting=lighting, linear=True
    )
    return mean_fur_luminance(image)


def reference_image(asset, toward_sun) -> np.ndarray:
    """The reference's straight-alpha linear image."""
    sun = {"type": "sun", "direction": tuple(toward_sun), "strength": STRENGTH}
    image, _ = pelt.render_reference(asset, VIEW, PROJECTION, SIDE, SIDE, samples=8, lights=[sun])
    # Premultiplied by coverage: back to straight color where the fur covers the pixel.
    alpha = image[..., 3:4]
    straight = np.where(alpha > 0, image[..., :3] / np.maximum(alpha, 1e-6), 0.0)
    return np.concatenate([straight, alpha], axis=-1)


def reference(asset, toward_sun) -> float:
    return mean_fur_luminance(reference_image(asset, toward_sun))


@pytest.mark.parametrize(
    "light, toward_sun",
    [
        ("side", np.cross((0.0, 0.0, 1.0), EYE / np.linalg.norm(EYE))),
        ("top", np.array([0.0, 0.0, 1.0])),
    ],
)
def test_prt_preview_is_as_bright_as_the_strands_it_was_baked_from(long_fur, light, toward_sun):
    # The transfer once shadowed through a fog of the slice coverage at one optical depth per
    # texel, whatever the hair's slant: 0.78 (side) and 0.80 (above) of the reference here. With
    # the density per unit of hair length along the height and extinction 1/2: 1.00 and 1.03.
    ratio = prt_preview(long_fur, toward_sun) / reference(long_fur, toward_sun)
    assert 0.88 < ratio < 1.12, f"{light}: preview / reference = {ratio:.3f}"


# Luminance planes / reference measured (side 1.20, top 1.29), a tenth either way; the fringe's
# mean coverage over the reference's, measured 1.64 and 1.51 (the instanced shells with their
# fins: 1.55 and 1.45).
PLANES_LUMINANCE = {"side": (1.10, 1.30), "top": (1.31, 1.51)}
FRINGE_RATIO = 1.75


@pytest.mark.parametrize(
    "light, toward_sun",
    [
        ("side", np.cross((0.0, 0.0, 1.0), EYE / np.linalg.norm(EYE))),
        ("top", np.array([0.0, 0.0, 1.0])),
    ],
)
def test_virtual_planes_agree_with_the_strands_they_were_sliced_from(long_fur, light, toward_sun):
    # The raycast paper's planes, sliced from the same strands the reference traces, under a sun
    # (Kajiya-Kay, no ambient, as the reference has no sky): covering as much of the picture,
    # and brighter by what the method misses where the fur is seen from above (a ray crosses
    # few planes there and sees the skin, the paper's §3.5): 1.24 from the side and 1.41 from
    # above (1.20 and 1.29 while the fins were lit by the growth direction alone, which left the
    # rim's fins black under a sun along the hair; lit by the hair's spread, they add more than
    # the reference's fringe), where the instanced shells gave 0.98 and 1.03 (docs/accuracy.md).
    # The bounds hold the figures to a tenth either way. The fringe is held near the shells' own.
    lighting = {
        "model": "kajiya-kay",
        "direction": tuple(toward_sun),
        "color": (STRENGTH,) * 3,
        "ambient": (0.0, 0.0, 0.0),
    }
    planes = pelt.Preview(long_fur, adapter="cpu").render(
        VIEW, PROJECTION, SIDE, SIDE, lighting=lighting, linear=True, shell_method="planes"
    )
    truth = reference_image(long_fur, toward_sun)
    ratio = mean_fur_luminance(planes) / mean_fur_luminance(truth)
    coverage = planes[..., 3].sum() / truth[..., 3].sum()
    # The fringe: where the reference is neither clear nor opaque.
    fringe = (truth[..., 3] > 0.02) & (truth[..., 3] < 0.9)
    fringe_ratio = planes[..., 3][fringe].mean() / truth[..., 3][fringe].mean()
    low, high = PLANES_LUMINANCE[light]
    assert low < ratio < high, f"{light}: planes / reference = {ratio:.3f}"
    assert 0.97 < coverage < 1.08, f"{light}: coverage planes / reference = {coverage:.3f}"
    assert fringe_ratio < FRINGE_RATIO, f"{light}: fringe planes / reference = {fringe_ratio:.3f}"
