"""Property-based fuzzing of the Python API (hypothesis): every public entry point, fed arbitrary
numbers (NaN, infinities, subnormals, 1e±300, negative and oversized integers) and arrays, either
returns outputs that are all finite or raises a ``pelt.PeltError`` that names what is wrong.
Anything else (another exception, an unnamed error, NaN in an output) fails; a crash, a hang or an
abort kills the process, which ``scripts/fuzz.py`` runs under a time and memory limit.

The number of examples per target is ``PELT_FUZZ_EXAMPLES`` (default 100). ``scripts/fuzz.py`` sets
``PELT_FUZZ_SEEDED`` and passes ``--hypothesis-seed``, so that a long run in chunks draws new cases in
each chunk; without it, the cases are those of the test's name (``derandomize``)."""

import os
import re

import numpy as np
import pelt
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

EXAMPLES = int(os.environ.get("PELT_FUZZ_EXAMPLES", "100"))
FUZZ = settings(
    max_examples=EXAMPLES,
    deadline=None,
    derandomize="PELT_FUZZ_SEEDED" not in os.environ,
    database=None,
    suppress_health_check=list(HealthCheck),
)

# Every case that asks for more is refused by the budget, quickly.
pelt.set_memory_limit(64 << 20)

NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1e-45, 1e-30, 1e30, 3.4e38, 1e300, -1.0, 0.5]),
    st.floats(-2.0, 2.0),
)
INTEGERS = st.one_of(st.integers(-3, 40), st.integers(-(2**70), 2**70), st.sampled_from([2**32, 2**64 - 1]))
SMALL = st.integers(-2, 12)


def loose(valid, wild=NUMBERS):
    """Mostly ``valid`` (7 in 8), so that calls reach the work, else anything."""
    return st.one_of(*[valid] * 7, wild)


def ints(lo, hi):
    return loose(st.integers(lo, hi), INTEGERS)


def named(error: BaseException) -> bool:
    """A refusal that says what is wrong: a Pelt error naming a parameter or an array, or the
    binding's own TypeError naming the argument."""
    text = str(error)
    if isinstance(error, pelt.PeltError):
        return bool(re.search(r"`[^`]+`", text)) or text.startswith(("invalid mesh", "cancelled"))
    return isinstance(error, TypeError) and text.startswith("argument '")


def finite(value) -> bool:
    """Every float reachable in ``value`` (arrays, dicts, lists, numbers) is finite."""
    if isinstance(value, np.ndarray):
        return value.dtype.kind not in "fc" or bool(np.isfinite(value).all())
    if isinstance(value, dict):
        return all(finite(v) for v in value.values())
    if isinstance(value, (list, tuple)):
        return all(finite(v) for v in value)
    if isinstance(value, float):
        return np.isfinite(value)
    return True


def check(call):
    """Runs ``call``; the contract above."""
    try:
        result = call()
    except (pelt.PeltError, TypeError) as error:
        assert named(error), f"unnamed error: {type(error).__name__}: {error}"
        event("refused")
        return None
    assert finite(result), "an output is not finite"
    event("ok")
    return result


def octahedron(scale=1.0):
    positions = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], np.float32)
    triangles = np.array(
        [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]], np.uint32
    )
    return pelt.FurMesh(positions * np.float32(scale), triangles)


@FUZZ
@given(
    positions=st.one_of(
        st.lists(st.tuples(*[st.floats(-1, 1)] * 3), min_size=3, max_size=12),
        st.lists(st.tuples(*[loose(st.floats(-1, 1))] * 3), max_size=12),
    ),
    triangles=st.one_of(
        st.lists(st.tuples(*[st.integers(0, 2)] * 3), min_size=1, max_size=12),
        st.lists(st.tuples(*[ints(0, 2)] * 3), max_size=12),
    ),
    lengths=st.one_of(st.none(), st.lists(NUMBERS, max_size=13)),
)
def test_fur_mesh(positions, triangles, lengths):
    def build():
        p = np.array(positions, np.float64).reshape(-1, 3)
        t = np.array(triangles, dtype=object).reshape(-1, 3)
        t = t.astype(np.int64) if all(abs(int(v)) < 2**63 for v in t.ravel()) else t.astype(np.float64)
        length = None if lengths is None else np.array(lengths, np.float64)
        mesh = pelt.FurMesh(p.astype(np.float32), t, length=length)
        return {"normals": mesh.normals, "tangents": mesh.tangents, "stats": mesh.stats()}

    with np.errstate(all="ignore"):
        check(build)


