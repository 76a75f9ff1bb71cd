"""The comb operators through ``bpy.ops`` (and the interactive comb's session, which its modal
handler drives) on real meshes, each result checked against numpy or ``bpy_extras`` computations
made here: which vertices change, by how much, that the comb stays tangential, and that Esc,
undo and refusals leave the data exactly as it was."""

import bpy
import numpy as np
import pytest
from bpy_extras import view3d_utils
from conftest import add_suzanne, datablock_snapshot
from mathutils import Matrix, Vector

RNG = np.random.default_rng(11)


def vertex_array(collection, prop, columns, dtype=np.float64):
    values = np.empty(len(collection) * columns, np.float32 if dtype is np.float64 else dtype)
    collection.foreach_get(prop, values)
    return values.reshape(-1, columns).astype(dtype)


def unit_normals(mesh):
    n = vertex_array(mesh.vertex_normals, "vector", 3)
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def read_comb(mesh):
    attribute = mesh.attributes["pelt_comb"]
    assert (attribute.domain, attribute.data_type) == ("POINT", "FLOAT_VECTOR")
    values = np.empty(3 * len(mesh.vertices), np.float32)
    attribute.data.foreach_get("vector", values)
    return values.reshape(-1, 3)


def write_comb(mesh, comb):
    attribute = mesh.attributes.get("pelt_comb") or mesh.attributes.new("pelt_comb", "FLOAT_VECTOR", "POINT")
    attribute.data.foreach_set("vector", np.asarray(comb, np.float32).ravel())


def random_tangential_comb(mesh, scale=0.5):
    v = RNG.normal(size=(len(mesh.vertices), 3)) * scale
    n = unit_normals(mesh)
    return (v - n * np.einsum("ij,ij->i", v, n)[:, None]).astype(np.float32)


def normal_parts(comb, mesh):
    return np.einsum("ij,ij->i", comb.astype(np.float64), unit_normals(mesh))


def make_active(obj):
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)


# -- the scripted stroke ------------------------------------------------------------------------


def test_scripted_stroke_changes_exactly_the_vertices_inside(addon):
    obj = add_suzanne()
    mesh = obj.data
    before = random_tangential_comb(mesh)
    write_comb(mesh, before)
    positions = vertex_array(mesh.vertices, "co", 3)
    center = positions[100] + np.array([0.05, -0.02, 0.03])
    radius, delta, strength = 0.45, np.array([0.3, -0.2, 0.5]), 0.8

    assert bpy.ops.pelt.comb(center=center, radius=radius, delta=delta, strength=strength) == {"FINISHED"}
    after = read_comb(mesh)

    distance = np.linalg.norm(positions - center, axis=1)
    inside = distance < radius
    assert 10 < inside.sum() < len(positions) // 2
    changed = np.any(after != before, axis=1)
    np.testing.assert_array_equal(changed, inside)
    n = unit_normals(mesh)
    step = delta - n * (n @ delta)[:, None]
    weight = strength * (1.0 - (distance / radius) ** 2) ** 2
    np.testing.assert_allclose(after[inside], before[inside] + weight[inside, None] * step[inside], atol=1e-6)
    np.testing.assert_allclose(normal_parts(after - before, mesh), 0.0, atol=1e-6)


def test_scripted_stroke_creates_an_unpainted_comb(addon):
    obj = add_suzanne()
    mesh = obj.data
    assert "pelt_comb" not in mesh.attributes
    assert bpy.ops.pelt.comb(center=(0.0, -0.9, 0.0), radius=0.3, delta=(1.0, 0.0, 0.0)) == {"FINISHED"}
    comb = read_comb(mesh)
    positions = vertex_array(mesh.vertices, "co", 3)
    outside = np.linalg.norm(positions - (0.0, -0.9, 0.0), axis=1) >= 0.3
    np.testing.assert_array_equal(comb[outside], 0.0)
    assert np.abs(comb[~outside]).max() > 0.1


def test_scripted_stroke_in_edit_mode_is_kept(addon):
    obj = add_suzanne()
    bpy.ops.object.mode_set(mode="EDIT")
    assert bpy.ops.pelt.comb(center=(0.0, -0.9, 0.0), radius=0.5, delta=(1.0, 0.0, 0.0)) == {"FINISHED"}
    assert obj.mode == "EDIT"
    bpy.ops.object.mode_set(mode="OBJECT")
    assert np.abs(read_comb(obj.data)).max() > 0.1


# -- gravity and smoothing ----------------------------------------------------------------------


