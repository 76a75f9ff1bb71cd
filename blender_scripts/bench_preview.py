"""Benchmark: the live preview in Blender, on the adapter the preferences choose (the CPU one
without a GPU), with a 30k-triangle sphere baked and drawn at 960×540.

- ``blender.preview.frame``: a full-size frame on the worker thread (pose and attributes
  applied, rendered, turned into the texture's floats), median over views drawn one at a time;
  ``.interactive``: a frame during an orbit redrawn at 60 Hz (half size first where a full frame
  is over the worker's budget); ``.painted``: full size after red dabs, which the mesh's coarser
  levels would smear, once the worker has made them anew under the paint (the strokes' own
  frames draw the full mesh).
- ``blender.preview.remake``: the worker's remake of the levels after a stroke, median.
- ``blender.preview.redraw``: the main thread's share of a redraw (``Session.request`` and
  ``take_frame``: the view handed over, the pose read when it moved), the worst of the orbit's
  redraws (made while the worker renders) and a pose's; the GPU texture upload after it needs a
  window and is not counted.
- ``blender.preview.groom``: a paint dab's update (the mesh read again, the colors handed over)
  until its first frame is ready (polled as the add-on's timer does), median of several dabs.

Writes the figures as ``pelt bench`` JSON cases (``--json``) and prints them.
"""

import argparse
import math
import statistics
import time
from pathlib import Path

import bpy
import numpy as np
from _setup import register_addon, write_cases
from bench_preview_frame import projection
from mathutils import Matrix

WIDTH, HEIGHT = 960, 540
VIEWS = 9
REDRAWS = 120


def view_of(obj, turn: float) -> np.ndarray:
    camera = (
        Matrix.Rotation(turn, 4, "Z")
        @ Matrix.Translation((0, -3.2, 0))
        @ Matrix.Rotation(math.pi / 2, 4, "X")
    )
    return np.array(camera.inverted() @ obj.matrix_world, np.float32)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()

    addon = register_addon()
    live = addon.blender.live_preview
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=192, ring_count=80, radius=1.0)
    obj = bpy.context.active_object
    mesh = obj.data
    n = len(mesh.vertices)
    mesh.attributes.new("pelt_color", "FLOAT_COLOR", "POINT").data.foreach_set("color", np.ones(4 * n))
    settings = obj.pelt
    settings.enabled = True
    settings.tile_size = 0.3
    settings.fur_depth = 0.08
    settings.lighting = "KAJIYA_KAY"
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    mesh.calc_loop_triangles()
    size = f"{len(mesh.loop_triangles)} triangles, {WIDTH}×{HEIGHT}"

    live.start()
    session = live.session_of(obj, create=True)
    scene = bpy.context.scene

    def redraw(turn: float) -> tuple[float, object]:
        """One draw callback's work on the main thread: (seconds, the frame it took or None)."""
        # Blender evaluated the depsgraph before it drew the viewport.
        depsgraph = bpy.context.evaluated_depsgraph_get()
        start = time.perf_counter()
        session.request(obj, depsgraph, scene, view_of(obj, turn), projection(WIDTH, HEIGHT), WIDTH, HEIGHT)
        frame = session.take_frame()
        return time.perf_counter() - start, frame

    def full_frames(turns) -> list:
        """Each view drawn alone, the worker idle between: its full-size frame's seconds."""
        seconds = []
        for turn in turns:
            redraw(turn)
            assert session.worker.wait_idle(300.0), session.worker.error
            frame = session.take_frame()
            assert frame.scale == 1.0
            seconds.append(frame.seconds)
        return seconds

    def first_frame(start: float):
        """Polls as the main thread's timer does until a frame arrives: (frame, its latency)."""
        while (frame := session.take_frame()) is None:
            assert session.worker.error is None, session.worker.error
            time.sleep(0.001)
        return frame, frame.finished - start

    assert session.worker.wait_idle(300.0), session.worker.error
    session.take_frame()
    frames = full_frames([0.2 * i for i in range(VIEWS)])
    # An orbit: a redraw every 1/60 s with a new view while the worker renders (at half size
    # first where a full frame is over its budget).
    redraws, interactive = [], []
    for i in range(REDRAWS):
        seconds, frame = redraw(0.01 * i)
        redraws.append(seconds)
        if frame is not None:
            interactive.append(frame)
        time.sleep(1.0 / 60.0)
    assert session.worker.wait_idle(300.0), session.worker.error
    session.take_frame()
    # The pose moves: the redraw reads the evaluated positions.
    obj.modifiers.new("Breathe", "DISPLACE").strength = 0.05
    bpy.context.view_layer.update()
    redraws.append(redraw(0.0)[0])
    assert session.worker.wait_idle(300.0), session.worker.error
    session.take_frame()
    obj.modifiers.remove(obj.modifiers["Breathe"])
    bpy.context.view_layer.update()

    # Strokes: a dab of red 0.3 across, moving over the front; each until its first frame is
    # ready (then its full-size frame is waited for).
    strokes = []
    color = mesh.attributes["pelt_color"]
    painted = np.ones((n, 4), np.float32)
    positions = addon.io.bridge.read_positions(mesh)
    for i in range(5):
        centre = np.array([0.2 * (i - 2), -1.0, 0.1 * i], np.float32)
        painted[np.linalg.norm(positions - centre, axis=1) < 0.3, 1:3] = 0.1
        color.data.foreach_set("color", painted.ravel())
        bpy.context.view_layer.update()
        start = time.perf_counter()
        live.run_checks()
        redraw(0.0)
        strokes.append(first_frame(start))
        assert session.worker.wait_idle(300.0), session.worker.error
        session.take_frame()
    assert not session.out_of_date
    # The coarser levels would smear the dabs: each stroke's frames drew the full mesh, and the
    # worker made the levels anew once it settled (wait_idle waits for that).
    remakes = list(session.worker.remakes)
    assert remakes and not session.worker.preview.levels_dropped
    painted_frames = full_frames([0.2 * i + 0.05 for i in range(VIEWS // 2)])
    adapter = session.worker.adapter
    live.stop()
    device = f"{adapter['name']} ({adapter['device_type']})"
    scales = sorted({frame.scale for frame, _ in strokes} | {frame.scale for frame in interactive})

    cases = [
        {
            "name": "blender.preview.frame",
            "size": f"{size}, {device}: a full-size frame",
            "seconds": statistics.median(frames),
        },
        {
            "name": "blender.preview.frame.interactive",
            "size": f"{size}: a frame during an orbit redrawn at 60 Hz (sizes drawn: {scales})",
            "seconds": statistics.median(frame.seconds for frame in interactive),
        },
        {
            "name": "blender.preview.frame.painted",
            "size": f"{size}, red dabs painted, the levels made anew under them: a full-size frame",
            "seconds": statistics.median(painted_frames),
        },
        {
            "name": "blender.preview.remake",
            "size": f"{size}: the levels of detail made anew under a stroke's paint, on the worker",
            "seconds": statistics.median(remakes),
        },
        {
            "name": "blender.preview.redraw",
            "size": f"{size}: the worst of {len(redraws)} redraws while frames render (a pose among them)",
            "seconds": max(redraws),
        },
        {
            "name": "blender.preview.groom",
            "size": f"{size}: a repaint read, handed over and its first frame ready",
            "seconds": statistics.median(latency for _, latency in strokes),
        },
    ]
    write_cases(cases, args.json)


if __name__ == "__main__":
    main()
