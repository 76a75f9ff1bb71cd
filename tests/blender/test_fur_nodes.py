"""Pelt's Blender fur (``materials.py``, ``geonodes.py``, ``fur.py`` in ``addon/blender/``) in the
real bpy: the evaluated shells and fins against numpy from the base mesh, the materials, ownership
of the datablocks, and small Cycles / EEVEE renders."""

import functools
import math
import os
import shutil
from pathlib import Path

import bpy
import numpy as np
import pelt
import pytest
from conftest import REPO, datablock_snapshot

OBJECT = "Ball"
TILE = 0.5


@pytest.fixture
def addon(addon):
    """The registered add-on with its fur modules imported (they register no classes)."""
    from addon.blender import fur  # noqa: F401
    from addon.io import bridge, fur_layout, ownership  # noqa: F401

    return addon


@functools.cache
def baked_volume():
    volume = pelt.bake_volume(pelt.HairParams(), layers=8, resolution=32, fin_size=(64, 16))
    atlas, layout = pelt.pack_atlas(volume["shells"])
    return volume, atlas, layout


def furred_sphere(addon, *, segments=16, rings=8, length=None, comb=None, color=None):
    """A UV sphere named ``Ball`` with the painted attributes (``length``, ``comb`` and ``color``
    are functions of the vertex positions; a missing length or comb means Pelt's default),
    ``PeltUV`` and Pelt's images, as a bake leaves it; returns ``(object, images, layout)``."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=segments, ring_count=rings, radius=1.0)
    obj = bpy.context.active_object
    obj.name = OBJECT
    mesh = obj.data
    n = len(mesh.vertices)
    position = read(mesh.vertices, "co", n, 3)
    rgba = np.tile([1.0, 0.8, 0.6, 1.0], (n, 1)) if color is None else color(position)
    mesh.attributes.new("pelt_color", "FLOAT_COLOR", "POINT").data.foreach_set(
        "color", rgba.astype(np.float32).ravel()
    )
    if length is not None:
        values = length(position).astype(np.float32)
        mesh.attributes.new("pelt_length", "FLOAT", "POINT").data.foreach_set("value", values)
    if comb is not None:
        attribute = mesh.attributes.new("pelt_comb", "FLOAT_VECTOR", "POINT")
        attribute.data.foreach_set("vector", comb(position).astype(np.float32).ravel())
    bridge = addon.io.bridge
    patches = pelt.build_patches(bridge.read_mesh(mesh).fur_mesh(), tile_size=TILE, seed=1)
    bridge.write_patches(mesh, patches)
    volume, atlas, layout = baked_volume()
    images = {
        "shells": bridge.write_image(bpy.data.images, f"Pelt Shells {OBJECT}", atlas),
        "fin": bridge.write_image(bpy.data.images, f"Pelt Fin {OBJECT}", volume["fin"]),
    }
    for role, image in images.items():
        addon.io.ownership.tag(image, OBJECT, role)
    return obj, images, layout


def settings_for(addon, layers=None, **rest):
    volume, _, _ = baked_volume()
    layers = volume["layers"] if layers is None else layers
    return addon.io.fur_layout.FurSettings(layers=layers, tile_size=TILE, **{"shells": layers, **rest})


def build(addon, obj, images, layout, settings):
    return addon.blender.fur.build_fur(obj, images, layout, settings)


def evaluated(obj):
    """The modifier's output mesh (a copy that outlives the depsgraph update)."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    return bpy.data.meshes.new_from_object(obj.evaluated_get(depsgraph))


def read(collection, prop, count, columns=1, dtype=np.float32):
    flat = np.empty(count * columns, dtype)
    collection.foreach_get(prop, flat)
    return flat.reshape(count, columns) if columns > 1 else flat


def attribute(mesh, name, prop="value", columns=1):
    data = mesh.attributes[name].data
    return read(data, prop, len(data), columns)


def base_arrays(mesh):
    n = len(mesh.vertices)
    return read(mesh.vertices, "co", n, 3), read(mesh.vertex_normals, "vector", n, 3)


def expected_layers(layers, shells):
    """round(j (L - 1) / (S - 1)), halves up, for shells j = 1..S-1."""
    return [math.floor(j * (layers - 1) / (shells - 1) + 0.5) for j in range(1, shells)]


def face_corners_all_bald(mesh, length):
    vertices = read(mesh.polygons, "vertices", len(mesh.loops), 1, np.int32)  # all corners, flat
    starts = read(mesh.polygons, "loop_start", len(mesh.polygons), 1, np.int32)
    furred = np.maximum.reduceat(length[vertices] > 0, starts)
    return ~furred.astype(bool)