def test_gravity_points_down_in_the_tangent_planes(addon):
    obj = add_suzanne()
    obj.rotation_euler = (0.4, -0.3, 1.1)
    obj.scale = (1.5, 1.5, 1.5)
    bpy.context.view_layer.update()
    mesh = obj.data
    before = random_tangential_comb(mesh)
    write_comb(mesh, before)

    assert bpy.ops.pelt.comb_gravity(strength=0.75) == {"FINISHED"}
    after = read_comb(mesh).astype(np.float64)

    linear = np.array(obj.matrix_world)[:3, :3]
    down = np.linalg.inv(linear) @ np.array([0.0, 0.0, -1.0])
    down /= np.linalg.norm(down)
    n = unit_normals(mesh)
    pull = down - n * (n @ down)[:, None]
    np.testing.assert_allclose(after, 0.25 * before + 0.75 * pull, atol=1e-6)
    np.testing.assert_allclose(normal_parts(after, mesh), 0.0, atol=1e-6)


def test_gravity_hangs_down_in_the_world_under_non_uniform_scale(addon):
    obj = add_suzanne()
    obj.rotation_euler = (0.4, -0.3, 1.1)
    obj.scale = (1.0, 2.5, 0.5)
    bpy.context.view_layer.update()
    mesh = obj.data
    assert bpy.ops.pelt.comb_gravity() == {"FINISHED"}
    comb = read_comb(mesh).astype(np.float64)
    np.testing.assert_allclose(normal_parts(comb, mesh), 0.0, atol=1e-6)
    # in the world, each comb is the steepest way down its tangent plane
    linear = np.array(obj.matrix_world)[:3, :3]
    world_n = unit_normals(mesh) @ np.linalg.inv(linear)
    world_n /= np.linalg.norm(world_n, axis=1, keepdims=True)
    down = np.array([0.0, 0.0, -1.0])
    slope = down - world_n * (world_n @ down)[:, None]
    world = comb @ linear.T
    steep = np.linalg.norm(slope, axis=1) > 0.1
    cosine = np.einsum("ij,ij->i", world[steep], slope[steep])
    cosine /= np.linalg.norm(world[steep], axis=1) * np.linalg.norm(slope[steep], axis=1)
    assert cosine.min() > 0.9999
    assert steep.mean() > 0.8


def test_gravity_on_selected_vertices_from_edit_mode(addon):
    obj = add_suzanne()
    mesh = obj.data
    before = random_tangential_comb(mesh)
    write_comb(mesh, before)
    selected = RNG.random(len(mesh.vertices)) < 0.3
    # a face or edge left selected would select its vertices in Edit Mode
    mesh.polygons.foreach_set("select", np.zeros(len(mesh.polygons), bool))
    mesh.edges.foreach_set("select", np.zeros(len(mesh.edges), bool))
    mesh.vertices.foreach_set("select", selected)
    bpy.ops.object.mode_set(mode="EDIT")

    assert bpy.ops.pelt.comb_gravity(only_selected=True) == {"FINISHED"}
    assert obj.mode == "EDIT"
    bpy.ops.object.mode_set(mode="OBJECT")
    after = read_comb(mesh)
    np.testing.assert_array_equal(after[~selected], before[~selected])
    assert np.all(np.any(after[selected] != before[selected], axis=1))


def edge_roughness(comb, mesh):
    edges = vertex_array(mesh.edges, "vertices", 2, np.int64)
    return np.mean(np.sum((comb[edges[:, 0]] - comb[edges[:, 1]]) ** 2, axis=1))


def test_smooth_evens_out_the_comb(addon):
    obj = add_suzanne()
    mesh = obj.data
    before = random_tangential_comb(mesh).astype(np.float64)
    write_comb(mesh, before)

    assert bpy.ops.pelt.comb_smooth(iterations=4, factor=0.5) == {"FINISHED"}
    after = read_comb(mesh).astype(np.float64)

    assert edge_roughness(after, mesh) < 0.5 * edge_roughness(before, mesh)
    np.testing.assert_allclose(normal_parts(after, mesh), 0.0, atol=1e-6)
    # lengths are averaged, not shrunk by averaging directions that disagree
    ratio = np.linalg.norm(after, axis=1).mean() / np.linalg.norm(before, axis=1).mean()
    assert 0.85 < ratio < 1.15


