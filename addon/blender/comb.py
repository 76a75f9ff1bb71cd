# SPDX-License-Identifier: GPL-3.0-or-later
"""The Comb operator (Lengyel et al. 2001, §3): lean the hair by dragging a circle over the mesh.

Interactive (invoked from the 3D viewport): a circle follows the mouse, the wheel sizes it, and
dragging with the left button adds the drag, moved to each vertex's depth and projected into its
tangent plane, to ``pelt_comb`` of the vertices inside, with a smooth falloff. Each stroke is one
undo step; Esc or right-click puts the comb back as it was when the operator started.

Non-interactive (``execute``, for scripts and tests): one stroke with an object-space sphere,
``center``, ``radius`` and ``delta``.
"""

import bpy
import numpy as np
import pelt

from ..io import comb_math
from ..io.names import COMB
from . import comb_draw, point_data
from .point_data import TargetError

# Events the comb lets through to the viewport, so the view can still be turned and zoomed.
NAVIGATION = {
    "MIDDLEMOUSE", "TRACKPADPAN", "TRACKPADZOOM", "MOUSEROTATE", "MOUSESMARTZOOM",
    "NDOF_MOTION", "NUMPAD_1", "NUMPAD_2", "NUMPAD_3", "NUMPAD_4", "NUMPAD_5", "NUMPAD_6",
    "NUMPAD_7", "NUMPAD_8", "NUMPAD_9", "NUMPAD_PERIOD", "NUMPAD_PLUS", "NUMPAD_MINUS",
}  # fmt: skip
FINISH = {"RET", "NUMPAD_ENTER", "SPACE"}
CANCEL = {"ESC", "RIGHTMOUSE"}
GROW = {"WHEELUPMOUSE", "RIGHT_BRACKET"}
SHRINK = {"WHEELDOWNMOUSE", "LEFT_BRACKET"}
RADIUS_STEP = 1.1
UNDO_MESSAGE = "Pelt Comb"


def screen_view(region, region_3d) -> comb_math.ScreenView:
    """The projection of a 3D viewport region, as ``comb_math`` takes it."""
    return comb_math.ScreenView(
        window=np.array(region_3d.window_matrix, dtype=np.float64),
        view=np.array(region_3d.view_matrix, dtype=np.float64),
        width=region.width,
        height=region.height,
        is_perspective=region_3d.is_perspective,
    )


def viewport_region(context):
    """The 3D viewport region to comb in and its view, ``(region, region_3d)``: the region the
    operator runs in when it is a viewport, else (a button in the sidebar) the main viewport of
    its 3D View area (the last WINDOW region, which quad view keeps for the free view), or
    ``(None, None)`` outside a 3D View."""
    area = context.area
    if area is None or area.type != "VIEW_3D":
        return None, None
    if context.region is not None and context.region.type == "WINDOW" and context.region_data is not None:
        return context.region, context.region_data
    windows = [r for r in area.regions if r.type == "WINDOW"]
    return (windows[-1], area.spaces.active.region_3d) if windows else (None, None)


