# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes a bake (``pelt.FurAsset``) into Blender: UV map ``PeltUV`` and face attribute
``pelt_patch`` on the mesh, the ``Pelt …`` images, the fur material and modifier, and the guard
hairs' Curves object (``guard_hairs``).

Every datablock Pelt creates carries two custom properties, ``pelt_owner`` (the object's name) and
``pelt_role`` (what it is), and is found again by them, never by name: a user's own image called
"Pelt Shells Suzanne" is never touched (Blender gives Pelt's a ``.001`` name instead).

All pixels are prepared before the first datablock changes, and the mesh is written last (after
checking the sizes). If writing fails anyway, the datablocks created so far are removed, so a bake
either lands whole or leaves the scene as it was.
"""

import json
import re
from pathlib import Path

import bpy
import pelt

from ..io import bridge
from ..io.names import OWNER, ROLE, datablock_name
from ..io.ownership import find_owned, tag
from . import guard_hairs

# Image roles: (name stem, color data?).
IMAGE_ROLES = {
    "shells": ("Shells", True),
    "tangents": ("Tangents", False),
    "fin": ("Fin", True),
}


def prepare_images(asset: pelt.FurAsset) -> tuple[dict, dict]:
    """The images of ``asset`` as ``{role: (rgba [H,W,4] uint8, color?)}`` and the atlas layout
    plus the transfer's decode table, before anything in Blender changes."""
    volume = asset.volume
    shells, layout = pelt.pack_atlas(volume["shells"])
    images = {
        "shells": (shells, True),
        "tangents": (pelt.pack_atlas(volume["tangents"])[0], False),
        "fin": (volume["fin"], True),
    }
    info = {
        "layout": layout,
        "layers": volume["layers"],
        "layer_spacing": volume["layer_spacing"],
        "resolution": volume["resolution"],
        "fin_height": int(volume["fin"].shape[0]),
    }
    transfer = asset.transfer
    if transfer is not None:
        for k, texture in enumerate(transfer["packed_u8"]):
            images[f"transfer_{k}"] = (pelt.pack_atlas(texture)[0], False)
        info["transfer"] = {
            "order": transfer["order"],
            "textures": int(transfer["packed_u8"].shape[0]),
            "scale": transfer["scale"].tolist(),
            "bias": transfer["bias"].tolist(),
        }
    return images, info


def _image_name(role: str, obj) -> str:
    stem = IMAGE_ROLES.get(role, (f"Transfer {role.removeprefix('transfer_')}", False))[0]
    return datablock_name(stem, obj.name)


def _image_path(name: str):
    """``(file, filepath)`` beside the saved .blend (``//pelt_textures/…``), or None to pack."""
    if not bpy.data.filepath:
        return None
    folder = Path(bpy.path.abspath("//pelt_textures"))
    folder.mkdir(parents=True, exist_ok=True)
    file = folder / (re.sub(r"[^\w.-]+", "_", name) + ".png")
    return file, bpy.path.relpath(str(file))


class _Undo:
    """Datablocks a failed write must remove again."""

    def __init__(self):
        self.created: list = []

    def restore(self) -> None:
        for datablock in reversed(self.created):
            _remove(datablock)


def _remove(datablock) -> None:
    for collection in (bpy.data.hair_curves, bpy.data.images, bpy.data.materials, bpy.data.node_groups):
        if datablock.name in collection and collection[datablock.name] == datablock:
            collection.remove(datablock)
            return


def write_images(obj, images: dict, undo: _Undo) -> dict:
    """Creates or refills Pelt's images for ``obj``; returns ``{role: image}``. Images of roles no
    longer produced (a lower transfer order) are removed."""
    written = {}
    # Packed into the .blend (an unsaved file): all encoded up front, side by side.
    packed = not bpy.data.filepath
    encoded = dict(zip(images, bridge.encode_pngs(list(images.values())), strict=True)) if packed else {}
    for role, (rgba, color) in images.items():
        image = find_owned(bpy.data.images, obj.name, role)
        fresh = image is None
        name = image.name if image is not None else _image_name(role, obj)
        path, png = _image_path(name), encoded.get(role)
        image = bridge.write_image(bpy.data.images, name, rgba, color=color, image=image, path=path, png=png)
        if fresh:
            tag(image, obj.name, role)
            undo.created.append(image)
        written[role] = image
    for image in [im for im in bpy.data.images if im.get(OWNER) == obj.name]:
        if image.get(ROLE) not in written:
            bpy.data.images.remove(image)
    return written


def write_asset(obj, asset: pelt.FurAsset, *, build_material=None) -> dict:
    """Writes ``asset`` into ``obj`` and Pelt's datablocks; returns what was written and how long
    it took, for the report. ``build_material(obj, images, info, asset)`` adds the material and
    modifier (``None``: images and UVs only)."""
    images, info = prepare_images(asset)
    undo = _Undo()
    try:
        written = write_images(obj, images, undo)
        if build_material is not None:
            undo.created.extend(build_material(obj, written, info, asset))
        strands = guard_hairs.prepare(obj, asset.guard_hairs)
        if strands is not None:
            undo.created.append(strands)
        # Last: it checks the sizes before changing the mesh, and nothing after it can fail.
        bridge.write_patches(obj.data, asset.patches)
    except Exception:
        undo.restore()
        raise
    guard_hairs.commit(obj, strands)
    obj.pelt.last_bake = json.dumps({"stages": asset.report, "layers": info["layers"], **_summary(info)})
    return {"images": sorted(written), "info": info}


def note_scene_changes(obj, changes: list[str]) -> None:
    """Adds the scene settings the bake changed to ``obj``'s last-bake record (the panel shows
    them)."""
    record = json.loads(obj.pelt.last_bake or "{}")
    record["scene_changes"] = changes
    obj.pelt.last_bake = json.dumps(record)


def _summary(info: dict) -> dict:
    transfer = info.get("transfer")
    return {"transfer_order": transfer["order"] if transfer else None}
