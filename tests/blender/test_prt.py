"""``pelt.bake_transfer`` and ``pelt.sh_project_equirect`` from Python."""

import math

import numpy as np
import pelt
import pytest


@pytest.fixture(scope="module")
def small_volume():
    return pelt.bake_volume(pelt.HairParams(density=1024), layers=6, resolution=16, trim=False)


def test_transfer_of_a_baked_volume(small_volume):
    density = small_volume["density"]
    t = pelt.bake_transfer(density, layer_spacing=2.0, order=3, directions=64)
    assert t["order"] == 3 and t["bands"] == []
    assert t["coefficients"].shape == (6, 16, 16, 9) and t["coefficients"].dtype == np.float32
    assert np.isfinite(t["coefficients"]).all()
    # 9 coefficients pack into 3 RGBA textures per layer.
    assert t["packed_f16"].shape == (3, 6, 16, 16, 4) and t["packed_f16"].dtype == np.float16
    assert t["packed_u8"].dtype == np.uint8 and len(t["scale"]) == len(t["bias"]) == 9
    # The 8-bit textures decode within one quantization step.
    k = 4
    decoded = t["packed_u8"][k // 4, ..., k % 4] / 255.0 * t["scale"][k] + t["bias"][k]
    step = abs(t["scale"][k]) / 255.0
    assert np.abs(decoded - t["coefficients"][..., k]).max() <= step * 0.51 + 1e-6
    # Light from above reaches the top layer better than the skin under the hair: DC falls inward.
    dc = t["coefficients"][..., 0].mean(axis=(1, 2))
    assert dc[-1] > dc[0]


def test_auto_order_reports_the_band_table(small_volume):
    t = pelt.bake_transfer(small_volume["density"], layer_spacing=2.0, directions=64)
    orders = [row["order"] for row in t["bands"]]
    assert orders == list(range(1, 9))
    assert t["order"] in orders and isinstance(t["tolerance_met"], bool)


def test_transfer_errors_and_cancel(small_volume):
    density = small_volume["density"]
    with pytest.raises(pelt.InvalidParameterError, match="layer_spacing"):
        pelt.bake_transfer(density, layer_spacing=-1.0, order=2)
    with pytest.raises(pelt.InvalidParameterError, match="phase"):
        pelt.bake_transfer(density, layer_spacing=1.0, order=2, phase="glossy")
    with pytest.raises(pelt.PeltError, match="density"):
        pelt.bake_transfer(np.zeros((4, 3, 5), np.float32), layer_spacing=1.0, order=2)
    with pytest.raises(pelt.BakeCancelled):
        pelt.bake_transfer(density, layer_spacing=1.0, order=2, progress=lambda f: f < 0.2)


def test_equirect_projection_of_a_constant_sky_is_dc_only():
    image = np.full((32, 64, 3), 0.5, np.float32)
    coeffs = pelt.sh_project_equirect(image, 3)
    assert coeffs.shape == (9, 3)
    # ∫ c·Y00 dω = c · 4π / (2√π) = 2√π c.
    assert np.allclose(coeffs[0], 0.5 * 2 * math.sqrt(math.pi), rtol=1e-5)
    assert np.abs(coeffs[1:]).max() < 1e-5
