"""``pelt.Preview``: the wgpu preview of a baked asset from Python, on the CPU adapter (lavapipe),
with matrices in Blender's conventions (math order, OpenGL clip depth)."""

import math

import numpy as np
import pelt
import pytest

SIDE = 64


def uv_sphere(segments=24, rings=12):
    """A unit sphere as ``(positions [V, 3], triangles [T, 3])``, counter-clockwise from outside."""
    positions = [(0.0, 0.0, 1.0)]
    for r in range(1, rings):
        theta = math.pi * r / rings
        for s in range(segments):
            phi = 2 * math.pi * s / segments
            sin = math.sin(theta)
            positions.append((sin * math.cos(phi), sin * math.sin(phi), math.cos(theta)))
    positions.append((0.0, 0.0, -1.0))
    south = len(positions) - 1

    def ring(r, s):
        return 1 + (r - 1) * segments + s % segments

    triangles = [(0, ring(1, s), ring(1, s + 1)) for s in range(segments)]
    for r in range(1, rings - 1):
        for s in range(segments):
            a, b, c, d = ring(r, s), ring(r + 1, s), ring(r + 1, s + 1), ring(r, s + 1)
            triangles += [(a, b, c), (a, c, d)]
    triangles += [(south, ring(rings - 1, s + 1), ring(rings - 1, s)) for s in range(segments)]
    return np.array(positions, np.float32), np.array(triangles, np.uint32)


def bake(*, layers=8, transfer=True, hair=None, **options):
    positions, triangles = uv_sphere()
    mesh = pelt.FurMesh(positions, triangles)
    return pelt.Pipeline().bake(
        mesh,
        tile_size=0.5,
        hair=hair or pelt.HairParams(density=1024),
        layers=layers,
        resolution=32,
        fin_size=(64, 16),
        fur_depth=0.1,
        transfer=transfer,
        order=3,
        directions=64,
        **options,
    )


@pytest.fixture(scope="module")
def asset():
    return bake()


@pytest.fixture(scope="module")
def preview(asset):
    return pelt.Preview(asset, adapter="cpu")


