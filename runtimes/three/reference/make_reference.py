"""The wgpu preview's picture of a skinned, animated, furred character, for the three.js runtime's
browser test to compare with.

Bakes Blender's Suzanne (Pelt's Python API, Kajiya–Kay lighting), binds it to a three-node
skeleton whose head nods, exports it in `engine` mode (the `PELT_shell_fur` extension), poses
the preview at the test's time by linear blend skinning computed here from the same skeleton, and
renders it with the test's camera and light. Writes, into the folder given:

- `character.glb`: the export the browser loads;
- `scene.json`: time, image size, camera (view and projection, column-major, OpenGL clip
  space), light (the preview's Kajiya–Kay parameters, object space = world space here);
- `preview.png`: the preview's frame (sRGB) on black (the coat painted bald on one side);
- `strands_character.glb`, `strands_scene.json`, `strands_preview.png`: the same with a longer
  coat whose guard hairs are strands (the runtime's ribbons against the preview's strands);
- `prt_character.glb`, `prt_scene.json`, `prt_preview.png`: the painted coat with its transfer,
  lit by PRT (a sun and a uniform sky);
- `thin_character.glb`, `thin_scene.json`, `thin_preview.png`: a small sphere under a coat half
  its radius deep, whose shells spread up to 2.25 times their skin's area (the hair thins by as
  much, in both renderers).

Run with the project's virtual environment: `python make_reference.py OUT_DIR`.
"""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pelt

TIME = 0.5  # seconds: the nod at its deepest
SIZE = 384
NOD = 0.5  # radians


def blender_mesh(add, **options):
    """A Blender primitive (``add``, a ``bpy.ops.mesh`` operator's name): float32 positions and
    uint32 loop triangles."""
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    getattr(bpy.ops.mesh, add)(**options)
    mesh = bpy.context.active_object.data
    mesh.calc_loop_triangles()
    positions = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", positions)
    triangles = np.empty(3 * len(mesh.loop_triangles), np.uint32)
    mesh.loop_triangles.foreach_get("vertices", triangles)
    return positions.reshape(-1, 3), triangles.reshape(-1, 3)


