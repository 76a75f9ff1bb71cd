"""The parameter schema (``pelt.SCHEMA``, each number's range stated once in the crate) against
the add-on's properties and the module's own validation: a property may not let an artist type a
value the bake refuses, and a default must lie inside its range."""

import math

import pelt
import pytest

# Add-on property -> (parameter set, parameter) of the schema.
PROPERTIES = {
    "density": ("hair", "density"),
    "guard_fraction": ("hair", "guard_fraction"),
    "taper": ("hair", "taper"),
    "curl": ("hair", "curl"),
    "helix_radius": ("hair", "helix_radius"),
    "helix_frequency": ("hair", "helix_frequency"),
    "slant": ("hair", "slant"),
    "length_jitter": ("hair", "length_jitter"),
    "clump_strength": ("hair", "clump_strength"),
    "clump_count": ("hair", "clump_count"),
    "root_color": ("hair", "root_color"),
    "tip_color": ("hair", "tip_color"),
    "color_jitter": ("hair", "color_jitter"),
    "layers": ("volume", "layers"),
    "guard_share": ("volume", "guard_share"),
    "prt_order": ("transfer", "order"),
    "prt_tolerance": ("bake", "tolerance"),
    "tile_size": ("patches", "tile_size"),
    "fur_depth": ("bake", "fur_depth"),
    "min_shells": ("render", "min_shells"),
    "max_shells": ("render", "max_shells"),
    "plane_loop_limit": ("render", "plane_loop_limit"),
}

# Keyword arguments of the module's functions that stand for a schema field: their default is the
# crate's.
KEYWORDS = {
    "tile_size": ("patches", "tile_size"),
    "seed": ("patches", "seed"),
    "layers": ("volume", "layers"),
    "resolution": ("volume", "resolution"),
    "coverage": ("volume", "coverage"),
    "vertical_filter": ("volume", "vertical_filter"),
    "fin_slab": ("volume", "fin_slab"),
    "trim": ("volume", "trim"),
    "lod": ("volume", "lod"),
    "mipmaps": ("volume", "mipmaps"),
    "guard_hairs": ("volume", "guard_hairs"),
    "guard_share": ("volume", "guard_share"),
    "directions": ("transfer", "directions"),
    "method": ("transfer", "method"),
    "order": ("transfer", "order"),
    "phase": ("transfer", "phase"),
}
# The whole bake's own keywords (`pelt.SCHEMA["bake"]`) where a function's keyword differs from the
# transfer's own (the pipeline bakes with the Kajiya-Kay phase), and `Preview.render`'s.
BAKE_KEYWORDS = {
    name: ("bake", name) for name in ("fur_depth", "transfer", "order", "tolerance", "phase", "planes")
}
RENDER_KEYWORDS = {name: ("render", name) for name in pelt.SCHEMA["render"]["defaults"]}
FUNCTIONS = [
    (pelt.Pipeline.bake, BAKE_KEYWORDS),
    (pelt.Pipeline.peak_bytes, BAKE_KEYWORDS),
    (pelt.bake_volume, {}),
    (pelt.bake_transfer, {}),
    (pelt.build_patches, {}),
    (pelt.Preview.render, RENDER_KEYWORDS),
]


def test_every_set_states_defaults_and_ranges_with_units():
    assert set(pelt.SCHEMA) == {"bake", "patches", "field", "hair", "volume", "transfer", "render"}
    for name, schema in pelt.SCHEMA.items():
        assert schema["ranges"], name
        for parameter, r in schema["ranges"].items():
            assert r["min"] <= r["max"] and r["unit"], (name, parameter)
    assert pelt.SCHEMA["hair"]["ranges"]["slant"]["unit"] == "radians"
    assert pelt.SCHEMA["volume"]["ranges"]["guard_share"]["min_open"]
    assert pelt.SCHEMA["hair"]["defaults"]["density"] == pelt.HairParams().density
    assert pelt.SCHEMA["patches"]["ranges"]["max_stretch"]["min_field"] == "stretch_tolerance"
    assert pelt.SCHEMA["render"]["ranges"]["max_shells"]["min_field"] == "min_shells"
    assert pelt.SCHEMA["bake"]["ranges"]["fur_depth"] == {
        "min": 0.0,
        "max": 1e6,
        "min_open": True,
        "min_field": None,
        "unit": "object units",
    }


