# SPDX-License-Identifier: GPL-3.0-or-later
"""The live preview's worker thread: frames render off Blender's main thread (no bpy here).

The main thread hands over what a frame needs (``Request``: the view, the size, the lighting, and
any pose or painted attributes to apply first) and takes back finished frames (``Frame``); it never
waits on a render. Only the newest request is kept: a view that moved on while a frame rendered is
not drawn, but the pose and the attributes of a dropped request are carried into the next, so no
update is lost. ``pelt.Preview.render`` releases the GIL, so Blender keeps running while it works.
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


def texture_pixels(rgba: np.ndarray) -> np.ndarray:
    """``[H, W, 4]`` uint8, top row first → flat float32 in 0..1, bottom row first (Blender's
    textures run bottom-up)."""
    floats = np.ascontiguousarray(rgba[::-1], np.float32).ravel()
    floats *= 1.0 / 255.0
    return floats


class Worker:
    """Renders the newest request with the preview that ``build()`` makes on the worker thread
    (device creation and upload take a while too). After a failure the worker stops and keeps the
    error in ``error``; the caller decides whether to start another (on the CPU adapter)."""

    def __init__(self, build: Callable[[], pelt.Preview]):
        self._build = build
        self._condition = threading.Condition()
        self._pending: Request | None = None
        self._frame: Frame | None = None
        self._frame_is_new = False
        self._busy = False
        self._stopping = False
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
    def ready(self) -> bool:
        """Whether the preview is built (frames can render)."""
        return self.preview is not None

    @property
    def alive(self) -> bool:
        return self._thread.is_alive()

    def wait_idle(self, timeout: float) -> bool:
        """Waits until no request waits or renders (scripts and tests); ``True`` when idle."""
        deadline = time.monotonic() + timeout
        with self._condition:
            while self._thread.is_alive() and (
                self._pending is not None or self._busy or self.preview is None
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

    def _next(self) -> Request | None:
        with self._condition:
            while self._pending is None and not self._stopping:
                self._condition.wait()
            if self._stopping:
                return None
            request, self._pending = self._pending, None
            self._busy = True
            return request

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
            start = time.perf_counter()
            try:
                if request.pose is not None:
                    preview.deform(*request.pose)
                if request.attributes:
                    preview.update(**request.attributes)
                rgba = preview.render(
                    request.view,
                    request.projection,
                    request.width,
                    request.height,
                    lighting=request.lighting,
                    **request.options,
                )
                pixels = texture_pixels(rgba)
            except BaseException as error:
                self.error = error
                break
            finished = time.perf_counter()
            frame = Frame(
                request.key, pixels, request.width, request.height, finished - start, request.made, finished
            )
            with self._condition:
                self._frame, self._frame_is_new, self._busy = frame, True, False
                self._condition.notify_all()
        self._finish()

    def _finish(self) -> None:
        with self._condition:
            self._busy = False
            self._stopping = True
            self._condition.notify_all()
