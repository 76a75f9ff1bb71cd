"""Paint Color, Paint Length and Apply Length Paint through ``bpy.ops`` on real meshes: the
attributes they make (domain, type, values), the active color attribute and the mode, conversions
of attributes of the wrong kind, and refusals that leave everything as it was."""

import bpy
import numpy as np
import pytest
from conftest import add_suzanne, datablock_snapshot


def srgb_to_linear(c):
    c = np.asarray(c, np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def read(mesh, name, prop, columns):
    attribute = mesh.attributes[name]
    values = np.empty(len(attribute.data) * columns, np.float32)
    attribute.data.foreach_get(prop, values)
    return values.reshape(len(attribute.data), columns) if columns > 1 else values


def kind(mesh, name):
    attribute = mesh.attributes[name]
    return attribute.domain, attribute.data_type


def make_active(obj):
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)


def test_paint_color_starts_in_the_coats_color_and_enters_vertex_paint(addon):
    obj = add_suzanne()
    obj.pelt.root_color = (0.3, 0.1, 0.05)
    obj.pelt.tip_color = (0.2, 0.4, 0.1)
    assert bpy.ops.pelt.paint_color() == {"FINISHED"}
    mesh = obj.data
    assert kind(mesh, "pelt_color") == ("POINT", "FLOAT_COLOR")
    # Per channel the brighter end of the coat, which the bake divides the coat by.
    start = np.array([0.3, 0.4, 0.1, 1.0], np.float32)
    np.testing.assert_allclose(read(mesh, "pelt_color", "color", 4), np.tile(start, (len(mesh.vertices), 1)))
    assert mesh.attributes.active_color_name == "pelt_color"
    assert obj.mode == "VERTEX_PAINT"


def test_paint_color_keeps_painted_colors(addon):
    obj = add_suzanne()
    mesh = obj.data
    colors = np.random.default_rng(1).random((len(mesh.vertices), 4)).astype(np.float32)
    mesh.attributes.new("pelt_color", "FLOAT_COLOR", "POINT").data.foreach_set("color", colors.ravel())
    mesh.attributes.new("Col", "FLOAT_COLOR", "POINT")
    mesh.attributes.active_color_name = "Col"
    assert bpy.ops.pelt.paint_color() == {"FINISHED"}
    np.testing.assert_array_equal(read(mesh, "pelt_color", "color", 4), colors)
    assert mesh.attributes.active_color_name == "pelt_color"


def test_paint_color_converts_a_corner_byte_color(addon, capfd):
    obj = add_suzanne()
    mesh = obj.data
    # every corner of a vertex holds that vertex's color, so the per-vertex mean is that color
    per_vertex = np.random.default_rng(2).random((len(mesh.vertices), 4)).astype(np.float32)
    corner_vertex = np.empty(len(mesh.loops), np.int64)
    mesh.loops.foreach_get("vertex_index", corner_vertex)
    attribute = mesh.attributes.new("pelt_color", "BYTE_COLOR", "CORNER")
    attribute.data.foreach_set("color", per_vertex[corner_vertex].ravel())
    stored = read(mesh, "pelt_color", "color", 4)  # as bytes hold them
    expected = np.empty_like(per_vertex)
    expected[corner_vertex] = stored
    capfd.readouterr()
    assert bpy.ops.pelt.paint_color() == {"FINISHED"}
    assert "converted 'pelt_color' from CORNER BYTE_COLOR to POINT FLOAT_COLOR" in capfd.readouterr().out
    assert kind(mesh, "pelt_color") == ("POINT", "FLOAT_COLOR")
    np.testing.assert_allclose(read(mesh, "pelt_color", "color", 4), expected, atol=2e-3)
    assert obj.mode == "VERTEX_PAINT"


def test_paint_color_from_edit_mode(addon):
    obj = add_suzanne()
    bpy.ops.object.mode_set(mode="EDIT")
    assert bpy.ops.pelt.paint_color() == {"FINISHED"}
    assert obj.mode == "VERTEX_PAINT"
    assert kind(obj.data, "pelt_color") == ("POINT", "FLOAT_COLOR")


def test_paint_length_creates_length_and_its_gray_helper(addon):
    obj = add_suzanne()
    assert bpy.ops.pelt.paint_length() == {"FINISHED"}
    mesh = obj.data
    n = len(mesh.vertices)
    assert kind(mesh, "pelt_length") == ("POINT", "FLOAT")
    np.testing.assert_array_equal(read(mesh, "pelt_length", "value", 1), np.ones(n))
    assert kind(mesh, "pelt_length_paint") == ("POINT", "FLOAT_COLOR")
    # length 1 paints mid gray as seen (sRGB 0.5), i.e. linear 0.214
    gray = srgb_to_linear(0.5)
    np.testing.assert_allclose(
        read(mesh, "pelt_length_paint", "color", 4), np.tile([gray, gray, gray, 1.0], (n, 1)), rtol=1e-6
    )
    assert mesh.attributes.active_color_name == "pelt_length_paint"
    assert obj.mode == "VERTEX_PAINT"