def test_evaluated_mesh_has_skin_shells_and_fins(addon):
    obj, images, layout = furred_sphere(addon)
    base = obj.data
    faces, edges, verts = len(base.polygons), len(base.edges), len(base.vertices)
    settings = settings_for(addon, shells=4)
    build(addon, obj, images, layout, settings)
    out = evaluated(obj)
    assert len(out.polygons) == settings.shells * faces + edges
    # The skin and every shell keep the mesh's vertices; a fin has four of its own.
    assert len(out.vertices) == settings.shells * verts + 4 * edges
    assert out.attributes["pelt_layer"].domain == "POINT"
    assert out.attributes["pelt_fin_uv"].domain == "CORNER"
    assert out.attributes["pelt_fin_uv"].data_type == "FLOAT2"


@pytest.mark.parametrize("shells", [8, 5, 2])
def test_shell_vertices_lift_by_layer_depth_and_length_along_the_normal(addon, shells):
    rng = np.random.default_rng(7)
    obj, images, layout = furred_sphere(addon, length=lambda p: rng.uniform(0.3, 1.7, len(p)))
    position, normal = base_arrays(obj.data)
    length = attribute(obj.data, "pelt_length")
    n = len(position)
    settings = settings_for(addon, layers=8, shells=shells, depth=0.2, fins=False)
    build(addon, obj, images, layout, settings)
    out = evaluated(obj)
    co = read(out.vertices, "co", len(out.vertices), 3)
    layer = attribute(out, "pelt_layer")
    assert len(co) == shells * n
    blocks = co.reshape(shells, n, 3)
    np.testing.assert_allclose(blocks[0], position, atol=1e-6)
    assert np.all(layer[:n] == 0)
    for j, k in enumerate(expected_layers(8, shells), start=1):
        assert np.all(layer[j * n : (j + 1) * n] == k)
        lift = k / 8 * 0.2 * length[:, None] * normal
        np.testing.assert_allclose(blocks[j], position + lift, atol=1e-5)
    assert expected_layers(8, shells)[-1] == 7  # fewer shells keep the full fur depth


def test_modifier_panel_inputs_drive_the_fur(addon):
    obj, images, layout = furred_sphere(addon)
    faces, edges = len(obj.data.polygons), len(obj.data.edges)
    modifier = build(addon, obj, images, layout, settings_for(addon, layers=8, shells=8))
    inputs = {i.name: i.identifier for i in modifier.node_group.interface.items_tree if i.in_out == "INPUT"}
    modifier[inputs["Shells"]] = 3
    modifier[inputs["Fins"]] = False
    obj.update_tag()
    assert len(evaluated(obj).polygons) == 3 * faces
    # More shells than layers draw every layer once.
    modifier[inputs["Shells"]] = 20
    modifier[inputs["Fins"]] = True
    obj.update_tag()
    out = evaluated(obj)
    assert len(out.polygons) == 8 * faces + edges
    assert sorted(set(attribute(out, "pelt_layer"))) == list(range(8))


def test_comb_shears_the_shells_by_its_tangential_part(addon):
    obj, images, layout = furred_sphere(addon, comb=lambda p: np.tile([0.0, 0.0, -0.8], (len(p), 1)))
    position, normal = base_arrays(obj.data)
    comb = attribute(obj.data, "pelt_comb", "vector", 3)
    n = len(position)
    build(addon, obj, images, layout, settings_for(addon, layers=4, shells=4, depth=0.1, fins=False))
    co = read(evaluated(obj).vertices, "co", 4 * n, 3).reshape(4, n, 3)
    growth = normal + comb - normal * np.sum(normal * comb, axis=1, keepdims=True)
    for k in range(1, 4):
        np.testing.assert_allclose(co[k], position + k / 4 * 0.1 * growth, atol=1e-5)


def test_bald_faces_grow_no_shells_and_bald_edges_no_fins(addon):
    # The top cap is bald.
    obj, images, layout = furred_sphere(addon, length=lambda p: np.where(p[:, 2] > 0.1, 0.0, 1.0))
    base = obj.data
    length = attribute(base, "pelt_length")
    bald_faces = face_corners_all_bald(base, length)
    edge_ends = read(base.edges, "vertices", len(base.edges), 2, np.int32)
    furred_edges = int(np.count_nonzero((length[edge_ends] > 0).any(axis=1)))
    assert 0 < bald_faces.sum() < len(base.polygons) and furred_edges < len(base.edges)
    settings = settings_for(addon, shells=4)
    build(addon, obj, images, layout, settings)
    out = evaluated(obj)
    shell_faces = (settings.shells - 1) * int(np.count_nonzero(~bald_faces))
    assert len(out.polygons) == len(base.polygons) + shell_faces + furred_edges


def material_of_faces(mesh):
    index = read(mesh.polygons, "material_index", len(mesh.polygons), 1, np.int32)
    names = np.array([m.name if m else "" for m in mesh.materials])
    return names[index]


