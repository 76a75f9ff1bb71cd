"""Cycles' render of the baked fur (the Geometry Nodes shells and fins with Pelt's materials)
against the ground truth: the reference renderer's strands, traced with exact shadows, lit by the
same sun and World; and against the preview of the same view."""

import math

import bpy
import mathutils
import numpy as np
import pelt
import pytest

SIDE = 96
# Rec. 709 luminance weights.
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
# Sun rotations (Blender's, XYZ Euler): from the upper front right, and from the camera's right.
SUNS = {
    "key": (math.radians(50.0), 0.0, math.radians(30.0)),
    "side": (math.radians(90.0), 0.0, math.radians(90.0)),
}
SUN_STRENGTH = 3.0
WORLD = 0.3


def furred_sphere_scene(light: str):
    """A smooth sphere with the image benchmark's fur proportions (tile 0.3, depth 0.15: the
    reference renderer can hold its strands), the add-on's other defaults, seen from the front a
    little above, under a sun and a grey World; baked."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32)
    obj = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    settings = obj.pelt
    settings.enabled = True
    settings.tile_size = 0.3
    settings.fur_depth = 0.15
    scene = bpy.context.scene
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0.0, -5.0, 1.5)
    camera.rotation_euler = (math.radians(73.3), 0.0, 0.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.data.energy = SUN_STRENGTH
    sun.data.angle = 0.0
    sun.rotation_euler = SUNS[light]
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("Grey")
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = WORLD
    scene.world = world
    render = scene.render
    render.resolution_x = render.resolution_y = SIDE
    render.resolution_percentage = 100
    render.film_transparent = True
    scene.view_settings.view_transform = "Standard"
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    return scene, obj, camera, sun


def cycles_image(scene, path) -> np.ndarray:
    """Cycles' linear, premultiplied image, top row first."""
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 16
    scene.cycles.use_denoising = False
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(str(path))
    pixels = np.empty(len(image.pixels), np.float32)
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    return pixels.reshape(SIDE, SIDE, 4)[::-1]


def reference_image(scene, obj, camera, sun) -> np.ndarray:
    """The reference's linear, premultiplied image of the baked asset under the same lights."""
    from addon.blender import lighting, preview

    asset = preview.preview_of(obj)[1]
    depsgraph = bpy.context.evaluated_depsgraph_get()
    projection = np.array(camera.calc_matrix_camera(depsgraph, x=SIDE, y=SIDE), np.float32)
    view = np.array(camera.matrix_world.inverted() @ obj.matrix_world, np.float32)
    toward_sun = tuple(sun.matrix_world.to_3x3() @ mathutils.Vector((0.0, 0.0, 1.0)))
    lights = [
        {"type": "sun", "direction": toward_sun, "strength": SUN_STRENGTH},
        {"type": "environment", "sh": lighting.world_ambient(scene)},
    ]
    image, _ = pelt.render_reference(asset, view, projection, SIDE, SIDE, samples=8, lights=lights)
    return image


def preview_image(obj) -> np.ndarray:
    """The preview's linear image (straight alpha from the add-on), premultiplied."""
    from addon.blender import preview

    image = preview.render_camera(bpy.context, obj)
    return np.concatenate([image[..., :3] * image[..., 3:], image[..., 3:]], axis=-1)


def fur_luminance(image: np.ndarray, covered: np.ndarray) -> float:
    """Mean straight luminance of the ``covered`` pixels of a premultiplied image."""
    return float((image[..., :3] @ LUMINANCE)[covered].sum() / image[..., 3][covered].sum())


@pytest.mark.parametrize("light", ["key", "side"])
def test_cycles_renders_the_fur_as_bright_as_the_strands_it_was_baked_from(addon, tmp_path, light):
    # Cycles once shaded the fins by their own quads' normals and let every shell shadow the ones
    # below, layer by layer: 0.65 (key) and 0.41 (side) of the reference here at 160². The
    # materials now light the fins as hair and darken the shells by the preview's Banks term:
    # 1.03 and 0.91.
    scene, obj, camera, sun = furred_sphere_scene(light)
    cycles = cycles_image(scene, tmp_path / "cycles.exr")
    truth = reference_image(scene, obj, camera, sun)
    shown = preview_image(obj)
    covered = (cycles[..., 3] > 0.5) & (truth[..., 3] > 0.5) & (shown[..., 3] > 0.5)
    assert covered.mean() > 0.25
    to_truth = fur_luminance(cycles, covered) / fur_luminance(truth, covered)
    assert 0.85 < to_truth < 1.15, f"{light}: Cycles / reference = {to_truth:.3f}"
    # The preview at the add-on's defaults (16 layers) is 0.86 (key) and 0.82 (side) of the
    # reference itself; Cycles is held to it within what that leaves.
    to_preview = fur_luminance(cycles, covered) / fur_luminance(shown, covered)
    assert 0.9 < to_preview < 1.3, f"{light}: Cycles / preview = {to_preview:.3f}"
