# SPDX-License-Identifier: GPL-3.0-or-later
"""The live preview's worker thread: frames render off Blender's main thread (no bpy here).

The main thread hands over what a frame needs (``Request``: the view, the size, the lighting, and
any pose or painted attributes to apply first) and takes back finished frames (``Frame``); it never
waits on a render. Only the newest request is kept: a view that moved on while a frame rendered is
not drawn, but the pose and the attributes of a dropped request are carried into the next, so no
update is lost. ``pelt.Preview.render`` releases the GIL, so Blender keeps running while it works.

Where a full frame takes longer than ``Worker.budget`` (a CPU adapter at a large viewport), each
new request is drawn first at half the size, stretched over the viewport, and then, if no newer
request came meanwhile, at full size: a stroke or an orbit reaches the screen in about half the
time, and the picture sharpens when the user stops.

A repaint that the mesh's coarser levels of detail would smear leaves the full mesh drawn, several
times slower far away (``pelt.Preview.levels_dropped``). Once the repaints have stopped for
``Worker.settle`` seconds the worker makes the levels anew under the new paint
(``pelt.Preview.remake_levels``), before the next frame: once per stroke, not per dab.
"""

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pelt


@dataclass
class Request:
    """One frame to render: what ``pelt.Preview.render`` takes, and what to change before it."""

    key: tuple
    view: np.ndarray
    projection: np.ndarray
    width: int
    height: int
    lighting: dict
    options: dict
    # (positions, normals) that ``pelt.Preview.deform`` poses the fur with first; None keeps the pose.
    pose: tuple | None = None
    # Keyword arguments of ``pelt.Preview.update`` (painted colors, lengths) applied first.
    attributes: dict | None = None
    # The fur depth (the bake's) set first where the preview's differs; None keeps it.
    fur_depth: float | None = None
    # time.perf_counter() when the request was made (the oldest carried change's, when merged).
    made: float = field(default_factory=time.perf_counter)


@dataclass
class Frame:
    """A finished frame, as Blender's GPU texture takes it: ``pixels`` float32 in 0..1 (display
    sRGB, straight alpha), flat, bottom row first."""

    key: tuple
    pixels: np.ndarray
    width: int
    height: int
    # Wall time of applying the request and rendering, on the worker.
    seconds: float
    # time.perf_counter() when the request was made, and when the frame was ready.
    requested: float
    finished: float
    # The frame's size over the request's (1 at full size).
    scale: float = 1.0


def scaled_size(width: int, height: int, scale: float) -> tuple[int, int]:
    return max(1, round(width * scale)), max(1, round(height * scale))


