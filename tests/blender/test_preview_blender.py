"""Render Preview from Blender: the scene camera's view of the fur, rendered by Pelt's wgpu
renderer on the CPU adapter into the image "Pelt Preview" (headless)."""

import math

import bpy
import numpy as np
import pytest
from conftest import add_suzanne, datablock_snapshot, small_fur


def furred_suzanne_with_camera(*, prt=False):
    obj = add_suzanne()
    settings = small_fur(obj, fur_depth=0.15)
    settings.lighting = "PRT" if prt else "KAJIYA_KAY"
    settings.prt_auto_order = False
    settings.prt_order = 2
    scene = bpy.context.scene
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0.0, -5.0, 0.0)
    camera.rotation_euler = (math.pi / 2, 0.0, 0.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 96, 80, 100
    return obj


def preview_pixels() -> np.ndarray:
    image = next(im for im in bpy.data.images if im.get("pelt_role") == "preview")
    assert image.name == "Pelt Preview"
    pixels = np.empty(image.size[0] * image.size[1] * 4, np.float32)
    image.pixels.foreach_get(pixels)
    return pixels.reshape(image.size[1], image.size[0], 4)


@pytest.mark.parametrize("prt", [False, True])
def test_render_preview_fills_pelt_preview_with_the_furred_object(addon, prt):
    obj = furred_suzanne_with_camera(prt=prt)
    assert bpy.ops.pelt.render_preview() == {"FINISHED"}
    pixels = preview_pixels()
    assert pixels.shape == (80, 96, 4)
    covered = pixels[..., 3] > 0.5
    # Suzanne, 2.7 units wide at 5 units with the default 50 mm lens (~39.6° across 96 px), is
    # centred: the middle is covered, the corners are background.
    assert covered[40, 48] and not covered[0, 0] and not covered[-1, -1]
    assert 0.1 < covered.mean() < 0.9
    assert np.isfinite(pixels).all()
    # A second render (nothing changed) reuses the device and draws the same picture.
    assert bpy.ops.pelt.render_preview() == {"FINISHED"}
    assert np.array_equal(preview_pixels(), pixels)
    # Bald everywhere: the fur's fringe disappears, the covered area shrinks.
    length = obj.data.attributes.new("pelt_length", "FLOAT", "POINT")
    length.data.foreach_set("value", np.zeros(len(obj.data.vertices), np.float32))
    assert bpy.ops.pelt.render_preview() == {"FINISHED"}
    assert (preview_pixels()[..., 3] > 0.5).sum() < covered.sum()


def test_render_preview_draws_the_shells_as_the_object_asks(addon):
    obj = furred_suzanne_with_camera()
    images = {}
    for method in ("INSTANCED", "MARCHED", "AUTO", "PLANES"):
        obj.pelt.shell_method = method
        assert bpy.ops.pelt.render_preview() == {"FINISHED"}
        images[method] = preview_pixels()
    from addon.blender import preview

    assert not np.array_equal(images["INSTANCED"], images["MARCHED"])
    # The virtual planes: their slices are baked for them (and only for them), and they cover
    # what the shells cover.
    asset = preview.preview_of(obj)[1]
    assert asset.planes is not None and asset.planes["planes"] == obj.pelt.planes
    assert not np.array_equal(images["PLANES"], images["INSTANCED"])
    covered = [(images[m][..., 3] > 0.5).sum() for m in ("INSTANCED", "PLANES")]
    assert abs(covered[0] - covered[1]) <= 0.05 * covered[0], covered
    # Auto marches, on every adapter.
    assert np.array_equal(images["AUTO"], images["MARCHED"])


def test_render_preview_after_bake_draws_the_new_bake(addon):
    # Bake runs the stages in its own job, so the preview's next job finds them all reused: it
    # once kept the scene built from the bake before and drew the old shells (and, after a change
    # of topology, refused to draw: "color must have one row per vertex"). A new fur depth runs
    # no stage at all under Kajiya-Kay, and the preview kept its old depth.
    obj = furred_suzanne_with_camera()
    assert bpy.ops.pelt.render_preview() == {"FINISHED"}
    before = preview_pixels()
    obj.pelt.fur_depth = 0.3
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert bpy.ops.pelt.render_preview() == {"FINISHED"}
    deeper = preview_pixels()
    # Fur twice as deep reaches further out around the head.
    assert (deeper[..., 3] > 0.5).sum() > (before[..., 3] > 0.5).sum()
    # More shells: Bake re-runs the volume, the preview's own job then reuses it.
    obj.pelt.layers = 16
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    assert bpy.ops.pelt.render_preview() == {"FINISHED"}
    assert not np.array_equal(preview_pixels(), deeper)


def test_render_preview_without_a_camera_changes_nothing(addon):
    furred_suzanne_with_camera()
    bpy.context.scene.camera = None
    before = datablock_snapshot()
    with pytest.raises(RuntimeError, match="no camera"):
        bpy.ops.pelt.render_preview()
    assert datablock_snapshot() == before


def test_object_lighting_turns_the_world_into_the_objects_frame(addon):
    from addon.blender import preview

    obj = add_suzanne()
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    bpy.context.scene.collection.objects.link(sun)
    sun.rotation_euler = (0.0, math.pi / 2, 0.0)  # the sun's +Z toward world +X
    obj.rotation_euler = (0.0, 0.0, math.pi / 2)  # object +X is world +Y, object -Y is world +X
    bpy.context.view_layer.update()
    light = preview.object_lighting(bpy.context.scene, obj, "kajiya-kay", None)
    assert np.allclose(light["direction"], (0.0, -1.0, 0.0), atol=1e-6)
    # The same rotation applied to SH: a delta light's projection along world +X becomes the
    # projection along object -Y.
    import pelt

    world = np.outer(pelt.sh_project_light((1.0, 0.0, 0.0), 3), [1.0, 1.0, 1.0])
    rotation = np.array(obj.matrix_world.to_3x3(), np.float64)
    local = preview.rotate_sh(world, rotation)
    expected = np.outer(pelt.sh_project_light((0.0, -1.0, 0.0), 3), [1.0, 1.0, 1.0])
    assert np.allclose(local, expected, atol=1e-4)


def test_a_prt_preview_in_the_dark_is_black(addon):
    # A black World and no light: under PRT every light of the preview comes from the scene's SH,
    # so nothing may light the fur (a default directional light added to the World once made the
    # add-on's PRT preview 36% brighter than its lights).
    furred_suzanne_with_camera(prt=True)
    world = bpy.data.worlds.new("Dark")
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    bpy.context.scene.world = world
    for obj in [o for o in bpy.context.scene.objects if o.type == "LIGHT"]:
        bpy.data.objects.remove(obj)
    assert bpy.ops.pelt.render_preview() == {"FINISHED"}
    pixels = preview_pixels()
    assert (pixels[..., 3] > 0.5).mean() > 0.1
    assert pixels[..., :3].max() < 1e-3, pixels[..., :3].max()


def test_the_preview_is_stored_scene_linear_for_the_view_transform(addon):
    # Blender shows its renders through the scene's view transform; the preview image must hold
    # scene-linear values so that it is shown the same way (an sRGB byte image is shown as is).
    obj = furred_suzanne_with_camera()
    assert bpy.ops.pelt.render_preview() == {"FINISHED"}
    image = next(im for im in bpy.data.images if im.get("pelt_role") == "preview")
    assert image.is_float and not image.colorspace_settings.is_data
    assert image.colorspace_settings.name in ("Linear Rec.709", "Linear")
    from addon.blender import preview

    linear = preview.render_camera(bpy.context, obj)
    assert linear.dtype == np.float32
    np.testing.assert_allclose(preview_pixels(), linear[::-1], atol=1e-6)


def _fur_mean(pixels: np.ndarray, covered: np.ndarray) -> np.ndarray:
    """Mean linear RGB of the covered pixels, made straight (the preview is premultiplied)."""
    return pixels[covered, :3].sum(axis=0) / pixels[covered, 3].sum()


def test_painted_colors_show_as_painted(addon):
    # Painted colors once multiplied the coat's own: Paint Color's starting brown darkened the
    # fur about 7 times, and white paint showed the coat's brown. Now the coat only shades the paint.
    obj = furred_suzanne_with_camera()
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.data.energy = 3.0
    sun.rotation_euler = (math.radians(60), 0.0, math.radians(-20))
    bpy.context.scene.collection.objects.link(sun)
    assert bpy.ops.pelt.render_preview() == {"FINISHED"}
    unpainted = preview_pixels()
    covered = unpainted[..., 3] > 0.5
    coat = _fur_mean(unpainted, covered)

    # A new pelt_color starts in the coat's own color: nothing changes until one paints.
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.pelt.paint_color() == {"FINISHED"}
    bpy.ops.object.mode_set(mode="OBJECT")
    assert bpy.ops.pelt.render_preview() == {"FINISHED"}
    np.testing.assert_allclose(_fur_mean(preview_pixels(), covered), coat, rtol=0.03)

    shown = {}
    for name, paint in (("white", (1.0, 1.0, 1.0)), ("orange", (1.0, 0.45, 0.1))):
        colors = np.tile(np.array([*paint, 1.0], np.float32), (len(obj.data.vertices), 1))
        obj.data.attributes["pelt_color"].data.foreach_set("color", colors.ravel())
        obj.data.update()
        assert bpy.ops.pelt.render_preview() == {"FINISHED"}
        shown[name] = _fur_mean(preview_pixels(), covered)
    # White paint shows white fur (the coat's brown has red twice its blue), brighter than the
    # coat's; orange shows orange: per channel the white fur times the paint (the highlight is
    # the light's color, a few percent of the white fur: that is the tolerance).
    white = shown["white"]
    assert white.max() < 1.1 * white.min(), white
    assert white.mean() > 2.0 * coat.mean(), (white, coat)
    np.testing.assert_allclose(shown["orange"], white * np.array([1.0, 0.45, 0.1]), atol=0.05 * white.mean())
