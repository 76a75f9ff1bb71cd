# SPDX-License-Identifier: GPL-3.0-or-later
"""``pelt.bake``: mesh → patches → hair volume → transfer → UVs, images, material and modifier.

Interactive (``INVOKE_DEFAULT`` with a window) the bake runs on a worker thread (``bake_job``)
while a modal timer shows progress in the status bar; Esc cancels. From scripts and headless
(``EXEC_DEFAULT``) it runs to the end before returning. Either way nothing is written until the
bake has succeeded, and only stages whose inputs changed run again (``pelt.Pipeline``).
"""

import hashlib
import math
import time
from dataclasses import dataclass

import bpy
import numpy as np
import pelt

from ..io import bake_job, bridge, fur_layout
from . import fur, preferences, topology, writer

# Stages of a bake, in order (for the progress bar).
STAGES = pelt.STAGES
# Seconds between progress updates of the modal operator.
POLL_SECONDS = 0.1


def object_scale(obj) -> float:
    """World units per object unit (mean of the axes' scales), for world-space settings."""
    scale = [abs(s) for s in obj.matrix_world.to_scale()]
    mean = sum(scale) / 3.0
    return mean if math.isfinite(mean) and mean > 0.0 else 1.0


def hair_params(settings) -> pelt.HairParams:
    """``Object.pelt`` as ``pelt.HairParams`` (raises ``pelt.InvalidParameterError``)."""
    return pelt.HairParams(
        seed=settings.seed,
        density=settings.density,
        guard_fraction=settings.guard_fraction,
        undercoat={"length": list(settings.undercoat_length), "width": list(settings.undercoat_width)},
        overcoat={"length": list(settings.overcoat_length), "width": list(settings.overcoat_width)},
        taper=settings.taper,
        curl=settings.curl,
        helix_radius=settings.helix_radius,
        helix_frequency=settings.helix_frequency,
        slant=settings.slant,
        length_jitter=settings.length_jitter,
        clump_strength=settings.clump_strength,
        clump_count=settings.clump_count,
        root_color=list(settings.root_color),
        tip_color=list(settings.tip_color),
        color_jitter=settings.color_jitter,
    )


def bake_options(obj) -> dict:
    """Keyword arguments of ``pelt.Pipeline.bake`` from the object's settings (object units)."""
    settings = obj.pelt
    scale = object_scale(obj)
    return {
        "tile_size": settings.tile_size / scale,
        "seed": settings.patch_seed,
        "hair": hair_params(settings),
        "layers": settings.layers,
        "resolution": int(settings.resolution),
        "coverage": settings.coverage,
        "fur_depth": settings.fur_depth / scale,
        "transfer": settings.lighting == "PRT",
        "order": None if settings.prt_auto_order else settings.prt_order,
        "tolerance": settings.prt_tolerance,
        "guard_hairs": settings.guard_hairs,
        "guard_share": settings.guard_share,
        # Only the virtual planes read their slices.
        "planes": settings.planes if settings.shell_method == "PLANES" else 0,
    }


def memory_estimate(obj):
    """``(estimated peak bytes of baking obj, the limit)``, or None while a setting is invalid
    (the bake then reports it)."""
    try:
        return pelt.Pipeline.peak_bytes(**bake_options(obj)), pelt.memory_limit()
    except pelt.PeltError:
        return None


def signature(arrays, options: dict) -> bytes:
    """A hash of what a bake reads: two reads with the same signature bake the same asset. The
    painted colors and lengths count only where the bake reads them: the colors' presence (the
    coat grows under paint), and both by value when guard hairs are placed by them; otherwise
    the preview takes them without a bake (``pelt.Preview.update``)."""
    digest = hashlib.blake2b(digest_size=16)
    painted = (arrays.color, arrays.length)
    read = (arrays.positions, arrays.triangles, arrays.triangle_polygons, arrays.normals, arrays.comb)
    for values in read + (painted if options.get("guard_hairs") else ()):
        digest.update(b"-" if values is None else np.ascontiguousarray(values).tobytes())
    digest.update(b"c" if arrays.color is not None else b"-")
    digest.update(repr(sorted(options.items())).encode())
    return digest.digest()


@dataclass
class Record:
    """The last bake of an object, by whichever operator ran it: what the live preview draws."""

    asset: pelt.FurAsset
    # The job's ``bakes_that_ran``: a preview built from an earlier count is stale.
    bakes_that_ran: int
    signature: bytes


# session_uid -> Record of the object's last successful bake.
RECORDS: dict[int, Record] = {}


def remember(uid: int, job: bake_job.BakeJob) -> None:
    """Keeps a finished, successful job as the last bake of the object ``uid`` (its session_uid)."""
    RECORDS[uid] = Record(job.asset, job.bakes_that_ran, job.signature)