def test_smooth_without_a_comb_changes_nothing(addon):
    add_suzanne()
    before = datablock_snapshot()
    with pytest.raises(RuntimeError, match=r"has no comb to smooth"):
        bpy.ops.pelt.comb_smooth()
    assert datablock_snapshot() == before


# -- comb from hair curves ----------------------------------------------------------------------


def add_hair(surface, roots_world, directions_world, matrix):
    """A hair Curves object on ``surface`` whose object matrix is ``matrix``, one 3-point strand
    per root (a bend in the middle: only root and tip decide the direction)."""
    curves = bpy.data.hair_curves.new("Hair")
    curves.add_curves([3] * len(roots_world))
    to_local = np.linalg.inv(np.array(matrix))
    tips = roots_world + directions_world
    middle = roots_world + 0.5 * directions_world + 0.05 * np.cross(directions_world, [0.0, 0.0, 1.0])
    points = np.stack([roots_world, middle, tips], axis=1).reshape(-1, 3)
    local = points @ to_local[:3, :3].T + to_local[:3, 3]
    curves.position_data.foreach_set("vector", local.astype(np.float32).ravel())
    obj = bpy.data.objects.new("Hair", curves)
    obj.matrix_world = matrix
    bpy.context.collection.objects.link(obj)
    curves.surface = surface
    return obj


def test_comb_from_curves_follows_the_strands(addon):
    obj = add_suzanne()
    obj.matrix_world = Matrix.LocRotScale(
        Vector((1.0, 2.0, 0.5)), Vector((0.3, 0.2, -0.5)).to_track_quat().to_matrix(), None
    )
    bpy.context.view_layer.update()
    mesh = obj.data
    matrix = np.array(obj.matrix_world)
    positions = vertex_array(mesh.vertices, "co", 3)
    n = unit_normals(mesh)
    rooted = np.arange(0, len(positions), 9)
    # strands leaning 20-40 degrees from the normal, in a random tangent direction
    tangent = RNG.normal(size=(len(rooted), 3))
    tangent -= n[rooted] * np.einsum("ij,ij->i", tangent, n[rooted])[:, None]
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    angle = np.radians(RNG.uniform(20, 40, len(rooted)))
    local_dir = n[rooted] * np.cos(angle)[:, None] + tangent * np.sin(angle)[:, None]
    roots_world = positions[rooted] @ matrix[:3, :3].T + matrix[:3, 3]
    add_hair(obj, roots_world, 0.2 * local_dir @ matrix[:3, :3].T, Matrix.Translation((0.5, -1.0, 0.0)))
    make_active(obj)

    assert bpy.ops.pelt.comb_from_curves() == {"FINISHED"}
    comb = read_comb(mesh).astype(np.float64)

    at_roots = comb[rooted]
    cosine = np.einsum("ij,ij->i", at_roots / np.linalg.norm(at_roots, axis=1, keepdims=True), tangent)
    assert np.degrees(np.arccos(np.clip(cosine, -1, 1))).max() < 3.0
    # the shells lean like the strands: tangential length tan(angle) below 45 degrees
    np.testing.assert_allclose(np.linalg.norm(at_roots, axis=1), np.tan(angle), rtol=0.05)
    # every other vertex of the head got a comb from its neighbours (the eyes have no strand...)
    np.testing.assert_allclose(normal_parts(comb, mesh), 0.0, atol=1e-6)
    reached = np.linalg.norm(comb, axis=1) > 1e-4
    assert reached.mean() > 0.9


def test_comb_from_curves_keeps_vertices_no_strand_reaches(addon):
    obj = add_suzanne()
    mesh = obj.data
    before = random_tangential_comb(mesh)
    write_comb(mesh, before)
    positions = vertex_array(mesh.vertices, "co", 3)
    # one strand, on the nose: the eyes are separate pieces of the mesh and keep their comb
    root = int(np.argmin(positions[:, 1]))
    add_hair(obj, positions[[root]], np.array([[0.0, -0.3, 0.1]]), Matrix.Identity(4))
    make_active(obj)
    assert bpy.ops.pelt.comb_from_curves() == {"FINISHED"}
    after = read_comb(mesh)
    kept = np.all(after == before, axis=1)
    assert 0 < kept.sum() < len(positions) // 2


