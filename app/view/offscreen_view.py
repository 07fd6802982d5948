"""A 3D view that renders offscreen and shows the picture in a plain widget.

Why not :class:`pyvistaqt.QtInteractor`: it is a ``QOpenGLWidget``, and one OpenGL widget
turns its whole top-level window into an OpenGL surface — Qt then composes the entire
window (every dock, every pyqtgraph repaint) through OpenGL. On a machine without a GPU
that is Mesa's llvmpipe, and it cost more than the 3D render itself (issue 14: 42–58 ms of
the main thread and ~300 ms of the GUI process's CPU per shown frame on office.json).

Here the scene renders into an offscreen VTK render window (the same llvmpipe, but only
the 3D view's own pixels, only when the scene changed), is read back once per render and
drawn by :class:`OffscreenCanvas`, a plain raster ``QWidget``; the main window stays a
raster window. The canvas forwards mouse and wheel events to a
``vtkGenericRenderWindowInteractor`` so interactor styles, observers, picking and
pyvista's widgets (the transform gizmo) work as in an on-screen plotter. Renders asked for
by the interactor style (orbit, zoom) or by pyvista widgets are merged: at most one render
per repaint of the canvas.

A change (a new frame, an edit, a drag, orbiting) renders at :data:`INTERACTIVE_SCALE` of
the view's resolution, with text, points and lines scaled to keep their on-screen size,
and the picture is drawn stretched; :data:`SETTLE_S` after the last such render it renders
once more at full resolution. On software OpenGL much of a render is per pixel
(office.json at 632 × 586: 22 ms; at half the width and height: 11 ms).

Key events are not forwarded: the view's keys are the window's Qt shortcuts, and VTK's
default keys (``q`` quits, ``w`` wireframe, ``3`` stereo…) do not belong in the app.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
import pyvista as pv
from PyQt6.QtCore import QPointF, QRectF, QSize, Qt, QTimer
from PyQt6.QtGui import QImage, QMouseEvent, QPainter, QWheelEvent
from PyQt6.QtWidgets import QSizePolicy, QWidget
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkUnsignedCharArray

#: Fraction of the width and height of the view's first render after a change.
INTERACTIVE_SCALE = 0.5
#: This long (s) after the last reduced render, the view renders again at full resolution.
SETTLE_S = 0.3


class OffscreenPlotter(pv.Plotter):
    """A pyvista plotter whose ``render()`` asks the canvas for a repaint.

    pyvista's widgets call ``render()`` after every change (the gizmo on every mouse
    move); here that schedules one render with the canvas's next repaint instead of
    rendering at once. :meth:`render_now` renders at once (screenshots, picking checks).

    Attributes
    ----------
    interactor : OffscreenCanvas
        The Qt widget that shows the picture and takes the mouse (the same attribute name
        as :class:`pyvistaqt.QtInteractor`'s widget).
    """

    def __init__(self, canvas: OffscreenCanvas, *, size: tuple[int, int]):
        self.interactor = canvas
        self._sync_render = False
        super().__init__(off_screen=True, window_size=list(size))
        self._first_time = False  # pyvista renders only after show(); this view is shown
        # No anti-aliasing (pyvista's theme asks for 8× MSAA): on software OpenGL (Mesa
        # llvmpipe) it multiplied the render time by 2.5–3.
        self.disable_anti_aliasing()
        self.render_window.SetMultiSamples(0)
        # Translucent actors blended in depth-sorted order, not with VTK's order-independent
        # translucency: its extra full-window float passes doubled the render time on
        # llvmpipe (158 → 75 ms for office.json at 1320×835).
        self.renderer.SetUseOIT(False)

    def render(self) -> None:  # noqa: D102 - pyvista API, deferred to the canvas repaint
        if self._sync_render:
            super().render()
        else:
            self.interactor.request_render()

    def render_now(self) -> None:
        """Render into the offscreen window at once (the canvas shows it on its repaint)."""
        self._sync_render = True
        try:
            super().render()
        finally:
            self._sync_render = False

    def screenshot(self, *args: Any, **kwargs: Any) -> Any:  # noqa: D102 - pyvista API
        self._sync_render = True
        try:
            return super().screenshot(*args, **kwargs)
        finally:
            self._sync_render = False


class OffscreenCanvas(QWidget):
    """Plain widget showing an :class:`OffscreenPlotter`'s picture; forwards the mouse.

    ``on_render`` (optional) is called before each render the canvas makes (the viewport
    uses it to count renders and to keep the cut-away of walls current).
    """

    def __init__(self, parent: QWidget | None = None, *,
                 on_render: Callable[[], None] | None = None):
        super().__init__(parent)
        self.setAttribute(Qt.WidgetAttribute.WA_OpaquePaintEvent)
        self.setMouseTracking(True)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Expanding)
        self._on_render = on_render
        self._dirty = True
        self._image: QImage | None = None
        self._pixels = vtkUnsignedCharArray()
        self._buffer: np.ndarray | None = None
        self._button: Qt.MouseButton | None = None
        self._wheel = 0
        self._closed = False
        #: The scale of the picture shown (1.0: full resolution).
        self.scale = 1.0
        self._settle = QTimer(self)
        self._settle.setSingleShot(True)
        self._settle.timeout.connect(self._refine)
        self._refining = False
        self.plotter = OffscreenPlotter(self, size=self._device_size())
        iren = self.plotter.iren.interactor
        # The style's "render now" becomes a request: one render per repaint.
        iren.EnableRenderOff()
        iren.AddObserver("RenderEvent", lambda *_: self.request_render())
        iren.Initialize()

    # --- rendering --------------------------------------------------------------------
    def sizeHint(self) -> QSize:  # noqa: D102 - Qt API
        return QSize(640, 480)

    def request_render(self) -> None:
        """Render with the next repaint (Qt merges repaint requests)."""
        if self._closed:
            return
        self._dirty = True
        self.update()

    def _refine(self) -> None:
        self._refining = True
        self.request_render()

    def _device_size(self) -> tuple[int, int]:
        ratio = self.devicePixelRatioF()
        return max(int(round(self.width() * ratio)), 1), max(int(round(self.height() * ratio)), 1)

    def _render_and_read(self) -> None:
        if self._on_render is not None:
            self._on_render()
        # A change shows at once at reduced size (a quarter of the pixels: the panels and
        # the 3D view are current sooner after an edit, and playback or a drag keeps its
        # rate); SETTLE_S after the last such render, one full render refines it.
        scale = 1.0 if self._refining or self._image is None else INTERACTIVE_SCALE
        self._refining = False
        win = self.plotter.render_window
        with _scaled(self.plotter, scale):
            self.plotter.render_now()
            w, h = win.GetSize()
            win.GetPixelData(0, 0, w - 1, h - 1, 0, self._pixels, 0)
        rgb = vtk_to_numpy(self._pixels).reshape(h, w, 3)
        # VTK's rows run bottom-up, Qt's top-down; the copy keeps the buffer alive.
        self._buffer = np.ascontiguousarray(rgb[::-1])
        image = QImage(self._buffer.data, w, h, 3 * w, QImage.Format.Format_RGB888)
        self._image = image
        self._dirty = False
        self.scale = scale
        if scale < 1.0:
            self._settle.start(int(SETTLE_S * 1e3))

    def paintEvent(self, _event: Any) -> None:  # noqa: N802, D102 - Qt API
        if self._closed:
            return
        if self._dirty or self._image is None:
            self._render_and_read()
        painter = QPainter(self)
        painter.setRenderHint(QPainter.RenderHint.SmoothPixmapTransform, self.scale < 1.0)
        if self._image is not None:
            painter.drawImage(QRectF(self.rect()), self._image)
        painter.end()

    def resizeEvent(self, event: Any) -> None:  # noqa: N802, D102 - Qt API
        super().resizeEvent(event)
        if self._closed:
            return
        w, h = self._device_size()
        self.plotter.render_window.SetSize(w, h)
        self.plotter.iren.interactor.SetSize(w, h)
        self.plotter.iren.interactor.ConfigureEvent()
        self.request_render()

    def close_canvas(self) -> None:
        """Release the VTK window (idempotent)."""
        if self._closed:
            return
        self._closed = True
        self._image = None
        self._settle.stop()
        self.plotter.close()

    # --- input ------------------------------------------------------------------------
    def _set_event(self, pos: QPointF, modifiers: Qt.KeyboardModifier, *, repeat: int = 0) -> None:
        ratio = self.devicePixelRatioF()
        ctrl = bool(modifiers & Qt.KeyboardModifier.ControlModifier)
        shift = bool(modifiers & Qt.KeyboardModifier.ShiftModifier)
        self.plotter.iren.interactor.SetEventInformation(
            int(round(pos.x() * ratio)), int(round((self.height() - pos.y() - 1) * ratio)),
            int(ctrl), int(shift), "\0", repeat, None)

    def mousePressEvent(self, event: QMouseEvent) -> None:  # noqa: N802, D102 - Qt API
        if self._closed:
            return
        repeat = 1 if event.type() == event.Type.MouseButtonDblClick else 0
        self._set_event(event.position(), event.modifiers(), repeat=repeat)
        iren = self.plotter.iren.interactor
        self._button = event.button()
        if self._button == Qt.MouseButton.LeftButton:
            iren.LeftButtonPressEvent()
        elif self._button == Qt.MouseButton.RightButton:
            iren.RightButtonPressEvent()
        elif self._button == Qt.MouseButton.MiddleButton:
            iren.MiddleButtonPressEvent()

    def mouseReleaseEvent(self, event: QMouseEvent) -> None:  # noqa: N802, D102 - Qt API
        if self._closed:
            return
        self._set_event(event.position(), event.modifiers())
        iren = self.plotter.iren.interactor
        button, self._button = self._button, None
        if button == Qt.MouseButton.LeftButton:
            iren.LeftButtonReleaseEvent()
        elif button == Qt.MouseButton.RightButton:
            iren.RightButtonReleaseEvent()
        elif button == Qt.MouseButton.MiddleButton:
            iren.MiddleButtonReleaseEvent()

    def mouseMoveEvent(self, event: QMouseEvent) -> None:  # noqa: N802, D102 - Qt API
        if self._closed:
            return
        self._set_event(event.position(), event.modifiers())
        self.plotter.iren.interactor.MouseMoveEvent()

    def wheelEvent(self, event: QWheelEvent) -> None:  # noqa: N802, D102 - Qt API
        if self._closed:
            return
        self._set_event(event.position(), event.modifiers())
        self._wheel += event.angleDelta().y()
        iren = self.plotter.iren.interactor
        while self._wheel >= 120:
            iren.MouseWheelForwardEvent()
            self._wheel -= 120
        while self._wheel <= -120:
            iren.MouseWheelBackwardEvent()
            self._wheel += 120


@contextmanager
def _scaled(plotter: pv.Plotter, scale: float) -> Iterator[None]:
    """Render ``plotter``'s window at ``scale`` of its size, text, points and lines alike.

    The window, its DPI (text) and every actor's point size and line width are scaled and
    restored afterwards: picking and the interactor keep working in full-size pixels.
    """
    if scale == 1.0:
        yield
        return
    win = plotter.render_window
    size, dpi = win.GetSize(), win.GetDPI()
    props = []
    renderers = win.GetRenderers()
    for r in range(renderers.GetNumberOfItems()):
        actors = renderers.GetItemAsObject(r).GetActors()
        for a in range(actors.GetNumberOfItems()):
            prop = actors.GetItemAsObject(a).GetProperty()
            props.append((prop, prop.GetPointSize(), prop.GetLineWidth()))
    win.SetSize(max(int(size[0] * scale), 1), max(int(size[1] * scale), 1))
    win.SetDPI(max(int(round(dpi * scale)), 1))
    for prop, point, line in props:
        prop.SetPointSize(max(point * scale, 1.0))
        prop.SetLineWidth(max(line * scale, 1.0))
    try:
        yield
    finally:
        win.SetSize(*size)
        win.SetDPI(dpi)
        for prop, point, line in props:
            prop.SetPointSize(point)
            prop.SetLineWidth(line)
