"""Figures only the report draws: the EN 14363 running-safety quantities against their
limits, and the mode shapes of the least-damped and the hunting modes."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from express.drawing.geometry import ModelGeometry
from express.drawing.modes import figure_mode_shape, mode_shape
from express.numeric.statespace import VehicleModel

__all__ = ["figure_assessment", "mode_figures"]


def figure_assessment(criteria: Sequence[Any], *, title: str = "EN 14363 running safety", ax=None):
    """Each criterion with a limit as ``value / limit`` (bars; 1 is the limit).

    Parameters
    ----------
    criteria : sequence of Criterion
        :class:`express.analysis.curving.assessment.Criterion` (``name``, ``value``,
        ``limit``, ``passed``); those without a limit are left out.
    ax : matplotlib.axes.Axes, optional
        Draw into this axes and return it (the figure's layout is then the caller's); by
        default a new figure is made and returned.

    Returns
    -------
    matplotlib.figure.Figure, matplotlib.axes.Axes or None
        None when no criterion has a limit; ``ax`` when given.
    """
    from express.analysis.plots import axes_for

    rated = [c for c in criteria if c.limit]
    if not rated:
        return None
    figure, axis = axes_for(ax, figsize=(7.2, 1.2 + 0.28 * len(rated)))
    ratios = [c.value / c.limit for c in rated]
    colours = ["#2a7ab9" if c.passed else "#c0392b" for c in rated]
    axis.barh(range(len(rated)), ratios, color=colours)
    axis.axvline(1.0, color="#c0392b", linestyle="--", linewidth=1.0, label="limit")
    axis.set_yticks(range(len(rated)), [c.name for c in rated], fontsize="small")
    axis.invert_yaxis()
    axis.set_xlabel("value / limit [-]")
    axis.set_xlim(0.0, max(1.1, 1.05 * max(ratios)))
    axis.set_title(title)
    axis.legend(loc="lower right")
    if ax is not None:
        return ax
    figure.tight_layout()
    return figure


def mode_figures(vehicle: VehicleModel, geometry: ModelGeometry, speed: float, modes: Sequence[Any]) -> list[tuple[Any, str]]:
    """``(figure, caption)`` of the least-damped mode and, when another, of the first
    hunting mode and of a flexible body's first mode (its first bending, else its first
    torsion: the body drawn deformed) (``modes``:
    :attr:`express.analysis.modes.modes.EigenResult.modes`, least stable first; numbered as
    ``express eigen``)."""
    chosen = [(1, "least-damped mode")]
    hunting = next((k for k, mode in enumerate(modes, start=1) if mode.kind.startswith("hunting")), None)
    if hunting is not None and hunting != 1:
        chosen.append((hunting, "hunting mode"))
    elif hunting == 1:
        chosen[0] = (1, "least-damped mode, hunting")
    if geometry.modes:  # a flexible body: its first bending (else torsion) mode, drawn deformed
        flexible = [k for k, mode in enumerate(modes, start=1) if mode.kind.endswith(" bending")]
        flexible = flexible or [k for k, mode in enumerate(modes, start=1) if " torsion" in mode.kind]
        if flexible and all(flexible[0] != k for k, _ in chosen):
            chosen.append((min(flexible, key=lambda k: modes[k - 1].frequency_hz), "flexible body's first mode"))
    figures = []
    for number, what in chosen:
        mode = modes[number - 1]
        figure = figure_mode_shape(geometry, mode_shape(vehicle, speed, number), mode.kind)
        figures.append((figure, f"Mode {number}, the {what}: {mode.describe()}, {mode.frequency_hz:.3f} Hz, "
                                f"damping ratio {mode.damping_ratio:.3f} (displaced shape over the model)."))
    return figures