HAIR_FIELDS = {
    "density": INTEGERS,
    "segments": INTEGERS,
    "clump_count": INTEGERS,
    "seed": INTEGERS,
    "curl": NUMBERS,
    "taper": NUMBERS,
    "slant": NUMBERS,
    "guard_fraction": NUMBERS,
    "length_jitter": NUMBERS,
    "helix_radius": NUMBERS,
    "undercoat": st.fixed_dictionaries(
        {"length": st.tuples(NUMBERS, NUMBERS), "width": st.tuples(NUMBERS, NUMBERS)}
    ),
    "root_color": st.tuples(NUMBERS, NUMBERS, NUMBERS),
}


@FUZZ
@given(
    fields=st.dictionaries(st.sampled_from(sorted(HAIR_FIELDS)), st.just(None), max_size=4).flatmap(
        lambda keys: st.fixed_dictionaries({k: HAIR_FIELDS[k] for k in keys})
    )
)
def test_hair_params(fields):
    check(lambda: pelt.HairParams(**fields).to_dict())


@FUZZ
@given(
    layers=ints(1, 8),
    resolution=ints(1, 24),
    fin=st.tuples(ints(1, 32), ints(1, 16)),
    vertical=loose(st.floats(0, 3)),
    slab=loose(st.floats(0.01, 1)),
    density=st.integers(-1, 300),
)
def test_bake_volume(layers, resolution, fin, vertical, slab, density):
    def bake():
        hair = pelt.HairParams(density=max(density, 0)) if density >= 0 else None
        return pelt.bake_volume(
            hair, layers, resolution, fin_size=fin, vertical_filter=vertical, fin_slab=slab
        )

    check(bake)


@FUZZ
@given(
    shape=st.tuples(st.integers(0, 4), st.integers(0, 6)),
    values=st.one_of(
        st.lists(st.floats(0, 2), min_size=1, max_size=8), st.lists(NUMBERS, min_size=1, max_size=8)
    ),
    spacing=loose(st.floats(0.1, 8)),
    order=st.one_of(st.none(), ints(1, 5)),
    directions=ints(16, 80),
    sigma=loose(st.floats(0, 4)),
    method=st.sampled_from(["sweep", "brute", "other"]),
)
def test_bake_transfer(shape, values, spacing, order, directions, sigma, method):
    layers, res = shape
    density = np.resize(np.array(values, np.float32), (layers, res, res))
    check(
        lambda: pelt.bake_transfer(
            density, layer_spacing=spacing, order=order, directions=directions, sigma=sigma, method=method,
            phase="isotropic",
        )
    )  # fmt: skip


@FUZZ
@given(order=SMALL, direction=st.tuples(NUMBERS, NUMBERS, NUMBERS), angle=NUMBERS,
       image=st.tuples(st.integers(0, 6), st.integers(0, 6), NUMBERS))  # fmt: skip
def test_spherical_harmonics(order, direction, angle, image):
    check(lambda: pelt.sh_project_light(direction, order, angle))
    h, w, value = image
    check(lambda: pelt.sh_project_equirect(np.full((h, w, 3), value, np.float32), order))


@FUZZ
@given(
    scale=st.sampled_from([1e-30, 1e-20, 1e-6, 1.0, 1e6, 1e20, 1e30]),
    tile=loose(st.floats(0.1, 2)),
    seed=ints(0, 2**64 - 1),
    alignment=loose(st.floats(0.1, 45)),
    down=st.tuples(*[loose(st.floats(-1, 1))] * 3),
    faces=st.one_of(st.none(), ints(1, 4096)),
)
def test_build_patches(scale, tile, seed, alignment, down, faces):
    mesh = octahedron(scale)

    def build():
        p = pelt.build_patches(
            mesh, tile, seed, max_alignment_deg=alignment, down=down, max_patch_faces=faces
        )
        return {"uv": p.uv, "direction": p.direction, "quality": p.quality}

    check(build)


