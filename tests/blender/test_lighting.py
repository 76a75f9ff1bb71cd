"""The scene's World and lights as the preview's spherical-harmonic lighting."""

import math

import bpy
import numpy as np
import pelt


def world(color, strength):
    w = bpy.data.worlds.new("World")
    background = w.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*color, 1.0)
    background.inputs["Strength"].default_value = strength
    bpy.context.scene.world = w
    return w


def test_constant_world_is_its_radiance_times_the_integral_of_y00(addon):
    from addon.blender import lighting

    world((0.2, 0.4, 0.6), 2.0)
    sh = lighting.world_sh(bpy.context.scene, 3)
    # ∫ Y00 dω = 4π · 1/(2√π) = 2√π; every other coefficient integrates to zero.
    assert np.allclose(sh[0], np.array([0.4, 0.8, 1.2]) * 2 * math.sqrt(math.pi), rtol=1e-5)
    assert np.abs(sh[1:]).max() < 1e-5


def test_environment_texture_projects_the_image(addon):
    from addon.blender import lighting

    w = world((0, 0, 0), 1.5)
    height, width = 16, 32
    image = bpy.data.images.new("sky", width, height, float_buffer=True)
    top_bright = np.zeros((height, width, 4), np.float32)
    top_bright[: height // 2] = 1.0  # rows top to bottom: the upper hemisphere is lit
    image.pixels.foreach_set(top_bright[::-1].ravel())
    texture = w.node_tree.nodes.new("ShaderNodeTexEnvironment")
    texture.image = image
    w.node_tree.links.new(texture.outputs["Color"], w.node_tree.nodes["Background"].inputs["Color"])
    sh = lighting.world_sh(bpy.context.scene, 2)
    expected = pelt.sh_project_equirect(np.ascontiguousarray(top_bright[..., :3]), 2) * 1.5
    assert np.allclose(sh, expected, atol=1e-6)
    assert sh[2, 0] > 0  # Y10 ~ z: brighter above


def test_a_sun_adds_its_cap_along_its_axis(addon):
    from addon.blender import lighting

    world((0, 0, 0), 0.0)
    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = 3.0
    sun.color = (1.0, 0.5, 0.25)
    sun.angle = 0.0
    obj = bpy.data.objects.new("Sun", sun)
    bpy.context.scene.collection.objects.link(obj)
    obj.rotation_euler = (0.0, math.pi / 2, 0.0)  # its +Z axis turned to +X
    bpy.context.view_layer.update()
    sh = lighting.world_sh(bpy.context.scene, 3)
    expected = np.outer(pelt.sh_project_light((1.0, 0.0, 0.0), 3), [3.0, 1.5, 0.75])
    assert np.allclose(sh, expected, atol=1e-5)
    direction, color = lighting.key_light(bpy.context.scene)
    assert np.allclose(direction, (1, 0, 0), atol=1e-6) and np.allclose(color, [3.0, 1.5, 0.75])


def test_kajiya_kay_takes_the_worlds_low_bands_as_ambient(addon):
    # A preview lit by a sun under a black World once kept the renderer's default ambient (0.12),
    # lighting the fur a sun leaves in shadow (6.8x the reference under a back light). The
    # World's bands 0 and 1 go over as `environment`: its mean radiance and how it changes with
    # the normal.
    from addon.blender import preview

    obj = bpy.data.objects.new("Furred", bpy.data.meshes.new("Furred"))
    bpy.context.scene.collection.objects.link(obj)
    world((0.2, 0.4, 0.6), 2.0)
    light = preview.object_lighting(bpy.context.scene, obj, "kajiya-kay", None)
    environment = np.asarray(light["environment"])
    assert environment.shape == (4, 3) and "ambient" not in light
    mean = environment[0] / np.sqrt(4.0 * np.pi)
    assert np.allclose(mean, (0.4, 0.8, 1.2), rtol=1e-4)
    assert np.abs(environment[1:]).max() < 1e-4 * environment[0].max()
    world((0.0, 0.0, 0.0), 1.0)
    light = preview.object_lighting(bpy.context.scene, obj, "kajiya-kay", None)
    assert not np.asarray(light["environment"]).any()