def test_comb_from_curves_without_curves_changes_nothing(addon):
    obj = add_suzanne()
    write_comb(obj.data, random_tangential_comb(obj.data))
    comb = read_comb(obj.data).copy()
    other = bpy.data.objects.new("Other", bpy.data.meshes.new("Other"))
    add_hair(other, np.zeros((1, 3)), np.ones((1, 3)), Matrix.Identity(4))  # grown on another mesh
    make_active(obj)
    before = datablock_snapshot()
    with pytest.raises(RuntimeError, match=r"no hair Curves object has 'Suzanne' as its surface"):
        bpy.ops.pelt.comb_from_curves()
    assert datablock_snapshot() == before
    np.testing.assert_array_equal(read_comb(obj.data), comb)


@pytest.mark.parametrize("operator", ["comb", "comb_gravity", "comb_smooth", "comb_from_curves"])
def test_refuses_an_object_that_is_not_a_mesh(addon, operator):
    bpy.ops.object.empty_add()
    before = datablock_snapshot()
    with pytest.raises(RuntimeError, match=r"'Empty' is not a mesh \(type EMPTY\)"):
        getattr(bpy.ops.pelt, operator)()
    assert datablock_snapshot() == before


# -- the interactive comb -----------------------------------------------------------------------


def viewport():
    """The 3D viewport of the factory screen (it exists in background mode too)."""
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "WINDOW")
    return region, area.spaces.active.region_3d


def view_plane_drag(region, rv3d, point, drag):
    """The world vector in the view plane through ``point`` that moves its projection by ``drag``
    pixels, from Blender's own forward projection: at one depth the projection is affine, so two
    probes along the view's right and up axes give it exactly. (Blender's unprojection helpers
    invert the perspective matrix in single precision, which loses about 1% with the default
    0.01-1000 clip range.)"""
    axes = rv3d.view_matrix.inverted().to_3x3()
    right, up = axes.col[0], axes.col[1]
    base = view3d_utils.location_3d_to_region_2d(region, rv3d, point)
    jacobian = np.column_stack(
        [
            np.array(view3d_utils.location_3d_to_region_2d(region, rv3d, point + axis) - base)
            for axis in (right, up)
        ]
    )
    a, b = np.linalg.solve(jacobian, drag)
    return np.array(right) * a + np.array(up) * b


def expected_dab(obj, region, rv3d, mouse, drag, radius_px):
    """The deltas one dab adds, computed vertex by vertex with ``bpy_extras.view3d_utils``."""
    mesh = obj.data
    matrix = np.array(obj.matrix_world)
    to_object = np.linalg.inv(matrix[:3, :3])
    eye = np.array(rv3d.view_matrix.inverted().translation)
    n = unit_normals(mesh)
    world_n = n @ to_object
    deltas = np.zeros((len(mesh.vertices), 3))
    for i, v in enumerate(mesh.vertices):
        p = obj.matrix_world @ v.co
        xy = view3d_utils.location_3d_to_region_2d(region, rv3d, p)
        d = np.hypot(*(np.array(xy) - mouse))
        if d >= radius_px or np.dot(world_n[i], np.array(p) - eye) >= 0.0:
            continue
        direction = to_object @ view_plane_drag(region, rv3d, p, drag)
        direction /= np.linalg.norm(direction)
        delta = direction * np.hypot(*drag) / radius_px * (1.0 - (d / radius_px) ** 2) ** 2
        deltas[i] = delta - n[i] * (n[i] @ delta)
    return deltas


def start_session(addon, obj):
    from addon.blender import comb

    return comb, comb.CombSession(obj)


def test_interactive_dab_combs_the_vertices_under_the_circle(addon):
    obj = add_suzanne()
    obj.rotation_euler.z = 0.3
    bpy.context.view_layer.update()
    mesh = obj.data
    before = random_tangential_comb(mesh, 0.2)
    write_comb(mesh, before)
    region, rv3d = viewport()
    assert rv3d.is_perspective
    nose = obj.matrix_world @ mesh.vertices[int(np.argmin(vertex_array(mesh.vertices, "co", 3)[:, 1]))].co
    mouse = np.array(view3d_utils.location_3d_to_region_2d(region, rv3d, nose))
    drag, radius_px, strength = np.array([12.0, -5.0]), 25.0, 0.5

    comb, session = start_session(addon, obj)
    session.begin_stroke()
    moved = session.dab(comb.screen_view(region, rv3d), mouse, drag, radius_px, strength, True)
    session.end_stroke()
    after = read_comb(mesh)

    expected = expected_dab(obj, region, rv3d, mouse, drag, radius_px) * strength
    changed = np.any(after != before, axis=1)
    assert moved == changed.sum() and 10 < moved < len(mesh.vertices) // 3
    np.testing.assert_array_equal(changed, np.any(expected != 0.0, axis=1))
    np.testing.assert_allclose(after, before + expected, atol=1e-5)
    np.testing.assert_allclose(normal_parts(after - before, mesh), 0.0, atol=1e-6)


