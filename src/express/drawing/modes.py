"""Mode shapes: the model drawn displaced along an eigenvector, still or animated.

Mode ``N`` is the ``N``-th mode of :func:`express.analysis.stability.stability.eigen_analysis`
(1-based, least stable first: one per conjugate pair, sorted by descending real part).
Its displacement part ``phi`` (complex, shape (n,)) moves every body by
``q(t) = a Re(phi e^{i wt})`` (a flexible body's points also by its modal coordinates,
its outline bent: :func:`express.drawing.geometry.modal_offsets`); the scale ``a`` makes the largest point displacement
:data:`DISPLAY_FRACTION` of the drawing's size, so that every mode is visible.
"""

from __future__ import annotations

import base64
import html
import io
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from express.base.diagnostics import ArgumentError
from express.base.units import KMH
from express.drawing.geometry import ModelGeometry, displaced_geometry
from express.drawing.views import figure_model
from express.numeric.statespace import VehicleModel

__all__ = ["DISPLAY_FRACTION", "ModeShape", "animate_mode_shape", "figure_flexible_mode", "figure_mode_shape", "mode_shape"]

#: Largest displacement drawn, as a fraction of the drawing's size.
DISPLAY_FRACTION = 0.08


@dataclass(frozen=True)
class ModeShape:
    """One mode: ``eigenvalue`` [1/s] and the displacement part ``phi`` by DOF name."""

    number: int
    eigenvalue: complex
    phi: dict[str, complex]
    speed: float

    @property
    def frequency_hz(self) -> float:
        return abs(self.eigenvalue.imag) / (2.0 * np.pi)

    @property
    def damping_ratio(self) -> float:
        size = abs(self.eigenvalue)
        return float(-self.eigenvalue.real / size) if size > 0 else 0.0


def mode_shape(vehicle: VehicleModel, speed: float, number: int) -> ModeShape:
    """Mode ``number`` (1-based, the order of ``express eigen``) at ``speed`` [m/s].

    Raises
    ------
    ValueError
        If ``number`` is not between 1 and the number of modes.
    """
    values, vectors = np.linalg.eig(vehicle.state_matrix(float(speed)))
    keep = np.flatnonzero(values.imag >= 0.0)
    order = keep[np.lexsort((-values.imag[keep], -values.real[keep]))]
    if not 1 <= number <= order.size:
        raise ArgumentError(f"mode {number}: the model has modes 1 to {order.size} at this speed")
    index = order[number - 1]
    phi = vectors[: vehicle.n, index]
    largest = phi[np.argmax(np.abs(phi))]
    if abs(largest) > 0:
        phi = phi / largest  # real and 1 at the largest entry: a readable phase
    return ModeShape(number, complex(values[index]), dict(zip(vehicle.dofs, phi, strict=True)), float(speed))


def _largest_motion(geometry: ModelGeometry, dofs: dict[str, float]) -> float:
    """The largest displacement [m] of a point, a body centre or a bent outline's sample
    when the model moves by ``dofs``."""
    moved = displaced_geometry(geometry, dofs)
    largest = max((float(np.linalg.norm(np.subtract(moved.points[p], x))) for p, x in geometry.points.items()),
                  default=0.0)
    for body, shifted in zip(geometry.bodies, moved.bodies, strict=True):
        largest = max(largest, float(np.linalg.norm(np.subtract(shifted.centre, body.centre))),
                      *(max(abs(uy), abs(uz)) for _, uy, uz in shifted.bend))
    return largest


def _size(geometry: ModelGeometry) -> float:
    return geometry.span((1, 2)) if geometry.span((1, 2)) > 0.1 * geometry.span() else geometry.span()


def _scale(geometry: ModelGeometry, mode: ModeShape) -> float:
    largest = max(_largest_motion(geometry, {name: float(part(value)) for name, value in mode.phi.items()})
                  for part in (np.real, np.imag))
    return DISPLAY_FRACTION * _size(geometry) / largest if largest > 0 else 0.0


