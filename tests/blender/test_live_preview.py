"""Live Preview off Blender's main thread, in the real Blender with the real renderer (lavapipe):
frames render on the worker while the main thread only hands over views; a stale bake is never
run by the preview (the panel says "out of date"); painted colors reach the picture without a
bake; the pose follows the evaluated mesh; a device that fails falls back to the CPU. The draw
callback's GPU upload needs a window (not headless); everything before it runs here."""

import bpy
import numpy as np
import pelt
import pytest
from conftest import add_suzanne, small_fur
from mathutils import Matrix

WIDTH, HEIGHT = 96, 80


def projection() -> np.ndarray:
    """A perspective like the viewport's window matrix (OpenGL clip space)."""
    near, far, focal = 0.1, 100.0, 2.0
    aspect = WIDTH / HEIGHT
    return np.array(
        [
            [focal / aspect, 0, 0, 0],
            [0, focal, 0, 0],
            [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
            [0, 0, -1, 0],
        ],
        np.float32,
    )


def view_of(obj, distance=5.0, turn=0.0) -> np.ndarray:
    """The view matrix × the object's matrix of a camera ``distance`` in front (−Y), turned by
    ``turn`` radians about Z, as the draw callback computes it."""
    camera = (
        Matrix.Rotation(turn, 4, "Z")
        @ Matrix.Translation((0, -distance, 0))
        @ Matrix.Rotation(np.pi / 2, 4, "X")
    )
    return np.array(camera.inverted() @ obj.matrix_world, np.float32)


@pytest.fixture
def live(addon):
    addon.blender.live_preview.start()
    yield addon.blender.live_preview
    addon.blender.live_preview.stop()


def furred_suzanne():
    obj = add_suzanne()
    settings = small_fur(obj, fur_depth=0.15)
    settings.lighting = "KAJIYA_KAY"
    settings.guard_hairs = False
    return obj


def heard(live) -> None:
    """The edit reaches the preview as in Blender: the depsgraph handler hears it, then the check
    timer (which does not run headless) reads the mesh again."""
    bpy.context.view_layer.update()
    live.run_checks()


def drawn(live, obj, view=None, timeout=120.0) -> np.ndarray:
    """Requests a frame as the draw callback does, waits for the worker, returns ``[H, W, 4]``."""
    session = live.session_of(obj, create=True)
    for _ in range(2):  # a bake started by the preview is taken by the poll
        assert session.worker is not None or session.job is not None, session.message
        if session.job is not None:
            assert session.job.wait(timeout)
        live.poll()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    view = view_of(obj) if view is None else view
    session.request(obj, depsgraph, bpy.context.scene, view, projection(), WIDTH, HEIGHT)
    assert session.worker.wait_idle(timeout), session.worker.error
    assert session.worker.error is None, session.worker.error
    frame = session.take_frame()
    assert frame is not None and (frame.width, frame.height) == (WIDTH, HEIGHT)
    return frame.pixels.reshape(HEIGHT, WIDTH, 4)[::-1]


def test_frames_render_on_the_worker_and_the_main_thread_only_hands_over(live):
    obj = furred_suzanne()
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    pixels = drawn(live, obj)
    covered = pixels[..., 3] > 0.5
    assert covered[HEIGHT // 2, WIDTH // 2] and not covered[0, 0]
    assert 0.05 < covered.mean() < 0.9
    session = live.session_of(obj)
    # Nothing changed: the draw callback hands over nothing and no frame comes.
    depsgraph = bpy.context.evaluated_depsgraph_get()
    session.request(obj, depsgraph, bpy.context.scene, view_of(obj), projection(), WIDTH, HEIGHT)
    assert session.worker.wait_idle(60.0) and session.take_frame() is None
    # A turned view renders a new frame; the panel shows the adapter and the frame time.
    turned = drawn(live, obj, view=view_of(obj, turn=0.5))
    assert not np.array_equal(turned, pixels)
    status = session.status()
    assert any("ms a frame" in line and "cpu" in line.lower() for line in status), status
    # The worker took the newest view only: of three handed over at once, the last is drawn.
    for turn in (0.1, 0.2, 0.5):
        session.request(
            obj, depsgraph, bpy.context.scene, view_of(obj, turn=turn), projection(), WIDTH, HEIGHT
        )
    assert session.worker.wait_idle(60.0)
    assert np.array_equal(session.take_frame().pixels.reshape(HEIGHT, WIDTH, 4)[::-1], turned)


def test_the_viewport_depth_hides_the_fur_behind_other_objects(live):
    obj = furred_suzanne()
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    plain = drawn(live, obj)
    session = live.session_of(obj)
    # Another object's depth one unit in front of the camera over the left half, as the draw
    # callback reads it from the viewport (window depth, rows top first).
    clip = projection().astype(np.float64) @ np.array([0.0, 0.0, -1.0, 1.0])
    wall = np.ones((HEIGHT, WIDTH), np.float32)
    wall[:, : WIDTH // 2] = 0.5 * clip[2] / clip[3] + 0.5
    reads = []

    def read_depth():
        reads.append(1)
        return wall

    depsgraph = bpy.context.evaluated_depsgraph_get()
    view = view_of(obj, distance=5.001)
    session.request(obj, depsgraph, bpy.context.scene, view, projection(), WIDTH, HEIGHT, read_depth)
    assert session.worker.wait_idle(60.0)
    walled = session.take_frame().pixels.reshape(HEIGHT, WIDTH, 4)[::-1]
    assert (plain[:, : WIDTH // 2, 3] > 0.5).sum() > 20
    assert (walled[:, : WIDTH // 2, 3] == 0).all()
    assert (walled[:, WIDTH // 2 :, 3] > 0.5).sum() > 20
    # The depth is read only for a frame handed over: a redraw of the same view reads nothing.
    session.request(obj, depsgraph, bpy.context.scene, view, projection(), WIDTH, HEIGHT, read_depth)
    assert reads == [1]


def test_virtual_planes_before_their_bake_draw_the_shells_until_bake(live):
    obj = furred_suzanne()
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    shells = drawn(live, obj)
    session = live.session_of(obj)
    obj.pelt.shell_method = "PLANES"
    live.poll()
    live.run_checks()
    # The bake has no slices yet: the preview keeps drawing its shells and asks for a bake.
    assert session.out_of_date
    again = drawn(live, obj, view=view_of(obj, distance=5.01))
    assert session.worker.error is None and session.message is None
    assert np.abs(again.astype(np.float32) - shells).mean() < 0.05
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    live.poll()
    assert not session.out_of_date
    planes = drawn(live, obj)
    assert (planes[..., 3] > 0.5).mean() > 0.05


def test_a_stale_bake_is_never_run_by_the_preview(live):
    obj = furred_suzanne()
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    before = drawn(live, obj)
    session = live.session_of(obj)
    record = session.record
    assert not session.out_of_date
    obj.pelt.tile_size *= 1.5
    live.poll()  # the timer sees the setting change and schedules a check
    live.run_checks()
    assert session.out_of_date and "Out of date: Bake to update" in session.status()
    # Drawing goes on with the bake it has: no job started, the same record, the same picture.
    again = drawn(live, obj, view=view_of(obj, distance=5.01))
    assert session.job is None and session.record is record
    assert np.abs(again.astype(np.float32) - before).mean() < 0.05
    # Bake: the preview draws the new bake and is up to date.
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    live.poll()
    assert session.record is not record and not session.out_of_date
    assert not np.array_equal(drawn(live, obj), before)


def test_the_preview_bakes_on_its_worker_when_the_object_has_no_bake(live):
    obj = furred_suzanne()
    session = live.session_of(obj, create=True)
    assert session.job is not None and "Baking the preview" in session.status()[0]
    pixels = drawn(live, obj)
    assert (pixels[..., 3] > 0.5).mean() > 0.05
    # That bake wrote nothing into the scene (only Bake does).
    assert "PeltUV" not in obj.data.uv_layers and not bpy.data.materials


def test_painted_colors_reach_the_picture_without_a_bake(live):
    obj = furred_suzanne()
    n = len(obj.data.vertices)
    color = obj.data.attributes.new("pelt_color", "FLOAT_COLOR", "POINT")
    color.data.foreach_set("color", np.ones(4 * n, np.float32))
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    before = drawn(live, obj)
    session = live.session_of(obj)
    record = session.record
    obj.data.attributes["pelt_color"].data.foreach_set(
        "color", np.tile([1.0, 0.0, 0.0, 1.0], n).astype(np.float32)
    )
    heard(live)
    after = drawn(live, obj)
    covered = (before[..., 3] > 0.5) & (after[..., 3] > 0.5)
    red_before = before[covered, 0] - before[covered, 1]
    red_after = after[covered, 0] - after[covered, 1]
    assert red_after.mean() > red_before.mean() + 0.1
    # Repainting is no reason to bake (no guard hairs placed by the paint): the same record.
    assert session.record is record and not session.out_of_date
    # Lengths painted too: shorter fur, still no bake.
    obj.data.attributes.new("pelt_length", "FLOAT", "POINT").data.foreach_set(
        "value", np.full(n, 0.2, np.float32)
    )
    heard(live)
    shorter = drawn(live, obj)
    assert (shorter[..., 3] > 0.5).sum() < (after[..., 3] > 0.5).sum() and not session.out_of_date
    # Without paint the bake grows the coat as set, not under paint: out of date.
    obj.data.attributes.remove(obj.data.attributes["pelt_color"])
    heard(live)
    assert session.out_of_date


def test_a_repaint_the_levels_cannot_hold_is_remade_into_them_once_it_settles(live):
    obj = furred_suzanne()
    bpy.ops.object.modifier_add(type="SUBSURF")
    bpy.ops.object.modifier_apply(modifier="Subdivision")
    n = len(obj.data.vertices)
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    drawn(live, obj)
    session = live.session_of(obj)
    worker, preview = session.worker, session.worker.preview
    width, height = 4 * WIDTH, 4 * HEIGHT

    def frame(turn: float, timeout: float = 120.0) -> np.ndarray | None:
        """The frame of a view from afar (a coarse level), or None while a remake is due."""
        depsgraph = bpy.context.evaluated_depsgraph_get()
        view = view_of(obj, distance=25.0, turn=turn)
        session.request(obj, depsgraph, bpy.context.scene, view, projection(), width, height)
        idle = worker.wait_idle(timeout)
        assert worker.error is None, worker.error
        pixels = session.take_frame().pixels.reshape(height, width, 4)
        return pixels if idle else None

    frame(0.0)
    assert preview.last_frame["mesh_level"] >= 1, preview.last_frame
    # Red dabs one vertex across on a white coat: the coarse levels dropped most of their
    # vertices, so the frames after a repaint draw the full mesh.
    white = np.ones((n, 4), np.float32)
    color = obj.data.attributes.new("pelt_color", "FLOAT_COLOR", "POINT")

    def dab(every: int) -> None:
        white[::every, 1:3] = 0.0
        color.data.foreach_set("color", white.ravel())
        heard(live)

    worker.settle = 30.0  # the stroke goes on
    dab(97)
    assert frame(0.001, timeout=3.0) is None, "a remake is due, once the stroke settles"
    assert preview.last_frame["mesh_level"] == 0 and preview.levels_dropped
    assert worker.remakes == []
    # The stroke's last dab: once it settles the worker makes the levels anew under the paint.
    worker.settle = 0.0
    dab(89)
    full = frame(0.002)
    assert preview.last_frame["mesh_level"] == 0
    assert len(worker.remakes) == 1 and not preview.levels_dropped
    remade = frame(0.003)
    assert preview.last_frame["mesh_level"] >= 1, preview.last_frame
    # The dabs still show, as the full mesh drew them (measured: opacity 3.2% more, where the
    # coarse silhouette stands out, and red 3.7% less).
    assert abs(coverage(remade) - coverage(full)) <= 0.05 * coverage(full)
    assert abs(redness(remade) - redness(full)) <= 0.1 * redness(full)


def coverage(rgba: np.ndarray) -> float:
    """Summed opacity."""
    return float(rgba[..., 3].sum(dtype=np.float64))


def redness(rgba: np.ndarray) -> float:
    """Red over green, summed."""
    return float((rgba[..., 0] - rgba[..., 1]).sum(dtype=np.float64))


def test_a_comb_stroke_leans_the_fur_at_once_and_asks_for_a_bake(live):
    obj = furred_suzanne()
    n = len(obj.data.vertices)
    comb = obj.data.attributes.new("pelt_comb", "FLOAT_VECTOR", "POINT")
    comb.data.foreach_set("vector", np.zeros(3 * n, np.float32))
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    before = drawn(live, obj)
    session = live.session_of(obj)
    record = session.record
    # Combed hard sideways (+X): the fur leans and the coverage moves toward +X on screen.
    obj.data.attributes["pelt_comb"].data.foreach_set(
        "vector", np.tile([3.0, 0.0, 0.0], n).astype(np.float32)
    )
    heard(live)
    after = drawn(live, obj)

    def lean(pixels):
        """Covered pixels right of the middle column minus those left of it."""
        covered = pixels[..., 3] > 0
        return int(covered[:, WIDTH // 2 :].sum()) - int(covered[:, : WIDTH // 2].sum())

    assert lean(after) > lean(before) + 10
    # No bake ran; the patches follow the comb at the next Bake, so the panel asks for one.
    assert session.record is record and session.out_of_date


def test_the_preview_follows_the_pose(live):
    obj = furred_suzanne()
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    rest = drawn(live, obj)
    displace = obj.modifiers.new("Push", "DISPLACE")
    displace.strength = 0.6
    bpy.context.view_layer.update()  # the depsgraph handler hears the edit
    posed = drawn(live, obj)
    assert (posed[..., 3] > 0.5).sum() > (rest[..., 3] > 0.5).sum() * 1.1
    # Back to the rest shape when the modifier goes.
    obj.modifiers.remove(displace)
    bpy.context.view_layer.update()  # the depsgraph handler hears the edit
    back = drawn(live, obj)
    assert np.abs(back.astype(np.float32) - rest).mean() < 1e-3


def test_a_missing_gpu_falls_back_to_the_cpu(live, addon):
    obj = furred_suzanne()
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    try:
        pelt.Preview(addon.blender.bake.RECORDS[obj.session_uid].asset, adapter="gpu")
        pytest.skip("this machine has a GPU adapter")
    except pelt.PeltError:
        pass
    # The preference "GPU" on a machine without one: the device cannot be made.
    session = live._State.sessions[obj.session_uid] = live.Session(obj)
    session.adapter = "gpu"
    session.start(obj)
    session.worker._thread.join(60.0)
    live.poll()
    assert session.adapter == "cpu" and "drawing on the CPU" in session.message
    pixels = drawn(live, obj)
    assert (pixels[..., 3] > 0.5).mean() > 0.05
    assert any("drawing on the CPU" in line for line in session.status())


def test_switching_off_stops_the_workers(live):
    obj = furred_suzanne()
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    drawn(live, obj)
    worker = live.session_of(obj).worker
    live.stop()
    worker._thread.join(30.0)
    assert not worker.alive and not live.is_on() and live.session_of(obj) is None
    handlers = bpy.app.handlers
    assert live.on_depsgraph_update not in handlers.depsgraph_update_post
    assert live.on_load not in handlers.load_pre


def test_opening_a_file_switches_the_preview_off(live):
    obj = furred_suzanne()
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    drawn(live, obj)
    worker = live.session_of(obj).worker
    bpy.ops.wm.read_factory_settings(use_empty=True)
    worker._thread.join(30.0)
    assert not worker.alive and not live.is_on()


def test_a_slow_worker_draws_half_size_first_then_sharpens(live):
    obj = furred_suzanne()
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    drawn(live, obj)
    session = live.session_of(obj)
    worker = session.worker
    worker.budget = 0.0  # every full frame is over it
    drawn(live, obj, view=view_of(obj, turn=0.1))  # a full frame that sets the worker slow
    # Every frame the worker publishes, whether or not a redraw took it before the next (polling
    # would miss the half-size frame when the full one follows before this thread runs again).
    frames = []
    publish = worker._publish

    def record(frame, *, last):
        frames.append(frame)
        publish(frame, last=last)

    worker._publish = record
    depsgraph = bpy.context.evaluated_depsgraph_get()
    session.request(obj, depsgraph, bpy.context.scene, view_of(obj, turn=0.3), projection(), WIDTH, HEIGHT)
    assert worker.wait_idle(120.0) and worker.error is None, worker.error
    assert [f.scale for f in frames] == [0.5, 1.0]
    half, full = frames
    assert (half.scale, half.width, half.height) == (0.5, WIDTH // 2, HEIGHT // 2)
    assert (full.scale, full.width, full.height) == (1.0, WIDTH, HEIGHT)
    # The half-size frame is the full one seen at half the resolution: coverage agrees.
    half_alpha = half.pixels.reshape(HEIGHT // 2, WIDTH // 2, 4)[..., 3]
    full_alpha = (
        full.pixels.reshape(HEIGHT, WIDTH, 4)[..., 3].reshape(HEIGHT // 2, 2, WIDTH // 2, 2).mean((1, 3))
    )
    assert np.abs(half_alpha.mean() - full_alpha.mean()) < 0.03


def test_depth_at_half_size_keeps_the_nearest_of_each_block(addon):
    rng = np.random.default_rng(3)
    depth = rng.random((9, 13)).astype(np.float32)
    small = addon.io.live.scaled_depth(depth, 6, 4)
    assert small.shape == (4, 6)
    rows = [0, 2, 4, 6, 9]  # floor(k · 9 / 4)
    cols = [0, 2, 4, 6, 8, 10, 13]  # floor(k · 13 / 6)
    for r in range(4):
        for c in range(6):
            assert small[r, c] == depth[rows[r] : rows[r + 1], cols[c] : cols[c + 1]].min()


def test_a_renamed_object_keeps_its_preview_and_a_deleted_one_frees_it(live):
    obj = furred_suzanne()
    assert bpy.ops.pelt.bake() == {"FINISHED"}
    drawn(live, obj)
    session = live.session_of(obj)
    obj.name = "Renamed"
    obj.pelt.tile_size *= 1.5
    live.poll()  # the settings are still followed under the new name
    live.run_checks()
    assert session.name == "Renamed" and session.out_of_date
    worker = session.worker
    bpy.data.objects.remove(obj)
    live.poll()
    worker._thread.join(30.0)
    assert not worker.alive and not live._State.sessions
