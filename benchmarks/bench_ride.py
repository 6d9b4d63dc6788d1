#!/usr/bin/env python3
"""Ride benchmark: spectral ride analysis of a 3-D car over 2000 frequencies.

Run from the repository root::

    PYTHONPATH=src python3 benchmarks/bench_ride.py            # full run (~1 min)
    PYTHONPATH=src python3 benchmarks/bench_ride.py --quick    # smoke test

Everything runs on ONE core (BLAS/OpenMP thread counts set to 1 before NumPy is
imported, unless already set in the environment).

The car (written by :func:`car_toml`, the same data as a Manchester-benchmark-like
passenger coach): body and two bogie frames with all six DOFs, four wheelsets with x, y,
z, roll and yaw, each wheel on a vertical contact spring to its own rail ground
(``W1_railL``, ...), series (Maxwell) yaw dampers: 42 coordinates (38 DOFs and the
strokes of the four yaw dampers), an 80-state state space, 12 driven track inputs
(four lateral irregularities, eight rail heights).

Measured (medians of ``--runs`` runs after one warm-up run, in one process):

1. ``ride_response`` of ERRI low at 160 km/h over 2000 log-spaced frequencies 0.1-50 Hz
   (alignment, vertical, cross level; every output: 3 floor points x 3 directions, Y,
   y - yR and both dynamic wheel loads of every wheelset), and the whole analysis
   (``ride_response`` + ``point_comfort`` + ``wheel_forces``).  Target: < 1 s.
2. Baseline, same outputs: a plain per-frequency loop, ``numpy.linalg.solve`` of
   ``(-w^2 M + i w C + K) H = P + i w Pd`` for the driven inputs, the cross-spectral
   input matrix of ``track_input_spectrum`` and ``G_y = diag(C H G_u H^H C^H)``.
   Ratio = baseline / ``ride_response``; ``max_rel_diff`` = the largest difference of
   the output PSDs relative to each output's peak.

The last line of the output is exactly
``ride_s=<x> analysis_s=<y> baseline_s=<z> speedup=<r> max_rel_diff=<d>``.
"""

from __future__ import annotations

import os

for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS",
                  "VECLIB_MAXIMUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import datetime  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from machine import cpu_name, usable_cores  # noqa: E402  (benchmarks/machine.py)

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT / "src") not in sys.path:
    sys.path.insert(0, str(ROOT / "src"))

TARGET_S = 1.0
FREQUENCIES = (0.1, 50.0, 2000)
SPEED_KMH = 160.0

_PARAMETERS = """
mc = 32000.0
Icx = 56800.0
Icy = 1970000.0
Icz = 1970000.0
hc = 1.8
hf = 1.2
mt = 2615.0
Itx = 1722.0
Ity = 1476.0
Itz = 3067.0
ht = 0.6
mw = 1813.0
Iwx = 1120.0
Iwy = 112.0
Iwz = 1120.0
lT = 9.5
a = 1.28
b1 = 1.0
b2 = 1.0
r0 = 0.46
b0 = 0.75
kx1 = 31.39e6
ky1 = 3.884e6
kz1 = 1.22e6
cz1 = 4000.0
kx2 = 160000.0
ky2 = 160000.0
kz2 = 430000.0
cz2 = 20000.0
cy2 = 32000.0
kyaw = 2.0e6
cyaw = 500000.0
kH = 1.2e9
f1 = 10.0e6
f2 = 8.5e6
Gamma = 0.15
delta = 0.007
kR = 2.0e7
mu = 0.3
P0 = "(mc + 2*mt + 4*mw)*g/8"
G = 1.5
g = 9.81
v = "160 km/h"
"""


def _point(name, body, offset):
    return f'[points.{name}]\nbody = "{body}"\noffset = [{", ".join(offset)}]\n'


def _element(name, s_end, t_end, direction, stiffness, damping, series=False):
    tail = "series = true\n" if series else ""
    return (f'[elements.{name}]\nfrom = "{s_end}"\nto = "{t_end}"\ndirection = "{direction}"\n'
            f'stiffness = "{stiffness}"\ndamping = "{damping}"\n{tail}')


def _spring(name, upper, upper_offset, lower, lower_offset, pairs, series=False):
    """Points on two bodies and one element per (direction, stiffness, damping)."""
    text = _point(f"{name}_S", upper, upper_offset) + _point(f"{name}_T", lower, lower_offset)
    return text + "".join(_element(f"{name}_{d}", f"{name}_S", f"{name}_T", d, k, c, series) for d, k, c in pairs)


