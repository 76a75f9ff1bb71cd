# SPDX-License-Identifier: GPL-3.0-or-later
"""Live Preview: Pelt's fur drawn over the 3D viewport while Blender stays responsive.

Frames render on a worker thread (``live.Worker``); the viewport's draw callback only hands over
the view and the viewport's depth and draws the last finished frame, and a timer redraws the
viewport when a new one arrives. The worker renders the fur against that depth
(``pelt.Preview.render(occluders=...)``), so objects in front hide it and it hides what is
behind; its own skin and shells, drawn by Blender, are within the bias and do not.

Nothing here bakes in a draw callback: the preview draws the object's last bake (``bake.RECORDS``,
whichever operator made it; toggling the preview on starts a bake on its worker when there is
none), and when a setting or the mesh no longer matches it the panel says "out of date" until
Bake. Painted colors, lengths and comb need no bake to show: they are sent to the preview as they
change (``pelt.Preview.update``; the comb shears the shells and fins, and the patches follow it
at the next Bake), and the pose follows the evaluated mesh (``pose``).

A frame that fails on the GPU starts the preview again on the CPU adapter; one that fails there
stops the live preview with its reason in the panel. Blender keeps running either way.
"""

import bpy
import numpy as np
import pelt
from bpy.app.handlers import persistent

from ..io import bridge, live
from . import bake, pose, preferences
from .preview import object_lighting, render_options

# Seconds between the main thread's looks for a finished frame or a finished bake.
POLL_SECONDS = 1.0 / 30.0
# Seconds an edit waits before the mesh is read again (a stroke sends many updates).
CHECK_SECONDS = 0.05


