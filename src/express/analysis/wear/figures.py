"""The figures of a wear prediction: the quantities against mileage (``wear.png``) and the
profiles with the depth worn off them (``profiles.png``)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from express.analysis.plots import STYLE, new_figure, save_figure
from express.base.units import KMH

__all__ = ["figure_profiles", "figure_wear", "save_wear_figures"]


def figure_wear(rows: Sequence[dict]):
    """Equivalent conicity, linear critical speed, flange thickness Sd and height Sh
    (and qR) against the distance run (``rows`` of ``wear.csv``, SI)."""
    figure, axes = new_figure(2, 2, figsize=(9.0, 6.0), sharex=True)
    km = np.array([row["distance"] for row in rows]) / 1e3
    panels = ((axes[0, 0], "conicity", 1.0, "equivalent conicity (EN 15302) [-]"),
              (axes[0, 1], "critical_speed", 1.0 / KMH, "linear critical speed [km/h]"),
              (axes[1, 0], "flange_thickness", 1e3, "flange thickness Sd [mm]"),
              (axes[1, 1], "flange_height", 1e3, "flange height Sh, slope qR [mm]"))
    for axis, name, scale, label in panels:
        axis.plot(km, [row[name] * scale for row in rows], "o-", label=label.split(" [")[0].split(",")[0])
        axis.set_ylabel(label)
    axes[1, 1].plot(km, [row["flange_slope"] * 1e3 for row in rows], "s--", label="qR")
    axes[1, 1].legend()
    for axis in axes[1]:
        axis.set_xlabel("distance run [km]")
    figure.tight_layout()
    return figure


def figure_profiles(y: np.ndarray, heights: Sequence[np.ndarray], distances: Sequence[float]):
    """The wheel profile at every step (``heights`` [m] on ``y`` [m], side frame) and the
    depth worn off it since the start, against the lateral position."""
    figure, (top, bottom) = new_figure(2, 1, figsize=(8.0, 7.0), sharex=True)
    colours = [f"C{k % 10}" for k in range(len(heights))]
    for z, distance, colour in zip(heights, distances, colours, strict=True):
        top.plot(y * 1e3, -z * 1e3, color=colour, lw=0.8, label=f"{distance / 1e3:.4g} km")
        bottom.plot(y * 1e3, (z - heights[0]) * 1e3, color=colour, lw=0.8)
    top.set_ylabel("profile height above the taping line [mm]")
    bottom.set_ylabel("depth worn off [mm]")
    bottom.set_xlabel("lateral position from the taping line, toward the field side [mm]")
    if len(heights) <= 12:
        top.legend(fontsize="small", ncol=2)
    figure.tight_layout()
    return figure


def save_wear_figures(directory: Path, rows: Sequence[dict], y: np.ndarray, heights: Sequence[np.ndarray]) -> None:
    """``wear.png`` and ``profiles.png`` in ``directory`` (through the active output
    transaction); ``heights`` the profiles of the rows' steps on the nodes ``y`` [m]."""
    import matplotlib

    with matplotlib.rc_context(STYLE):
        wear = figure_wear(rows)
        profiles = figure_profiles(y, heights, [row["distance"] for row in rows])
    save_figure(wear, directory / "wear.png")
    save_figure(profiles, directory / "profiles.png")