def scaled_depth(depth: np.ndarray, width: int, height: int) -> np.ndarray:
    """``depth`` ``[H, W]`` at ``[height, width]``: the nearest of the pixels each new pixel
    covers (an occluder in any of them hides the fur there)."""
    rows = np.minimum((np.arange(height + 1) * depth.shape[0]) // height, depth.shape[0])
    cols = np.minimum((np.arange(width + 1) * depth.shape[1]) // width, depth.shape[1])
    by_row = np.minimum.reduceat(depth, rows[:-1], axis=0)
    return np.ascontiguousarray(np.minimum.reduceat(by_row, cols[:-1], axis=1))


def match_fur_depth(preview: pelt.Preview, fur_depth: float) -> None:
    """Sets ``preview.fur_depth`` to ``fur_depth`` (the bake's) where it differs: a new fur depth
    re-runs no stage under Kajiya-Kay, so a preview built before it is kept, and told the new depth
    (no upload). The preview holds it as float32."""
    if preview.fur_depth != np.float32(fur_depth):
        preview.fur_depth = fur_depth


# What ``Worker._next`` hands the thread when the levels of detail are due to be made anew.
REMAKE_LEVELS = "remake levels"


class Worker:
    """Renders the newest request with the preview that ``build()`` makes on the worker thread
    (device creation and upload take a while too). After a failure the worker stops and keeps the
    error in ``error``; the caller decides whether to start another (on the CPU adapter)."""

    # Seconds a full frame may take before new requests are drawn at half size first.
    budget = 1.0 / 15.0
    interactive_scale = 0.5
    # Seconds without a repaint before dropped levels of detail are made anew: a stroke's dabs
    # come faster, and each remake costs about a tenth of a second on 60k triangles.
    settle = 0.25

    def __init__(self, build: Callable[[], pelt.Preview]):
        self._build = build
        self._slow = False
        self._condition = threading.Condition()
        self._pending: Request | None = None
        self._frame: Frame | None = None
        self._frame_is_new = False
        self._busy = False
        self._stopping = False
        # time.perf_counter() after which the levels are made anew, or None.
        self._remake_at: float | None = None
        # Seconds each remake of the levels took (scripts and the bench read them).
        self.remakes: list[float] = []
        self.preview: pelt.Preview | None = None
        self.adapter: dict | None = None
        self.error: BaseException | None = None
        self._thread = threading.Thread(target=self._run, name="pelt-live", daemon=True)
        self._thread.start()

    def submit(self, request: Request) -> None:
        """Replaces the waiting request with ``request`` (main thread; never waits on a render)."""
        with self._condition:
            dropped = self._pending
            if dropped is not None:
                if request.pose is None:
                    request.pose = dropped.pose
                if request.fur_depth is None:
                    request.fur_depth = dropped.fur_depth
                if dropped.attributes:
                    request.attributes = {**dropped.attributes, **(request.attributes or {})}
                if dropped.pose is not None or dropped.attributes:
                    request.made = min(request.made, dropped.made)
            self._pending = request
            self._condition.notify_all()

    def take_frame(self) -> Frame | None:
        """The frame finished since the last call, or None."""
        with self._condition:
            if not self._frame_is_new:
                return None
            self._frame_is_new = False
            return self._frame

    @property
    def has_new_frame(self) -> bool:
        return self._frame_is_new

    @property
    def alive(self) -> bool:
        return self._thread.is_alive()

    def wait_idle(self, timeout: float) -> bool:
        """Waits until no request waits or renders and no remake of the levels is due (scripts and
        tests); ``True`` when idle."""
        deadline = time.monotonic() + timeout
        with self._condition:
            while self._thread.is_alive() and (
                self._pending is not None or self._busy or self.preview is None or self._remake_at is not None
            ):
                left = deadline - time.monotonic()
                if left <= 0.0:
                    return False
                self._condition.wait(left)
            return True

    def stop(self) -> None:
        """Asks the thread to end after the frame it renders (it is a daemon: nothing waits)."""
        with self._condition:
            self._stopping = True
            self._pending = None
            self._condition.notify_all()

    def _next(self) -> Request | str | None:
        """The next request, ``REMAKE_LEVELS`` when a repaint has settled (before any request),
        or None to stop."""
        with self._condition:
            while not self._stopping:
                now = time.perf_counter()
                if self._remake_at is not None and now >= self._remake_at:
                    self._remake_at, self._busy = None, True
                    return REMAKE_LEVELS
                if self._pending is not None:
                    request, self._pending = self._pending, None
                    self._busy = True
                    return request
                self._condition.wait(None if self._remake_at is None else self._remake_at - now)
            return None

    def _run(self) -> None:
        try:
            preview = self._build()
            self.adapter = dict(preview.adapter)
            self.preview = preview
        except BaseException as error:  # handed to the main thread, which reports it
            self.error = error
            self._finish()
            return
        with self._condition:
            self._condition.notify_all()
        while (request := self._next()) is not None:
            try:
                if request is REMAKE_LEVELS:
                    self._remake_levels(preview)
                    continue
                if request.fur_depth is not None:
                    match_fur_depth(preview, request.fur_depth)
                if request.pose is not None:
                    preview.deform(*request.pose)
                if request.attributes:
                    preview.update(**request.attributes)
                    self._schedule_remake(preview.levels_dropped)
                scales = (self.interactive_scale, 1.0) if self._slow else (1.0,)
                for scale in scales:
                    if scale == 1.0 and len(scales) > 1 and self._pending is not None:
                        break  # a newer request: draw it rather than sharpen this one
                    self._publish(self._render(preview, request, scale), last=scale == 1.0)
            except BaseException as error:
                self.error = error
                break
        self._finish()

    def _schedule_remake(self, dropped: bool) -> None:
        """After a repaint: the levels are made anew ``settle`` seconds after the last one that
        dropped some (one that drops none, such as painting back, cancels it)."""
        with self._condition:
            self._remake_at = time.perf_counter() + self.settle if dropped else None

    def _remake_levels(self, preview: pelt.Preview) -> None:
        start = time.perf_counter()
        remade = preview.remake_levels()
        with self._condition:
            if remade:
                self.remakes.append(time.perf_counter() - start)
            self._busy = False
            self._condition.notify_all()

    def _render(self, preview: pelt.Preview, request: Request, scale: float) -> Frame:
        start = time.perf_counter()
        width, height = scaled_size(request.width, request.height, scale)
        options = request.options
        if scale != 1.0 and options.get("occluders") is not None:
            options = {**options, "occluders": scaled_depth(options["occluders"], width, height)}
        # As Blender's texture takes it (bottom row first, float32), converted on Pelt's threads.
        texture = preview.render(
            request.view,
            request.projection,
            width,
            height,
            lighting=request.lighting,
            texture=True,
            **options,
        )
        pixels = texture.ravel()
        finished = time.perf_counter()
        if scale == 1.0:
            self._slow = finished - start > self.budget
        return Frame(request.key, pixels, width, height, finished - start, request.made, finished, scale)

    def _publish(self, frame: Frame, *, last: bool) -> None:
        with self._condition:
            # Busy until the full-size frame (or a newer request) follows a half-size one.
            self._frame, self._frame_is_new, self._busy = frame, True, not last
            self._condition.notify_all()

    def _finish(self) -> None:
        with self._condition:
            self._busy = False
            self._stopping = True
            self._condition.notify_all()
