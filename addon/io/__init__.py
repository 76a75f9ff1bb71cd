# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's parts that need no Blender: they never import bpy (nor anything from ``blender/``),
so they run in worker threads and in plain Python (tests/blender/test_addon_layout.py holds the rule).
"""
