"""The main job on a built-in default: Suzanne with a painted color and comb, through Pelt.

Run with the project's Python (``make demo``). Does the artist's whole flow headless, through the
add-on's operators: builds Suzanne, paints a default hair color (a brown gradient, darker at the
bottom) and length, combs the hair down with gravity, bakes (patches, hair volume, PRT transfer)
and writes under ``out/demo/``:

- ``demo.blend``: the scene with the painted ``pelt_*`` attributes, ``PeltUV``, ``pelt_patch``,
  the ``Pelt …`` images (packed) and the fur material and modifier;
- ``patches.png``: Suzanne from the front, faces colored by patch, hair direction drawn;
- ``shell_atlas.png``, ``tangent_atlas.png``, ``fin.png``: the hair volume's shell layers (atlas,
  layer 0 = skin top left), hair tangents and fin texture;
- ``transfer_K.exr`` / ``transfer_K.png`` + ``transfer.json``: the precomputed radiance transfer
  of that volume (order chosen by band selection), 4 SH coefficients per RGBA texture, each as a
  layer atlas in float16 and in 8 bits with the per-coefficient scale and bias of the sidecar;
- ``relit.png``: the volume seen from the side (layers bottom to top) lit through the transfer by
  a light from +x, +y, −x and −y at 30° elevation, left to right;
- ``preview.png``: Pelt's real-time renderer (wgpu, PRT lighting from the World and the sun) from
  the scene camera, as "Render Preview" writes it into the image ``Pelt Preview``;
- ``cycles.png``: one Cycles frame of the fur as Blender itself renders it (the Geometry Nodes
  shells and fins with Pelt's materials), from the front;
- ``stats.json``: Pelt's statistics of the mesh, the bake's stage report and timings.
"""

import argparse
import json
import math
import time
from pathlib import Path

import bpy
import numpy as np
from _setup import REPO, register_addon


def paint_defaults(mesh) -> None:
    """Default paint: a warm brown, darker toward the bottom (painted colors show as painted; the
    coat's root and tip colors only shade them); combed down (object -Z); length 1."""
    n = len(mesh.vertices)
    co = np.empty(3 * n, np.float32)
    mesh.vertices.foreach_get("co", co)
    height = co.reshape(n, 3)[:, 2]
    t = (height - height.min()) / max(float(np.ptp(height)), 1e-6)
    root, tip = np.array([0.3, 0.19, 0.11]), np.array([0.62, 0.42, 0.24])
    color = np.concatenate([root + t[:, None] * (tip - root), np.ones((n, 1))], axis=1)
    mesh.attributes.new("pelt_color", "FLOAT_COLOR", "POINT").data.foreach_set("color", color.ravel())
    comb = np.tile(np.array([0.0, 0.0, -1.0], np.float32), n)
    mesh.attributes.new("pelt_comb", "FLOAT_VECTOR", "POINT").data.foreach_set("vector", comb)
    mesh.attributes.new("pelt_length", "FLOAT", "POINT").data.foreach_set("value", np.ones(n, np.float32))


def srgb_to_linear(c: np.ndarray) -> np.ndarray:
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def relit_side_view(volume: dict, coefficients: np.ndarray, light: np.ndarray) -> np.ndarray:
    """The shells lit by ``light`` (SH coefficients) through the transfer, composited along +y
    front to back: ``[L·s, R, 3]`` linear, the top layer first, each layer ``s = R / L`` rows."""
    shells = volume["shells"].astype(np.float32) / 255.0
    radiance = np.maximum(coefficients @ light, 0.0)
    color = srgb_to_linear(shells[..., :3]) * radiance[..., None]
    alpha = shells[..., 3]
    layers, res = alpha.shape[:2]
    seen = np.zeros((layers, res, 3), np.float32)
    through = np.ones((layers, res), np.float32)
    for y in range(res):
        a = alpha[:, y, :]
        seen += (through * a)[..., None] * color[:, y, :]
        through *= 1.0 - a
    return np.repeat(seen[::-1], max(1, res // layers), axis=0)


def write_transfer(pelt, volume: dict, transfer: dict, out: Path) -> None:
    """The transfer's textures and the four relit side views."""
    for k in range(transfer["packed_f16"].shape[0]):
        pelt.save_exr(out / f"transfer_{k}.exr", pelt.pack_atlas(transfer["packed_f16"][k])[0])
        pelt.save_png(out / f"transfer_{k}.png", pelt.pack_atlas(transfer["packed_u8"][k])[0], srgb=False)
    (out / "transfer.json").write_text(transfer["sidecar"] + "\n")

    views = []
    for azimuth in (0.0, 90.0, 180.0, 270.0):
        a, e = np.radians(azimuth), np.radians(30.0)
        light = pelt.sh_project_light(
            (np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)), transfer["order"]
        )
        views.append(relit_side_view(volume, transfer["coefficients"], light))
    exposure = 1.0 / max(float(np.percentile(np.concatenate(views, axis=1), 99.5)), 1e-6)
    gap = np.zeros((views[0].shape[0], 4, 3), np.float32)
    picture = np.concatenate([x for v in views for x in (v * exposure, gap)][:-1], axis=1)
    encoded = np.where(
        picture <= 0.0031308, 12.92 * picture, 1.055 * np.clip(picture, 0, 1) ** (1 / 2.4) - 0.055
    )
    rgba = np.concatenate([encoded, np.ones((*encoded.shape[:2], 1))], axis=2)
    pelt.save_png(out / "relit.png", (np.clip(rgba, 0, 1) * 255 + 0.5).astype(np.uint8))


def stage_scene(scene) -> None:
    """A camera in front of Suzanne (she looks down −Y), a warm sun from the upper left and a dim
    sky: for the Cycles frame and the preview."""
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0.0, -4.2, 0.35)
    camera.rotation_euler = (math.radians(87.0), 0.0, 0.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.data.energy = 5.0
    sun.data.color = (1.0, 0.95, 0.85)
    sun.rotation_euler = (math.radians(50.0), math.radians(-35.0), math.radians(-20.0))
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("World")
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.25, 0.3, 0.4, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.6
    scene.world = world


def render_cycles(scene, path: Path, size: int, samples: int) -> None:
    """One Cycles frame (CPU) of the Geometry Nodes fur."""
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)