@FUZZ
@given(
    tile=loose(st.floats(0.1, 2)),
    depth=st.one_of(st.none(), loose(st.floats(0.01, 1))),
    layers=ints(2, 8),
    resolution=ints(1, 16),
    order=st.one_of(st.none(), ints(1, 4)),
    directions=ints(16, 48),
    transfer=st.booleans(),
    seed=ints(0, 2**64 - 1),
    guard=st.tuples(st.booleans(), loose(st.floats(0, 1)), loose(st.floats(0.01, 1))),
)
def test_pipeline(tile, depth, layers, resolution, order, directions, transfer, seed, guard):
    guard_hairs, guard_fraction, guard_share = guard
    try:
        hair = pelt.HairParams(density=256, guard_fraction=guard_fraction)
    except pelt.PeltError as error:
        assert named(error), error
        return
    kwargs = dict(tile_size=tile, fur_depth=depth, layers=layers, resolution=resolution, order=order,
                  directions=directions, transfer=transfer, seed=seed, hair=hair, fin_size=(16, 8),
                  guard_hairs=guard_hairs, guard_share=guard_share)  # fmt: skip
    check(lambda: pelt.Pipeline.peak_bytes(**kwargs))

    def bake():
        asset = pelt.Pipeline().bake(octahedron(), **kwargs)
        return {"uv": asset.patches.uv, "volume": asset.volume["coverage"], "transfer": asset.transfer,
                "guard_hairs": asset.guard_hairs}  # fmt: skip

    check(bake)


_ASSET = []


def octahedron_asset():
    """One small bake of the octahedron, made once, that the skin fuzz exports."""
    if not _ASSET:
        kwargs = dict(tile_size=0.8, layers=3, resolution=8, fin_size=(16, 8), transfer=False)
        _ASSET.append(pelt.Pipeline().bake(octahedron(), hair=pelt.HairParams(density=256), **kwargs))
    return _ASSET[0]


def rotation_matrix(angle, shift, scale):
    c, s = np.cos(angle) * scale, np.sin(angle) * scale
    return [[c, -s, 0, shift], [s, c, 0, 0], [0, 0, scale, 0], [0, 0, 0, 1]]


VALID_MATRIX = st.builds(rotation_matrix, st.floats(-3, 3), st.floats(-2, 2), st.floats(0.1, 3))
WILD_MATRIX = st.lists(st.lists(NUMBERS, min_size=4, max_size=4), min_size=4, max_size=4)


def matrices(count, wild):
    """``count`` 4×4 matrices of rotations, scales and translations, or (``wild``) of anything."""
    return st.lists(WILD_MATRIX if wild else VALID_MATRIX, min_size=count, max_size=count)


SKIN_PARTS = ("parents", "joints", "weights", "times", "rest", "poses", "transform")