class Session:
    """One object's live preview: its worker, the bake it draws and what it last sent."""

    def __init__(self, obj):
        self.uid = obj.session_uid
        self.name = obj.name
        self.worker: live.Worker | None = None
        self.job = None  # the bake started when the object had none
        self.record: bake.Record | None = None
        self.adapter = _adapter_preference()
        self.out_of_date = False
        self.message: str | None = None
        # Edits of the object (its pose may have moved) and of the lighting (the World, the lights,
        # the object's transform), counted by the depsgraph handler.
        self.edits = 0
        self.lighting_edits = 0
        self._posed_at = -1
        self._posed = False
        self._lit_at = -1
        self._lighting: dict | None = None
        self._order: int | None = None  # the bake's transfer order, None without a transfer
        self._has_planes = False  # whether the bake has the virtual planes' slices
        self._sent_key = None
        self._attributes: dict | None = None
        self._attributes_digest = None
        self.frame: live.Frame | None = None
        self.texture = None
        self.settings = settings_digest(obj.pelt)

    # Main thread: start, bake records, checks.

    def start(self, obj) -> None:
        """Draws the object's last bake, or starts one on a worker when it has none."""
        record = bake.RECORDS.get(self.uid)
        if record is not None:
            self._draw_bake(record)
            self.check(obj)
            return
        try:
            self.job = bake.start_job(obj).start()
            self.message = "Baking the preview…"
        except pelt.PeltError as error:
            self.message = f"Cannot bake the preview: {error}"

    def _draw_bake(self, record: bake.Record) -> None:
        kept = self.record is not None and self.worker is not None and self.worker.alive
        if kept and record.bakes_that_ran == self.record.bakes_that_ran:
            # No stage ran: the preview's scene is this bake's already.
            self.record = record
        else:
            self.record = record
            self._start_worker()
        transfer = record.asset.transfer  # a copy of its arrays: read once per bake
        self._order = transfer["order"] if transfer is not None else None
        self._has_planes = record.asset.planes is not None
        self.out_of_date = False
        self._attributes_digest = None

    def _start_worker(self) -> None:
        if self.worker is not None:
            self.worker.stop()
        asset, adapter = self.record.asset, self.adapter
        self.worker = live.Worker(lambda: pelt.Preview(asset, adapter=adapter))
        self._sent_key = None
        self._posed_at = -1
        self._posed = False

    def poll(self) -> bool:
        """Takes a finished bake, a newer record or a failure (main thread); True when the
        viewport should redraw."""
        if self.job is not None:
            if not self.job.done:
                return False
            job, self.job = self.job, None
            if job.error is not None:
                self.message = f"Cannot bake the preview: {job.error}"
                return True
            bake.remember(self.uid, job)
            self.message = None
        record = bake.RECORDS.get(self.uid)
        if record is not None and record is not self.record:
            self._draw_bake(record)
            return True
        worker = self.worker
        if worker is not None and worker.error is not None:
            self._fail(worker.error)
            return True
        return worker is not None and worker.has_new_frame

    def _fail(self, error: BaseException) -> None:
        if isinstance(error, pelt.InvalidParameterError):
            # A setting the renderer refuses: no other device would take it.
            self.message = f"Live preview stopped: {error}"
            self.worker = None
        elif self.adapter != "cpu":
            self.message = f"The GPU preview failed ({error}); drawing on the CPU"
            self.adapter = "cpu"
            self._start_worker()
        else:
            self.message = f"Live preview stopped: {error}"
            self.worker.stop()
            self.worker = None

    def check(self, obj) -> None:
        """Reads the mesh and the settings again after an edit: out of date when a bake would
        change the asset; painted colors, lengths and comb sent to the preview when they
        changed."""
        if self.record is None or obj.mode == "EDIT":
            return  # leaving Edit Mode is an edit too
        try:
            arrays = bridge.read_object(obj)
            options = bake.bake_options(obj)
        except pelt.PeltError as error:
            self.out_of_date, self.message = True, str(error)
            return
        self.out_of_date = bake.signature(arrays, options) != self.record.signature
        # The comb shears the shells and fins at once (the patches follow it at the next Bake).
        painted = (("color", arrays.color), ("length", arrays.length), ("comb", arrays.comb))
        attributes = {name: values for name, values in painted if values is not None}
        digest = hash(tuple((name, values.tobytes()) for name, values in attributes.items()))
        if digest != self._attributes_digest:
            if self._attributes_digest is not None or attributes:
                self._attributes = attributes
            self._attributes_digest = digest

    # Main thread: the draw callback's part (never waits on the worker).

    def request(
        self, obj, depsgraph, scene, view, projection, width: int, height: int, read_depth=None
    ) -> None:
        """Hands the worker the frame to draw next, when anything it shows changed.
        ``read_depth()`` gives the viewport's depth ``[height, width]`` (rows top first) that the
        fur is composited against (``pelt.Preview.render(occluders=...)``), read only for a
        frame handed over; None draws the fur over everything."""
        worker, record = self.worker, self.record
        if worker is None or record is None:
            return
        asset = record.asset
        model = "prt" if obj.pelt.lighting == "PRT" and self._order is not None else "kajiya-kay"
        if self._lit_at != self.lighting_edits or self._lighting is None or self._lighting["model"] != model:
            self._lighting = object_lighting(scene, obj, model, self._order)
            self._lit_at = self.lighting_edits
        target = None
        if self._posed_at != self.edits:
            self._posed_at = self.edits
            # Positions alone: the worker computes the normals, off the main thread.
            posed = pose.target(asset, obj, depsgraph, normals=False)
            rest = (asset.mesh.positions, asset.mesh.normals) if self._posed else None
            target = posed if posed is not None else rest
            self._posed = posed is not None
        options = render_options(obj)
        if options["shell_method"] == "planes" and not self._has_planes:
            # Virtual Planes asked for before a bake made their slices: the bake's shells until
            # then (the panel says "out of date").
            options["shell_method"] = "auto"
        view = np.ascontiguousarray(view, np.float32)
        projection = np.ascontiguousarray(projection, np.float32)
        key = (
            view.tobytes(),
            projection.tobytes(),
            width,
            height,
            repr(options),
            asset.fur_depth,
            self._lit_at,
            _State.scene_edits,
        )
        if key == self._sent_key and target is None and self._attributes is None:
            return
        depth = read_depth() if read_depth is not None else None
        if depth is not None:
            options = {**options, "occluders": depth}
        worker.submit(
            live.Request(
                key,
                view,
                projection,
                width,
                height,
                self._lighting,
                options,
                target,
                self._attributes,
                fur_depth=asset.fur_depth,
            )
        )
        self._sent_key, self._attributes = key, None

    def take_frame(self) -> live.Frame | None:
        frame = self.worker.take_frame() if self.worker is not None else None
        if frame is not None:
            self.frame = frame
        return frame

    def status(self) -> list[str]:
        """The panel's lines about this preview."""
        lines = []
        if self.job is not None:
            lines.append(f"Baking the preview: {self.job.stage} {self.job.fraction:.0%}")
        if self.out_of_date:
            lines.append("Out of date: Bake to update")
        if self.message and self.job is None:
            lines.append(self.message)
        note = pose.NOTES.get(self.uid)
        if note:
            lines.append(note)
        worker = self.worker
        if worker is not None and worker.adapter is not None:
            adapter = worker.adapter
            line = f"{adapter['name']} ({adapter['device_type']})"
            if self.frame is not None:
                seconds = self.frame.seconds
                line += f": {seconds * 1000:.0f} ms a frame ({1.0 / max(seconds, 1e-6):.0f} fps)"
            lines.append(line)
        return lines

    def stop(self) -> None:
        if self.worker is not None:
            self.worker.stop()
        if self.job is not None:
            self.job.cancel()
        self.worker = self.job = self.texture = None