def test_shells_use_pelt_fur_and_fins_pelt_fin(addon):
    obj, images, layout = furred_sphere(addon)
    base_faces, edges = len(obj.data.polygons), len(obj.data.edges)
    settings = settings_for(addon, shells=3)
    modifier = build(addon, obj, images, layout, settings)
    names = material_of_faces(evaluated(obj))
    assert list(names[: 3 * base_faces]) == [f"Pelt Fur {OBJECT}"] * (3 * base_faces)
    assert list(names[3 * base_faces :]) == [f"Pelt Fin {OBJECT}"] * edges
    assert modifier.name == "Pelt Fur" and modifier.node_group.name == f"Pelt Fur {OBJECT}"
    fur, fin = bpy.data.materials[f"Pelt Fur {OBJECT}"], bpy.data.materials[f"Pelt Fin {OBJECT}"]
    for material, image in ((fur, images["shells"]), (fin, images["fin"])):
        assert material["pelt_owner"] == OBJECT and material.surface_render_method == "DITHERED"
        textures = [n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeTexImage"]
        assert [t.image for t in textures] == [image]
    assert [n.interpolation for n in fur.node_tree.nodes if n.bl_idname == "ShaderNodeTexImage"] == [
        "Closest"
    ]
    assert modifier.node_group["pelt_owner"] == OBJECT
    # The node group's inputs show in the modifier panel, set from the settings.
    values = {
        i.name: modifier[i.identifier]
        for i in modifier.node_group.interface.items_tree
        if i.in_out == "INPUT" and i.socket_type != "NodeSocketGeometry"
    }
    assert values == pytest.approx(
        {
            "Layers": settings.layers,
            "Shells": 3,
            "Depth": settings.depth,
            "Fins": True,
            "Tile Size": TILE,
            "Bald Skin": True,
        }
    )
    # No slot or material was added to the user's mesh: the materials live on the modifier's output.
    assert len(obj.data.materials) == 0 and len(obj.material_slots) == 0


def test_fins_stand_on_edges_with_their_uv(addon):
    obj, images, layout = furred_sphere(addon)
    position, normal = base_arrays(obj.data)
    base_faces, verts = len(obj.data.polygons), len(obj.data.vertices)
    ends = read(obj.data.edges, "vertices", len(obj.data.edges), 2, np.int32)
    build(addon, obj, images, layout, settings_for(addon, shells=2, depth=0.3))
    out = evaluated(obj)
    co = read(out.vertices, "co", len(out.vertices), 3)
    uv = attribute(out, "pelt_fin_uv", "vector", 2)
    corner_vertex = read(out.loops, "vertex_index", len(out.loops), 1, np.int32)
    starts = read(out.polygons, "loop_start", len(out.polygons), 1, np.int32)[2 * base_faces :]
    assert len(starts) == len(ends)
    starts_u = []
    for fin, (a, b) in zip(starts, ends, strict=True):
        corners = np.arange(fin, fin + 4)
        p, t = co[corner_vertex[corners]], uv[corners]
        root, tip = t[:, 1] == 0.0, t[:, 1] == 1.0
        assert root.sum() == 2 and tip.sum() == 2
        ab = [a, b] if np.allclose(p[root][0], position[a], atol=1e-6) else [b, a]
        np.testing.assert_allclose(p[root], position[ab], atol=1e-6)
        tips = p[tip] if np.allclose(t[tip][0, 0], t[root][0, 0]) else p[tip][::-1]
        np.testing.assert_allclose(tips, position[ab] + 0.3 * normal[ab], atol=1e-5)
        # u runs from a random start along the edge, in tiles; the tip shares its root's u.
        u_root = t[root, 0] if ab == [a, b] else t[root, 0][::-1]
        span = np.linalg.norm(position[b] - position[a]) / TILE
        assert u_root[1] - u_root[0] == pytest.approx(span, abs=1e-5)
        assert sorted(t[tip, 0]) == pytest.approx(sorted(t[root, 0]))
        starts_u.append(u_root[0])
    # Each fin carries the normal of its unsheared plane, edge cross (sum of the ends' normals).
    along = position[ends[:, 1]] - position[ends[:, 0]]
    fin_normal = np.cross(along, normal[ends[:, 0]] + normal[ends[:, 1]])
    fin_normal /= np.linalg.norm(fin_normal, axis=1, keepdims=True)
    stored = attribute(out, "pelt_fin_normal", "vector", 3)[2 * base_faces :]
    np.testing.assert_allclose(stored, fin_normal, atol=1e-5)
    # The random start of each fin spreads over the texture's width.
    assert min(starts_u) >= 0.0 and max(starts_u) <= 1.0 and np.std(starts_u) > 0.15
    assert len(out.vertices) == 2 * verts + 4 * len(ends)


def pelt_counts():
    return {
        name: sorted(d.name for d in getattr(bpy.data, name))
        for name in ("materials", "node_groups", "images")
    }


def test_building_again_replaces_pelt_datablocks(addon):
    obj, images, layout = furred_sphere(addon)
    first = build(addon, obj, images, layout, settings_for(addon, shells=4))
    group, fur = first.node_group, bpy.data.materials[f"Pelt Fur {OBJECT}"]
    before = pelt_counts()
    second = build(addon, obj, images, layout, settings_for(addon, shells=2, fins=False))
    assert pelt_counts() == before
    assert len(obj.modifiers) == 1 and second == obj.modifiers[0]
    assert second.node_group == group and bpy.data.materials[f"Pelt Fur {OBJECT}"] == fur
    assert len(evaluated(obj).polygons) == 2 * len(obj.data.polygons)


def test_users_look_alike_datablocks_are_never_touched(addon):
    user = bpy.data.materials.new(f"Pelt Fur {OBJECT}")
    user.diffuse_color = (0.1, 0.9, 0.1, 1.0)
    user_nodes = sorted(n.name for n in user.node_tree.nodes)
    user_group = bpy.data.node_groups.new(f"Pelt Fur {OBJECT}", "GeometryNodeTree")
    obj, images, layout = furred_sphere(addon)
    other = bpy.data.materials.new("Pelt Fin Other")
    addon.io.ownership.tag(other, "Other", "fin_material")

    modifier = build(addon, obj, images, layout, settings_for(addon, shells=2))
    assert user.name == f"Pelt Fur {OBJECT}" and "pelt_owner" not in user
    assert sorted(n.name for n in user.node_tree.nodes) == user_nodes
    assert tuple(user.diffuse_color) == pytest.approx((0.1, 0.9, 0.1, 1.0))
    assert modifier.node_group != user_group and len(user_group.nodes) == 0
    ours = addon.io.ownership.find_owned(bpy.data.materials, OBJECT, "fur_material")
    assert ours is not user and ours.name.startswith(f"Pelt Fur {OBJECT}.")
    assert set(material_of_faces(evaluated(obj))) == {ours.name, f"Pelt Fin {OBJECT}"}

    fur = addon.blender.fur
    fur.remove_fur(obj, images=True)
    assert (
        bpy.data.materials.get(user.name) == user and bpy.data.node_groups.get(user_group.name) == user_group
    )
    assert bpy.data.materials.get("Pelt Fin Other") == other


def test_remove_fur_leaves_no_pelt_datablock(addon):
    fur = addon.blender.fur
    obj, images, layout = furred_sphere(addon)
    before = datablock_snapshot()
    build(addon, obj, images, layout, settings_for(addon))
    assert datablock_snapshot() != before
    removed = fur.remove_fur(obj)
    assert datablock_snapshot() == before
    assert sorted(removed) == sorted(
        ["modifier Pelt Fur", f"Pelt Fur {OBJECT}", f"Pelt Fur {OBJECT}", f"Pelt Fin {OBJECT}"]
    )
    fur.remove_fur(obj, images=True)
    for collection in (bpy.data.materials, bpy.data.node_groups, bpy.data.images):
        assert addon.io.ownership.all_owned(collection, OBJECT) == []
    assert len(obj.modifiers) == 0 and len(evaluated(obj).polygons) == len(obj.data.polygons)


def test_bad_inputs_raise_before_anything_changes(addon):
    fur = addon.blender.fur
    obj, images, layout = furred_sphere(addon)
    before = datablock_snapshot()
    settings = settings_for(addon)
    with pytest.raises(pelt.InvalidParameterError, match="fin"):
        fur.build_fur(obj, {"shells": images["shells"]}, layout, settings)
    with pytest.raises(pelt.InvalidParameterError, match="columns"):
        fur.build_fur(obj, images, {"rows": 2, "tile": 32}, settings)
    with pytest.raises(pelt.InvalidParameterError, match="render_method"):
        fur.build_fur(obj, images, layout, settings, render_method="OPAQUE")
    lamp = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
    with pytest.raises(pelt.InvalidMeshError):
        fur.build_fur(lamp, images, layout, settings)
    bpy.data.objects.remove(lamp)
    bpy.data.lights.remove(bpy.data.lights["Lamp"])
    assert datablock_snapshot() == before
    with pytest.raises(pelt.InvalidParameterError, match="shells"):
        addon.io.fur_layout.FurSettings(layers=4, shells=5)
    with pytest.raises(pelt.InvalidParameterError, match="depth"):
        addon.io.fur_layout.FurSettings(depth=float("nan"))


def test_atlas_uv_reads_every_layer_from_the_blender_image(addon):
    """The material's atlas lookup (``fur_layout.atlas_uv``) on the atlas as Blender stores it
    (rows bottom-up) returns each layer's texel, even at cell borders."""
    volume, atlas, layout = baked_volume()
    res, layers = volume["resolution"], volume["layers"]
    blender_rows = atlas[::-1]  # what bridge.write_image stores: bottom row first
    texel = (np.arange(res) + 0.5) / res
    u, v = np.meshgrid(texel, texel)  # v runs down the tile (Pelt's rows)
    for tiles in (0.0, 3.0, -2.0):
        for k in range(layers):
            uv = np.stack([u + tiles, v - tiles], axis=-1)
            a = addon.io.fur_layout.atlas_uv(uv, np.full(u.shape, k), layout["columns"], layout["rows"], res)
            x = np.floor(a[..., 0] * layout["width"]).astype(int)
            y = np.floor(a[..., 1] * layout["height"]).astype(int)
            np.testing.assert_array_equal(blender_rows[y, x], volume["shells"][k])
    # Exactly on a tile's border (fract = 0), the lookup stays in its own cell.
    edges = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]])
    for k in range(layers):
        a = addon.io.fur_layout.atlas_uv(edges, np.full(3, k), layout["columns"], layout["rows"], res)
        column, row = k % layout["columns"], k // layout["columns"]
        assert np.all(np.floor(a[:, 0] * layout["columns"]) == column)
        assert np.all(np.floor((1.0 - a[:, 1]) * layout["rows"]) == row)


