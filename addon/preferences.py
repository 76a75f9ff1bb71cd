# SPDX-License-Identifier: GPL-3.0-or-later
"""Add-on preferences: worker threads, GPU adapter of the preview, bake cache size."""

import bpy
import pelt

from . import bake_job

# One cache of bake pipelines for the whole session.
CACHE = bake_job.PipelineCache()


def _apply_threads(prefs, _context=None) -> None:
    pelt.set_thread_count(prefs.threads)


def _apply_cache(prefs, _context=None) -> None:
    CACHE.capacity = prefs.cache_size


class PeltPreferences(bpy.types.AddonPreferences):
    # Extensions are registered under their package name (e.g. ``bl_ext.user_default.pelt``).
    bl_idname = __package__

    threads: bpy.props.IntProperty(
        name="Threads",
        description="Worker threads of Pelt's bakes (0: one per CPU core)",
        default=0,
        min=0,
        max=1024,
        soft_max=64,
        update=_apply_threads,
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
        layout.prop(self, "adapter")
        layout.prop(self, "cache_size")


def get(context=None):
    """The preferences, or None while the add-on is not registered under its package name."""
    context = context or bpy.context
    addon = context.preferences.addons.get(__package__)
    return addon.preferences if addon is not None else None


def apply(context=None) -> None:
    """Applies saved preferences at registration."""
    prefs = get(context)
    if prefs is not None:
        if prefs.threads:
            _apply_threads(prefs)
        _apply_cache(prefs)


CLASSES = (PeltPreferences,)
