#!/usr/bin/env python3
"""Make the figures of docs/contact.md on the nonlinear contact (run from the repository
root)::

    PYTHONPATH=src python3 docs/figures/make_nonlinear_contact_figures.py

* manchester_contact_benchmark.png: the Manchester contact benchmark's case A-2.2
  (S1002 on UIC60 1:40, 10 kN a wheel, 2.4 mrad of yaw per mm), lateral, normal and
  longitudinal forces against CONTACT's results (tests/test_manchester_contact.py holds
  them, docs/validation.md lists them), with the table law (the default), FASTSIM and Polach;
* nonlinear_critical_speed_manchester_s1002.png: what
  ``express critical-speed examples/manchester-s1002.toml --nonlinear --plot`` draws.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from express.analysis.plots import STYLE, save_figure
from express.cli import main
from express.rail.contact_forces import quasi_static_forces, wheelset_contact
from express.rail.contact_geometry import ContactSetup
from express.rail.contact_tables import YAW_NODES, contact_tables
from express.rail.profiles import standard_profile

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from test_manchester_contact import G, LOAD, MU, NU, REFERENCE, YAW_PER_MM  # noqa: E402


def benchmark_figure() -> Figure:
    tables = contact_tables(standard_profile("S1002"), standard_profile("60E1"), ContactSetup(),
                            youngs_modulus=2 * G * (1 + NU), poisson=NU, yaw_nodes=YAW_NODES)
    contact = wheelset_contact(tables, LOAD, MU)
    y = np.linspace(0.0, 10.0, 401)
    curves = {}
    for law in ("table", "fastsim", "polach"):
        rows = [quasi_static_forces(contact, v * 1e-3, YAW_PER_MM * v, speed=2.0, law=law) for v in y]
        curves[law] = np.array([(-r["Y_left"], r["N_left"], abs(r["Y_right"]), -r["Fx_left"]) for r in rows]) / 1e3
    ref_y = REFERENCE["y_mm"]
    references = (REFERENCE["right_FY_N"] / 1e3, np.abs(REFERENCE["left_FY_N"]) / 1e3, REFERENCE["right_FX_N"] / 1e3)
    with matplotlib.rc_context(STYLE):
        figure = Figure(figsize=(12.0, 4.2))
        axes = figure.subplots(1, 3)
        panels = ((0, "flanging wheel: lateral force on the rail [kN]"), (2, "other wheel: |lateral force| [kN]"),
                  (3, "flanging wheel: longitudinal force on the rail [kN]"))
        for axis, (column, label), reference in zip(axes, panels, references, strict=True):
            axis.plot(y, curves["table"][:, column], color="C3", label="EXPRESS, table of the exact theory (default)")
            axis.plot(y, curves["fastsim"][:, column], color="C0", linestyle=":", label="EXPRESS, FASTSIM")
            axis.plot(y, curves["polach"][:, column], color="C1", linestyle="--", label="EXPRESS, Polach")
            axis.plot(ref_y, reference, "o", color="black", markersize=4, label="CONTACT (Vollebregt)")
            axis.set_xlabel("lateral displacement y [mm] (yaw 2.4 mrad per mm)")
            axis.set_ylabel(label)
        axes[0].plot(y, curves["fastsim"][:, 1], color="C2", linewidth=1.0, label="EXPRESS normal force [kN]")
        axes[0].plot(ref_y, REFERENCE["right_FN_N"] / 1e3, "s", color="C2", markersize=3,
                     label="CONTACT normal force [kN]")
        axes[0].legend(fontsize="small", loc="upper left")
        figure.suptitle("Manchester contact benchmark A-2.2: S1002 on UIC60 1:40, 10 kN a wheel, mu 0.3")
        figure.tight_layout()
    return figure


def main_figures() -> None:
    save_figure(benchmark_figure(), HERE / "manchester_contact_benchmark.png")
    status = main(["critical-speed", str(ROOT / "examples" / "manchester-s1002.toml"), "--nonlinear",
                   "--plot", str(HERE / "nonlinear_critical_speed_manchester_s1002.png")])
    if status:
        raise SystemExit(status)


if __name__ == "__main__":
    main_figures()
