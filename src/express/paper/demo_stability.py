"""The demo's Fig. 11 (critical speed against conicity, both cars) and the steered car's
stability map (root locus in the complex plane, damping ratio against speed).

:func:`measure_stability` sweeps the conicity; :func:`vcr_shape` reduces the sweep to
the features the paper states (where the steered car's maximum lies, whether the
conventional car's ``V_cr`` falls with ``Gamma``); the low-conicity fall is diagnosed
with a check run of the steered car with its steering link cut.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from express.analysis.stability.critical_options import CriticalOptions
from express.analysis.stability.stability import WINDOW_JUMP, unstable_windows
from express.base.units import KMH
from express.paper.demo_common import Cars, write_figure, write_table
from express.paper.numbers import PAPER

__all__ = [
    "CONICITIES",
    "V_MAX",
    "WINDOW_JUMP",
    "LowConicity",
    "StabilityMap",
    "StabilitySweep",
    "VcrShape",
    "measure_stability",
    "measure_stability_map",
    "unstable_windows",
    "vcr_shape",
    "write_stability",
    "write_stability_map",
]

#: Top of the critical-speed scan [m/s].
V_MAX = 200.0
#: Conicities of Fig. 11.
CONICITIES = np.round(np.linspace(0.02, 0.40, 39), 4)
_OPTIONS = CriticalOptions(v_max=V_MAX)


@dataclass(frozen=True)
class LowConicity:
    """Why the steered car's ``V_cr`` falls at small conicity: the first conicity whose
    ``V_cr`` is below half the maximum, its unstable mode, and the same car with the
    steering link cut (``link_cut_kmh`` None: stable over the whole scan)."""

    conicity: float
    speed_kmh: float
    mode: str
    frequency_hz: float
    link_cut_kmh: float | None


@dataclass(frozen=True)
class StabilitySweep:
    """Fig. 11: critical speed of each car at each conicity.

    Attributes
    ----------
    conicities : numpy.ndarray, shape (G,)
    speeds_kmh : mapping of str to numpy.ndarray
        Per car, ``V_cr`` [km/h] (nan: stable up to ``v_max``), shape (G,).
    unstable_at_min : mapping of str to numpy.ndarray
        Per car, unstable already at the lowest speed scanned (bool, shape (G,)).
    window_end_kmh : mapping of str to numpy.ndarray
        Per car, where ``V_cr`` jumps: the speed [km/h] above ``V_cr`` from which the car
        is stable again (``inf``: unstable up to ``v_max``); nan where not checked
        (:func:`unstable_windows`).
    modes : mapping of str to tuple
        Per car, the description of the mode that goes unstable (None where stable).
    v_min, v_max, tolerance_kmh : float
        Scan range [m/s] and bisection tolerance [km/h].
    low_conicity : LowConicity or None
    """

    conicities: np.ndarray
    speeds_kmh: Mapping[str, np.ndarray]
    unstable_at_min: Mapping[str, np.ndarray]
    window_end_kmh: Mapping[str, np.ndarray]
    modes: Mapping[str, tuple[str | None, ...]]
    v_min: float
    v_max: float
    tolerance_kmh: float
    low_conicity: LowConicity | None


@dataclass(frozen=True)
class VcrShape:
    """The features of Fig. 11 the paper states, measured on a sweep [km/h]."""

    steered_max_kmh: float
    steered_max_conicity: float
    steered_first_kmh: float
    steered_first_unstable_at_min: bool
    steered_half_conicity: float | None
    steered_at_reference_kmh: float
    steered_last_kmh: float
    conventional_first_kmh: float
    conventional_last_kmh: float
    conventional_at_reference_kmh: float
    conventional_falls: bool
    conventional_monotonic: bool
    reference_conicity: float
    first_conicity: float
    last_conicity: float

    @property
    def steered_fall(self) -> float:
        """``V_cr`` at the smallest conicity as a fraction of the maximum (steered car)."""
        return self.steered_first_kmh / self.steered_max_kmh


def measure_stability(cars: Cars, conicities: np.ndarray = CONICITIES, *, diagnose: bool = True) -> StabilitySweep:
    """Critical speeds of both cars over ``conicities``, the unstable windows where
    ``V_cr`` jumps, and (with ``diagnose``) the link-cut check of the low-conicity fall."""
    from express.analysis.stability.stability import critical_speed, critical_speed_vs_conicity

    conicities = np.asarray(conicities, dtype=float)
    speeds, unstable, windows, modes, sweeps = {}, {}, {}, {}, {}
    for name, car in cars.items():
        sweep = critical_speed_vs_conicity(car, conicities, _OPTIONS)
        sweeps[name] = sweep
        speeds[name] = np.array([c.speed_kmh if c.found else np.nan for c in sweep])
        unstable[name] = np.array([c.unstable_at_min for c in sweep])
        windows[name] = unstable_windows(car, conicities, speeds[name], unstable[name], v_max=V_MAX,
                                         tolerance_kmh=_OPTIONS.tolerance_kmh)
        modes[name] = tuple(c.mode.describe() if c.found else None for c in sweep)
    low = None
    steered = speeds["steered"]
    peak = float(np.nanmax(steered)) if np.isfinite(steered).any() else np.nan
    falls = [(g, c) for g, c in zip(conicities, sweeps["steered"], strict=True)
             if c.found and not c.unstable_at_min and c.speed_kmh < 0.5 * peak]
    if diagnose and falls:
        gamma, case = falls[0]
        cut = critical_speed(cars.steered.with_values({"Gamma": float(gamma), "kLU": 1.0}), _OPTIONS)
        low = LowConicity(float(gamma), case.speed_kmh, case.mode.describe(), case.mode.frequency_hz,
                          cut.speed_kmh if cut.found else None)
    return StabilitySweep(conicities, speeds, unstable, windows, modes, _OPTIONS.v_min, _OPTIONS.v_max,
                          _OPTIONS.tolerance_kmh, low)


def vcr_shape(sweep: StabilitySweep, reference: float = PAPER.conicity_of_max_vcr.value) -> VcrShape:
    """The features of Fig. 11 measured on ``sweep``; ``reference`` is the conicity
    where the paper puts the steered car's maximum."""
    g = sweep.conicities
    steered, conventional = sweep.speeds_kmh["steered"], sweep.speeds_kmh["conventional"]
    k = int(np.nanargmax(steered))
    below_half = [gamma for gamma, v in zip(g, steered, strict=True) if gamma < g[k] and v < 0.5 * steered[k]]
    i_ref = int(np.argmin(np.abs(g - reference)))
    finite = conventional[np.isfinite(conventional)]
    steps = np.diff(finite)
    return VcrShape(
        steered_max_kmh=float(steered[k]), steered_max_conicity=float(g[k]),
        steered_first_kmh=float(steered[0]),
        steered_first_unstable_at_min=bool(sweep.unstable_at_min["steered"][0]),
        steered_half_conicity=float(max(below_half)) if below_half else None,
        steered_at_reference_kmh=float(steered[i_ref]), steered_last_kmh=float(steered[-1]),
        conventional_first_kmh=float(conventional[0]), conventional_last_kmh=float(conventional[-1]),
        conventional_at_reference_kmh=float(conventional[i_ref]),
        # falls: lower at the end, and no rise beyond the bisection's resolution on the way
        conventional_falls=bool(finite.size == conventional.size and finite[-1] < finite[0]
                                and np.all(steps <= 2 * sweep.tolerance_kmh)),
        conventional_monotonic=bool(finite.size == conventional.size and np.all(steps < 0)),
        reference_conicity=float(g[i_ref]), first_conicity=float(g[0]), last_conicity=float(g[-1]),
    )


