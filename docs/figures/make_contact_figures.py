#!/usr/bin/env python3
"""Make the contact figures of docs/contact.md (run from the repository root):

    PYTHONPATH=src python3 docs/figures/make_contact_figures.py

* contact_geometry_s1002_60e1.png and conicity_s1002_60e1.png: what
  ``express contact-geometry`` and ``express conicity --plot`` draw for S1002 on 60E1,
  1:40, 1435 mm gauge, 1360 mm flange back;
* conicity_en15302_reference.png: the nine EN 15302 reference cases, computed against
  the standard's results and tolerance band.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from express.analysis.plots import STYLE, save_figure
from express.cli import main
from express.base.diagnostics import ModelError
from express.rail.conicity import equivalent_conicity, parse_delta_r

HERE = Path(__file__).resolve().parent


def reference_figure() -> Figure:
    folder = resources.files("express").joinpath("data").joinpath("en15302")
    table = np.loadtxt(folder.joinpath("reference_conicity.csv").read_text().splitlines(), delimiter=",", comments="#", skiprows=5)
    amplitude = table[:, 0]
    with matplotlib.rc_context(STYLE):
        figure = Figure(figsize=(9.0, 7.5))
        axes = figure.subplots(3, 3, sharex=True).ravel()
        for i, ax in enumerate(axes, start=1):
            function = parse_delta_r(folder.joinpath(f"E{i}.csv").read_text(), f"E{i}.csv")
            reference = table[:, i]
            tolerance = np.minimum(0.05, 0.5 * reference)
            ax.fill_between(amplitude, reference - tolerance, reference + tolerance, color="#cccccc", label="tolerance")
            ax.plot(amplitude, reference, color="#555555", linestyle="--", linewidth=1.0, label="EN 15302 result")
            values = []
            for a in amplitude:
                try:
                    values.append(float(equivalent_conicity(function, amplitudes=a * 1e-3)))
                except ModelError:  # beyond the tabulated delta r
                    values.append(np.nan)
            ax.plot(amplitude, values, color="#1f77b4", label="express")
            ax.set_title(f"E{i}", fontsize=9)
            if i > 6:
                ax.set_xlabel("amplitude [mm]")
            if i % 3 == 1:
                ax.set_ylabel("tan γe")
        axes[0].legend(fontsize=7, loc="lower right")
        figure.suptitle("EN 15302 reference cases: equivalent conicity against the standard's results")
        figure.tight_layout()
    return figure


if __name__ == "__main__":
    common = ["S1002", "60E1", "--inclination", "1:40", "--gauge", "1435 mm", "--flange-back", "1360 mm"]
    assert main(["contact-geometry", *common, "--plot", str(HERE / "contact_geometry_s1002_60e1.png")]) == 0
    assert main(["conicity", *common, "--amplitudes", "0.5:7.5:0.1 mm",
                 "--plot", str(HERE / "conicity_s1002_60e1.png")]) == 0
    save_figure(reference_figure(), HERE / "conicity_en15302_reference.png")