def test_painted_grays_become_lengths(addon):
    obj = add_suzanne()
    mesh = obj.data
    assert bpy.ops.pelt.paint_length() == {"FINISHED"}
    n = len(mesh.vertices)
    # what a brush leaves: sRGB grays from black to white, written as Blender stores them (linear)
    seen = np.linspace(0.0, 1.0, n)
    rgba = np.ones((n, 4))
    rgba[:, :3] = srgb_to_linear(seen)[:, None]
    mesh.attributes["pelt_length_paint"].data.foreach_set("color", rgba.astype(np.float32).ravel())
    assert bpy.ops.pelt.apply_length_paint() == {"FINISHED"}
    length = read(mesh, "pelt_length", "value", 1)
    np.testing.assert_allclose(length, 2.0 * seen, atol=1e-5)
    assert length[0] == 0.0  # black is bald
    assert obj.mode == "VERTEX_PAINT"


def test_paint_length_shows_existing_lengths_and_warns_above_white(addon, capfd):
    obj = add_suzanne()
    mesh = obj.data
    n = len(mesh.vertices)
    length = np.linspace(0.0, 3.0, n).astype(np.float32)
    mesh.attributes.new("pelt_length", "FLOAT", "POINT").data.foreach_set("value", length)
    capfd.readouterr()
    assert bpy.ops.pelt.paint_length() == {"FINISHED"}
    assert "lengths above 2 (up to 3)" in capfd.readouterr().out
    linear = read(mesh, "pelt_length_paint", "color", 4)[:, 0]
    np.testing.assert_allclose(linear, srgb_to_linear(np.minimum(length / 2.0, 1.0)), atol=1e-6)
    np.testing.assert_array_equal(read(mesh, "pelt_length", "value", 1), length)  # not touched


def test_paint_length_keeps_unapplied_paint(addon):
    obj = add_suzanne()
    mesh = obj.data
    assert bpy.ops.pelt.paint_length() == {"FINISHED"}
    painted = np.full(4 * len(mesh.vertices), 0.7, np.float32)
    mesh.attributes["pelt_length_paint"].data.foreach_set("color", painted)
    bpy.ops.object.mode_set(mode="OBJECT")
    assert bpy.ops.pelt.paint_length() == {"FINISHED"}
    np.testing.assert_array_equal(read(mesh, "pelt_length_paint", "color", 4).ravel(), painted)


def test_paint_length_converts_a_face_int_length(addon, capfd):
    obj = add_suzanne()
    mesh = obj.data
    mesh.attributes.new("pelt_length", "INT", "FACE").data.foreach_set(
        "value", np.full(len(mesh.polygons), 2)
    )
    capfd.readouterr()
    assert bpy.ops.pelt.paint_length() == {"FINISHED"}
    assert "converted 'pelt_length' from FACE INT to POINT FLOAT" in capfd.readouterr().out
    assert kind(mesh, "pelt_length") == ("POINT", "FLOAT")
    np.testing.assert_allclose(read(mesh, "pelt_length", "value", 1), 2.0)


@pytest.mark.parametrize("operator", ["paint_color", "paint_length", "apply_length_paint"])
def test_refuses_an_object_that_is_not_a_mesh(addon, operator):
    bpy.ops.object.empty_add()
    before = datablock_snapshot()
    with pytest.raises(RuntimeError, match=r"'Empty' is not a mesh \(type EMPTY\)"):
        getattr(bpy.ops.pelt, operator)()
    assert datablock_snapshot() == before
    assert bpy.context.active_object.mode == "OBJECT"


def test_apply_without_painted_length_changes_nothing(addon):
    obj = add_suzanne()
    before = datablock_snapshot()
    with pytest.raises(RuntimeError, match=r"no painted length: use Paint Length first"):
        bpy.ops.pelt.apply_length_paint()
    assert datablock_snapshot() == before
    assert obj.mode == "OBJECT"


def test_hidden_object_is_refused(addon):
    obj = add_suzanne()
    obj.hide_set(True)
    before = datablock_snapshot()
    with pytest.raises(RuntimeError, match=r"is hidden"):
        bpy.ops.pelt.paint_color()
    assert datablock_snapshot() == before
    assert obj.mode == "OBJECT"


def test_string_attribute_of_that_name_is_refused(addon):
    obj = add_suzanne()
    obj.data.attributes.new("pelt_color", "STRING", "POINT")
    before = datablock_snapshot()
    with pytest.raises(RuntimeError, match=r"cannot be converted: rename or remove it"):
        bpy.ops.pelt.paint_color()
    assert datablock_snapshot() == before
    assert obj.mode == "OBJECT"


def test_panel_and_operators_are_registered_with_tooltips(addon):
    assert bpy.types.VIEW3D_PT_pelt_paint_comb.bl_parent_id == "VIEW3D_PT_pelt"
    names = (
        "paint_color",
        "paint_length",
        "apply_length_paint",
        "comb",
        "comb_gravity",
        "comb_smooth",
        "comb_from_curves",
    )
    for name in names:
        rna = getattr(bpy.ops.pelt, name).get_rna_type()
        assert rna.description, name
        for prop in rna.properties:
            if prop.identifier != "rna_type":
                assert prop.description, f"{name}.{prop.identifier}"
        assert {"REGISTER", "UNDO"} <= set(getattr(bpy.types, f"PELT_OT_{name}").bl_options)
