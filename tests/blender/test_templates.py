"""Pelt's shipped node trees (``addon/blender/templates.py``): the copies a bake appends equal the trees the
code builds, a first bake takes them instead of building, and stale templates or trees baked by
older code are replaced by fresh ones without leaving anything behind."""

import bpy
import numpy as np
import pelt
import pytest
from conftest import datablock_snapshot


@pytest.fixture
def modules(addon):
    from addon.blender import fur, geonodes, materials, templates
    from addon.io import fur_layout, ownership

    assert templates.PATH.is_file(), f"{templates.PATH} is missing: `make setup` writes it"
    return fur, fur_layout, geonodes, materials, ownership, templates


def describe(tree) -> tuple:
    """Everything that makes a node tree what it is: each node's type, name, settings and unlinked
    input values, and every link."""

    def value(socket):
        v = getattr(socket, "default_value", None)
        if v is None or isinstance(v, (bpy.types.ID, str, bool, int, float)):
            return repr(v)
        return repr([round(x, 7) for x in v])

    nodes = []
    for node in tree.nodes:
        settings = tuple(
            (prop, repr(getattr(node, prop)))
            for prop in ("operation", "data_type", "domain", "input_type", "mode", "attribute_name", "uv_map")
            if hasattr(node, prop)
        )
        unlinked = [s for s in node.inputs if not s.is_linked and not s.is_unavailable]
        inputs = tuple((s.identifier, value(s)) for s in unlinked)
        nodes.append((node.name, node.bl_idname, settings, inputs))
    links = sorted(
        (link.from_node.name, link.from_socket.identifier, link.to_node.name, link.to_socket.identifier)
        for link in tree.links
    )
    return tuple(sorted(nodes)), tuple(links)


def test_templates_equal_the_trees_the_code_builds(modules):
    fur, _, _, _, _, templates = modules
    for role, build in fur.template_builders().items():
        collection = getattr(bpy.data, templates.ROLES[role][0])
        built = build("built")
        missing = f"{role}: no template"
        copy = templates.fresh(role, "copied", build=lambda name, missing=missing: pytest.fail(missing))
        tree = lambda block: block if isinstance(block, bpy.types.NodeTree) else block.node_tree  # noqa: E731
        assert len(tree(copy).nodes) > 10
        assert describe(tree(copy)) == describe(tree(built)), role
        if role == "fur_nodes":
            sockets = lambda g: [(i.name, i.in_out, i.socket_type) for i in g.interface.items_tree]  # noqa: E731
            assert sockets(copy) == sockets(built) and copy.is_modifier
        assert not copy.use_fake_user and templates.TEMPLATE not in copy
        collection.remove(built)
        collection.remove(copy)
    assert len(bpy.data.libraries) == 0


def furred_cube(fur_layout):
    bpy.ops.mesh.primitive_cube_add()
    obj = bpy.context.active_object
    volume = pelt.bake_volume(pelt.HairParams(), layers=4, resolution=16, fin_size=(32, 8))
    atlas, layout = pelt.pack_atlas(volume["shells"])
    images = {
        "shells": bpy.data.images.new("atlas", atlas.shape[1], atlas.shape[0], alpha=True),
        "fin": bpy.data.images.new("fin", 32, 8, alpha=True),
    }
    settings = fur_layout.FurSettings(layers=4, shells=4, tile_size=0.5)
    return obj, images, layout, settings