def test_cancel_restores_the_comb_bit_for_bit(addon):
    obj = add_suzanne()
    mesh = obj.data
    original = random_tangential_comb(mesh)
    write_comb(mesh, original)
    region, rv3d = viewport()
    center = np.array([region.width / 2, region.height / 2])
    comb, session = start_session(addon, obj)
    for _ in range(3):
        session.begin_stroke()
        for step in range(4):
            session.dab(comb.screen_view(region, rv3d), center + 7 * step, (7.0, 7.0), 200.0, 1.0, False)
        session.end_stroke()
    assert not np.array_equal(read_comb(mesh), original)
    session.restore()
    assert read_comb(mesh).tobytes() == original.tobytes()


def test_cancel_removes_a_comb_the_session_created(addon):
    obj = add_suzanne()
    before = datablock_snapshot()
    region, rv3d = viewport()
    comb, session = start_session(addon, obj)
    session.begin_stroke()
    center = np.array([region.width / 2, region.height / 2])
    assert session.dab(comb.screen_view(region, rv3d), center, (10.0, 0.0), 300.0, 1.0, True) > 0
    session.end_stroke()
    session.restore()
    assert "pelt_comb" not in obj.data.attributes
    assert datablock_snapshot() == before


def test_each_stroke_is_one_undo_step(addon):
    obj = add_suzanne()
    write_comb(obj.data, np.zeros((len(obj.data.vertices), 3)))
    bpy.ops.ed.undo_push(message="before")
    region, rv3d = viewport()
    center = np.array([region.width / 2, region.height / 2])
    comb, session = start_session(addon, obj)
    states = []
    for stroke in range(2):
        session.begin_stroke()
        session.dab(comb.screen_view(region, rv3d), center, (0.0, 15.0 * (stroke + 1)), 300.0, 1.0, False)
        session.end_stroke()
        states.append(read_comb(obj.data).copy())
    assert not np.array_equal(states[0], states[1])
    # what Blender does when the operator finishes: its own undo step holds the last stroke
    bpy.ops.ed.undo_push(message="Comb")

    bpy.ops.ed.undo()
    np.testing.assert_array_equal(read_comb(bpy.data.objects["Suzanne"].data), states[0])
    bpy.ops.ed.undo()
    np.testing.assert_array_equal(read_comb(bpy.data.objects["Suzanne"].data), 0.0)


def test_screen_projection_matches_blender(addon):
    obj = add_suzanne()
    region, rv3d = viewport()
    from addon.blender import comb

    view = comb.screen_view(region, rv3d)
    world = vertex_array(obj.data.vertices, "co", 3)[::25]
    pixels, w, in_front = view.project(world)
    assert in_front.all()
    moved = view.drag_at_depth((9.0, -4.0), w)
    view_axis = np.array(rv3d.view_matrix.inverted().col[2].xyz)
    for p, delta, xy in zip(world, moved, pixels, strict=True):
        np.testing.assert_allclose(xy, view3d_utils.location_3d_to_region_2d(region, rv3d, p), atol=1e-3)
        # the drag stays in the view plane of the point and moves its projection by the drag
        assert abs(delta @ view_axis) < 1e-6
        np.testing.assert_allclose(
            view3d_utils.location_3d_to_region_2d(region, rv3d, p + delta),
            xy + np.array([9.0, -4.0]),
            atol=1e-3,
        )
        np.testing.assert_allclose(delta, view_plane_drag(region, rv3d, Vector(p), (9.0, -4.0)), rtol=1e-5)


def test_the_sidebar_button_combs_in_the_main_viewport(addon):
    from addon.blender import comb

    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == "VIEW_3D")
    main, rv3d = viewport()
    sidebar = next(r for r in area.regions if r.type == "UI")
    with bpy.context.temp_override(window=window, area=area, region=sidebar):
        assert comb.viewport_region(bpy.context) == (main, rv3d)
    with bpy.context.temp_override(window=window, area=area, region=main):
        assert comb.viewport_region(bpy.context) == (main, rv3d)
    outliner = next(a for a in window.screen.areas if a.type == "OUTLINER")
    with bpy.context.temp_override(window=window, area=outliner, region=outliner.regions[-1]):
        assert comb.viewport_region(bpy.context) == (None, None)