def translation(x, y, z):
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def rotation_x(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def skeleton():
    """Root at the origin, a neck below the head, the head above it nodding about x."""
    names = ["Root", "Neck", "Head"]
    parents = [-1, 0, 1]
    rest = np.stack([np.eye(4), translation(0, 0, -0.6), translation(0, 0, 0.6)])
    times = np.array([0.0, 0.5, 1.0], np.float32)
    poses = np.stack([rest.copy() for _ in times])
    for k, t in enumerate(times):
        poses[k, 2] = rest[2] @ rotation_x(NOD * math.sin(math.pi * t))
    return names, parents, rest, times, poses


def world(locals_, parents):
    out = np.empty_like(locals_)
    for j, parent in enumerate(parents):
        out[j] = locals_[j] if parent < 0 else out[parent] @ locals_[j]
    return out


def look_at(eye, target, up):
    """The view matrix (world to view, camera looking down −z), OpenGL convention."""
    eye, target, up = (np.asarray(v, float) for v in (eye, target, up))
    f = target - eye
    f /= np.linalg.norm(f)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = s, u, -f
    view[:3, 3] = -view[:3, :3] @ eye
    return view


def perspective(fov_y, aspect, near, far):
    f = 1.0 / math.tan(fov_y / 2)
    return np.array(
        [
            [f / aspect, 0, 0, 0],
            [0, f, 0, 0],
            [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
            [0, 0, -1, 0],
        ]
    )


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    positions, triangles = blender_mesh("primitive_monkey_add")
    write_scene(out, "", positions, triangles, guard_hairs=False)
    write_scene(out, "strands_", positions, triangles, guard_hairs=True)
    write_scene(out, "prt_", positions, triangles, guard_hairs=False, prt=True)
    positions, triangles = blender_mesh("primitive_ico_sphere_add", subdivisions=4, radius=THIN_RADIUS)
    write_scene(out, "thin_", positions, triangles, guard_hairs=False, fur_depth=THIN_RADIUS / 2)


# The PRT scene's sky: a uniform radiance (linear RGB), and the sun's cap radius.
PRT_SKY = 0.15
PRT_LIGHT_RADIUS = 0.2
# The thinning scene's sphere radius (its fur is half as deep).
THIN_RADIUS = 0.5


def write_scene(
    out: Path,
    prefix: str,
    positions,
    triangles,
    *,
    guard_hairs: bool,
    prt: bool = False,
    fur_depth: float | None = None,
) -> None:
    """The scene's files under ``out``, named with ``prefix``: with ``guard_hairs``, a longer coat
    whose guard hairs are strands (the preview composites them in its "depth" order, as the
    three.js runtime draws them); with ``prt``, the coat's transfer baked and PRT lighting; with
    ``fur_depth``, a coat that deep and unpainted (length 1 everywhere)."""
    count = len(positions)
    comb = np.tile(np.array([0.0, 0.0, -0.4], np.float32), (count, 1))
    color = np.tile(np.array([0.85, 0.6, 0.35, 1.0], np.float32), (count, 1))
    # The short coat is painted: bald on the head's right (the viewer's left), growing to full
    # length across the face, so the runtime's painted lengths (the skin's self-shadow too) are
    # compared; the guard-hair coat and a coat of a given depth keep length 1.
    painted = not guard_hairs and fur_depth is None
    length = np.clip((positions[:, 0] + 0.1) / 0.5, 0.0, 1.0) if painted else np.ones(count)
    mesh = pelt.FurMesh(positions, triangles, comb=comb, color=color, length=length.astype(np.float32))
    strands = {"guard_hairs": True, "guard_share": 0.5} if guard_hairs else {}
    hair = pelt.HairParams(density=2500, guard_fraction=0.1 if guard_hairs else 0.05)
    depth = fur_depth if fur_depth is not None else 0.15 if guard_hairs else 0.08
    asset = pelt.Pipeline().bake(
        mesh, tile_size=0.3, fur_depth=depth, layers=16, resolution=64, hair=hair,
        transfer=prt, seed=7, **strands,
    )  # fmt: skip

    names, parents, rest, times, poses = skeleton()
    head = np.clip((positions[:, 2] + 0.3) / 0.6, 0.0, 1.0).astype(np.float32)
    joints = np.tile(np.array([1, 2], np.uint32), (count, 1))
    weights = np.stack([1.0 - head, head], axis=1).astype(np.float32)
    pelt.export_gltf(
        asset,
        out / f"{prefix}character.glb",
        mode="engine",
        name="Character",
        transform=np.eye(4),
        skin={"skeleton": 0, "joints": joints, "weights": weights},
        skeletons=[
            {
                "names": names,
                "parents": parents,
                "rest": rest,
                "animations": [{"name": "Nod", "times": times, "poses": poses}],
            }
        ],
    )

    # The pose at TIME (a sample of the animation), by linear blend skinning of the rest mesh.
    key = int(np.flatnonzero(np.isclose(times, TIME))[0])
    skin = world(poses[key], parents) @ np.linalg.inv(world(rest, parents))
    blended = weights[:, 0, None, None] * skin[1] + weights[:, 1, None, None] * skin[2]
    homogeneous = np.concatenate([positions, np.ones((count, 1), np.float32)], axis=1)
    posed = np.einsum("vij,vj->vi", blended, homogeneous)[:, :3].astype(np.float32)

    view = look_at((0.0, -4.2, 0.6), (0.0, 0.0, 0.1), (0.0, 0.0, 1.0))
    projection = perspective(math.radians(38.0), 1.0, 0.1, 100.0)
    lighting = {"model": "kajiya-kay", "direction": (0.4, -0.5, 0.75), "color": (math.pi,) * 3}
    if prt:
        sky = np.zeros((asset.transfer["order"] ** 2, 3), np.float32)
        sky[0] = PRT_SKY * math.sqrt(4 * math.pi)
        lighting = {**lighting, "model": "prt", "environment": sky, "light_radius": PRT_LIGHT_RADIUS}
    preview = pelt.Preview(asset, adapter="cpu")
    preview.deform(posed)
    black = (0.0, 0.0, 0.0, 1.0)
    # The runtime casts no shadows yet: the preview without the body's shadow is what it draws.
    frame = preview.render(
        view,
        projection,
        SIZE,
        SIZE,
        lighting=lighting,
        fins=True,
        body_shadow=False,
        background=black,
        strand_order="depth",
    )
    pelt.save_png(out / f"{prefix}preview.png", frame)
    scene = {
        "model": f"{prefix}character.glb",
        "time": TIME,
        "width": SIZE,
        "height": SIZE,
        "view": view.T.reshape(-1).tolist(),
        "projection": projection.T.reshape(-1).tolist(),
        # The runtime's lighting options (runtimes/three/src/lighting.js).
        "lighting": {"direction": lighting["direction"], "color": lighting["color"]}
        | ({"model": "prt", "prt": {"sky": [PRT_SKY] * 3, "lightRadius": PRT_LIGHT_RADIUS}} if prt else {}),
        "shells": int(asset.layers - 1),
    }
    if guard_hairs:
        scene["guard_strands"] = int(preview.guard_strands)
    (out / f"{prefix}scene.json").write_text(json.dumps(scene, indent=1))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit("usage: make_reference.py OUT_DIR")
    main(Path(sys.argv[1]))