def car_toml() -> str:
    """The benchmark car (module docstring) as a model file."""
    text = '[model]\nname = "ride_car"\n[parameters]' + _PARAMETERS
    bodies = [("CB", "mc", '"Icx", "Icy", "Icz"', '"x", "y", "z", "rx", "ry", "rz"', '0, 0, "hc"')]
    wheelsets = []
    for t, bogie_x in (("T1", "lT"), ("T2", "-lT")):
        bodies.append((t, "mt", '"Itx", "Ity", "Itz"', '"x", "y", "z", "rx", "ry", "rz"', f'"{bogie_x}", 0, "ht"'))
        for w, sign in ((f"W{2 * len(wheelsets) // 2 + 1}", ""), (f"W{2 * len(wheelsets) // 2 + 2}", "-")):
            wheelsets.append((w, t, bogie_x, sign))
            bodies.append((w, "mw", '"Iwx", "Iwy", "Iwz"', '"x", "y", "z", "rx", "rz"', f'"{bogie_x} + {sign}a", 0, "r0"'))
    for body, mass, inertia, dofs, position in bodies:
        text += f'[bodies.{body}]\nmass = "{mass}"\ninertia = [{inertia}]\ndofs = [{dofs}]\nposition = [{position}]\n'
    for w, t, _, sign in wheelsets:
        for side, y in (("L", "b0"), ("R", "-b0")):
            text += f"[grounds.{w}_rail{side}]\n"
            text += _spring(f"{w}_c{side}", w, ["0", f'"{y}"', '"-r0"'], f"{w}_rail{side}", ["0", f'"{y}"', "0"],
                            [("z", "kH", "0")])
        for side, y in (("L", "b1"), ("R", "-b1")):
            text += _spring(f"{w}_p{side}", t, [f'"{sign}a"', f'"{y}"', '"r0 - ht"'], w, ["0", f'"{y}"', "0"],
                            [("x", "kx1", "0"), ("y", "ky1", "0"), ("z", "kz1", "cz1")])
    for t, bogie_x in (("T1", "lT"), ("T2", "-lT")):
        for side, y in (("L", "b2"), ("R", "-b2")):
            text += _spring(f"{t}_s{side}", "CB", [f'"{bogie_x}"', f'"{y}"', '"0.9 - hc"'], t,
                            ["0", f'"{y}"', '"0.9 - ht"'], [("x", "kx2", "0"), ("y", "ky2", "0"), ("z", "kz2", "cz2")])
            text += _spring(f"{t}_yaw{side}", "CB", [f'"{bogie_x}"', f'"1.3*{y}"', '"0.9 - hc"'], t,
                            ["0", f'"1.3*{y}"', '"0.9 - ht"'], [("x", "kyaw", "cyaw")], series=True)
        text += _spring(f"{t}_dy", "CB", [f'"{bogie_x}"', "0", '"0.9 - hc"'], t, ["0", "0", '"0.9 - ht"'],
                        [("y", "0", "cy2")])
    text += ('[rail]\nspeed = "v"\ncant_base = "G"\ngravity = "g"\nwheelsets = ["W1", "W2", "W3", "W4"]\n'
             '[rail.wheel_rail]\nf1 = "f1"\nf2 = "f2"\nconicity = "Gamma"\nr0 = "r0"\nb = "b0"\n'
             'flange_clearance = "delta"\nrail_stiffness = "kR"\nfriction = "mu"\nwheel_load = "P0"\n')
    for name, x in (("floor_front", "lT"), ("floor_centre", "0"), ("floor_rear", "-lT")):
        text += f'[rail.outputs.{name}]\nbody = "CB"\noffset = ["{x}", 0, "hf - hc"]\n'
    return text


def _median_time(function, runs):
    function()  # warm-up
    times, result = [], None
    for _ in range(runs):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return statistics.median(times), times, result