def start_job(obj, *, apply_topology: bool = False) -> bake_job.BakeJob:
    """Reads ``obj`` and its settings (main thread) and returns the job, not yet started. With
    ``apply_topology`` (Bake) the mesh read is the one with the modifiers at the top of the stack
    applied (``topology``), which ``finish`` gives the object if the bake succeeds."""
    applied = topology.prepare(obj) if apply_topology else None
    try:
        arrays = bridge.read_mesh(applied.mesh) if applied is not None else bridge.read_object(obj)
        options = bake_options(obj)
    except BaseException:
        topology.revert(obj, applied)
        raise
    job = bake_job.BakeJob(preferences.CACHE.get(obj.session_uid), arrays.fur_mesh, options)
    job.applied = applied
    # Of the mesh as the object has it after the bake (the topology modifiers applied).
    job.signature = signature(arrays, options)
    return job


def finish(obj, job: bake_job.BakeJob, build_material=None) -> str:
    """Writes a finished job's asset into Blender and returns the report line; raises the
    job's error (nothing written) when it failed or was cancelled."""
    applied = job.applied
    if job.error is not None:
        topology.revert(obj, applied)
        raise job.error
    start = time.perf_counter()
    topology.swap_in(obj, applied)
    try:
        written = writer.write_asset(obj, job.asset, build_material=build_material)
    except BaseException:
        topology.revert(obj, applied)
        raise
    topology.commit(obj, applied)
    remember(obj.session_uid, job)
    changes = []
    if build_material is not None:
        # After everything else succeeded: a failed bake leaves the scene as it was.
        changes = fur.prepare_scene(bpy.context.scene, fur_settings(obj, written["info"], job.asset))
        writer.note_scene_changes(obj, changes)
    stages = ", ".join(
        f"{s['stage']} {s['seconds']:.2f} s" if s["ran"] else f"{s['stage']} skipped"
        for s in job.asset.report
    )
    report = f"Pelt: baked {obj.name}: {stages}, written in {time.perf_counter() - start:.2f} s"
    if applied is not None:
        report += f"; applied {', '.join(applied.names)} so that the whole mesh has fur (Ctrl+Z undoes)"
    if changes:
        report += f"; so that the fur renders: {', '.join(changes)} (Ctrl+Z undoes)"
    return report


class PELT_OT_bake(bpy.types.Operator):
    """Bake the fur of the active object: patches, hair volume, transfer, then UVs, images and material"""

    bl_idname = "pelt.bake"
    bl_label = "Bake Fur"
    bl_options = {"REGISTER", "UNDO"}

    _job = None
    _timer = None
    _object_name = ""

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"

    def _fail(self, obj_name: str, error: BaseException):
        if isinstance(error, pelt.BakeCancelled):
            self.report({"WARNING"}, f"Pelt: bake of {obj_name} cancelled, nothing changed")
        else:
            self.report({"ERROR"}, f"Pelt: {obj_name}: {error}")
        return {"CANCELLED"}

    def execute(self, context):
        obj = context.active_object
        try:
            job = start_job(obj, apply_topology=True).start()
            job.wait()
            self.report({"INFO"}, finish(obj, job, build_material=build_material))
        except pelt.PeltError as error:
            return self._fail(obj.name, error)
        return {"FINISHED"}

    def invoke(self, context, event):
        if context.window is None:
            return self.execute(context)
        obj = context.active_object
        try:
            self._job = start_job(obj, apply_topology=True).start()
        except pelt.PeltError as error:
            return self._fail(obj.name, error)
        self._object_name = obj.name
        wm = context.window_manager
        self._timer = wm.event_timer_add(POLL_SECONDS, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        job = self._job
        if event.type == "ESC" and event.value == "PRESS":
            job.cancel()
            return {"RUNNING_MODAL"}
        if event.type != "TIMER" or not job.done:
            # The bake runs on its worker; Blender keeps handling every other event.
            stage = STAGES.index(job.stage) if job.stage in STAGES else 0
            context.window_manager.progress_update(int((stage + job.fraction) / len(STAGES) * 100))
            context.workspace.status_text_set(
                f"Pelt: baking {self._object_name}: {job.stage} {job.fraction:.0%} (Esc to cancel)"
            )
            return {"PASS_THROUGH"}
        self._end(context)
        obj = bpy.data.objects.get(self._object_name)
        if obj is None or obj.type != "MESH":
            topology.revert(None, job.applied)
            self.report({"ERROR"}, f"Pelt: {self._object_name} was removed during the bake, nothing written")
            return {"CANCELLED"}
        try:
            self.report({"INFO"}, finish(obj, job, build_material=build_material))
        except pelt.PeltError as error:
            return self._fail(self._object_name, error)
        return {"FINISHED"}

    def _end(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)


def build_material(obj, images, info, asset):
    """The fur material, fin material and Geometry Nodes modifier, so EEVEE and Cycles render
    the bake (``fur.build_fur``); every check runs before anything is created."""
    settings = fur_settings(obj, info, asset)
    fur.build_fur(obj, images, info["layout"], settings, fin_height=info["fin_height"])
    return []


def fur_settings(obj, info, asset) -> fur_layout.FurSettings:
    """The Blender fur's layout for the written bake ``info`` of ``asset``."""
    return fur_layout.FurSettings.for_volume(
        info,
        depth=asset.fur_depth,
        shells=max(1, min(obj.pelt.max_shells, info["layers"])),
        fins=obj.pelt.fins,
        tile_size=asset.tile_size,
    )


CLASSES = (PELT_OT_bake,)