def test_settings_for_a_trimmed_volume_keep_the_layer_spacing(addon):
    # 6 layers kept of 8 asked for: layer k still sits at k / 8 of the depth asked for.
    settings = addon.io.fur_layout.FurSettings.for_volume({"layers": 6, "layer_spacing": 0.125}, depth=0.4)
    assert (settings.layers, settings.shells) == (6, 6)
    assert settings.depth / settings.layers == pytest.approx(0.4 / 8)


# --- renders -------------------------------------------------------------------------------

EEVEE_ON_REQUEST = pytest.mark.skipif(
    not os.environ.get("PELT_TEST_EEVEE"),
    reason="EEVEE compiles its shaders on the CPU here (about 60 s with llvmpipe): PELT_TEST_EEVEE=1 runs it",
)


def staged_scene(engine: str, size: int, samples: int):
    scene = bpy.context.scene
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    camera.location = (0.0, -4.5, 0.0)
    camera.rotation_euler = (math.pi / 2, 0.0, 0.0)
    scene.camera = camera
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.rotation_euler = (0.8, 0.2, 0.5)
    sun.data.energy = 3.0
    scene.collection.objects.link(sun)
    scene.world = bpy.data.worlds.new("World")
    scene.world.color = (0.3, 0.3, 0.3)
    render = scene.render
    render.engine = engine
    render.resolution_x = render.resolution_y = size
    render.resolution_percentage = 100
    render.film_transparent = True
    if engine == "CYCLES":
        scene.cycles.device = "CPU"
        scene.cycles.samples = samples
        scene.cycles.use_denoising = False
    else:
        scene.eevee.taa_render_samples = samples
    return scene


