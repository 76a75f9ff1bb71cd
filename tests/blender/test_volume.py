"""``pelt.HairParams`` and ``pelt.bake_volume`` from Python: fields, errors, arrays, progress."""

import numpy as np
import pelt
import pytest


def test_hair_params_defaults_fields_and_docs():
    p = pelt.HairParams()
    assert p.density == 16384 and p.segments == 16
    assert p.undercoat["length"] == [0.55, 0.8]
    # Every field is documented with its default and range in the class docstring.
    for field in pelt.HairParams.fields():
        assert f"``{field}``" in pelt.HairParams.__doc__, field
    assert set(p.to_dict()) == set(pelt.HairParams.fields())
    q = pelt.HairParams(density=100, curl=0.5, undercoat={"width": (0.001, 0.002)})
    assert (q.density, q.curl) == (100, 0.5)
    assert q.undercoat == {"length": [0.55, 0.8], "width": [0.001, 0.002]}
    assert q != p and pelt.HairParams() == p


@pytest.mark.parametrize(
    ("field", "value", "words"),
    [
        ("density", -1, "density"),
        ("density", 1 << 21, "[0, 1048576]"),
        ("curl", 1.5, "[0, 1]"),
        ("curl", float("nan"), "curl"),
        ("segments", 0, "[1, 64]"),
        ("root_color", [2.0, 0.0, 0.0], "root_color"),
        ("undercoat", {"length": [0.9, 0.1]}, "min <= max"),
        ("undercoat", {"colour": [0.1]}, "undercoat.colour"),
        ("taper", "thin", "taper"),
    ],
)
def test_bad_hair_values_raise_and_keep_the_old_value(field, value, words):
    p = pelt.HairParams()
    before = p.to_dict()
    with pytest.raises(pelt.InvalidParameterError) as err:
        setattr(p, field, value)
    assert field in str(err.value) and words in str(err.value)
    assert p.to_dict() == before
    with pytest.raises(pelt.InvalidParameterError):
        pelt.HairParams(**{field: value})


def test_unknown_field_is_an_attribute_error():
    with pytest.raises(AttributeError, match="fluffiness"):
        pelt.HairParams(fluffiness=1)
    with pytest.raises(AttributeError):
        _ = pelt.HairParams().fluffiness


def test_bake_volume_arrays():
    v = pelt.bake_volume(pelt.HairParams(density=2000), layers=8, resolution=32, fin_size=(64, 16))
    layers = v["layers"]
    assert 1 <= layers <= 8 and v["stats"]["trimmed"] == 8 - layers
    assert v["shells"].shape == (layers, 32, 32, 4) and v["shells"].dtype == np.uint8
    assert v["tangents"].shape == (layers, 32, 32, 4)
    assert v["coverage"].shape == (layers, 32, 32) and v["coverage"].dtype == np.float32
    assert v["density"] is v["coverage"]
    assert v["fin"].shape == (16, 64, 4)
    # Each LOD level keeps the skin and halves the hair layers above it, down to one layer.
    counts, count = [], layers
    while count > 1:
        count = 1 + count // 2 if count > 2 else 1
        counts.append(count)
    assert [a.shape[0] for a in v["lod"]] == counts
    if layers > 2:
        assert np.array_equal(v["lod"][0][0], v["shells"][0]), "the skin stays apart"
    assert [a.shape[1] for a in v["mips"]] == [16, 8, 4, 2, 1]
    assert np.all(v["shells"][0, ..., 3] == 255), "the skin is opaque"
    assert np.isfinite(v["coverage"]).all() and (v["coverage"] >= 0).all()
    # Mean coverage of the skin layer: the roots' cross-sections, between 0 and the tile.
    assert 0 < v["stats"]["mean_coverage"][0] < 1
    again = pelt.bake_volume(pelt.HairParams(density=2000), layers=8, resolution=32, fin_size=(64, 16))
    assert np.array_equal(again["shells"], v["shells"]) and np.array_equal(again["fin"], v["fin"])


def test_zero_density_is_an_opaque_skin_under_empty_shells():
    v = pelt.bake_volume(pelt.HairParams(density=0), layers=6, resolution=16, trim=False)
    assert np.all(v["shells"][0, ..., 3] == 255)
    assert np.all(v["shells"][1:, ..., 3] == 0)


def test_bad_volume_parameters():
    with pytest.raises(pelt.InvalidParameterError, match="layers"):
        pelt.bake_volume(layers=0)
    with pytest.raises(pelt.InvalidParameterError, match="coverage"):
        pelt.bake_volume(coverage="perfect")
    with pytest.raises(pelt.InvalidParameterError, match="fin_slab"):
        pelt.bake_volume(fin_slab=-1.0)


def test_progress_reports_and_cancels():
    seen = []
    pelt.bake_volume(layers=4, resolution=16, fin_size=(16, 4), progress=seen.append)
    assert seen and seen == sorted(seen) and seen[-1] == 1.0
    with pytest.raises(pelt.BakeCancelled):
        pelt.bake_volume(layers=4, resolution=16, progress=lambda f: f < 0.3)

    def broken(_fraction):
        raise ValueError("progress bar bug")

    with pytest.raises(ValueError, match="progress bar bug"):
        pelt.bake_volume(layers=4, resolution=16, progress=broken)
