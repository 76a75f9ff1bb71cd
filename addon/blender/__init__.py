# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's Blender glue: operators, panels, properties and the datablocks Pelt makes, on top of
``io/``."""