def test_first_bake_copies_the_templates_and_sets_the_object_values(modules, monkeypatch):
    fur, fur_layout, geonodes, materials, _, _ = modules
    obj, images, layout, settings = furred_cube(fur_layout)
    for name in ("new_fur_material", "new_fin_material"):
        monkeypatch.setattr(materials, name, lambda _: pytest.fail("built instead of copied"))
    monkeypatch.setattr(geonodes, "new_node_group", lambda _: pytest.fail("built instead of copied"))
    modifier = fur.build_fur(obj, images, layout, settings, fin_height=8)

    fur_material = bpy.data.materials[f"Pelt Fur {obj.name}"]
    fin_material = bpy.data.materials[f"Pelt Fin {obj.name}"]
    nodes = fur_material.node_tree.nodes
    assert nodes[materials.ATLAS_NODE].image == images["shells"]
    assert nodes[materials.COLUMNS_NODE].outputs[0].default_value == layout["columns"]
    assert nodes[materials.ROWS_NODE].outputs[0].default_value == layout["rows"]
    assert np.isclose(nodes[materials.INSET_NODE].outputs[0].default_value, 0.5 / layout["tile"])
    assert fin_material.node_tree.nodes[materials.FIN_NODE].image == images["fin"]
    fin_inset = fin_material.node_tree.nodes[materials.FIN_INSET_NODE].outputs[0].default_value
    assert np.isclose(fin_inset, 0.5 / 8)
    group = modifier.node_group
    assert group.name == f"Pelt Fur {obj.name}"
    assert group.nodes[geonodes.SKIN_MATERIAL_NODE].inputs["Material"].default_value == fur_material
    assert group.nodes[geonodes.FIN_MATERIAL_NODE].inputs["Material"].default_value == fin_material
    assert not any("Template" in block.name for block in [*bpy.data.materials, *bpy.data.node_groups])
    assert len(bpy.data.libraries) == 0


def test_stale_templates_are_built_instead(modules, monkeypatch):
    fur, fur_layout, _, _, _, templates = modules
    obj, images, layout, settings = furred_cube(fur_layout)
    # Templates written by other sources than these are not used (nor left behind).
    monkeypatch.setattr(templates, "SIGNATURE", "other sources")
    before = datablock_snapshot()
    fur.build_fur(obj, images, layout, settings)
    after = datablock_snapshot()
    added = [f"Pelt Fur {obj.name}", f"Pelt Fin {obj.name}"]
    assert after["materials"] == sorted([*before["materials"], *added])
    assert after["node_groups"] == [f"Pelt Fur {obj.name}"]
    assert after["libraries"] == []


def test_trees_baked_by_older_code_are_replaced_in_place(modules):
    fur, fur_layout, geonodes, _, ownership, _ = modules
    obj, images, layout, settings = furred_cube(fur_layout)
    modifier = fur.build_fur(obj, images, layout, settings)
    material = bpy.data.materials[f"Pelt Fur {obj.name}"]
    material.name = "Renamed by the user"
    material[ownership.BUILT] = "older code"
    material.node_tree.nodes.clear()
    modifier.node_group[ownership.BUILT] = "older code"
    obj.data.materials.append(material)
    before = datablock_snapshot()

    fur.build_fur(obj, images, layout, settings)
    assert datablock_snapshot() == before
    fresh = bpy.data.materials["Renamed by the user"]
    assert len(fresh.node_tree.nodes) > 10 and fresh.node_tree.nodes["Pelt Atlas"].image == images["shells"]
    assert obj.data.materials[0] == fresh, "the object's material slot follows the fresh material"
    group = geonodes.find_modifier(obj).node_group
    assert group.nodes[geonodes.SHELL_MATERIAL_NODE].inputs["Material"].default_value == fresh
    assert ownership.is_owned(fresh, obj.name, "fur_material")


@pytest.mark.parametrize("content", [None, b"not a .blend file"])
def test_a_missing_or_corrupt_template_file_falls_back_to_building(modules, monkeypatch, tmp_path, content):
    fur, fur_layout, _, materials, _, templates = modules
    path = tmp_path / "node_templates.blend"
    if content is not None:
        path.write_bytes(content)
    monkeypatch.setattr(templates, "PATH", path)
    obj, images, layout, settings = furred_cube(fur_layout)
    modifier = fur.build_fur(obj, images, layout, settings)
    material = bpy.data.materials[f"Pelt Fur {obj.name}"]
    assert material.node_tree.nodes[materials.ATLAS_NODE].image == images["shells"]
    assert modifier.node_group is not None and len(modifier.node_group.nodes) > 10
    assert len(bpy.data.libraries) == 0