@pytest.mark.parametrize("function, own", FUNCTIONS, ids=lambda f: getattr(f, "__qualname__", ""))
def test_keyword_defaults_are_the_crate_s(function, own):
    import inspect

    keywords = {**KEYWORDS, **own}
    checked = 0
    for name, parameter in inspect.signature(function).parameters.items():
        default = parameter.default
        if name not in keywords or default in (None, Ellipsis, inspect.Parameter.empty):
            continue
        set_name, field = keywords[name]
        assert default == pelt.SCHEMA[set_name]["defaults"][field], f"{function.__qualname__}({name}=...)"
        checked += 1
    assert checked, "no keyword of the schema checked"


@pytest.mark.parametrize("name", ["fur_depth", "tile_size"])
@pytest.mark.parametrize("value", [0.0, -1.0, 2e6, math.nan])
def test_one_fur_depth_range_for_the_bake_the_preview_and_the_export(name, value):
    """The bake and the preview refuse the same depths (`pelt.SCHEMA["bake"]["ranges"]["fur_depth"]`),
    naming what the user set: a bake without `fur_depth` is one tile deep."""
    with pytest.raises(pelt.InvalidParameterError, match=name):
        pelt.Pipeline.peak_bytes(**{name: value})


@pytest.mark.parametrize("parameter", sorted(pelt.SCHEMA["hair"]["ranges"]))
def test_hair_params_refuse_just_past_each_end_of_its_range(parameter):
    r = pelt.SCHEMA["hair"]["ranges"][parameter]
    default = pelt.SCHEMA["hair"]["defaults"]
    field = parameter.split(".")[0]
    value = default[field]
    if isinstance(value, int) and r["min"] <= 0:
        beyond = [r["max"] + 1]
    else:
        step = 1 if isinstance(value, int) else max(abs(r["max"] - r["min"]), 1.0) * 1e-3
        beyond = [r["min"] - step, r["max"] + step]
    for x in beyond:
        x = int(x) if isinstance(value, int) else x
        if "." in parameter:  # a coat's [min, max] pair
            coat = dict(default[field])
            coat[parameter.split(".")[1]] = [x, x]
            kwargs = {field: coat}
        elif isinstance(value, list):
            kwargs = {field: [x] * len(value)}
        else:
            kwargs = {field: x}
        with pytest.raises(pelt.InvalidParameterError, match=parameter.split(".")[0]):
            pelt.HairParams(**kwargs)


def test_the_addons_properties_stay_inside_the_schema(addon):
    import bpy

    properties = bpy.types.Object.bl_rna.properties["pelt"].fixed_type.properties
    for prop_name, (set_name, parameter) in PROPERTIES.items():
        r = pelt.SCHEMA[set_name]["ranges"][parameter]
        prop = properties[prop_name]
        where = f"{prop_name} ({set_name}.{parameter}, [{r['min']}, {r['max']}])"
        assert prop.hard_max <= r["max"] * (1 + 1e-6), f"{where}: max {prop.hard_max}"
        if r["min_open"]:
            assert prop.hard_min > r["min"], f"{where}: min {prop.hard_min} must be above it"
        else:
            assert prop.hard_min >= r["min"] - 1e-6 * max(1.0, abs(r["min"])), f"{where}: min {prop.hard_min}"
        defaults = list(prop.default_array) if getattr(prop, "is_array", False) else [prop.default]
        for d in defaults:
            assert r["min"] <= d <= r["max"] and math.isfinite(d), f"{where}: default {d}"
