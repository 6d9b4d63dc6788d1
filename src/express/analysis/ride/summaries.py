"""Summaries of a vehicle's ride response: comfort per output point, wheel forces, Y/Q.

This module owns what is read off a :class:`~.vehicle.RideResponse` (or off the time
histories of a simulation): per output point the RMS accelerations, the weighted RMS,
Sperling's Wz and EN 12299's N_MV (:mod:`.comfort`); per wheelset the lateral wheel
force, the dynamic wheel loads and Y/Q with the dynamic load (``docs/ride.md``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from express.analysis.ride.comfort import mean_comfort, mean_comfort_spectral, sperling_index, sperling_index_time
from express.analysis.ride.spectral import check_frequencies, check_psd, spectral_rms
from express.analysis.ride.vehicle import AXES, RideResponse, output_points, point_rows
from express.analysis.ride.weighting import WB, WD, weigh_time_history
from express.base.diagnostics import InputError
from express.numeric.statespace import VehicleModel

__all__ = [
    "PointComfort",
    "WheelForces",
    "comfort_from_psd",
    "comfort_from_time_histories",
    "point_comfort",
    "simulation_accelerations",
    "wheel_forces",
    "y_over_q_level",
]

FloatArray = NDArray[np.float64]


# --- comfort -----------------------------------------------------------------------------


@dataclass(frozen=True)
class PointComfort:
    """Comfort at one output point.

    Attributes
    ----------
    directions : tuple of str
        Axes the point moves in (the others count as zero in ``n_mv``).
    rms, weighted_rms : dict of str to float
        Acceleration RMS per axis [m/s^2], unweighted and weighted (Wd for x and y, Wb
        for z).
    wz : dict of str to float
        Sperling's index, ``"y"`` with the lateral and ``"z"`` with the vertical weighting.
    n_mv : float
        EN 12299 simplified mean comfort.
    a_p95 : dict of str to float
        Its 95th percentiles of the weighted 5-s RMS per axis [m/s^2].
    method : str
        ``"gaussian"`` or ``"rms"`` (from spectra) or ``"time"`` (from histories).
    """

    directions: tuple[str, ...]
    rms: dict[str, float]
    weighted_rms: dict[str, float]
    wz: dict[str, float]
    n_mv: float
    a_p95: dict[str, float]
    method: str

    def as_dict(self) -> dict:
        """The indices as plain data (accelerations in m/s^2)."""
        return {"directions": list(self.directions), "rms": self.rms, "weighted_rms": self.weighted_rms,
                "wz": self.wz, "n_mv": self.n_mv, "a_p95": self.a_p95, "method": self.method}


_WEIGHTING = {"x": WD, "y": WD, "z": WB}
_SPERLING = {"y": "lateral", "z": "vertical"}


def comfort_from_psd(frequencies: ArrayLike, psds: Mapping[str, ArrayLike], method: str = "gaussian") -> PointComfort:
    """:class:`PointComfort` from acceleration PSDs [(m/s^2)^2/Hz] by axis (``x``, ``y``, ``z``)."""
    f = check_frequencies(frequencies, "comfort_from_psd", positive=True)
    g = {axis: check_psd(psds[axis], f.size, f"comfort_from_psd ({axis})") for axis in AXES if axis in psds}
    zero = np.zeros(f.size)
    comfort = mean_comfort_spectral(f, g.get("x", zero), g.get("y", zero), g.get("z", zero), method=method)
    p95 = {"x": comfort.a_xp95, "y": comfort.a_yp95, "z": comfort.a_zp95}
    return PointComfort(
        directions=tuple(g),
        rms={axis: float(spectral_rms(f, psd)) for axis, psd in g.items()},
        weighted_rms={axis: float(spectral_rms(f, _WEIGHTING[axis].magnitude(f) ** 2 * psd)) for axis, psd in g.items()},
        wz={axis: sperling_index(f, psd, _SPERLING[axis]) for axis, psd in g.items() if axis in _SPERLING},
        n_mv=comfort.n_mv, a_p95={axis: p95[axis] for axis in g}, method=method,
    )


def point_comfort(response: RideResponse, method: str = "gaussian") -> dict[str, PointComfort]:
    """:func:`comfort_from_psd` of every output point of ``response``."""
    return {
        point: comfort_from_psd(response.frequencies, {a: response.psd_of(f"{point}.a{a}") for a in axes}, method)
        for point, axes in response.directions.items() if axes
    }


def comfort_from_time_histories(histories: Mapping[str, ArrayLike], sampling_rate: float) -> PointComfort:
    """:class:`PointComfort` from sampled accelerations [m/s^2] by axis (mean removed).

    Wz from the periodogram (:func:`.comfort.sperling_index_time`), N_MV from 5-s
    windows (:func:`.comfort.mean_comfort`); at least one 5-s window is needed.
    """
    x = {axis: np.asarray(histories[axis], dtype=float) for axis in AXES if axis in histories}
    x = {axis: signal - signal.mean() for axis, signal in x.items()}
    if not x:
        raise InputError("comfort_from_time_histories: no acceleration given (axes x, y, z)")
    zero = np.zeros(next(iter(x.values())).size)
    comfort = mean_comfort(x.get("x", zero), x.get("y", zero), x.get("z", zero), sampling_rate)
    p95 = {"x": comfort.a_xp95, "y": comfort.a_yp95, "z": comfort.a_zp95}

    def rms(signal: np.ndarray) -> float:
        return float(np.sqrt(np.mean(signal**2)))

    return PointComfort(
        directions=tuple(x), rms={a: rms(s) for a, s in x.items()},
        weighted_rms={a: rms(weigh_time_history(s, sampling_rate, _WEIGHTING[a])) for a, s in x.items()},
        wz={a: sperling_index_time(s, sampling_rate, _SPERLING[a]) for a, s in x.items() if a in _SPERLING},
        n_mv=comfort.n_mv, a_p95={a: p95[a] for a in x}, method="time",
    )


# --- wheel forces ------------------------------------------------------------------------


def y_over_q_level(sigma_y: float, sigma_q: float, covariance: float, q0: float, z: float = 3.0) -> float:
    """The level r that ``Y / (Q0 + dQ)`` exceeds with the probability of ``z`` standard
    deviations of a normal variable, for jointly Gaussian, zero-mean Y and dQ.

    ``Y / (Q0 + dQ) > r`` (with ``Q0 + dQ > 0``) is ``Y - r dQ > r Q0``, and
    ``Y - r dQ`` is normal with variance ``s_Y^2 - 2 r C + r^2 s_Q^2``; setting
    ``r Q0 = z sqrt(...)`` gives the positive root of
    ``(Q0^2 - z^2 s_Q^2) r^2 + 2 z^2 C r - z^2 s_Y^2 = 0``.  Both signs of Y are tried
    (C -> -C) and the larger level returned; ``inf`` if ``z s_Q >= Q0`` (the wheel
    unloads that often).  With ``s_Q = 0`` it is ``z s_Y / Q0``.
    """
    a = q0**2 - (z * sigma_q) ** 2
    if a <= 0:
        return math.inf
    levels = [(-(z**2) * c + math.sqrt((z**2 * c) ** 2 + a * (z * sigma_y) ** 2)) / a for c in (covariance, -covariance)]
    return max(levels)


@dataclass(frozen=True)
class WheelForces:
    """Wheel/rail forces of one wheelset (:func:`wheel_forces`).

    Attributes
    ----------
    wheelset : str
    wheel_load : float
        Static wheel load Q0 [N].
    y_rms : float
        RMS of the lateral force of one wheel [N].
    dq_rms : dict of str to float
        RMS of the dynamic wheel load per side ``L``, ``R`` [N]; zeros without
        vertical rail inputs (``dynamic_q`` False).
    yq_rms : float
        RMS of ``Y / Q0`` (static load).
    yq_level : dict of str to float
        ``Y / Q`` with the dynamic load exceeded with probability ``1 - Phi(z)`` per side
        (:func:`y_over_q_level`); ``inf`` where the wheel unloads (:attr:`unloads`).
    z : float
        The number of standard deviations used.
    y_rel_rms : float
        RMS of ``y - yR`` [m].
    flange_clearance : float
        [m].
    dynamic_q : bool
    """

    wheelset: str
    wheel_load: float
    y_rms: float
    dq_rms: dict[str, float]
    yq_rms: float
    yq_level: dict[str, float]
    z: float
    y_rel_rms: float
    flange_clearance: float
    dynamic_q: bool

    @property
    def unloads(self) -> dict[str, bool]:
        """Per side, whether ``z`` standard deviations of the dynamic wheel load reach the
        static load (``z s_Q >= Q0``): the wheel unloads more often than the level's
        probability, and ``Y / Q`` has no such level."""
        return {side: self.z * self.dq_rms[side] >= self.wheel_load for side in self.dq_rms}

    def as_dict(self) -> dict:
        """The forces as plain data (SI: N, m); ``yq_sigmas`` is :attr:`z`; ``yq_level`` is
        None on a side that unloads (``unloads``)."""
        levels = {side: None if self.unloads[side] else level for side, level in self.yq_level.items()}
        return {"wheel_load": self.wheel_load, "y_rms": self.y_rms, "dq_rms": self.dq_rms, "dynamic_q": self.dynamic_q,
                "yq_rms": self.yq_rms, "yq_level": levels, "unloads": self.unloads, "yq_sigmas": self.z,
                "y_rel_rms": self.y_rel_rms, "flange_clearance": self.flange_clearance}

    def notes(self) -> list[str]:
        """One sentence per side that unloads, with the figures."""
        return [f"{self.wheelset} {side}: {self.z:g} standard deviations of the dynamic wheel load "
                f"({self.z:g} x {self.dq_rms[side] / 1e3:.2f} kN) reach the static load {self.wheel_load / 1e3:.2f} kN: "
                f"the wheel unloads more often than that; Y/Q has no {self.z:g}-sigma level"
                for side, unloads in self.unloads.items() if unloads]


def wheel_forces(response: RideResponse, vehicle: VehicleModel, z: float = 3.0) -> dict[str, WheelForces]:
    """Y, dQ and Y/Q of every wheelset of ``vehicle`` from ``response``."""
    if not (math.isfinite(z) and z > 0):
        raise InputError(f"wheel_forces: z must be > 0, got {z!r}")
    out = {}
    for w in vehicle.wheelsets:
        y_name = f"{w.name}.Y"
        sigma_y = response.rms(y_name)
        dynamic = w.name in response.wheel_sides
        dq, levels = {}, {}
        for side in ("L", "R"):
            name = f"{w.name}.dQ{side}"
            dq[side] = response.rms(name) if dynamic else 0.0
            covariance = response.covariance(y_name, name) if dynamic else 0.0
            levels[side] = y_over_q_level(sigma_y, dq[side], covariance, w.wheel_load, z)
        out[w.name] = WheelForces(w.name, w.wheel_load, sigma_y, dq, sigma_y / w.wheel_load, levels, z,
                                  response.rms(f"{w.name}.y_rel"), w.flange_clearance, dynamic)
    return out


# --- time histories of a simulation ------------------------------------------------------


def simulation_accelerations(vehicle: VehicleModel, result: Any, track: Any) -> dict[str, dict[str, FloatArray]]:
    """Accelerations [m/s^2] of the output points along a simulation, by point and axis.

    For a linear run (no flange contact, saturation or bump stops) they come exactly from
    the state equation ``x' = A x + B u + Bd u'`` with the run's track inputs
    (:func:`express.analysis.time.simulate.track_inputs`); otherwise from second-order
    central differences of the velocities.

    Parameters
    ----------
    vehicle : VehicleModel
    result : express.analysis.time.simulate.SimulationResult
    track : express.rail.track.Track
        The track of the run.
    """
    from express.analysis.time.simulate import track_inputs

    options = result.options
    linear = not (options.get("flange") or options.get("saturation") or options.get("clearances"))
    if linear:
        inputs = track_inputs(vehicle, track, result.distance, result.speed)
        form = vehicle.form
        states = np.concatenate([result.q, result.q_dot[:, form.massive]], axis=1)
        rates = states @ vehicle.state_matrix(result.speed).T + inputs.drive(vehicle, result.speed)
        q_ddot = np.zeros_like(result.q)
        q_ddot[:, form.massive] = rates[:, vehicle.n:]
    else:
        q_ddot = np.gradient(result.q_dot, result.time, axis=0, edge_order=2)
    out = {}
    for point in output_points(vehicle):
        by_axis = point_rows(vehicle, point.body, point.offset, f"output {point.name}", point.name)
        out[point.name] = {axis: q_ddot @ row for axis, row in by_axis.items()}
    return out