def figure_flexible_mode(geometry: ModelGeometry, coordinate: str):
    """The three views with a flexible body deformed by its free-free mode ``coordinate``
    (``CB.vb1``) alone, scaled to be seen, over the undeformed model (``express draw --mode``).

    Raises
    ------
    ArgumentError
        For a coordinate that is not a flexible body's mode (naming those there are).
    """
    mode = next((m for m in geometry.modes if m.coordinate == coordinate), None)
    if mode is None:
        known = ", ".join(m.coordinate for m in geometry.modes) or "none (the model has no flexible bodies)"
        raise ArgumentError(f"--mode {coordinate}: not a flexible body's mode; the modes are: {known}")
    largest = _largest_motion(geometry, {coordinate: 1.0})
    amplitude = DISPLAY_FRACTION * _size(geometry) / largest if largest > 0 else 0.0
    title = (f"{geometry.name}: {mode.label} ({coordinate}), f = {mode.frequency_hz:.3f} Hz free-free, "
             f"drawn at q = {amplitude:.3g} sqrt(kg) m")
    return figure_model(geometry, title=title, deformed=displaced_geometry(geometry, {coordinate: amplitude}))


def _displaced(geometry: ModelGeometry, mode: ModeShape, phase: float, scale: float) -> ModelGeometry:
    turn = np.exp(1j * phase)
    return displaced_geometry(geometry, {name: scale * float((value * turn).real) for name, value in mode.phi.items()})


def _title(geometry: ModelGeometry, mode: ModeShape, label: str) -> str:
    speed = f" at {mode.speed / KMH:.0f} km/h" if np.isfinite(mode.speed) else ""
    what = f": {label}" if label else ""
    return (f"{geometry.name}, mode {mode.number}{what}{speed} — f = {mode.frequency_hz:.3f} Hz, "
            f"damping ratio {mode.damping_ratio:.3f}")


def figure_mode_shape(geometry: ModelGeometry, mode: ModeShape, label: str = ""):
    """The three views with the mode's displaced shape over the undisplaced model."""
    scale = _scale(geometry, mode)
    return figure_model(geometry, title=_title(geometry, mode, label), deformed=_displaced(geometry, mode, 0.0, scale))


def animate_mode_shape(geometry: ModelGeometry, mode: ModeShape, suffix: str, label: str = "", frames: int = 24) -> bytes:
    """One period of the mode as an animated GIF (``suffix == ".gif"``) or a
    self-contained HTML page (``".html"``), returned as bytes."""
    from matplotlib.animation import FuncAnimation, PillowWriter

    from express.drawing.views import draw_view

    if suffix not in (".gif", ".html"):
        raise ArgumentError(f"animation format {suffix!r}: use .gif or .html")
    scale = _scale(geometry, mode)
    figure = figure_model(geometry, title=_title(geometry, mode, label))
    axes = figure.axes
    limits = [(axis.get_xlim(), axis.get_ylim()) for axis in axes]

    def frame(k: int):
        shape = _displaced(geometry, mode, 2.0 * np.pi * k / frames, scale)
        for axis, view, (xlim, ylim) in zip(axes, ("plan", "side", "end"), limits, strict=True):
            axis.clear()
            draw_view(axis, geometry, view, alpha=0.25, labels=False, limits=(xlim, ylim))
            draw_view(axis, shape, view, labels=False, limits=(xlim, ylim))
        return []

    if suffix == ".html":
        pictures = []
        for k in range(frames):
            frame(k)
            buffer = io.BytesIO()
            figure.savefig(buffer, format="png", dpi=60, metadata={"Software": None})
            pictures.append(base64.b64encode(buffer.getvalue()).decode("ascii"))
        return _html_animation(_title(geometry, mode, label), pictures).encode("utf-8")
    animation = FuncAnimation(figure, frame, frames=frames, interval=80, blit=False)
    with tempfile.TemporaryDirectory(prefix="express-gif-") as folder:
        path = Path(folder) / "mode.gif"
        figure.set_dpi(60)
        animation.save(path, writer=PillowWriter(fps=12))
        return path.read_bytes()


def _html_animation(title: str, pictures: list[str]) -> str:
    """A self-contained page cycling through base64 PNG frames (no network, no library)."""
    frames = ",\n".join(f'"data:image/png;base64,{p}"' for p in pictures)
    safe = html.escape(title)
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{safe}</title></head>
<body style="font-family: sans-serif">
<h1 style="font-size: 1rem">{safe}</h1>
<img id="mode" alt="{safe}" src="{pictures[0] and 'data:image/png;base64,' + pictures[0]}">
<script>
const frames = [{frames}];
let k = 0;
setInterval(() => {{ k = (k + 1) % frames.length; document.getElementById("mode").src = frames[k]; }}, 80);
</script>
</body></html>
"""
