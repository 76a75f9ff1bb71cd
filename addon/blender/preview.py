# SPDX-License-Identifier: GPL-3.0-or-later
"""See the fur: "Render Preview" renders the scene camera's view of the active object with Pelt's
wgpu renderer into the float image ``Pelt Preview``, scene-linear so that Blender shows it through
the scene's view transform like its own renders (headless too); "Live Preview" (``live_preview``)
draws the same renderer over the 3D viewport. Both draw the object as posed (``pose.py``).

One ``pelt.Preview`` (device + uploaded scene) is kept per object and rebuilt only when a bake
ran a stage; otherwise only the painted colors and lengths are re-sent. Lighting comes from the
World and the lights (``lighting.py``), turned into the object's own frame, where the renderer
works.
"""

import bpy
import numpy as np
import pelt

from ..io import bridge, live
from ..io.names import datablock_name
from ..io.ownership import find_owned, tag
from . import bake, lighting, materials, pose, preferences

PREVIEW_IMAGE = datablock_name("Preview")
PREVIEW_ROLE = "preview"

# session_uid -> (pelt.Preview, the pipeline's `bakes_that_ran` it was built at)
_PREVIEWS: dict = {}


def rotate_sh(coefficients: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """SH coefficients ``[n², 3]`` of ``f`` re-expressed for ``g(d) = f(rotation @ d)``: the
    crate's exact rotation by ``rotationᵀ`` (``pelt.sh_rotate`` turns a lobe along ``d`` to
    ``r @ d``, and ``g``'s lobe along ``d`` is ``f``'s along ``rotation @ d``)."""
    return pelt.sh_rotate(coefficients, np.ascontiguousarray(np.asarray(rotation, np.float64).T))


def object_lighting(scene, obj, model: str, order: int | None) -> dict:
    """The ``lighting`` dict of ``pelt.Preview.render`` for ``obj``: the key light and the World's
    low bands as ambient (Kajiya-Kay) or the World and lights as SH (PRT), both in the object's
    frame."""
    world = obj.matrix_world
    rotation = np.array(world.to_3x3().normalized(), np.float64)
    target = tuple(world.translation)
    if model == "prt" and order:
        environment = lighting.world_sh(scene, order, target)
        # g(d_object) = f(R d_object): the world's radiance seen from the object's frame. The
        # lights are in the SH already: no directional light on top (the renderer's default one
        # would add light the scene does not have).
        return {"model": "prt", "environment": rotate_sh(environment, rotation), "color": (0.0, 0.0, 0.0)}
    direction, color = lighting.key_light(scene, target)
    local = rotation.T @ np.asarray(direction, np.float64)
    return {
        "model": "kajiya-kay",
        "direction": tuple(local),
        "color": tuple(float(c) for c in color),
        "environment": rotate_sh(lighting.world_ambient(scene), rotation),
        # What the Blender materials shade with, so that a render agrees with the preview.
        "diffuse": materials.HAIR_DIFFUSE,
        "self_shadow": materials.SELF_SHADOW,
    }


def preview_of(obj) -> tuple[pelt.Preview, pelt.FurAsset]:
    """The object's preview, rebuilt when a bake of its pipeline ran a stage since it was built
    (this one, or Bake's or an export's before it), else with colors, lengths and fur depth
    updated."""
    job = bake.start_job(obj).start()
    job.wait()
    if job.error is not None:
        raise job.error
    bake.remember(obj.session_uid, job)
    asset = job.asset
    cached = _PREVIEWS.get(obj.session_uid)
    if cached is None or cached[1] != job.bakes_that_ran:
        prefs = preferences.get()
        preview = pelt.Preview(asset, adapter=prefs.adapter if prefs is not None else "auto")
        _PREVIEWS[obj.session_uid] = (preview, job.bakes_that_ran)
    else:
        preview = cached[0]
        mesh = asset.mesh
        preview.update(color=mesh.color, length=mesh.length)
        live.match_fur_depth(preview, asset.fur_depth)
    return preview, asset


def render_options(obj) -> dict:
    """The keyword arguments of ``pelt.Preview.render`` that ``obj``'s settings choose (the fur
    depth is the preview's own, set to the bake's: ``preview_of``, ``live.Request``)."""
    settings = obj.pelt
    return {
        "fins": settings.fins,
        "shell_method": settings.shell_method.lower(),
        "plane_loop_limit": settings.plane_loop_limit,
        "lod": settings.lod,
        "min_shells": min(settings.min_shells, settings.max_shells),
        "max_shells": settings.max_shells,
    }


def render_camera(context, obj) -> np.ndarray:
    """The scene camera's view of ``obj`` at the render resolution: ``[H, W, 4]`` float32,
    scene-linear, straight alpha (Blender's color management displays it)."""
    scene = context.scene
    camera = scene.camera
    if camera is None:
        raise pelt.RenderError("the scene has no camera")
    render = scene.render
    width = max(1, render.resolution_x * render.resolution_percentage // 100)
    height = max(1, render.resolution_y * render.resolution_percentage // 100)
    preview, asset = preview_of(obj)
    depsgraph = context.evaluated_depsgraph_get()
    pose.apply(preview, asset, obj, depsgraph)
    projection = camera.calc_matrix_camera(
        depsgraph, x=width, y=height, scale_x=render.pixel_aspect_x, scale_y=render.pixel_aspect_y
    )
    view = camera.matrix_world.inverted() @ obj.matrix_world
    model = "prt" if obj.pelt.lighting == "PRT" and asset.transfer is not None else "kajiya-kay"
    return preview.render(
        np.array(view, np.float32),
        np.array(projection, np.float32),
        width,
        height,
        lighting=object_lighting(scene, obj, model, preview.transfer_order),
        linear=True,
        **render_options(obj),
    )


class PELT_OT_render_preview(bpy.types.Operator):
    """Render the scene camera's view of the active object's fur with Pelt's real-time renderer
    into the image "Pelt Preview\""""

    bl_idname = "pelt.render_preview"
    bl_label = "Render Preview"
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"

    def execute(self, context):
        obj = context.active_object
        try:
            pixels = render_camera(context, obj)
        except pelt.PeltError as error:
            self.report({"ERROR"}, f"Pelt: {obj.name}: {error}")
            return {"CANCELLED"}
        image = bridge.write_linear_image(
            bpy.data.images, PREVIEW_IMAGE, pixels, image=find_owned(bpy.data.images, obj.name, PREVIEW_ROLE)
        )
        tag(image, obj.name, PREVIEW_ROLE)
        note = pose.NOTES.get(obj.session_uid)
        if note is not None:
            self.report({"WARNING"}, f"Pelt: {obj.name}: {note}")
        self.report({"INFO"}, f"Pelt: rendered {image.name} ({pixels.shape[1]}×{pixels.shape[0]})")
        return {"FINISHED"}


def forget_previews() -> None:
    """Frees Render Preview's devices (the add-on is unregistered)."""
    _PREVIEWS.clear()


CLASSES = (PELT_OT_render_preview,)