def look_at(eye, target=(0.0, 0.0, 0.0), up=(0.0, 0.0, 1.0)):
    """A view matrix in the math convention (as ``np.array(mathutils.Matrix)``)."""
    eye, target, up = (np.asarray(v, np.float64) for v in (eye, target, up))
    f = target - eye
    f /= np.linalg.norm(f)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def gl_perspective(fov_deg=40.0, near=0.5, far=20.0, aspect=1.0):
    """An OpenGL projection (clip depth -1..1), as Blender's ``window_matrix`` is."""
    t = 1.0 / math.tan(math.radians(fov_deg) / 2)
    return np.array(
        [
            [t / aspect, 0, 0, 0],
            [0, t, 0, 0],
            [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
            [0, 0, -1, 0],
        ]
    )


def gl_orthographic(half, near, far):
    return np.array(
        [
            [1 / half, 0, 0, 0],
            [0, 1 / half, 0, 0],
            [0, 0, -2 / (far - near), -(far + near) / (far - near)],
            [0, 0, 0, 1],
        ]
    )


VIEW = look_at((0.0, -4.0, 1.0))
PROJECTION = gl_perspective()


def test_frames_are_numpy_images_in_both_formats(preview, asset):
    assert preview.adapter["device_type"] == "Cpu"
    assert preview.transfer_order == asset.transfer["order"] == 3
    image = preview.render(VIEW, PROJECTION, SIDE, SIDE)
    assert image.shape == (SIDE, SIDE, 4) and image.dtype == np.uint8
    # The sphere fills the middle (opaque skin) and misses the corners.
    assert image[SIDE // 2, SIDE // 2, 3] == 255
    assert image[0, 0, 3] == 0 and image[-1, -1, 3] == 0
    assert image[SIDE // 2, SIDE // 2, :3].max() > 0
    linear = preview.render(VIEW, PROJECTION, SIDE, SIDE, linear=True)
    assert linear.shape == (SIDE, SIDE, 4) and linear.dtype == np.float32
    assert np.isfinite(linear).all()
    assert np.abs(np.round(linear[..., 3] * 255) - image[..., 3]).max() <= 3
    # Both lighting models, and the same frame twice is the same image.
    kk = preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting="kajiya-kay")
    assert not np.array_equal(kk, image)
    assert np.array_equal(preview.render(VIEW, PROJECTION, SIDE, SIDE), image)
    info = preview.last_frame
    assert info["shells"] == asset.layers - 1 and info["level"] == 0
    # As a texture (Blender's GPUTexture): the same frame bottom row first, in float32, the
    # bytes over 255 (or linear as it was).
    texture = preview.render(VIEW, PROJECTION, SIDE, SIDE, texture=True)
    assert texture.shape == (SIDE, SIDE, 4) and texture.dtype == np.float32
    assert texture.flags.c_contiguous
    np.testing.assert_allclose(texture, image[::-1] / 255.0, rtol=0, atol=1e-7)
    linear_texture = preview.render(VIEW, PROJECTION, SIDE, SIDE, linear=True, texture=True)
    assert np.array_equal(linear_texture, linear[::-1])


def test_marched_shells_cover_what_instanced_shells_cover(preview):
    # Both lighting models; the marched hull covers the same pixels as the instanced shells to a
    # percent, and is as bright to within 15% where both are opaque.
    for lighting in ("kajiya-kay", "prt"):
        instanced = preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting=lighting)
        marched = preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting=lighting, shell_method="marched")
        assert not np.array_equal(instanced, marched)
        covered = [int((image[..., 3] > 0).sum()) for image in (instanced, marched)]
        assert abs(covered[0] - covered[1]) <= 0.01 * covered[0], covered
        both = (instanced[..., 3] == 255) & (marched[..., 3] == 255)
        means = [float(image[both][:, :3].mean()) for image in (instanced, marched)]
        assert abs(means[0] - means[1]) <= 0.15 * means[0], means


def test_virtual_planes_draw_the_slices_of_a_bake_that_asked_for_them():
    # The raycast paper's planes: one hull traced through the asset's slices. They cover what
    # the shells cover, look otherwise, and a higher loop limit never lets more skin through.
    asset = bake(transfer=False, planes=8)
    assert asset.planes["planes"] == 8
    assert asset.planes["slices"].shape == (16, 64, 128, 4)
    assert [s["stage"] for s in asset.report] == ["patches", "volume", "planes"]
    preview = pelt.Preview(asset, adapter="cpu")
    shells = preview.render(VIEW, PROJECTION, SIDE, SIDE)
    planes = preview.render(VIEW, PROJECTION, SIDE, SIDE, shell_method="planes")
    covered = [int((image[..., 3] > 0).sum()) for image in (shells, planes)]
    assert abs(covered[0] - covered[1]) <= 0.03 * covered[0], covered
    assert not np.array_equal(shells, planes)

    def planes_opacity(limit):
        image = preview.render(VIEW, PROJECTION, SIDE, SIDE, shell_method="planes", plane_loop_limit=limit)
        return float(image[..., 3].sum())

    opacity = [planes_opacity(1), planes_opacity(32)]
    assert opacity[0] < opacity[1], opacity
    assert bake(transfer=False).planes is None


def test_auto_shell_method_marches_on_a_cpu_adapter(preview):
    auto = preview.render(VIEW, PROJECTION, SIDE, SIDE, shell_method="auto")
    cpu = preview.adapter["device_type"] == "Cpu"
    expected = preview.render(VIEW, PROJECTION, SIDE, SIDE, shell_method="marched" if cpu else "instanced")
    other = preview.render(VIEW, PROJECTION, SIDE, SIDE, shell_method="instanced" if cpu else "marched")
    assert np.array_equal(auto, expected)
    assert not np.array_equal(auto, other)