def write_stability(outdir: Path, sweep: StabilitySweep, cars: Cars, log: Callable[[str], None]) -> list[Path]:
    """Draw Fig. 11 and write it with its data; returns the paths written."""
    from express.analysis.plots import figure_critical_speed

    columns: dict[str, object] = {"Gamma": sweep.conicities}
    curves = []
    for name in ("steered", "conventional"):
        speeds, unstable = sweep.speeds_kmh[name], sweep.unstable_at_min[name]
        columns[f"Vcr_{name}_kmh"] = speeds
        columns[f"unstable_at_lowest_speed_{name}"] = unstable.astype(int)
        ends = np.asarray(sweep.window_end_kmh[name], dtype=float)
        columns[f"stable_again_{name}_kmh"] = np.where(np.isinf(ends), np.nan, ends)  # no inf written
        columns[f"unstable_to_top_{name}"] = np.isinf(ends).astype(int)
        columns[f"mode_{name}"] = ["" if m is None else m for m in sweep.modes[name]]
        curves.append({"label": "forced steering" if name == "steered" else "conventional bogies",
                       "conicity": sweep.conicities, "speed_kmh": speeds, "style": name, "unstable_at_min": unstable,
                       "window_end_kmh": sweep.window_end_kmh[name], "color": "#1f77b4" if name == "steered" else "#d62728"})
    caption = ("Eigenvalues of A(v) on straight track, linear creep; V_cr = lowest speed at which a real part turns "
               f"positive (scan {sweep.v_min / KMH:.1f}-{sweep.v_max / KMH:.0f} km/h, bisection to "
               f"{sweep.tolerance_kmh:g} km/h). Crosses: unstable already at the lowest speed scanned. Bars: unstable only "
               "in a window (stable again above it), so V_cr jumps; the line is broken at both.")
    figure = figure_critical_speed(curves, running_speed_kmh=cars.steered.speed / KMH,
                                   nominal_conicity=cars.steered.values.get("Gamma"), caption=caption)
    paths = write_figure(figure, outdir / "fig11_critical_speed")
    paths.append(write_table(outdir / "fig11_critical_speed.csv", columns))
    shape = vcr_shape(sweep)
    log(f"  Fig. 11: steered max {shape.steered_max_kmh:.0f} km/h at Gamma {shape.steered_max_conicity:.2f}; "
        f"conventional {shape.conventional_first_kmh:.0f} -> {shape.conventional_last_kmh:.0f} km/h")
    return paths