def _adapter_preference() -> str:
    prefs = preferences.get()
    return prefs.adapter if prefs is not None else "auto"


class _State:
    """The draw handler, the timer and the sessions of the live preview."""

    handler = None
    sessions: dict[int, Session] = {}
    # Objects whose mesh is read again when the check timer fires.
    to_check: set[int] = set()
    # Depsgraph updates seen: another object may have moved in front of the fur.
    scene_edits = 0
    # Whether the viewport's depth could be read (False after it failed once: fur over everything).
    depth_readable = True


def is_on() -> bool:
    return _State.handler is not None


def session_of(obj, *, create: bool = False) -> Session | None:
    """The object's session; with ``create`` a new one is made and started."""
    session = _State.sessions.get(obj.session_uid)
    if session is None and create:
        session = _State.sessions[obj.session_uid] = Session(obj)
        session.start(obj)
    return session


def _object_of(uid: int, session: Session):
    """The session's object: by its name, else (renamed) by a look through the objects, whose
    name the session then keeps; None when the object is gone."""
    obj = bpy.data.objects.get(session.name)
    if obj is not None and obj.session_uid == uid:
        return obj
    obj = next((o for o in bpy.data.objects if o.session_uid == uid), None)
    if obj is not None:
        session.name = obj.name
    return obj


def _objects_by_uid() -> dict:
    """Each session's object by its session_uid (the sessions whose object is gone left out)."""
    objects = ((uid, _object_of(uid, session)) for uid, session in _State.sessions.items())
    return {uid: obj for uid, obj in objects if obj is not None}


def _redraw_viewports() -> None:
    for window in bpy.context.window_manager.windows if bpy.context.window_manager else ():
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


def settings_digest(settings) -> tuple:
    """Every value of ``Object.pelt``: setting one from a script or the UI tags no depsgraph
    update, so the timer compares these."""
    values = []
    for prop in settings.bl_rna.properties:
        if prop.identifier != "rna_type":
            value = getattr(settings, prop.identifier)
            values.append(tuple(value) if getattr(prop, "is_array", False) else value)
    return tuple(values)


def poll() -> float | None:
    """The timer: finished bakes, frames and failures, changed settings; redraws the viewports
    for them."""
    if not is_on():
        return None
    redraw = False
    for uid, session in list(_State.sessions.items()):
        obj = _object_of(uid, session)
        if obj is None:
            # The object was deleted: its worker and device go too.
            session.stop()
            del _State.sessions[uid]
            continue
        redraw |= session.poll()
        digest = settings_digest(obj.pelt)
        if digest != session.settings:
            session.settings = digest
            session.lighting_edits += 1  # the lighting model is a setting too
            _schedule_check(uid)
            redraw = True
    if redraw:
        _redraw_viewports()
    return POLL_SECONDS


def run_checks() -> None:
    """The check timer: reads the edited objects again (``Session.check``)."""
    objects = _objects_by_uid()
    for uid in _State.to_check:
        session, obj = _State.sessions.get(uid), objects.get(uid)
        if session is not None and obj is not None:
            session.check(obj)
    _State.to_check.clear()
    _redraw_viewports()


@persistent
def on_load(*_args) -> None:
    """Another file: its objects have no sessions; the preview switches off."""
    stop()


@persistent
def on_depsgraph_update(scene, depsgraph) -> None:
    """Counts the edits that change what the sessions draw; schedules a check of edited meshes."""
    sessions = _State.sessions
    if not sessions:
        return
    _State.scene_edits += 1
    meshes = {obj.data.session_uid: uid for uid, obj in _objects_by_uid().items() if obj.data is not None}
    lighting = False
    for update in depsgraph.updates:
        datablock = update.id.original
        if isinstance(datablock, (bpy.types.World, bpy.types.Light, bpy.types.Scene)):
            lighting = True
            continue
        uid = datablock.session_uid
        if isinstance(datablock, bpy.types.Mesh):
            uid = meshes.get(uid)
        session = sessions.get(uid)
        if session is None:
            continue
        session.edits += 1
        if update.is_updated_transform:
            session.lighting_edits += 1
        if update.is_updated_geometry or not update.is_updated_transform:
            _schedule_check(uid)
    if lighting:
        for session in sessions.values():
            session.lighting_edits += 1


@persistent
def on_frame_change(scene, depsgraph=None) -> None:
    """An animation frame may pose every object again."""
    for session in _State.sessions.values():
        session.edits += 1


