"""Draw docs/figures/ride_weightings.png: the comfort weightings of express.analysis.ride.

Run from the repository root: ``python docs/figures/ride_weightings.py``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from express.analysis.ride import WB, WC, WD, WK, sperling_weighting

# ISO 2631-1:1997 tables 3 and 4 (x 1000) at a few nominal frequencies, as markers
TABLE_F = np.array([0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0])
TABLE = {
    "Wd": np.array([62.4, 243, 853, 1011, 890, 409, 202, 100, 38.8]) / 1000,
    "Wk": np.array([31.2, 121, 418, 482, 531, 1039, 988, 636, 246]) / 1000,
}


def weightings_figure() -> Figure:
    """Two panels: EN 12299 / ISO 2631 weightings, and Sperling's B(f)."""
    fig = Figure(figsize=(10, 4.2), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    f = np.logspace(-1, 2.3, 600)
    for weighting, style in ((WB, "-"), (WD, "-"), (WC, "-"), (WK, "--")):
        ax1.loglog(f, weighting.magnitude(f), style, label=weighting.name)
    for values in TABLE.values():
        ax1.loglog(TABLE_F, values, "o", mfc="none", color="k", ms=5)
    ax1.plot([], [], "o", mfc="none", color="k", label="ISO 2631-1 table")
    ax1.set(xlabel="frequency f [Hz]", ylabel="|W(i 2 pi f)|", title="EN 12299 / ISO 2631 weightings", ylim=(1e-2, 2))
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend()
    f2 = np.logspace(-1, np.log10(40), 400)
    ax2.semilogx(f2, sperling_weighting(f2, "vertical"), label="B_z (vertical)")
    ax2.semilogx(f2, sperling_weighting(f2, "lateral"), label="B_y (lateral) = 1.25 B_z")
    ax2.axvspan(0.5, 30, color="0.9", zorder=0, label="Wz band 0.5-30 Hz")
    ax2.set(xlabel="frequency f [Hz]", ylabel="B(f)", title="Sperling's weighting")
    ax2.grid(True, which="both", alpha=0.3)
    ax2.legend()
    return fig


if __name__ == "__main__":
    out = Path(__file__).with_name("ride_weightings.png")
    weightings_figure().savefig(out, dpi=110, metadata={"Software": None})
    print(out)
