# SPDX-License-Identifier: GPL-3.0-or-later
"""Add-on preferences: worker threads, memory limit, GPU adapter of the preview, bake cache size."""

import bpy
import pelt

from ..io import bake_job

# One cache of bake pipelines for the whole session.
CACHE = bake_job.PipelineCache()

# Blender registers an extension under its top package (e.g. ``bl_ext.user_default.pelt``), the
# parent of this module's package.
PACKAGE = __package__.rpartition(".")[0]


def _apply_threads(prefs, _context=None) -> None:
    pelt.set_thread_count(prefs.threads)


def _apply_memory(prefs, _context=None) -> None:
    gib = prefs.memory_limit_gib
    pelt.set_memory_limit(gib * 2**30 if gib > 0 else None)


def _apply_cache(prefs, _context=None) -> None:
    CACHE.capacity = prefs.cache_size


class PeltPreferences(bpy.types.AddonPreferences):
    bl_idname = PACKAGE

    threads: bpy.props.IntProperty(
        name="Threads",
        description="Worker threads of Pelt's bakes (0: one per CPU core)",
        default=0,
        min=0,
        max=1024,
        soft_max=64,
        update=_apply_threads,
    )
    memory_limit_gib: bpy.props.FloatProperty(
        name="Memory Limit (GiB)",
        description=(
            "Most memory a bake may plan to use; a bake above it stops before it starts and says "
            "what to lower (0: half of this computer's memory)"
        ),
        default=0.0,
        min=0.0,
        soft_max=256.0,
        precision=1,
        update=_apply_memory,
    )
    adapter: bpy.props.EnumProperty(
        name="Preview Device",
        description="Device of the live preview",
        items=(
            ("auto", "Automatic", "The GPU when there is one, else the CPU renderer"),
            ("gpu", "GPU", "A hardware GPU only"),
            ("cpu", "CPU", "The CPU (software) renderer"),
        ),
        default="auto",
    )
    cache_size: bpy.props.IntProperty(
        name="Cached Objects",
        description="Objects whose bake stages are kept in memory, so re-bakes run only what changed",
        default=8,
        min=1,
        max=256,
        update=_apply_cache,
    )

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(self, "threads")
        layout.prop(self, "memory_limit_gib")
        layout.label(
            text=f"Limit now: {format_bytes(pelt.memory_limit())} of {format_bytes(pelt.physical_memory())}"
        )
        layout.prop(self, "adapter")
        layout.prop(self, "cache_size")


def format_bytes(n: float) -> str:
    """``n`` bytes for people: ``1.2 GiB``."""
    for unit in ("B", "KiB", "MiB", "GiB"):
        if n < 1024 or unit == "GiB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1024
    return f"{n:.1f} GiB"


def get(context=None):
    """The preferences, or None while the add-on is not registered under its package name."""
    context = context or bpy.context
    addon = context.preferences.addons.get(PACKAGE)
    return addon.preferences if addon is not None else None


def apply(context=None) -> None:
    """Applies saved preferences at registration."""
    prefs = get(context)
    if prefs is not None:
        if prefs.threads:
            _apply_threads(prefs)
        if prefs.memory_limit_gib > 0:
            _apply_memory(prefs)
        _apply_cache(prefs)


CLASSES = (PeltPreferences,)