def timed(timings: dict, key: str, operator, **properties) -> None:
    start = time.perf_counter()
    if operator(**properties) != {"FINISHED"}:
        raise SystemExit(f"{key} did not finish")
    timings[key] = time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=REPO / "out" / "demo")
    parser.add_argument("--cycles-size", type=int, default=320, help="side of the Cycles frame")
    parser.add_argument("--cycles-samples", type=int, default=16, help="samples of the Cycles frame")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    import pelt

    addon = register_addon()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    timings = {}

    start = time.perf_counter()
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.active_object
    obj.name = "Suzanne"
    bpy.ops.object.shade_smooth()
    paint_defaults(obj.data)
    timings["build_and_paint_s"] = time.perf_counter() - start

    timed(timings, "check_mesh_s", bpy.ops.pelt.check_mesh)
    stats = json.loads(obj.pelt.last_check)
    timed(timings, "comb_gravity_s", bpy.ops.pelt.comb_gravity, strength=1.0)
    bpy.ops.pelt.apply_preset(preset="MINK")
    settings = obj.pelt
    settings.enabled = True
    settings.lighting = "PRT"
    settings.tile_size = 0.1
    settings.fur_depth = 0.08
    settings.root_color = (0.12, 0.07, 0.04)
    settings.tip_color = (0.62, 0.42, 0.24)
    timed(timings, "bake_s", bpy.ops.pelt.bake)
    bake_report = json.loads(settings.last_bake)

    # The asset of that bake: the cached pipeline answers at once (every stage reused).
    asset = addon.blender.bake.start_job(obj).start()
    asset.wait()
    asset = asset.asset
    fur = asset.mesh
    patches = asset.patches
    volume = asset.volume
    transfer = asset.transfer
    pelt.save_png(args.out / "patches.png", patches.picture(fur, width=768, height=768))
    pelt.save_png(args.out / "shell_atlas.png", pelt.pack_atlas(volume["shells"])[0])
    pelt.save_png(args.out / "tangent_atlas.png", pelt.pack_atlas(volume["tangents"])[0], srgb=False)
    pelt.save_png(args.out / "fin.png", volume["fin"])
    write_transfer(pelt, volume, transfer, args.out)

    scene = bpy.context.scene
    stage_scene(scene)
    layers = volume["layers"]
    addon.blender.fur.prepare_scene(scene, addon.io.fur_layout.FurSettings(layers=layers, shells=layers))
    start = time.perf_counter()
    render_cycles(scene, (args.out / "cycles.png").resolve(), args.cycles_size, args.cycles_samples)
    timings["cycles_frame_s"] = time.perf_counter() - start

    scene.render.resolution_x = scene.render.resolution_y = args.cycles_size
    scene.render.resolution_percentage = 100
    timed(timings, "render_preview_s", bpy.ops.pelt.render_preview)
    preview = next(im for im in bpy.data.images if im.get("pelt_role") == "preview")
    # Scene-linear: saved through the scene's view transform, as Blender saves its renders.
    preview.save_render(str((args.out / "preview.png").resolve()), scene=scene)

    blend = args.out / "demo.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend.resolve()))
    report = {"pelt": pelt.__version__, "threads": pelt.thread_count(), "object": obj.name, "stats": stats}
    report["patches"] = {k: v for k, v in patches.quality.items() if isinstance(v, (int, float))}
    report["volume"] = volume["stats"]
    report["transfer"] = {"order": transfer["order"], "bands": transfer["bands"]}
    report["bake"] = bake_report["stages"]
    report["timings"] = timings
    (args.out / "stats.json").write_text(json.dumps(report, indent=2) + "\n")

    print(f"pelt {pelt.__version__} demo ({pelt.thread_count()} threads)")
    print(
        f"  built Suzanne ({stats['vertices']} vertices, {stats['faces']} triangles, "
        f"{stats['components']} components), painted pelt_color and pelt_length, combed down "
        f"(gravity) in {timings['comb_gravity_s'] * 1000:.0f} ms"
    )
    for stage in bake_report["stages"]:
        print(f"  bake: {stage['stage']:<9} {stage['seconds']:6.2f} s  {stage['summary']}")
    q = patches.quality
    print(
        f"  patches: alignment {q['mean_alignment_deg']:.2f}°, "
        f"stretch ok on {q['stretch_within_fraction']:.1%}, {q['flipped_faces']} flipped, "
        f"seams {q['seam_length_fraction']:.1%}"
    )
    chosen = next(row for row in transfer["bands"] if row["order"] == transfer["order"])
    print(f"  transfer: order {transfer['order']} by band selection (error {chosen['error']:.2%})")
    print(f"  rendered the wgpu preview (PRT) in {timings['render_preview_s']:.2f} s: preview.png")
    print(f"  rendered the Geometry Nodes fur with Cycles in {timings['cycles_frame_s']:.1f} s: cycles.png")
    print(f"  wrote {blend} and the images, transfer_*.exr/png, relit.png, stats.json in {args.out}")


if __name__ == "__main__":
    main()