def render(scene, path: Path) -> np.ndarray:
    """Renders ``scene`` to ``path``; returns its pixels, ``[H, W, 4]`` bottom row first."""
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(str(path))
    pixels = np.empty(len(image.pixels), np.float32)
    image.pixels.foreach_get(pixels)
    size = tuple(image.size)
    bpy.data.images.remove(image)
    return pixels.reshape(size[1], size[0], 4)


def covered(pixels: np.ndarray) -> np.ndarray:
    """Pixels the sphere (and its fur) cover: the film is transparent elsewhere."""
    return pixels[..., 3] > 0.5


def fur_grows_the_silhouette(addon, tmp_path, engine, size, samples):
    fur = addon.blender.fur

    # Painted red above the equator, blue below.
    def color(p):
        return np.where(p[:, 2:] > 0.0, [[1.0, 0.15, 0.15, 1.0]], [[0.15, 0.15, 1.0, 1.0]])

    obj, images, layout = furred_sphere(addon, segments=32, rings=16, color=color)
    bpy.ops.object.shade_smooth()
    scene = staged_scene(engine, size, samples)
    bald = np.count_nonzero(covered(render(scene, tmp_path / "bald.png")))
    settings = settings_for(addon, depth=0.25)
    fur.build_fur(obj, images, layout, settings)
    fur.prepare_scene(scene, settings)
    pixels = render(scene, tmp_path / "fur.png")
    furred = np.count_nonzero(covered(pixels))
    # A bald sphere of radius 1 covers pi r^2 of the frame; fur of depth 0.25 (its tips at up to
    # 1.22 with the top layer at 7/8 depth) grows that disc by well over a quarter.
    assert bald > 0.2 * size * size
    assert furred > 1.25 * bald
    # The painted color tints the fur: the top half (image rows run bottom-up) is red, the bottom blue.
    top, bottom = pixels[size // 2 + 8 :], pixels[: size // 2 - 8]
    red = top[covered(top)][:, :3].mean(axis=0)
    blue = bottom[covered(bottom)][:, :3].mean(axis=0)
    assert red[0] > 2 * red[2] and blue[2] > 2 * blue[0]
    out = REPO / "out"
    out.mkdir(exist_ok=True)
    shutil.copyfile(tmp_path / "fur.png", out / f"fur_{engine.lower()}.png")


def test_cycles_renders_the_fur(addon, tmp_path):
    fur_grows_the_silhouette(addon, tmp_path, "CYCLES", 96, 4)


@EEVEE_ON_REQUEST
def test_eevee_renders_the_fur(addon, tmp_path):
    fur_grows_the_silhouette(addon, tmp_path, "BLENDER_EEVEE", 96, 4)


def test_bald_faces_keep_the_objects_own_materials(addon):
    # A head with its eyes in their own slot, painted bald: the fur's skin covers the furred
    # faces and leaves the eyes their material (the skin once took every face, and the eyes
    # vanished from renders). Without materials of its own, bald faces take the skin too.
    def bald_cap(p):
        return np.where(p[:, 2] > 0.75, 0.0, 1.0)

    obj, images, layout = furred_sphere(addon, length=bald_cap)
    mesh = obj.data
    build(addon, obj, images, layout, settings_for(addon, shells=2))
    base_faces = len(mesh.polygons)
    bald = face_corners_all_bald(mesh, bald_cap(read(mesh.vertices, "co", len(mesh.vertices), 3)))
    assert 0 < bald.sum() < base_faces
    skin = material_of_faces(evaluated(obj))[:base_faces]
    assert set(skin) == {f"Pelt Fur {OBJECT}"}

    body, eyes = bpy.data.materials.new("Body"), bpy.data.materials.new("Eyes")
    mesh.materials.append(body)
    mesh.materials.append(eyes)
    mesh.polygons.foreach_set("material_index", bald.astype(np.int32))
    build(addon, obj, images, layout, settings_for(addon, shells=2))
    skin = material_of_faces(evaluated(obj))[:base_faces]
    assert set(skin[bald]) == {"Eyes"}
    assert set(skin[~bald]) == {f"Pelt Fur {OBJECT}"}


def one_shell_in_cycles(addon, obj, images, layout, *, samples: int):
    """Builds ``obj``'s fur smooth-shaded with one shell and no fins, its material's specular
    lobe off (the base color does not scale it); returns the staged Cycles scene writing EXR."""
    bpy.ops.object.shade_smooth()
    build(addon, obj, images, layout, settings_for(addon, shells=1, fins=False))
    material = bpy.data.materials[addon.blender.materials.fur_material_name(obj)]
    for node in material.node_tree.nodes:
        if node.bl_idname == "ShaderNodeBsdfPrincipled":
            node.inputs["Specular IOR Level"].default_value = 0.0
    scene = staged_scene("CYCLES", 48, samples)
    scene.render.image_settings.file_format = "OPEN_EXR"
    return scene


def test_bald_skin_is_lambertian_with_the_previews_diffuse_coefficient(addon, tmp_path):
    # The preview's and the reference's skin is Lambertian with Kd = HAIR_DIFFUSE under every
    # light; a white bald skin (bald faces grow no shells; white atlas, white paint) renders at
    # HAIR_DIFFUSE of a plain white Principled BSDF on the same sphere, under the sun and the
    # world alike. Before, the skin took no Kd (ratio 1). The specular lobes are off.
    def bald(p):
        return np.zeros(len(p))

    def white(p):
        return np.ones((len(p), 4))

    obj, images, layout = furred_sphere(addon, segments=32, rings=16, length=bald, color=white)
    atlas = images["shells"]
    blank = np.full((atlas.size[1], atlas.size[0], 4), 255, np.uint8)
    addon.io.bridge.write_image(bpy.data.images, atlas.name, blank, image=atlas)
    scene = one_shell_in_cycles(addon, obj, images, layout, samples=16)
    fur = render(scene, tmp_path / "fur.exr")
    plain = bpy.data.materials.new("Plain")
    plain.use_nodes = True
    plain.node_tree.nodes["Principled BSDF"].inputs["Specular IOR Level"].default_value = 0.0
    plain.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    obj.modifiers["Pelt Fur"].show_render = False
    obj.data.materials.clear()
    obj.data.materials.append(plain)
    bare = render(scene, tmp_path / "plain.exr")
    seen = covered(fur) & covered(bare)
    assert seen.sum() > 500
    ratio = fur[seen][:, :3].mean() / bare[seen][:, :3].mean()
    assert ratio == pytest.approx(addon.blender.materials.HAIR_DIFFUSE, rel=0.01)


def test_painted_length_sets_how_much_fur_shadows_the_skin_and_bald_skin_has_none(addon, tmp_path):
    # The material's self-shadowing (the preview's Banks term) reads the painted length that the
    # node group stores: at the skin, hair of length l darkens by 1 - (1 - SELF_SHADOW)^l, so a
    # bald sphere's skin (Bald Skin on: no material of its own) is not darkened and half-length
    # hair darkens it by the square root. Before, every skin was darkened by SELF_SHADOW (ratio 1
    # between bald and furred). The specular lobe, which the base color does not scale, is off.
    materials = addon.blender.materials
    obj, images, layout = furred_sphere(addon, segments=32, rings=16, length=lambda p: np.ones(len(p)))
    scene = one_shell_in_cycles(addon, obj, images, layout, samples=4)
    mean = {}
    for length in (1.0, 0.5, 0.0):
        obj.data.attributes["pelt_length"].data.foreach_set(
            "value", np.full(len(obj.data.vertices), length, np.float32)
        )
        obj.data.update()
        pixels = render(scene, tmp_path / f"skin_{length}.exr")
        mean[length] = pixels[covered(pixels)][:, :3].mean()
    clear = 1.0 - materials.SELF_SHADOW
    assert mean[0.0] / mean[1.0] == pytest.approx(1.0 / clear, rel=0.01)
    assert mean[0.5] / mean[1.0] == pytest.approx(clear**-0.5, rel=0.01)


# --- the hair thins out where the fur's surfaces widen -------------------------------------


def polygon_areas(mesh) -> np.ndarray:
    """Each polygon's area from its corners' positions: half the length of its vector area."""
    co = read(mesh.vertices, "co", len(mesh.vertices), 3)
    corners = co[read(mesh.loops, "vertex_index", len(mesh.loops), 1, np.int32)]
    starts = read(mesh.polygons, "loop_start", len(mesh.polygons), 1, np.int32)
    counts = read(mesh.polygons, "loop_total", len(mesh.polygons), 1, np.int32)
    following = np.arange(len(corners)) + 1
    following[starts + counts - 1] = starts  # each polygon's last corner closes on its first
    vector_area = np.add.reduceat(np.cross(corners, corners[following]), starts)
    return 0.5 * np.linalg.norm(vector_area, axis=1)


def test_shells_and_fins_carry_how_far_they_widen(addon):
    # Lifted along diverging normals, a shell face is wider than its skin face and a fin wider at
    # its tip than at its edge: the faces carry how much, less 1, for the materials to thin their
    # hair by. A fin's tip is its edge lifted by each end's own top: wider by the lift's
    # difference along the edge over the edge's length², as the preview's fin_density has it.
    rng = np.random.default_rng(3)
    obj, images, layout = furred_sphere(addon, length=lambda p: rng.uniform(0.3, 1.7, len(p)))
    position, normal = base_arrays(obj.data)
    top = 0.4 * attribute(obj.data, "pelt_length")[:, None] * normal
    ends = read(obj.data.edges, "vertices", len(obj.data.edges), 2, np.int32)
    faces = len(obj.data.polygons)
    build(addon, obj, images, layout, settings_for(addon, layers=8, shells=3, depth=0.4))
    out = evaluated(obj)
    assert out.attributes["pelt_spread"].domain == "FACE"
    assert out.attributes["pelt_fin_spread"].domain == "FACE"
    area = polygon_areas(out)
    spread = attribute(out, "pelt_spread")
    for j in (1, 2):
        widened = area[j * faces : (j + 1) * faces] / area[:faces] - 1.0
        assert widened.mean() > 0.3
        np.testing.assert_allclose(spread[j * faces : (j + 1) * faces], widened, atol=1e-4)
    along = position[ends[:, 1]] - position[ends[:, 0]]
    lift = top[ends[:, 1]] - top[ends[:, 0]]
    expected = np.sum(lift * along, axis=1) / np.sum(along * along, axis=1)
    assert np.ptp(expected) > 0.5
    np.testing.assert_allclose(attribute(out, "pelt_fin_spread")[3 * faces :], expected, atol=1e-5)


def strip_of_faces(name: str, face_values: np.ndarray):
    """``len(face_values)`` unit squares in a row along x, centered at the origin, facing +z,
    each one's ``face_values`` a face attribute to set; returns the object."""
    n = len(face_values)
    x = np.arange(n + 1) - n / 2.0
    vertices = [(float(v), y, 0.0) for y in (-0.5, 0.5) for v in x]
    faces = [(i, i + 1, n + 2 + i, n + 1 + i) for i in range(n)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def set_attribute(mesh, name, data_type, domain, values):
    prop = {"FLOAT": "value", "FLOAT_VECTOR": "vector", "FLOAT2": "vector", "FLOAT_COLOR": "color"}
    attribute = mesh.attributes.new(name, data_type, domain)
    attribute.data.foreach_set(prop[data_type], np.asarray(values, np.float32).ravel())


def seen_from_above(engine: str, size: int, width: float):
    """``engine`` looking straight down on the origin over ``width`` units, film transparent; 64
    samples, since both let a ray through a surface of alpha a at random, with probability 1 - a."""
    scene = staged_scene(engine, size, 64)
    camera = scene.camera
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = width
    camera.location = (0.0, 0.0, 5.0)
    camera.rotation_euler = (0.0, 0.0, 0.0)
    scene.render.image_settings.file_format = "OPEN_EXR"
    return scene


def half_alpha(addon, image):
    """``image`` rewritten white, every texel's alpha 128 of 255."""
    flat = np.full((image.size[1], image.size[0], 4), 255, np.uint8)
    flat[..., 3] = 128
    addon.io.bridge.write_image(bpy.data.images, image.name, flat, image=image)
    return 128 / 255


@pytest.mark.parametrize("engine", ["CYCLES", pytest.param("BLENDER_EEVEE", marks=EEVEE_ON_REQUEST)])
def test_the_materials_thin_the_hair_where_their_faces_widened(addon, tmp_path, engine):
    # Optical depth -ln(1 - a) over the growth g, held within [1/4, 4] as the preview holds it:
    # alpha 1 - (1 - a)^(1/g). Shell faces widened 0, 1, 3 and -0.5 times (g = 1, 2, 4, 0.5) and
    # a fin widening to twice its edge at the tip. Before, every face showed the texel's alpha.
    materials = addon.blender.materials
    sphere, images, layout = furred_sphere(addon)
    build(addon, sphere, images, layout, settings_for(addon, shells=2))
    sphere.hide_render = True
    a = half_alpha(addon, images["shells"])
    half_alpha(addon, images["fin"])
    grown = np.array([1.0, 2.0, 4.0, 0.5])

    shells = strip_of_faces("Shells", grown - 1.0)
    mesh = shells.data
    set_attribute(mesh, "pelt_spread", "FLOAT", "FACE", grown - 1.0)
    set_attribute(mesh, "pelt_layer", "FLOAT", "POINT", np.ones(len(mesh.vertices)))
    set_attribute(mesh, "pelt_color", "FLOAT_COLOR", "POINT", np.ones((len(mesh.vertices), 4)))
    uv = mesh.uv_layers.new(name="PeltUV")
    uv.data.foreach_set("uv", np.full(2 * len(mesh.loops), 0.5, np.float32))
    mesh.materials.append(bpy.data.materials[materials.fur_material_name(sphere)])
    scene = seen_from_above(engine, 64, 4.0)
    pixels = render(scene, tmp_path / "shells.exr")
    # Each face's inner 10 by 10 pixels (16 to a face), left to right.
    inner = pixels[27:37, :, 3].reshape(10, 4, 16)[:, :, 3:13]
    np.testing.assert_allclose(inner.mean(axis=(0, 2)), 1.0 - (1.0 - a) ** (1.0 / grown), atol=0.015)

    shells.hide_render = True
    fin = strip_of_faces("Fin", np.zeros(1))
    mesh = fin.data
    set_attribute(mesh, "pelt_fin_spread", "FLOAT", "FACE", [1.0])
    set_attribute(mesh, "pelt_fin_normal", "FLOAT_VECTOR", "FACE", [0.0, 0.0, 1.0])
    set_attribute(mesh, "pelt_growth", "FLOAT_VECTOR", "POINT", np.tile([0.0, 1.0, 0.0], (4, 1)))
    set_attribute(mesh, "pelt_color", "FLOAT_COLOR", "POINT", np.ones((4, 4)))
    corners = read(mesh.loops, "vertex_index", len(mesh.loops), 1, np.int32)
    v = read(mesh.vertices, "co", 4, 3)[corners, 1] + 0.5  # 0 at the root (y = -0.5), 1 at the tip
    set_attribute(mesh, "pelt_fin_uv", "FLOAT2", "CORNER", np.stack([np.full(4, 0.3), v], axis=1))
    mesh.materials.append(bpy.data.materials[materials.fin_material_name(sphere)])
    scene.camera.data.ortho_scale = 1.0
    pixels = render(scene, tmp_path / "fin.exr")
    # Bands of 8 rows, bottom (the root, v = 0) to top; the outer pixels blend with the film.
    seen = pixels[:, 2:62, 3].reshape(8, 8 * 60).mean(axis=1)
    height = (np.arange(8) + 0.5) / 8
    np.testing.assert_allclose(seen, 1.0 - (1.0 - a) ** (1.0 / (1.0 + height)), atol=0.015)
