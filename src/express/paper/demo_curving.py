"""The demo's Fig. 9: both cars along the paper's curve (:func:`express.rail.track.paper_curve`).

:func:`measure_curving` runs the simulations and reduces them to a :class:`Curving`
record: steady values in the circular curve, peaks, flange contact, and the quantities
the summary's explanations need (cant deficiency, link force and stretch).  Track values
(radius, cant, lengths) are read from the track, vehicle values from the cars.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from express.base.units import KMH
from express.paper.demo_common import Cars, steady_mean, write_figure, write_table
from express.paper.numbers import PAPER

__all__ = ["CurveGeometry", "Curving", "curve_geometry", "measure_curving", "write_curving"]

_SERIES = ("rho1", "theta_L1", "psi_TW1", "psi_TW2", "Q1", "Q2")
#: The paper's names of Fig. 9 (its Q: the lateral force) -> the runs' output names (Y).
_RUN_NAMES = {"Q1": "Y1", "Q2": "Y2"}


@dataclass(frozen=True)
class CurveGeometry:
    """The one circular curve of a track and what leads to it [m]."""

    radius: float
    cant: float
    direction: str
    curve_length: float
    transition_length: float
    transition_shape: str
    lead_in: float
    curve_start: float
    curve_end: float
    length: float


def curve_geometry(track) -> CurveGeometry:
    """Read the geometry of a track with exactly one circular curve (as the paper's).

    Raises
    ------
    ValueError
        When the track has no circular curve or more than one.
    """
    segments = tuple(track.segments)
    curves = [k for k, segment in enumerate(segments) if hasattr(segment, "radius")]
    if len(curves) != 1:
        raise ValueError(f"the demo needs a track with one circular curve; this one has {len(curves)}")
    k = curves[0]
    curve = segments[k]
    boundaries = np.asarray(track.boundaries, dtype=float)
    transitions = [s for s in segments if hasattr(s, "shape")]
    first = segments[0]
    lead_in = float(first.length) if not hasattr(first, "shape") and not hasattr(first, "radius") else 0.0
    return CurveGeometry(
        radius=float(curve.radius), cant=float(curve.cant), direction=str(curve.direction),
        curve_length=float(curve.length),
        transition_length=float(transitions[0].length) if transitions else 0.0,
        transition_shape=str(transitions[0].shape) if transitions else "none",
        lead_in=lead_in, curve_start=float(boundaries[k]), curve_end=float(boundaries[k + 1]),
        length=float(boundaries[-1]),
    )


@dataclass(frozen=True)
class Curving:
    """Fig. 9: curve negotiation of both cars.

    Attributes
    ----------
    geometry : CurveGeometry
    speed : float
        Running speed [m/s] (the steered car's model speed).
    window : (float, float)
        Range of ``d1`` [m] over which steady values are averaged: the whole car in the
        circular curve.
    series : mapping
        ``"steered"`` / ``"conventional"`` -> ``d1`` and :data:`_SERIES` arrays (SI).
    steady : mapping of str to float
        ``"<name>_<car>"`` means over ``window`` (``psi_TW1_steered``, ``Q1_conventional``,
        ...) and ``"theta_L1"`` (steered car) [rad, N].
    peaks : mapping of str to float
        ``"Q1_steered_max"`` etc. [N].
    flanging : mapping of str to (bool, bool)
        Flange contact on axles 1 and 2 in the steady curve, per car.
    ideal_yaw : float
        ``a/R`` [rad].
    geometric_lever : float
        ``b_L l_T / (R l_LU)`` [rad].
    cant_deficiency : float
        ``v^2/R - g S / G`` [m/s^2].
    bogie_force : float
        ``(m_c/2 + m_t + 2 m_w)`` times the cant deficiency [N]: one bogie's lateral load.
    link_force, link_stretch : float
        Force [N] and stretch [m] of the steering link ``k_LU`` in the steady curve.
    link_stiffness, upper_arm : float
        The steered car's steering link ``k_LU`` [N/m] and upper lever arm ``l_LU`` [m].
    link_stiffness_for_paper_angle : float or None
        ``k_LU`` that would give the paper's lever angle at the same link force [N/m].
    lever_angle_check : float or None
        Steady lever angle of a check run with that ``k_LU`` [rad].
    lever_ratio, ideal_lever_ratio : float
        ``l_LL / l_LU`` and ``a / l_T``.
    car_mass : float
        [kg].
    kx1 : mapping of str to float or None
        Longitudinal axle-box stiffness per car [N/m].
    steady_state : mapping
        Per car, the steady state solved directly in the circular curve
        (:func:`express.analysis.curving.steady.steady_curving`, ``docs/curving.md``):
        ``psi_TW1``, ``aoa1`` [rad], ``YQ1`` (the leading wheelset's larger Y/Q), ``SY1``
        [N], ``dQQ0`` and ``passed`` (1.0 when every EN 14363 limit is met); a car
        without a steady state is left out.
    """

    geometry: CurveGeometry
    speed: float
    window: tuple[float, float]
    series: Mapping[str, Mapping[str, np.ndarray]]
    steady: Mapping[str, float]
    peaks: Mapping[str, float]
    flanging: Mapping[str, tuple[bool, bool]]
    ideal_yaw: float
    geometric_lever: float
    cant_deficiency: float
    bogie_force: float
    link_force: float
    link_stretch: float
    link_stiffness: float
    upper_arm: float
    link_stiffness_for_paper_angle: float | None
    lever_angle_check: float | None
    lever_ratio: float
    ideal_lever_ratio: float
    car_mass: float
    kx1: Mapping[str, float | None]
    steady_state: Mapping[str, Mapping[str, float]] = field(default_factory=dict)

    @property
    def lever_fraction(self) -> float:
        """Steady lever angle as a fraction of the geometric one."""
        return self.steady["theta_L1"] / self.geometric_lever


def _runs(cars: Cars, track):
    from express.analysis.time.simulate import simulate

    runs = {name: simulate(car, track, progress=False) for name, car in cars.items()}
    if runs["steered"].distance.size != runs["conventional"].distance.size:  # same speed and dt: same grid
        raise RuntimeError("the two runs have different time grids")
    return runs


def _steady_values(runs, window) -> tuple[dict, dict, dict, dict]:
    series = {name: {"d1": run.distance, **{k: run.outputs[_RUN_NAMES.get(k, k)] for k in _SERIES
                                            if _RUN_NAMES.get(k, k) in run.outputs}}
              for name, run in runs.items()}
    steady = {f"{k}_{name}": steady_mean(data[k], data["d1"], window)
              for name, data in series.items() for k in ("psi_TW1", "psi_TW2", "Q1", "Q2")}
    steady["theta_L1"] = steady_mean(series["steered"]["theta_L1"], series["steered"]["d1"], window)
    peaks = {f"{k}_{name}_max": float(np.max(data[k])) for name, data in series.items() for k in ("Q1", "Q2")}
    flanging = {name: tuple(bool(steady_mean(np.abs(run.outputs[f"flange{j}"]), run.distance, window) > 0)
                            for j in (1, 2)) for name, run in runs.items()}
    return series, steady, peaks, flanging


def _steady_states(cars: Cars, geometry: CurveGeometry) -> dict[str, dict[str, float]]:
    """The steady state of each car in the circular curve of the run, solved directly."""
    from express.analysis.curving.assessment import assess_steady
    from express.analysis.curving.steady import CurveError, SteadyCurve, steady_curving

    curve = SteadyCurve(geometry.radius, geometry.cant, geometry.direction)
    out = {}
    for name, car in cars.items():
        try:
            state = steady_curving(car, curve)[0]
        except CurveError:  # a variant without a steady state (the demo's checks change parameters): none shown
            continue
        wheel_rail = state.wheel_rail
        out[name] = {"psi_TW1": state.derived["psi_TW1"], "aoa1": float(wheel_rail.angle_of_attack[0, 0]),
                     "YQ1": float(wheel_rail.y_over_q[0, 0].max()), "SY1": float(wheel_rail.track_shift_force[0, 0]),
                     "dQQ0": float(wheel_rail.vehicle_unloading[0]), "passed": float(assess_steady(car, state).passed)}
    return out


def measure_curving(cars: Cars, track=None, *, check: bool = True) -> Curving:
    """Run both cars along ``track`` (default: the paper's curve) and reduce the runs.

    Parameters
    ----------
    cars : Cars
    track : Track, optional
        A track with one circular curve; default :func:`express.rail.track.paper_curve`.
    check : bool
        Also run the steered car with the ``k_LU`` estimated to give the paper's lever
        angle (one more simulation), to test that estimate.
    """
    from express.analysis.time.simulate import simulate
    from express.rail.track import paper_curve

    track = paper_curve() if track is None else track
    geometry = curve_geometry(track)
    runs = _runs(cars, track)
    values = cars.steered.values
    span = max(w.station for w in cars.steered.wheelsets) - min(w.station for w in cars.steered.wheelsets)
    window = (geometry.curve_start + span + 5.0, geometry.curve_end - 5.0)
    series, steady, peaks, flanging = _steady_values(runs, window)
    radius = geometry.radius
    deficiency = cars.steered.speed**2 / radius - values["g"] * geometry.cant / values["G"]
    stroke = values["bL"] * values["lT"] / radius  # displacement of the lever pin against the car body
    link_stretch = stroke - values["lLU"] * steady["theta_L1"]
    link_force = values["kLU"] * link_stretch
    paper_stretch = stroke - values["lLU"] * PAPER.lever_angle.value
    kLU_paper = link_force / paper_stretch if paper_stretch > 0 and link_force > 0 else None
    theta_check = None
    if check and kLU_paper is not None:
        softer = simulate(cars.steered.with_values({"kLU": kLU_paper}), track, progress=False)
        theta_check = steady_mean(softer.outputs["theta_L1"], softer.distance, window)
    return Curving(
        geometry=geometry, speed=cars.steered.speed, window=window, series=series, steady=steady, peaks=peaks,
        flanging=flanging, ideal_yaw=values["a"] / radius, geometric_lever=stroke / values["lLU"],
        cant_deficiency=deficiency,
        bogie_force=(values["mc"] / 2 + values["mt"] + 2 * values["mw"]) * deficiency,
        link_force=link_force, link_stretch=link_stretch, link_stiffness=values["kLU"], upper_arm=values["lLU"],
        link_stiffness_for_paper_angle=kLU_paper, lever_angle_check=theta_check,
        lever_ratio=values["lLL"] / values["lLU"], ideal_lever_ratio=values["a"] / values["lT"],
        car_mass=values["mc"] + 2 * values["mt"] + 4 * values["mw"],
        kx1={name: car.values.get("kx1") for name, car in cars.items()},
        steady_state=_steady_states(cars, geometry),
    )


def _caption(curving: Curving, cars: Cars) -> str:
    g = curving.geometry
    wheelset = cars.steered.wheelsets[0]
    return (f"Track: {g.lead_in:g} m straight, {g.transition_length:g} m {g.transition_shape} transition, "
            f"R = {g.radius:g} m with {g.cant * 1e3:g} mm cant for {g.curve_length:g} m, transition, straight; "
            f"{g.direction} curve; {curving.speed / KMH:.0f} km/h; flange clearance "
            f"{wheelset.flange_clearance * 1e3:g} mm, creep saturation (mu = {wheelset.friction:g}). "
            "Solid: forced steering; dashed: conventional bogies. (a): the axes are scaled so that the geometric "
            "lever angle b_L l_T rho_1 / l_LU would lie on the curvature curve.")


def write_curving(outdir: Path, curving: Curving, cars: Cars, log: Callable[[str], None]) -> list[Path]:
    """Draw Fig. 9 and write it with its data; returns the paths written."""
    from express.analysis.plots import figure_curving

    steered, conventional = curving.series["steered"], curving.series["conventional"]
    figure = figure_curving(
        steered, conventional, ideal_yaw=curving.ideal_yaw, geometric_lever=curving.geometric_lever,
        title=f"Fig. 9 - curve negotiation, R = {curving.geometry.radius:g} m, V = {curving.speed / KMH:.0f} km/h",
        caption=_caption(curving, cars))
    paths = write_figure(figure, outdir / "fig9_curving")
    columns = {"d1_m": steered["d1"], "rho1_1_m": steered["rho1"], "theta_L1_rad": steered["theta_L1"]}
    for name, data in curving.series.items():
        for k in ("psi_TW1", "psi_TW2"):
            columns[f"{k}_{name}_rad"] = data[k]
        for k in ("Q1", "Q2"):
            columns[f"{k}_{name}_N"] = data[k]
    paths.append(write_table(outdir / "fig9_curving.csv", columns))
    s = curving.steady
    log(f"  Fig. 9: theta_L1 = {s['theta_L1']:.4f} rad, Q1 = {s['Q1_steered'] / 1e3:.1f} kN (steered), "
        f"{s['Q1_conventional'] / 1e3:.1f} kN (conventional)")
    if curving.steady_state:
        names = list(curving.steady_state)
        keys = ("psi_TW1", "aoa1", "YQ1", "SY1", "dQQ0", "passed")
        units = {"psi_TW1": "rad", "aoa1": "rad", "YQ1": "", "SY1": "N", "dQQ0": "", "passed": ""}
        table = {"car": names, **{f"{k}_{units[k]}".rstrip("_"): [curving.steady_state[n][k] for n in names] for k in keys}}
        paths.append(write_table(outdir / "fig9_steady_state.csv", table))
        for name in names:
            state = curving.steady_state[name]
            log(f"  Fig. 9 steady state ({name}): psi_TW1 = {state['psi_TW1'] * 1e3:.2f} mrad (run's mean "
                f"{s[f'psi_TW1_{name}'] * 1e3:.2f}), angle of attack {state['aoa1'] * 1e3:.2f} mrad, Y/Q "
                f"{state['YQ1']:.3f}, EN 14363 {'met' if state['passed'] else 'NOT met'}")
    return paths