def test_opengl_depth_is_remapped_to_wgpu():
    # Orthographic, near 0 and far 10, the sphere's front 2 units away: GL depth -0.6, which
    # wgpu would clip without the remap to 0..1.
    preview = pelt.Preview(bake(transfer=False), adapter="cpu")
    image = preview.render(look_at((0.0, -3.0, 0.0)), gl_orthographic(1.5, 0.0, 10.0), SIDE, SIDE)
    assert image[SIDE // 2, SIDE // 2, 3] == 255
    covered = (image[..., 3] > 0).mean()
    # A disk of radius 1 (plus fur) in a 3 by 3 square.
    assert math.pi / 9 * 0.95 < covered < math.pi * 1.2**2 / 9


def gl_window_depth(projection, view_distance):
    """OpenGL window depth (0..1, as a depth buffer holds it) of a point ``view_distance`` in
    front of the camera, from the projection's definition."""
    clip = np.asarray(projection, np.float64) @ np.array([0.0, 0.0, -view_distance, 1.0])
    return 0.5 * clip[2] / clip[3] + 0.5


def test_occluders_hide_the_fur_behind_them(preview):
    plain = preview.render(VIEW, PROJECTION, SIDE, SIDE)
    # A wall one unit in front of the camera over the image's left half (rows top first).
    depth = np.ones((SIDE, SIDE), np.float32)
    depth[:, : SIDE // 2] = gl_window_depth(PROJECTION, 1.0)
    walled = preview.render(VIEW, PROJECTION, SIDE, SIDE, occluders=depth)
    assert (plain[:, : SIDE // 2, 3] > 0).sum() > 50
    assert (walled[:, : SIDE // 2, 3] == 0).all()
    assert np.array_equal(walled[:, SIDE // 2 :], plain[:, SIDE // 2 :])
    # The same wall far behind the sphere (the camera is 4.1 units from its centre) hides nothing.
    depth[:, : SIDE // 2] = gl_window_depth(PROJECTION, 8.0)
    assert np.array_equal(preview.render(VIEW, PROJECTION, SIDE, SIDE, occluders=depth), plain)
    # A wall through the sphere's middle hides its back fur only: where the front fur stands
    # within the bias of it (three fur depths by default) it stays; without a bias it goes.
    depth[:] = gl_window_depth(PROJECTION, np.linalg.norm([4.0, 1.0]) - 0.95)
    kept = preview.render(VIEW, PROJECTION, SIDE, SIDE, occluders=depth)
    cut = preview.render(VIEW, PROJECTION, SIDE, SIDE, occluders=depth, occluder_bias=0.0)
    assert (cut[..., 3] > 0).sum() < (kept[..., 3] > 0).sum() <= (plain[..., 3] > 0).sum()
    # A depth of the wrong shape or out of range is named.
    with pytest.raises(pelt.InvalidParameterError, match="occluders"):
        preview.render(VIEW, PROJECTION, SIDE, SIDE, occluders=np.ones((SIDE, SIDE + 1), np.float32))
    with pytest.raises(pelt.InvalidParameterError, match=r"occluders\.depth"):
        preview.render(VIEW, PROJECTION, SIDE, SIDE, occluders=np.full((SIDE, SIDE), np.nan, np.float32))
    with pytest.raises(pelt.InvalidParameterError, match=r"occluders\.bias"):
        preview.render(VIEW, PROJECTION, SIDE, SIDE, occluders=depth, occluder_bias=-1.0)


def test_lod_reports_the_level_it_drew(preview):
    near = preview.render(VIEW, PROJECTION, SIDE, SIDE, lod=True, min_shells=1)
    info = preview.last_frame
    far = preview.render(look_at((0.0, -16.0, 4.0)), PROJECTION, SIDE, SIDE, lod=True, min_shells=1)
    far_info = preview.last_frame
    assert far_info["fur_pixels"] < info["fur_pixels"]
    assert (far_info["level"], -far_info["shells"]) >= (info["level"], -info["shells"])
    assert near.shape == far.shape == (SIDE, SIDE, 4)
    with pytest.raises(pelt.InvalidParameterError, match="shell_count"):
        preview.render(VIEW, PROJECTION, SIDE, SIDE, lod=True, shells=3)


def test_a_far_dense_mesh_draws_a_coarser_level_and_mesh_error_zero_the_whole_mesh():
    positions, triangles = uv_sphere(96, 48)
    dense = pelt.Pipeline().bake(
        pelt.FurMesh(positions, triangles),
        tile_size=0.5,
        hair=pelt.HairParams(density=1024),
        layers=4,
        resolution=32,
        fin_size=(64, 16),
        fur_depth=0.1,
        transfer=False,
    )
    preview = pelt.Preview(dense, adapter="cpu")
    far = look_at((0.0, -12.0, 3.0))
    coarse = preview.render(far, PROJECTION, SIDE, SIDE)
    info = preview.last_frame
    assert info["mesh_level"] >= 1
    assert 2 * info["triangles"] <= len(triangles)
    whole = preview.render(far, PROJECTION, SIDE, SIDE, mesh_error=0.0)
    assert (preview.last_frame["mesh_level"], preview.last_frame["triangles"]) == (0, len(triangles))
    covered, covered_whole = (coarse[..., 3] > 0).sum(), (whole[..., 3] > 0).sum()
    assert abs(int(covered) - int(covered_whole)) <= 0.03 * covered_whole
    with pytest.raises(pelt.InvalidParameterError, match="mesh_error"):
        preview.render(far, PROJECTION, SIDE, SIDE, mesh_error=-1.0)
    # A uniform repaint keeps the coarser level; one bald ring of latitude, narrower than its
    # triangles, would be smeared by it: the whole mesh is drawn.
    vertices = len(positions)
    preview.update(color=np.tile(np.array([[1.0, 0.3, 0.2, 1.0]], np.float32), (vertices, 1)))
    preview.render(far, PROJECTION, SIDE, SIDE)
    assert preview.last_frame["mesh_level"] == info["mesh_level"]
    latitudes = np.unique(positions[:, 2])
    ring = positions[:, 2] == latitudes[len(latitudes) // 3]
    assert 0 < ring.sum() < 0.05 * vertices
    preview.update(length=np.where(ring, 0.0, 1.0).astype(np.float32))
    preview.render(far, PROJECTION, SIDE, SIDE)
    assert preview.last_frame["mesh_level"] == 0


def test_updates_rewrite_only_colors_and_lengths(asset):
    preview = pelt.Preview(asset, adapter="cpu")
    vertices = asset.mesh.vertex_count
    before = preview.uploads
    white = preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting="kajiya-kay")
    preview.update(color=np.tile(np.array([[1.0, 0.2, 0.2]], np.float32), (vertices, 1)))
    after = preview.uploads
    for kind in ("texture_bytes", "geometry_bytes", "transfer_bytes"):
        assert after[kind] == before[kind]
    assert after["attribute_bytes"] > before["attribute_bytes"]
    reddened = preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting="kajiya-kay")
    assert reddened[..., 1].sum() < 0.8 * white[..., 1].sum()
    # Bald everywhere renders exactly the (bald) skin.
    preview.update(length=np.zeros(vertices, np.float32))
    skin = preview.render(VIEW, PROJECTION, SIDE, SIDE, shells=0, fins=False)
    assert np.array_equal(preview.render(VIEW, PROJECTION, SIDE, SIDE), skin)


def test_a_new_fur_depth_is_drawn_without_an_upload_and_a_bad_one_changes_nothing(asset):
    preview = pelt.Preview(asset, adapter="cpu")
    assert preview.fur_depth == pytest.approx(asset.fur_depth)
    before = preview.uploads
    shallow = preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting="kajiya-kay")
    deeper = 2.0 * asset.fur_depth
    preview.fur_depth = deeper
    assert preview.fur_depth == pytest.approx(deeper)
    assert preview.uploads == before
    deep = preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting="kajiya-kay")
    assert (deep[..., 3] > 0).sum() > (shallow[..., 3] > 0).sum()
    for bad in (float("nan"), -0.1, 1e30):
        with pytest.raises(pelt.InvalidParameterError, match="`fur_depth`"):
            preview.fur_depth = bad
        assert preview.fur_depth == pytest.approx(deeper)
    preview.fur_depth = asset.fur_depth
    assert np.array_equal(preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting="kajiya-kay"), shallow)


def test_a_comb_update_leans_the_fur_and_a_bad_one_changes_nothing(asset):
    preview = pelt.Preview(asset, adapter="cpu")
    vertices = asset.mesh.vertex_count
    upright = preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting="kajiya-kay")
    before = preview.uploads
    # Combed hard along +X (right on screen, the camera looking along +Y): the fringe moves right.
    preview.update(comb=np.tile(np.array([[3.0, 0.0, 0.0]], np.float32), (vertices, 1)))
    assert preview.uploads["texture_bytes"] == before["texture_bytes"]
    assert preview.uploads["pose_bytes"] > before["pose_bytes"]
    leaning = preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting="kajiya-kay")

    def lean(image):
        """Covered pixels right of the middle column minus those left of it."""
        covered = image[..., 3] > 0
        return int(covered[:, SIDE // 2 :].sum()) - int(covered[:, : SIDE // 2].sum())

    assert lean(leaning) > lean(upright) + 10
    # A bad comb (with good colors) is named and changes neither.
    red = np.tile(np.array([[1.0, 0.0, 0.0]], np.float32), (vertices, 1))
    with pytest.raises(pelt.InvalidParameterError, match="comb"):
        preview.update(color=red, comb=np.zeros((vertices - 1, 3), np.float32))
    bad = np.zeros((vertices, 3), np.float32)
    bad[2, 0] = np.inf
    with pytest.raises(pelt.InvalidParameterError, match=r"comb\[2\]"):
        preview.update(color=red, comb=bad)
    assert np.array_equal(preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting="kajiya-kay"), leaning)
    assert preview.uploads["texture_bytes"] == before["texture_bytes"]


def test_a_pose_moves_the_fur_and_a_bad_pose_is_named(asset):
    preview = pelt.Preview(asset, adapter="cpu")
    mesh = asset.mesh
    rest = preview.render(VIEW, PROJECTION, SIDE, SIDE)
    before = preview.uploads
    # Squashed to half its height: the covered area shrinks; only the skin's vertices go up.
    squash = np.array([1.0, 1.0, 0.5], np.float32)
    preview.deform(mesh.positions * squash)
    squashed = preview.render(VIEW, PROJECTION, SIDE, SIDE)
    assert (squashed[..., 3] > 0).sum() < 0.9 * (rest[..., 3] > 0).sum()
    after = preview.uploads
    assert after["pose_bytes"] > before["pose_bytes"]
    for kind in ("texture_bytes", "geometry_bytes", "attribute_bytes", "transfer_bytes"):
        assert after[kind] == before[kind]
    for positions, normals, name in [
        (mesh.positions[:-1], None, "positions"),
        (np.full_like(mesh.positions, np.nan), None, "positions"),
        (mesh.positions, np.zeros_like(mesh.normals), "normals"),
        (mesh.positions[:, :2], None, "positions"),
    ]:
        with pytest.raises(pelt.InvalidMeshError, match=name):
            preview.deform(positions, normals)
    assert np.array_equal(preview.render(VIEW, PROJECTION, SIDE, SIDE), squashed)
    # Back at the rest shape: the rest's very picture.
    preview.deform(mesh.positions, mesh.normals)
    assert np.array_equal(preview.render(VIEW, PROJECTION, SIDE, SIDE), rest)


def test_kajiya_kay_under_a_sky_lights_fur_facing_it_more(preview):
    # Radiance 0.6 + 0.4 z, no sun: the fur's ambient is the irradiance about its normal over
    # π, 0.6 + 0.27 n_z, so the sphere's upper half is brighter than its lower half; the same
    # mean radiance alone (band 0) lights both halves alike.
    sh = pelt.sh_project_equirect(sky_image(lambda z: 0.6 + 0.4 * z), 2)
    lit = {"model": "kajiya-kay", "color": (0.0, 0.0, 0.0), "environment": sh}
    sky = preview.render(VIEW, PROJECTION, SIDE, SIDE, linear=True, lighting=lit)
    mean = preview.render(VIEW, PROJECTION, SIDE, SIDE, linear=True, lighting={**lit, "environment": sh[:1]})
    half = SIDE // 2
    upper, lower = (slice(4, half - 4), slice(half + 4, SIDE - 4))
    middle = slice(half - 12, half + 12)

    def brightness(image, rows):
        return image[rows, middle, :3].mean()

    assert brightness(sky, upper) > 1.15 * brightness(mean, upper)
    assert brightness(sky, lower) < 0.9 * brightness(mean, lower)
    # An explicit gradient (per unit of the normal's x, y, z) gives the same picture.
    g = 2.0 / 3.0 * np.sqrt(3.0 / (4.0 * np.pi)) * sh[[3, 1, 2]]
    explicit = {**lit, "environment": sh[:1], "ambient_gradient": g}
    np.testing.assert_allclose(
        preview.render(VIEW, PROJECTION, SIDE, SIDE, linear=True, lighting=explicit), sky, atol=2e-3
    )
    for bad, name in [
        ({**lit, "environment": np.full((4, 3), np.nan)}, "lighting.environment"),
        ({**lit, "ambient_gradient": np.zeros((2, 3))}, "lighting.ambient_gradient"),
    ]:
        with pytest.raises(pelt.InvalidParameterError, match=name):
            preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting=bad)


def sky_image(radiance, height=64):
    """An equirectangular image ``[H, 2H, 3]`` of ``radiance(z)`` (row 0 at the zenith)."""
    z = np.cos(np.pi * (np.arange(height) + 0.5) / height)
    rows = np.asarray(radiance(z), np.float32)
    return np.ascontiguousarray(np.broadcast_to(rows[:, None, None], (height, 2 * height, 3)))


def test_bad_input_names_the_problem_and_the_preview_survives(asset):
    preview = pelt.Preview(asset, adapter="cpu")
    good = preview.render(VIEW, PROJECTION, SIDE, SIDE)
    vertices = asset.mesh.vertex_count
    nan = VIEW.copy()
    nan[1, 2] = np.nan
    cases = [
        (lambda: preview.update(color=np.ones((vertices - 1, 4), np.float32)), "color"),
        (lambda: preview.update(length=np.ones((vertices, 2), np.float32)), "length"),
        (lambda: preview.render(nan, PROJECTION, SIDE, SIDE), "camera.view"),
        (lambda: preview.render(VIEW, np.eye(3), SIDE, SIDE), "projection_matrix"),
        (lambda: preview.render(VIEW, PROJECTION, 0, SIDE), "camera.width"),
        (lambda: preview.render(VIEW, PROJECTION, SIDE, -4), "height"),
        (lambda: preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting={"glow": 1.0}), "lighting.glow"),
        (
            lambda: preview.render(
                VIEW, PROJECTION, SIDE, SIDE, lighting={"model": "kajiya-kay", "transmit": 1.5}
            ),
            "kajiya_kay.transmit",
        ),
        (
            lambda: preview.render(VIEW, PROJECTION, SIDE, SIDE, lighting={"direction": (0, 0, 0)}),
            "direction",
        ),
        (lambda: setattr(preview, "fur_depth", float("nan")), "fur_depth"),
        # A transfer baked for another hair volume (other layers).
        (lambda: preview.set_transfer(bake(layers=6)), "transfer.layers"),
        (lambda: pelt.Preview(asset, adapter="quantum"), "adapter"),
        (lambda: preview.render(VIEW, PROJECTION, SIDE, SIDE, shell_method="ray"), "shell_method"),
        (lambda: preview.render(VIEW, PROJECTION, SIDE, SIDE, shells=-1), "`shells`.*got -1"),
        # The virtual planes without their slices, and a bad loop limit or plane count.
        (lambda: preview.render(VIEW, PROJECTION, SIDE, SIDE, shell_method="planes"), "shell_method"),
        (lambda: preview.render(VIEW, PROJECTION, SIDE, SIDE, plane_loop_limit=-1), "`plane_loop_limit`"),
        (lambda: bake(planes=257), "planes"),
        (lambda: bake(planes=-2), "`planes`.*got -2"),
    ]
    for call, name in cases:
        with pytest.raises(
            pelt.InvalidParameterError, match=name if "`" in name else name.replace(".", r"\.")
        ):
            call()
    # PRT without transfer textures.
    plain = pelt.Preview(bake(transfer=False), adapter="cpu")
    with pytest.raises(
        pelt.InvalidParameterError, match=r"lighting\.model.*needs a baked transfer.*transfer=True"
    ):
        plain.render(VIEW, PROJECTION, SIDE, SIDE, lighting="prt")
    # A camera 1000 units away (a narrow lens) is valid: it was refused as "singular".
    far = preview.render(look_at((0.0, -1000.0, 250.0)), gl_perspective(0.5, 900.0, 1100.0), SIDE, SIDE)
    assert (far[..., 3] > 0).mean() > 0.02  # the sphere covers about 5% of this frame
    # Nothing changed: the next valid frame is the same image.
    assert np.array_equal(preview.render(VIEW, PROJECTION, SIDE, SIDE), good)
    assert preview.transfer_order == 3


def test_guard_hairs_are_drawn_as_strands_over_the_shells():
    guarded = bake(hair=pelt.HairParams(density=1024, guard_fraction=0.2), guard_hairs=True)
    preview = pelt.Preview(guarded, adapter="cpu")
    assert preview.guard_strands == len(guarded.guard_hairs["counts"]) > 50
    shells = preview.render(VIEW, PROJECTION, SIDE, SIDE, guard_hairs=False)
    hybrid = preview.render(VIEW, PROJECTION, SIDE, SIDE)
    changed = np.abs(hybrid.astype(int) - shells.astype(int)).max(axis=-1) > 8
    assert changed.mean() > 0.01
    # Every order draws; a bad one is named.
    for order in ("depth", "banded", "sorted"):
        image = preview.render(VIEW, PROJECTION, SIDE, SIDE, strand_order=order)
        assert not np.array_equal(image, shells)
    with pytest.raises(pelt.InvalidParameterError, match="strand_order"):
        preview.render(VIEW, PROJECTION, SIDE, SIDE, strand_order="random")
    with pytest.raises(pelt.InvalidParameterError, match="strand_pixels"):
        preview.render(VIEW, PROJECTION, SIDE, SIDE, strand_pixels=float("nan"))
    # An asset without guard hairs draws none.
    assert pelt.Preview(bake(transfer=False), adapter="cpu").guard_strands == 0


@pytest.mark.parametrize(
    "name, value",
    [
        ("shells_per_pixel", 0.0),
        ("mesh_error", -1.0),
        ("strand_pixels", 65.0),
        ("plane_loop_limit", 0),
        ("background", (0.0, 0.0, 2.0, 1.0)),
    ],
)
def test_render_keywords_outside_the_schema_s_range_are_refused(preview, name, value):
    r = pelt.SCHEMA["render"]["ranges"][name]
    x = value[2] if isinstance(value, tuple) else value
    assert not r["min"] <= x <= r["max"] or (r["min_open"] and x == r["min"])
    with pytest.raises(pelt.InvalidParameterError, match=name):
        preview.render(VIEW, PROJECTION, 8, 8, **{name: value})


def test_max_shells_below_min_shells_and_a_depth_outside_the_bake_s_range_are_refused(preview):
    with pytest.raises(pelt.InvalidParameterError, match="max_shells"):
        preview.render(VIEW, PROJECTION, 8, 8, lod=True, min_shells=5, max_shells=4)
    depth = preview.fur_depth
    for bad in (0.0, -1.0, 2e6, math.nan):
        with pytest.raises(pelt.InvalidParameterError, match="fur_depth"):
            preview.fur_depth = bad
    assert preview.fur_depth == depth
