# SPDX-License-Identifier: GPL-3.0-or-later
"""A bake running on a worker thread while Blender stays responsive (no bpy here).

``pelt.Pipeline.bake`` releases the GIL, so the worker thread leaves Blender's main thread free;
the bake's progress callback records the current stage and fraction for the status bar and
returns ``False`` once a cancel was asked for, which stops the bake at its next check with
``pelt.BakeCancelled`` and no partial result.
"""

import threading
import time

import pelt

# Per pipeline (by id; the cache keeps it alive), how many of its bakes ran a stage. Whatever was
# built from an earlier bake of it (the preview's scene) is stale once this moves on, whichever
# operator ran the newer bake. Counts only grow, so a new pipeline that reuses an id never
# matches an older count.
_BAKES_THAT_RAN: dict[int, int] = {}
_BAKES_LOCK = threading.Lock()


class BakeJob:
    """One bake through ``pipeline`` with keyword arguments ``options`` of the mesh that
    ``make_mesh()`` returns (called on the worker: building a ``pelt.FurMesh`` validates and
    indexes the mesh, which is part of the bake, not of Blender's reading)."""

    def __init__(self, pipeline: pelt.Pipeline, make_mesh, options: dict):
        self._pipeline = pipeline
        self._make_mesh = make_mesh
        self._options = options
        self._cancel = threading.Event()
        self._thread = threading.Thread(target=self._run, name="pelt-bake", daemon=True)
        self.stage = "patches"
        self.fraction = 0.0
        self.asset: pelt.FurAsset | None = None
        self.error: BaseException | None = None
        self.seconds = 0.0
        # After the run: how many bakes of the pipeline, this one included, ran a stage.
        self.bakes_that_ran = 0
        # The mesh with its topology modifiers applied that the bake read (``topology.Applied``),
        # which ``bake.finish`` gives the object or discards; None when it read the object's.
        self.applied = None
        # ``bake.signature`` of what the job read.
        self.signature = b""

    def start(self) -> "BakeJob":
        self._thread.start()
        return self

    def cancel(self) -> None:
        """Asks the bake to stop; it ends with ``pelt.BakeCancelled`` at its next check."""
        self._cancel.set()

    @property
    def cancelled(self) -> bool:
        return self._cancel.is_set()

    @property
    def done(self) -> bool:
        return self._thread.ident is not None and not self._thread.is_alive()

    def wait(self, timeout: float | None = None) -> bool:
        """Waits for the bake to end; ``True`` when it has."""
        self._thread.join(timeout)
        return self.done

    def _progress(self, stage: str, fraction: float) -> bool:
        self.stage, self.fraction = stage, fraction
        return not self._cancel.is_set()

    def _run(self) -> None:
        start = time.perf_counter()
        try:
            if self._cancel.is_set():
                raise pelt.BakeCancelled("cancelled")
            mesh = self._make_mesh()
            self.asset = self._pipeline.bake(mesh, progress=self._progress, **self._options)
            ran = any(stage["ran"] for stage in self.asset.report)
            with _BAKES_LOCK:
                key = id(self._pipeline)
                _BAKES_THAT_RAN[key] = _BAKES_THAT_RAN.get(key, 0) + ran
                self.bakes_that_ran = _BAKES_THAT_RAN[key]
        except BaseException as error:  # handed to the main thread, which reports it
            self.error = error
        finally:
            self.seconds = time.perf_counter() - start


class PipelineCache:
    """One ``pelt.Pipeline`` per object (keyed by a stable id), least recently used dropped
    beyond ``capacity`` so the cached stages of many objects do not pile up in memory."""

    def __init__(self, capacity: int = 8):
        self.capacity = capacity
        self._pipelines: dict = {}

    def get(self, key) -> pelt.Pipeline:
        pipeline = self._pipelines.pop(key, None) or pelt.Pipeline()
        self._pipelines[key] = pipeline
        while len(self._pipelines) > max(1, self.capacity):
            self._pipelines.pop(next(iter(self._pipelines)))
        return pipeline

    def forget(self, key) -> None:
        self._pipelines.pop(key, None)

    def clear(self) -> None:
        self._pipelines.clear()

    def __len__(self) -> int:
        return len(self._pipelines)