def _schedule_check(uid: int) -> None:
    if not _State.to_check and bpy.app.timers is not None:
        bpy.app.timers.register(run_checks, first_interval=CHECK_SECONDS)
    _State.to_check.add(uid)


def _viewport_depth(width: int, height: int) -> np.ndarray | None:
    """The viewport's depth buffer ``[height, width]``, rows top first (the draw callback runs in
    the 3D view's ``POST_VIEW`` stage, where the scene's depth is bound); None when it cannot be
    read (the fur is then drawn over everything, as before compositing)."""
    if not _State.depth_readable:
        return None
    import gpu

    try:
        buffer = gpu.state.active_framebuffer_get().read_depth(0, 0, width, height)
        try:
            depth = np.frombuffer(buffer, np.float32)  # the buffer protocol: one copy
        except (TypeError, ValueError):
            depth = np.asarray(buffer.to_list(), np.float32)
        return np.ascontiguousarray(depth.reshape(height, width)[::-1])
    except (AttributeError, RuntimeError, TypeError, ValueError):
        _State.depth_readable = False
        return None


def _composite(texture) -> None:
    """Draws the frame over the whole region with straight alpha, no depth test (the worker
    already hid the fur behind the viewport's depth)."""
    import gpu
    from gpu_extras.presets import draw_texture_2d
    from mathutils import Matrix

    gpu.state.depth_test_set("NONE")
    gpu.state.depth_mask_set(False)
    gpu.state.blend_set("ALPHA")
    with gpu.matrix.push_pop(), gpu.matrix.push_pop_projection():
        gpu.matrix.load_identity()
        gpu.matrix.load_projection_matrix(Matrix.Identity(4))
        draw_texture_2d(texture, (-1.0, -1.0), 2.0, 2.0)
    gpu.state.blend_set("NONE")


def _draw():
    """The viewport's draw callback: hands over the view (and its depth), draws the last
    finished frame."""
    context = bpy.context
    obj = context.active_object
    region, region_3d = context.region, context.region_data
    if obj is None or obj.type != "MESH" or region_3d is None or not obj.pelt.enabled:
        return
    import gpu

    session = session_of(obj, create=True)
    width, height = region.width, region.height
    session.request(
        obj,
        context.evaluated_depsgraph_get(),
        context.scene,
        region_3d.view_matrix @ obj.matrix_world,
        region_3d.window_matrix,
        width,
        height,
        read_depth=lambda: _viewport_depth(width, height),
    )
    frame = session.take_frame()
    if frame is not None:
        data = gpu.types.Buffer("FLOAT", frame.pixels.size, frame.pixels)
        session.texture = gpu.types.GPUTexture((frame.width, frame.height), format="RGBA8", data=data)
    if session.texture is not None:
        # The last frame, stretched while the region was resized.
        _composite(session.texture)


def start() -> None:
    if is_on():
        return
    _State.handler = bpy.types.SpaceView3D.draw_handler_add(_draw, (), "WINDOW", "POST_VIEW")
    bpy.app.handlers.depsgraph_update_post.append(on_depsgraph_update)
    bpy.app.handlers.frame_change_post.append(on_frame_change)
    bpy.app.handlers.load_pre.append(on_load)
    bpy.app.timers.register(poll, first_interval=POLL_SECONDS)


def stop() -> None:
    """Switches the live preview off and frees its devices."""
    if _State.handler is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_State.handler, "WINDOW")
    _State.handler = None
    for handlers, function in (
        (bpy.app.handlers.depsgraph_update_post, on_depsgraph_update),
        (bpy.app.handlers.frame_change_post, on_frame_change),
        (bpy.app.handlers.load_pre, on_load),
    ):
        if function in handlers:
            handlers.remove(function)
    for timer in (poll, run_checks):
        if bpy.app.timers.is_registered(timer):
            bpy.app.timers.unregister(timer)
    for session in _State.sessions.values():
        session.stop()
    _State.sessions.clear()
    _State.to_check.clear()


class PELT_OT_live_preview(bpy.types.Operator):
    """Draw Pelt's real-time fur over the 3D viewport while you work (toggle); frames render off
    Blender's main thread"""

    bl_idname = "pelt.live_preview"
    bl_label = "Live Preview"

    def execute(self, context):
        if is_on():
            stop()
        else:
            start()
            obj = context.active_object
            if obj is not None and obj.type == "MESH" and obj.pelt.enabled:
                session_of(obj, create=True)
        _redraw_viewports()
        return {"FINISHED"}


CLASSES = (PELT_OT_live_preview,)