@FUZZ
@given(
    nodes=st.integers(1, 4),
    data=st.data(),
    influences=st.integers(1, 6),
    broken=st.sampled_from((None,) * len(SKIN_PARTS) + SKIN_PARTS),
    mode=st.sampled_from(["engine", "geometry"]),
)
def test_export_skin(tmp_path_factory, nodes, data, influences, broken, mode):
    """Half the cases are valid throughout (so the export runs); the others break one part."""

    def part(name, valid, wild):
        return data.draw(wild if broken == name else valid)

    vertices, count = 6, 6 * influences
    # A tree: each parent before its child.
    parents = [part("parents", st.integers(-1, j - 1), INTEGERS) for j in range(nodes)]
    joints = part("joints", st.lists(st.integers(0, nodes - 1), min_size=count, max_size=count),
                  st.lists(INTEGERS, min_size=count, max_size=count))  # fmt: skip
    weights = part("weights", st.lists(st.floats(0.01, 1), min_size=count, max_size=count),
                   st.lists(NUMBERS, min_size=count, max_size=count))  # fmt: skip
    times = part("times", st.lists(st.integers(0, 100), min_size=1, max_size=3, unique=True).map(
        lambda t: [x / 30 for x in sorted(t)]), st.lists(NUMBERS, min_size=1, max_size=3))  # fmt: skip
    poses = data.draw(matrices(len(times) * nodes, broken == "poses"))
    skeleton = {
        "names": [f"n{j}" for j in range(nodes)],
        "parents": parents,
        "rest": data.draw(matrices(nodes, broken == "rest")),
        "animations": [{"name": "a", "times": times, "poses": np.reshape(poses, (len(times), nodes, 4, 4))}],
    }
    skin = {
        "skeleton": 0,
        "joints": np.reshape(np.array(joints), (vertices, influences)),
        "weights": np.reshape(weights, (vertices, influences)),
    }
    transform = data.draw(matrices(1, broken == "transform"))[0]
    path = tmp_path_factory.mktemp("skin") / "x.glb"
    asset = octahedron_asset()
    check(
        lambda: pelt.export_gltf(asset, path, mode=mode, transform=transform, skin=skin, skeletons=[skeleton])
    )


MATERIAL_PARTS = ("slots", "triangle_slot", "name", "base_color", "factors", "times", "poses")


@FUZZ
@given(
    data=st.data(),
    slot_count=st.integers(0, 3),
    broken=st.sampled_from((None,) * len(MATERIAL_PARTS) + MATERIAL_PARTS),
    mode=st.sampled_from(["engine", "geometry"]),
)
def test_export_materials(tmp_path_factory, data, slot_count, broken, mode):
    """An object's own materials (on its bald faces) and its own animation: half the cases valid
    throughout, the others with one part broken."""

    def strategy(name, valid, wild):
        return wild if broken == name else valid

    def part(name, valid, wild):
        return data.draw(strategy(name, valid, wild))

    unit = st.floats(0, 1)
    color = strategy("base_color", st.lists(unit, min_size=4, max_size=4), st.lists(NUMBERS, max_size=6))
    name = strategy("name", st.text(min_size=1, max_size=20).filter(str.isprintable), st.text(max_size=80))
    material = st.fixed_dictionaries(
        {"name": name, "base_color": color, "metallic": strategy("factors", unit, NUMBERS), "roughness": unit}
    )
    valid_slots = st.lists(st.one_of(st.none(), material), min_size=slot_count, max_size=slot_count)
    wild_slots = st.one_of(st.lists(st.one_of(st.none(), material, INTEGERS), max_size=4), NUMBERS)
    slots = part("slots", valid_slots, wild_slots)
    # The octahedron has 8 triangles.
    valid_triangle_slots = st.lists(st.integers(0, max(slot_count - 1, 0)), min_size=8, max_size=8)
    triangle_slot = part("triangle_slot", valid_triangle_slots, st.lists(INTEGERS, max_size=10))
    times = part("times", st.lists(st.integers(0, 100), min_size=1, max_size=3, unique=True).map(
        lambda t: [x / 30 for x in sorted(t)]), st.lists(NUMBERS, min_size=1, max_size=3))  # fmt: skip
    poses = data.draw(matrices(len(times), broken == "poses"))
    animations = [{"name": "a", "times": times, "poses": np.reshape(poses, (len(times), 4, 4))}]
    materials = {"slots": slots, "triangle_slot": triangle_slot} if slot_count or broken else None
    path = tmp_path_factory.mktemp("materials") / "x.glb"
    asset = octahedron_asset()
    check(lambda: pelt.export_gltf(asset, path, mode=mode, materials=materials, animations=animations))


@FUZZ
@given(limit=st.one_of(st.none(), NUMBERS, INTEGERS), threads=INTEGERS)
def test_settings(limit, threads):
    try:
        check(lambda: pelt.set_memory_limit(limit))
        check(lambda: pelt.set_thread_count(threads))
    finally:
        pelt.set_memory_limit(64 << 20)
        pelt.set_thread_count(0)


if __name__ == "__main__":
    raise SystemExit(pytest.main([__file__, "-q"]))