def baseline(vehicle, spectra, speed, frequencies):
    """Output PSDs by a per-frequency ``numpy.linalg.solve`` loop and ``G_y = H G_u H^H``
    with the cross-spectral matrix of ``track_input_spectrum`` (inputs grouped by wheelset:
    lateral irregularity, left and right rail heights)."""
    from express.analysis.ride import spectral
    from express.analysis.ride.vehicle import _output_rows, rail_inputs
    from express.rail.track.spectra import COMPONENTS

    inputs = rail_inputs(vehicle)
    components = [c for c in COMPONENTS if c in spectra and np.any(inputs.mixing[:, COMPONENTS.index(c)])]
    psds = [spectral.spatial_to_temporal(spectra[c].psd, frequencies, speed) for c in components]
    groups = [[f"{w.name}.yR", f"{w.name}_railL.z", f"{w.name}_railR.z"] for w in vehicle.wheelsets]
    order = [inputs.names.index(name) for group in groups for name in group]
    mixing = inputs.mixing[order[:3]][:, [COMPONENTS.index(c) for c in components]]
    delays = spectral.wheelset_delays([w.station for w in vehicle.wheelsets], speed)
    g_u = spectral.track_input_spectrum(frequencies, psds, delays, mixing)
    columns = inputs.columns[order]
    rows, _, _ = _output_rows(vehicle, inputs, speed)
    d0, d1, d2, e0, e1 = rows.matrices()
    m, c_v, k = vehicle.mass, vehicle.damping(speed), vehicle.stiffness
    p, pd = vehicle.forcing(speed)[:, columns], vehicle.forcing_rate(speed)[:, columns]
    out = np.empty((frequencies.size, d0.shape[0]))
    for i, f in enumerate(frequencies):
        w = 2 * np.pi * f
        h = np.linalg.solve(-(w**2) * m + 1j * w * c_v + k, p + 1j * w * pd)
        h_out = (d0 + 1j * w * d1 - w**2 * d2) @ h + (e0 + 1j * w * e1)[:, columns]
        out[i] = np.einsum("pk,kl,pl->p", h_out, g_u[i], np.conj(h_out)).real
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--quick", action="store_true", help="3 runs, baseline once")
    args = parser.parse_args()
    runs = 3 if args.quick else args.runs

    from express.analysis.ride.summaries import point_comfort, wheel_forces
    from express.analysis.ride.vehicle import rail_inputs, ride_response, track_class_spectra
    from express.numeric.statespace import load_vehicle

    print(f"express ride benchmark, {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC")
    print(f"machine: {cpu_name()}, {usable_cores()} usable cores, load average {os.getloadavg()[0]:.2f}; "
          f"Python {platform.python_version()}, NumPy {np.__version__}")
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "ride_car.toml"
        path.write_text(car_toml(), encoding="utf-8")
        vehicle = load_vehicle(path)
    inputs = rail_inputs(vehicle)
    print(f"car: {vehicle.n} coordinates ({vehicle.n - vehicle.form.first_order.size} DOFs + "
          f"{vehicle.form.first_order.size} damper strokes), {vehicle.form.size} states, "
          f"{len(vehicle.inputs)} inputs of which {len(inputs.names)} driven by the track")
    speed = SPEED_KMH / 3.6
    frequencies = np.geomspace(*FREQUENCIES[:2], FREQUENCIES[2])
    spectra = track_class_spectra("ERRI-low")

    ride_s, ride_times, response = _median_time(lambda: ride_response(vehicle, spectra, speed, frequencies), runs)

    def analysis():
        result = ride_response(vehicle, spectra, speed, frequencies)
        return result, point_comfort(result), wheel_forces(result, vehicle)

    analysis_s, _, (_, comfort, _) = _median_time(analysis, runs)
    baseline_runs = 1 if args.quick else 3
    base_s, base_times, psd = _median_time(lambda: baseline(vehicle, spectra, speed, frequencies), baseline_runs)
    peaks = np.maximum(response.psd.max(axis=0), 1e-300)
    max_rel = float(np.max(np.abs(response.psd - psd) / peaks))
    print(f"ride_response: {frequencies.size} frequencies {FREQUENCIES[0]:g}-{FREQUENCIES[1]:g} Hz, "
          f"{len(response.names)} outputs, components {', '.join(response.components)}")
    print(f"  ride_response median {ride_s * 1e3:.1f} ms (runs {', '.join(f'{t * 1e3:.0f}' for t in ride_times)} ms)"
          f"  {'OK' if ride_s < TARGET_S else 'TARGET MISSED'} (target < {TARGET_S:g} s)")
    print(f"  whole analysis (+ comfort per point, wheel forces) median {analysis_s * 1e3:.1f} ms "
          f"{'OK' if analysis_s < TARGET_S else 'TARGET MISSED'}")
    print(f"  baseline (per-frequency numpy.linalg.solve + H G_u H^H) median {base_s * 1e3:.0f} ms "
          f"(runs {', '.join(f'{t * 1e3:.0f}' for t in base_times)} ms); speedup {base_s / ride_s:.1f}x")
    print(f"  agreement: max |PSD - baseline| / peak = {max_rel:.1e}")
    front = comfort["floor_front"]
    print(f"  floor_front: rms a_y {front.rms['y']:.3f}, a_z {front.rms['z']:.3f} m/s^2, Wz_y {front.wz['y']:.2f}, "
          f"Wz_z {front.wz['z']:.2f}, N_MV {front.n_mv:.2f}")
    print(f"ride_s={ride_s:.4f} analysis_s={analysis_s:.4f} baseline_s={base_s:.4f} speedup={base_s / ride_s:.2f} "
          f"max_rel_diff={max_rel:.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
