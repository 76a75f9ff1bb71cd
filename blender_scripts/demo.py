"""The main job on a built-in default: Suzanne with a painted color and comb, through Pelt.

Run with the project's Python (``make demo``): builds Suzanne, paints a default hair color (a
brown gradient, darker at the bottom), a comb pointing down the surface and a length of one, runs
the pipeline as far as it exists (today: checking the mesh in Pelt and baking the default hair
volume), and writes under ``out/demo/``:

- ``suzanne.blend``: the scene with the painted ``pelt_*`` attributes and the ``Pelt …`` images;
- ``shell_atlas.png``, ``tangent_atlas.png``, ``fin.png``: the default hair volume's shell layers
  (4×4 atlas, layer 0 = skin top left), hair tangents and fin texture, saved by Blender;
- ``stats.json``: Pelt's statistics of the mesh and the volume, and the time each step took.
"""

import argparse
import json
import time
from pathlib import Path

import bpy
import numpy as np
from _setup import REPO, register_addon


def paint_defaults(mesh) -> None:
    """Default hair: brown, darker toward the bottom; combed down (object -Z); length 1."""
    n = len(mesh.vertices)
    co = np.empty(3 * n, np.float32)
    mesh.vertices.foreach_get("co", co)
    height = co.reshape(n, 3)[:, 2]
    t = (height - height.min()) / max(float(np.ptp(height)), 1e-6)
    root, tip = np.array([0.12, 0.06, 0.03]), np.array([0.45, 0.28, 0.15])
    color = np.concatenate([root + t[:, None] * (tip - root), np.ones((n, 1))], axis=1)
    mesh.attributes.new("pelt_color", "FLOAT_COLOR", "POINT").data.foreach_set("color", color.ravel())
    comb = np.tile(np.array([0.0, 0.0, -1.0], np.float32), n)
    mesh.attributes.new("pelt_comb", "FLOAT_VECTOR", "POINT").data.foreach_set("vector", comb)
    mesh.attributes.new("pelt_length", "FLOAT", "POINT").data.foreach_set("value", np.ones(n, np.float32))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=REPO / "out" / "demo")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    import pelt

    register_addon()
    from addon import bridge

    bpy.ops.wm.read_factory_settings(use_empty=True)
    timings = {}

    start = time.perf_counter()
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.active_object
    obj.name = "Suzanne"
    paint_defaults(obj.data)
    obj.pelt.enabled = True
    timings["build_and_paint_s"] = time.perf_counter() - start

    start = time.perf_counter()
    if bpy.ops.pelt.check_mesh() != {"FINISHED"}:
        raise SystemExit("pelt.check_mesh did not finish")
    timings["check_mesh_s"] = time.perf_counter() - start
    stats = json.loads(obj.pelt.last_check)

    start = time.perf_counter()
    volume = pelt.bake_volume(pelt.HairParams())
    timings["bake_volume_s"] = time.perf_counter() - start
    images = {
        "shell_atlas": (pelt.pack_atlas(volume["shells"])[0], True),
        "tangent_atlas": (pelt.pack_atlas(volume["tangents"])[0], False),
        "fin": (volume["fin"], True),
    }
    for stem, (pixels, color) in images.items():
        image = bridge.write_image(bpy.data.images, f"Pelt {stem} {obj.name}", pixels, color=color)
        image.filepath_raw = str((args.out / f"{stem}.png").resolve())
        image.file_format = "PNG"
        image.save()

    blend = args.out / "suzanne.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend.resolve()))
    report = {"pelt": pelt.__version__, "threads": pelt.thread_count(), "object": obj.name, "stats": stats}
    report["volume"] = volume["stats"]
    report["timings"] = timings
    (args.out / "stats.json").write_text(json.dumps(report, indent=2) + "\n")

    print(f"pelt {pelt.__version__} demo ({pelt.thread_count()} threads)")
    print(
        "  built Suzanne and painted pelt_color, pelt_comb (down), pelt_length (1) "
        f"on {stats['vertices']} vertices"
    )
    print(
        f"  checked the mesh in Pelt: {stats['faces']} triangles, {stats['edges']} edges, "
        f"{stats['boundary_edges']} boundary edges, {stats['components']} components, "
        f"area {stats['surface_area']:.3f}"
    )
    vs = volume["stats"]
    print(
        f"  baked the default hair volume: {vs['strands']} strands into {vs['layers']} layers of "
        f"{volume['resolution']}² ({vs['trimmed']} trimmed) in {timings['bake_volume_s'] * 1000:.0f} ms"
    )
    print(f"  wrote {blend}, {', '.join(f'{s}.png' for s in images)} and {args.out / 'stats.json'}")


if __name__ == "__main__":
    main()