class CombSession:
    """The comb of one object during an interactive Comb.

    Holds the comb as it was at the start (what ``restore`` puts back, bit for bit; ``None`` when
    the attribute did not exist, so ``restore`` removes it again), the vertex data a dab needs
    (read once: the mesh cannot change while the operator runs) and the stroke count."""

    def __init__(self, obj):
        mesh = obj.data
        self.obj = obj
        self.created = COMB not in mesh.attributes
        self.note = point_data.ensure_point_attribute(obj, COMB, "FLOAT_VECTOR", 0.0)
        self.original = None if self.created else point_data.read_point(mesh, COMB)
        self.comb = point_data.read_point(mesh, COMB)
        self.normals = point_data.normals(mesh)
        matrix = np.array(obj.matrix_world, dtype=np.float64)
        self.linear = matrix[:3, :3]
        self.world_to_object = np.linalg.inv(self.linear)
        self.world = point_data.positions(mesh) @ self.linear.T + matrix[:3, 3]
        # normals transform with the inverse transpose
        self.world_normals = comb_math.unit_rows(self.normals @ self.world_to_object)
        edge_ends = self.world[point_data.edges(mesh)]
        self.arrow_size = (
            float(np.linalg.norm(edge_ends[:, 1] - edge_ends[:, 0], axis=1).mean()) if len(edge_ends) else 0.1
        )
        self.strokes = 0
        self.undo_steps = 0
        self.stroking = False
        self.segments = self._segments()

    def _segments(self) -> np.ndarray:
        return comb_draw.comb_segments(
            self.world, self.world_normals, self.comb @ self.linear.T, self.arrow_size
        )

    def begin_stroke(self) -> None:
        """A stroke starts. The previous stroke becomes its own undo step here, and the last one
        becomes the operator's own step when it finishes, so every stroke is one step."""
        if self.strokes > 0:
            bpy.ops.ed.undo_push(message=UNDO_MESSAGE)
            self.undo_steps += 1
        self.stroking = True

    def dab(self, view, mouse, drag, radius_px: float, strength: float, front_only: bool) -> int:
        """Combs with the circle at ``mouse`` dragged by ``drag`` pixels; returns how many vertices
        it moved."""
        indices, deltas, weights = comb_math.screen_dab(
            view, self.world, self.world_normals, self.world_to_object, mouse, drag, radius_px, front_only
        )
        if len(indices) == 0:
            return 0
        self.comb = comb_math.add_tangential(self.comb, self.normals, indices, deltas, weights * strength)
        point_data.write_point(self.obj.data, COMB, self.comb)
        self.segments = self._segments()
        return len(indices)

    def end_stroke(self) -> None:
        if self.stroking:
            self.stroking = False
            self.strokes += 1

    def restore(self) -> None:
        """Puts the comb back as it was when the session began. If strokes were already pushed as
        undo steps, the restored state becomes one too, so undo never brings back a state that
        differs from what the user saw last."""
        mesh = self.obj.data
        if self.created:
            mesh.attributes.remove(mesh.attributes[COMB])
            mesh.update()
        else:
            point_data.write_point(mesh, COMB, self.original)
        self.comb = self.original
        if self.undo_steps:
            bpy.ops.ed.undo_push(message=f"{UNDO_MESSAGE} Cancelled")


