"""Writes examples/library-guide.ipynb (the library guide, docs/library.md), unexecuted: run
``python tools/make_library_guide.py`` from the repository root after changing it."""
import nbformat as nbf

nb = nbf.v4.new_notebook()
cells = []
md = lambda s: cells.append(nbf.v4.new_markdown_cell(s))
code = lambda s: cells.append(nbf.v4.new_code_cell(s))
md("""# The library guide: stability against curving, end to end

A researcher's question (`docs/library.md`; run in CI by `tests/test_library_guide.py`):
**how do the Manchester car's primary longitudinal stiffness `kx1` (its primary yaw
stiffness, `kx1 b1²` per axle box pair) and its secondary yaw stiffness `kb2` trade the
linear critical speed against curving — the leading wheelset's angle of attack and the
largest Y/Q in R 600 m and R 400 m?**

Every number below is what the command line gives for the same inputs
(`tests/test_cli_library_agreement.py`); the library takes SI numbers or quantities with
their units, never the command line's km/h shorthand.""")
code("""import numpy as np
import pandas as pd
import matplotlib.pyplot as plt

import express
from express.analysis.curving.steady import SteadyCurve

car = express.load_vehicle("manchester.toml")
car""")
md("The curves and their speeds (the bundled tracks' line speeds, with their units):")
code("""curves = [SteadyCurve(600.0, 0.150), SteadyCurve(400.0, 0.150)]
speeds = ["115 km/h", "95 km/h"]
base = express.critical_speed(car)
print(f"critical speed of the car as built: {base.speed * 3.6:.1f} km/h")""")
md("""A grid of the two stiffnesses, each point a vehicle with new values (`with_values`,
milliseconds: the exact matrices are compiled once), its linear critical speed and its
steady states in both curves:""")
code("""rows = []
for kx1 in (5e6, 10e6, 20e6, 31.391e6):
    for kb2 in (10.5e3, 300e3, 1000e3):
        point = car.with_values({"kx1": kx1, "kb2": kb2})
        critical = express.critical_speed(point)
        states = express.steady_curving(point, curves, speeds=speeds)
        row = {"kx1 [MN/m]": kx1 / 1e6, "kb2 [kN m/rad]": kb2 / 1e3,
               "critical speed [km/h]": critical.speed * 3.6}
        for curve, state in zip(curves, states):
            columns = state.columns()
            row[f"aoa1 R{curve.radius:.0f} [mrad]"] = columns["aoa1"] * 1e3
            row[f"Y/Q max R{curve.radius:.0f}"] = float(np.max(state.wheel_rail.y_over_q))
        rows.append(row)
table = pd.DataFrame(rows)
table.round(3)""")
md("The trade-off: a stiffer primary yaw raises the critical speed and the angle of attack together.")
code("""fig, ax = plt.subplots(figsize=(6, 4))
for kb2, group in table.groupby("kb2 [kN m/rad]"):
    ax.plot(group["critical speed [km/h]"], group["aoa1 R400 [mrad]"], "o-", label=f"kb2 {kb2:g} kN m/rad")
ax.set_xlabel("linear critical speed [km/h]")
ax.set_ylabel("leading angle of attack in R 400 m [mrad]")
ax.legend()
ax.grid(True)""")
md("""The exact sensitivities of the critical speed (the implicit function theorem on the
symbolic matrices' derivatives), checked here against a central difference:""")
code("""from express.analysis.study.sensitivity import critical_speed_sensitivity
from express.analysis.stability.critical_options import CriticalOptions

exact = critical_speed_sensitivity(car, ["kx1", "kb2"], CriticalOptions(tolerance=0.0))
step = 1e-4 * car.values["kx1"]
up, down = (critical_speed_sensitivity(car.with_values({"kx1": car.values["kx1"] + s}), ["kx1"],
                                       CriticalOptions(tolerance=0.0)).critical_speed for s in (step, -step))
difference = (up - down) / (2 * step)
print(f"d v_crit / d kx1: exact {exact.as_dict()['sensitivities']['kx1']:.6e}, central difference {difference:.6e} (m/s per N/m)")""")
md("""The same numbers as data: the modes at the critical speed as a labelled table, and the
vehicle handed to control design — the floor's lateral displacement driven by the
track's alignment, each wheelset's delay a Padé approximant (`docs/drawings-and-interfaces.md`):""")
code("""modes = express.eigen(car, base.speed)
modes.to_pandas().head(3)""")
code("""from express.export.linear_system import to_control

plant = to_control(car, 30.0, outputs=["floor_front"], track=True, pade_order=6)
plant.ninputs, plant.noutputs, plant.nstates""")
nb.cells = cells
nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
nbf.write(nb, "examples/library-guide.ipynb")
