#!/usr/bin/env python3
"""Make the figure of docs/curving.md: the paper's Fig. 9 comparison in steady state
over R = 250...2000 m (run from the repository root)::

    PYTHONPATH=src python3 docs/figures/make_curving_figures.py

* curving_steady_fig9.png: the forced-steering and the conventional car of the paper
  (narrow gauge, dead-band contact, 100 mm cant) and the standard-gauge Manchester coach
  on S1002/60E1 1:40 (contact tables, 150 mm cant), every curve at 0.5 m/s^2 of cant
  deficiency: the angle of attack and the steering angle of the leading wheelset (with
  the ideal radial value a/R), the largest Y/Q and the track shift force of the leading
  wheelset.  It prints the values at R = 400 m and the solution times.
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from express.analysis.curving.steady import SteadyCurve, steady_curving
from express.analysis.plots import STYLE, save_figure
from express.model.parameters import expression_value
from express.numeric.statespace import load_vehicle

HERE = Path(__file__).resolve().parent
RADII = np.arange(250.0, 2001.0, 50.0)
DEFICIENCY = 0.5  # m/s^2
CARS = (("forced steering (narrow gauge)", "examples/forced-steering.toml", 0.100, "-"),
        ("conventional (narrow gauge)", "examples/conventional.toml", 0.100, "--"),
        ("Manchester coach, S1002/60E1", "examples/manchester-s1002.toml", 0.150, ":"))


def sweep(path: str, cant: float):
    vehicle = load_vehicle(path)
    rail = vehicle.model.rail
    base, g = expression_value(rail.cant_base, vehicle.values), expression_value(rail.gravity, vehicle.values)
    curves = [SteadyCurve(r, cant, "right") for r in RADII]
    speeds = [c.speed_for(DEFICIENCY, base, g) for c in curves]
    start = time.perf_counter()
    results = steady_curving(vehicle, curves, speeds=speeds)
    return vehicle, results, time.perf_counter() - start


def main() -> None:
    with matplotlib.rc_context(STYLE):
        figure = Figure(figsize=(8.4, 6.6))
        axes = figure.subplots(2, 2, sharex=True).ravel()
        for label, path, cant, style in CARS:
            vehicle, results, seconds = sweep(path, cant)
            out = [r.wheel_rail for r in results]
            aoa = np.array([o.angle_of_attack[0, 0] for o in out])
            steer = np.array([r.derived.get("psi_TW1", np.nan) for r in results])
            yq = np.array([o.y_over_q[0, 0].max() for o in out])
            shift = np.array([abs(o.track_shift_force[0, 0]) for o in out])
            axes[0].plot(RADII, aoa * 1e3, style, color="k", label=label)
            axes[1].plot(RADII, -steer * 1e3, style, color="k")
            axes[2].plot(RADII, yq, style, color="k")
            axes[3].plot(RADII, shift / 1e3, style, color="k")
            a = vehicle.values["a"]
            k = int(np.argmin(abs(RADII - 400.0)))
            print(f"{label}: {len(results)} curves in {seconds:.2f} s; R = 400 m: aoa {aoa[k] * 1e3:.2f} mrad, "
                  f"steering {-steer[k] * 1e3:.2f} mrad (a/R = {a / 400 * 1e3:.2f}), Y/Q {yq[k]:.3f}, "
                  f"SY {shift[k] / 1e3:.1f} kN, flanging {bool(out[k].flange_contact[0, 0].any())}")
        axes[1].plot(RADII, 1.15 / RADII * 1e3, color="0.6", lw=1, label="a/R, narrow gauge (a = 1.15 m)")
        axes[1].plot(RADII, 1.28 / RADII * 1e3, color="0.6", lw=1, ls="-.", label="a/R, Manchester (a = 1.28 m)")
        axes[0].set_ylabel("angle of attack, leading wheelset [mrad]")
        axes[1].set_ylabel("steering angle in the bogie [mrad]")
        axes[2].set_ylabel("largest Y/Q, leading wheelset [-]")
        axes[3].set_ylabel("|ΣY|, leading wheelset [kN]")
        for axis in axes:
            axis.grid(True, alpha=0.3)
        for axis in axes[2:]:
            axis.set_xlabel("curve radius R [m]")
        axes[0].legend(fontsize="small")
        axes[1].legend(fontsize="small")
        figure.suptitle(f"Steady-state curving (Fig. 9 in steady state): {DEFICIENCY} m/s² cant deficiency, right curves")
        figure.tight_layout()
    save_figure(figure, HERE / "curving_steady_fig9.png")
    print(f"wrote {HERE / 'curving_steady_fig9.png'}")


if __name__ == "__main__":
    main()
