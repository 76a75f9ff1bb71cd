# SPDX-License-Identifier: GPL-3.0-or-later
"""The scene's lighting as the preview takes it: the World as spherical harmonics (PRT) and a key
light (Kajiya-Kay), in world space.

- World: an Environment Texture node feeding the Background projects its equirectangular image
  (``pelt.sh_project_equirect``, exact per pixel cell) times the Background strength; otherwise
  the Background color times strength is a constant environment.
- Kajiya-Kay takes the World's mean radiance as its ambient term (a black World adds none).
- Lights: a Sun adds its SH projection (``pelt.sh_project_light``, a cap of its angular
  diameter) times color and strength; point, spot and area lights are taken as directional from
  their position toward the object, with the power that reaches it (watts over 4πd²).
"""

import math

import numpy as np
import pelt

# Equirect size for a constant World (any size projects a constant exactly).
_CONSTANT = (8, 16)


def _background(world):
    """``(color or None, strength, environment image or None)`` of the World's Background node."""
    if world is None:
        return (0.05, 0.05, 0.05), 1.0, None
    if world.node_tree is None:
        return tuple(world.color), 1.0, None
    output = next((n for n in world.node_tree.nodes if n.type == "OUTPUT_WORLD" and n.is_active_output), None)
    links = output.inputs["Surface"].links if output is not None else ()
    background = links[0].from_node if links else None
    if background is None or background.type != "BACKGROUND":
        return (0.0, 0.0, 0.0), 0.0, None
    strength = float(background.inputs["Strength"].default_value)
    color_input = background.inputs["Color"]
    if color_input.links and color_input.links[0].from_node.type == "TEX_ENVIRONMENT":
        image = color_input.links[0].from_node.image
        if image is not None and image.size[0] > 0 and image.size[1] > 0:
            return None, strength, image
    return tuple(color_input.default_value)[:3], strength, None


def _image_rgb(image) -> np.ndarray:
    """``[H, W, 3]`` linear float32, row 0 at the top (Blender stores rows bottom-up)."""
    width, height = image.size
    pixels = np.empty(width * height * 4, np.float32)
    image.pixels.foreach_get(pixels)
    return np.ascontiguousarray(pixels.reshape(height, width, 4)[::-1, :, :3])


def _background_sh(scene, order: int) -> np.ndarray:
    """The World's Background alone as SH ``[order², 3]`` (world space)."""
    color, strength, image = _background(scene.world)
    if image is not None:
        return pelt.sh_project_equirect(_image_rgb(image), order) * strength
    constant = np.broadcast_to(np.asarray(color, np.float32) * strength, (*_CONSTANT, 3))
    return pelt.sh_project_equirect(np.ascontiguousarray(constant), order)


def world_ambient(scene) -> np.ndarray:
    """The World's Background as SH ``[4, 3]`` (bands 0 and 1, world space): the Kajiya-Kay
    ambient, which ``pelt.Preview.render`` takes as ``environment`` (its mean radiance, brighter
    on fur facing where the World is bright)."""
    return _background_sh(scene, 2).astype(np.float32)


def world_sh(scene, order: int, target=(0.0, 0.0, 0.0)) -> np.ndarray:
    """World plus lights as SH ``[order², 3]`` float32 (world space), as seen from ``target``."""
    sh = _background_sh(scene, order)
    for obj in scene.objects:
        if obj.type != "LIGHT" or obj.hide_render:
            continue
        direction, radiance, half_angle = light_arrival(obj, target)
        if radiance is None:
            continue
        sh = sh + np.outer(pelt.sh_project_light(direction, order, half_angle), radiance)
    return sh.astype(np.float32)


def light_arrival(obj, target):
    """``(unit direction toward the light, RGB power per unit area, cone half-angle)`` of a
    light object at ``target``, or ``(None, None, None)`` for a light that gives nothing."""
    light = obj.data
    color = np.asarray(light.color, np.float32)
    if light.type == "SUN":
        z = obj.matrix_world.to_3x3() @ _vector((0.0, 0.0, 1.0))
        direction = _unit(z)
        return direction, color * light.energy, max(0.0, light.angle / 2.0)
    offset = np.asarray(obj.matrix_world.translation) - np.asarray(target, np.float64)
    distance = float(np.linalg.norm(offset))
    if distance < 1e-9 or light.energy <= 0.0:
        return None, None, None
    return tuple(offset / distance), color * light.energy / (4.0 * math.pi * distance**2), 0.0


def key_light(scene, target=(0.0, 0.0, 0.0)):
    """``(direction toward the light, RGB irradiance)`` of the strongest light at ``target``
    (Kajiya-Kay; a sun's strength × color, as ``pelt.Preview.render`` takes it), or a light from
    the upper front when the scene has none."""
    best = None
    for obj in scene.objects:
        if obj.type != "LIGHT" or obj.hide_render:
            continue
        direction, radiance, _ = light_arrival(obj, target)
        if radiance is not None and (best is None or radiance.sum() > best[1].sum()):
            best = (direction, radiance)
    if best is None:
        # A sun of strength π: a white surface facing it shows 1.
        return (0.3, -0.5, 0.8), np.full(3, math.pi, np.float32)
    return best


def _vector(values):
    import mathutils

    return mathutils.Vector(values)


def _unit(vector) -> tuple:
    length = vector.length
    return tuple(vector / length) if length > 0 else (0.0, 0.0, 1.0)