class PELT_OT_comb(bpy.types.Operator):
    """Comb the fur: drag inside the circle to lean the hair along the drag (wheel: size;
    Enter/Space: done; Esc/right-click: put the comb back as it was)"""

    bl_idname = "pelt.comb"
    bl_label = "Comb"
    bl_options = {"REGISTER", "UNDO"}

    center: bpy.props.FloatVectorProperty(
        name="Center",
        description="Center of the brush sphere, object space (scripted strokes)",
        subtype="XYZ",
        size=3,
    )
    radius: bpy.props.FloatProperty(
        name="Radius",
        description="Radius of the brush sphere, object-space distance (scripted strokes)",
        default=0.5,
        min=0.0,
        soft_max=10.0,
        subtype="DISTANCE",
    )
    delta: bpy.props.FloatVectorProperty(
        name="Delta",
        description="Comb added at the center, object space; its part in each vertex's tangent "
        "plane is used (length 1 leans the hair by 45°) (scripted strokes)",
        subtype="XYZ",
        size=3,
    )
    strength: bpy.props.FloatProperty(
        name="Strength",
        description="Scale of every change the brush makes",
        default=1.0,
        min=0.0,
        soft_max=1.0,
        max=10.0,
        subtype="FACTOR",
    )
    screen_radius: bpy.props.FloatProperty(
        name="Screen Radius",
        description="Radius of the interactive brush circle in pixels (mouse wheel changes it)",
        default=60.0,
        min=2.0,
        max=2000.0,
        subtype="PIXEL",
    )
    front_only: bpy.props.BoolProperty(
        name="Front Faces Only",
        description="The interactive brush leaves vertices whose normal faces away from the view",
        default=True,
    )
    interactive: bpy.props.BoolProperty(
        name="Interactive",
        description="Set while the comb runs in the viewport: its strokes cannot be repeated",
        default=False,
        options={"HIDDEN", "SKIP_SAVE"},
    )

    @classmethod
    def poll(cls, context):
        return context.active_object is not None

    def draw(self, context):
        layout = self.layout
        if self.interactive:
            layout.label(text="Undo strokes one by one with Ctrl+Z")
            return
        for name in ("center", "radius", "delta", "strength"):
            layout.prop(self, name)

    def execute(self, context):
        if self.interactive:
            self.report({"WARNING"}, "Pelt: an interactive comb cannot be repeated")
            return {"CANCELLED"}
        try:
            obj = point_data.active_mesh_object(context)
            point_data.check_convertible(obj, COMB)
            with point_data.object_mode(obj):
                note = point_data.ensure_point_attribute(obj, COMB, "FLOAT_VECTOR", 0.0)
                mesh = obj.data
                comb, inside = comb_math.sphere_stroke(
                    point_data.read_point(mesh, COMB),
                    point_data.positions(mesh),
                    point_data.normals(mesh),
                    self.center,
                    self.radius,
                    self.delta,
                    self.strength,
                )
                point_data.write_point(mesh, COMB, comb)
        except (TargetError, pelt.PeltError, RuntimeError) as error:
            self.report({"ERROR"}, f"Pelt: {error}")
            return {"CANCELLED"}
        if note:
            self.report({"WARNING"}, f"Pelt: {obj.name}: {note}")
        self.report({"INFO"}, f"Pelt: {obj.name}: combed {len(inside)} vertices")
        return {"FINISHED"}

    def invoke(self, context, event):
        self._region, self._region_3d = viewport_region(context)
        if self._region is None:
            self.report({"ERROR"}, "Pelt: Comb runs in the 3D Viewport (scripts: give center, radius, delta)")
            return {"CANCELLED"}
        try:
            obj = point_data.active_mesh_object(context)
            if obj.mode == "EDIT":
                raise TargetError("leave Edit Mode to comb")
            point_data.check_convertible(obj, COMB)
            self._session = CombSession(obj)
        except (TargetError, pelt.PeltError, RuntimeError) as error:
            self.report({"ERROR"}, f"Pelt: {error}")
            return {"CANCELLED"}
        if self._session.note:
            self.report({"WARNING"}, f"Pelt: {obj.name}: {self._session.note}")
        self.interactive = True
        self._mouse = self._region_mouse(event)
        self._handlers = (
            bpy.types.SpaceView3D.draw_handler_add(self._draw_circle, (), "WINDOW", "POST_PIXEL"),
            bpy.types.SpaceView3D.draw_handler_add(self._draw_comb, (), "WINDOW", "POST_VIEW"),
        )
        context.window_manager.modal_handler_add(self)
        self._show_status(context)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        session = self._session
        if event.type in NAVIGATION:
            return {"PASS_THROUGH"}
        context.area.tag_redraw()
        if event.type == "MOUSEMOVE":
            mouse = self._region_mouse(event)
            if session.stroking:
                view = screen_view(self._region, self._region_3d)
                session.dab(
                    view, self._mouse, mouse - self._mouse, self.screen_radius, self.strength, self.front_only
                )
            self._mouse = mouse
        elif event.type == "LEFTMOUSE":
            if event.value == "PRESS":
                session.begin_stroke()
            elif event.value == "RELEASE":
                session.end_stroke()
        elif event.type in GROW | SHRINK and event.value in {"PRESS", "NOTHING"}:
            factor = RADIUS_STEP if event.type in GROW else 1.0 / RADIUS_STEP
            self.screen_radius = float(np.clip(self.screen_radius * factor, 2.0, 2000.0))
            self._show_status(context)
        elif event.type in CANCEL and event.value == "PRESS":
            session.restore()
            self._finish(context)
            self.report({"INFO"}, "Pelt: comb put back as it was")
            return {"CANCELLED"}
        elif event.type in FINISH and event.value == "PRESS":
            session.end_stroke()
            self._finish(context)
            self.report({"INFO"}, f"Pelt: {session.obj.name}: {session.strokes} comb strokes")
            return {"FINISHED"}
        return {"RUNNING_MODAL"}

    def _region_mouse(self, event) -> np.ndarray:
        # window coordinates: the operator may start from the sidebar, and events keep its region
        return np.array([event.mouse_x - self._region.x, event.mouse_y - self._region.y], dtype=np.float64)

    def _show_status(self, context):
        text = (
            f"Comb  radius {self.screen_radius:.0f} px  strength {self.strength:.2f}  |  "
            "LMB drag: comb   Wheel: radius   Enter/Space: done   Esc/RMB: cancel"
        )
        context.area.header_text_set(text)
        context.workspace.status_text_set(text)

    def _finish(self, context):
        for handler in self._handlers:
            bpy.types.SpaceView3D.draw_handler_remove(handler, "WINDOW")
        context.area.header_text_set(None)
        context.workspace.status_text_set(None)
        context.area.tag_redraw()

    def _draw_circle(self):
        # POST_PIXEL handlers run for every 3D viewport; the circle belongs to the combed one
        if bpy.context.region == self._region:
            comb_draw.draw_circle(self._region, self._mouse, self.screen_radius)

    def _draw_comb(self):
        comb_draw.draw_lines(self._session.segments)


CLASSES = (PELT_OT_comb,)