@dataclass(frozen=True)
class StabilityMap:
    """Eigenvalues of one car over a speed range, and its modes followed across speeds.

    Attributes
    ----------
    speeds : numpy.ndarray, shape (S,)
        [m/s].
    eigenvalues : numpy.ndarray, complex, shape (S, 2n)
        [1/s], row per speed (:func:`express.analysis.stability.stability.root_locus`).
    branches : numpy.ndarray, complex, shape (S, M)
        The oscillatory modes followed across speeds (:func:`express.analysis.plots.mode_branches`).
    critical_kmh : float or None
        Critical speed in the range [km/h].
    """

    speeds: np.ndarray
    eigenvalues: np.ndarray
    branches: np.ndarray
    critical_kmh: float | None


def measure_stability_map(car, v_max: float = 150.0, points: int = 300) -> StabilityMap:
    """Root locus of ``car`` from 1 m/s to ``v_max`` [m/s] at ``points`` speeds."""
    from express.analysis.plots import mode_branches
    from express.analysis.stability.stability import critical_speed, root_locus

    speeds = np.linspace(1.0, v_max, points)
    eigenvalues = root_locus(car, speeds)
    result = critical_speed(car, replace(_OPTIONS, v_max=v_max))
    critical = result.speed_kmh if result.found and not result.unstable_at_min else None
    return StabilityMap(speeds, eigenvalues, mode_branches(eigenvalues), critical)


def write_stability_map(outdir: Path, stability_map: StabilityMap, name: str, *,
                        max_frequency_hz: float = 15.0) -> list[Path]:
    """Draw the root locus in the complex plane and the damping ratios against speed;
    write both with the followed modes as CSV; returns the paths written."""
    from express.analysis.plots import figure_damping_vs_speed, figure_root_locus_complex

    speeds_kmh = stability_map.speeds / KMH
    complex_figure = figure_root_locus_complex(
        speeds_kmh, stability_map.eigenvalues, title=f"{name}: eigenvalues from {speeds_kmh[0]:.1f} to {speeds_kmh[-1]:.0f} km/h",
        critical_kmh=stability_map.critical_kmh, max_frequency_hz=max_frequency_hz)
    paths = write_figure(complex_figure, outdir / "stability_root_locus")
    damping_figure = figure_damping_vs_speed(
        speeds_kmh, stability_map.branches, title=f"{name}: damping ratio of each mode against speed",
        critical_kmh=stability_map.critical_kmh, max_frequency_hz=max_frequency_hz)
    paths += write_figure(damping_figure, outdir / "stability_damping")
    columns: dict[str, object] = {"V_kmh": speeds_kmh}
    for j, branch in enumerate(stability_map.branches.T, 1):
        columns[f"mode{j}_re_1_s"] = branch.real
        columns[f"mode{j}_f_hz"] = branch.imag / (2 * np.pi)
    paths.append(write_table(outdir / "stability_modes.csv", columns))
    return paths
