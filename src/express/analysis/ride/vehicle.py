"""Vehicle-level ride: the stationary random response of a vehicle to track irregularity.

This module owns the link between a :class:`~express.numeric.statespace.VehicleModel` and the
spectral tools of :mod:`.spectral`: which inputs the track drives and how, which outputs
are reported and what they are computed from, and the response itself
(``docs/ride.md``, "Vehicle-level response"); :mod:`.summaries` turns a response into
comfort per point and wheel forces.

Track inputs
------------
The track has four mutually uncorrelated irregularity components (one-sided spatial
PSDs of :mod:`express.rail.track.spectra`): ``alignment`` a (lateral, + left),
``vertical`` z_v (mean rail height, + up), ``cross_level`` c (rail height difference
``z_R - z_L``, the sign of the cant) and ``gauge`` g (+ wider).  They drive:

- ``<W>.yR`` of every wheelset W (the lateral irregularity of the wheel/rail model):
  ``a``;
- the motion of a ground named after a body ``<B>_rail`` (both rails),
  ``<B>_railL`` (left rail) or ``<B>_railR`` (right rail), or of a ground that holds one
  wheelset and nothing else (both rails, or one rail when all its points lie on one
  side), the *rail grounds*:
  along z ``z_v``, ``z_v - c/2``, ``z_v + c/2``; along y ``a``, ``a + g/2``, ``a - g/2``.
  This is how a model receives vertical (and 3-D lateral) rail inputs: an element
  (the wheel/rail contact spring, or the primary suspension of a wheelset without
  vertical DOFs) from the body to its rail ground.

Every input of body or wheelset k, at station ``x_k``, is the irregularity the leading
one met ``tau_k = (x_lead - x_k) / v`` earlier (factor ``exp(-i w tau_k)``): the
wheelbase filtering.  Other inputs (flange penetrations, curvature, cant, other grounds,
rotations of rail grounds) stay zero and are listed in :attr:`RideResponse.notes`.

Outputs
-------
- ``<point>.ax``, ``.ay``, ``.az``: acceleration [m/s^2] of each ``[rail.outputs]``
  point, ``u = t + theta x r`` on its body (:mod:`express.assembly.kinematics`), for each
  direction in which the body's DOFs move the point;
- ``<W>.Y``: lateral force of one wheel of wheelset W [N], half the wheelset's linear
  lateral creep force ``-2 f2 (y'/v - psi)`` (both wheels have the same creepage and
  coefficients in the linear model; no flange contact; the ``Q<n>`` of a simulation
  without flange contact);
- ``<W>.y_rel``: wheelset lateral displacement relative to the track ``y - yR`` [m]
  (to compare with the flange clearance: the linear model holds while it stays inside);
- ``<W>.dQL``, ``<W>.dQR``: dynamic vertical wheel loads [N], the z force of the
  elements between the vehicle and the rail grounds of W, on the vehicle (+ up: more
  load); with one ground ``<W>_rail`` each wheel carries half of it.  Absent when the
  model has no vertical rail inputs.
- ``<E>.deflection``, ``<E>.rate``: deflection [m; rad] and its rate of every friction
  element and characteristic E (:func:`express.forces.linearisation.nonlinear_rows`),
  what the statistical linearisation of :mod:`.statistical` reads.

Each output is ``y = (D0 + i w D1 - w^2 D2) q + (E0 + i w E1) u`` and the state
``x = [q; q_D']`` solves ``(i w I - A) x = (B + i w Bd) u`` (:func:`.spectral.coordinate_response`: by modal superposition
where it is well conditioned, else by the Schur form).
Because the components are uncorrelated and each is fully coherent between wheelsets,
one right-hand side per component suffices: ``u_j(f) = sum_k T[k, j] exp(-i w tau_k)``
at the driven inputs k, and ``G_y = sum_j |H_yj|^2 G_j`` -- the same as
``H G_u H^H`` with the cross-spectral matrix of :func:`.spectral.track_input_spectrum`.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from express.analysis.frequency.frequency import require_stable
from express.analysis.ride.spectral import (
    check_frequencies,
    check_psd,
    coordinate_response,
    spatial_to_temporal,
    spectral_rms,
)
from express.analysis.ride.track_classes import TRACK_CLASSES, track_class_spectra
from express.analysis.time.rail_heights import HeightInputs, contact_springs, height_inputs
from express.assembly.kinematics import end_motion
from express.base.arguments import si_argument, si_arguments
from express.base.data import DataRecord, columns_frame
from express.base.diagnostics import AnalysisError, InputError
from express.base.names import did_you_mean
from express.forces.linearisation import nonlinear_rows
from express.model.modal_body import modal_motion
from express.model.parameters import expression_value
from express.model.records import ElementKind, Model
from express.numeric.statespace import VehicleModel
from express.rail.track.spectra import COMPONENTS

__all__ = [
    "AXES",
    "DEFAULT_BAND",
    "DEFAULT_POINTS",
    "TRACK_CLASSES",
    "RailInputs",
    "RideResponse",
    "felt_components",
    "point_rows",
    "rail_inputs",
    "ride_response",
    "track_class_spectra",
]

FloatArray = NDArray[np.float64]
AXES = ("x", "y", "z")
#: Default frequency band [Hz] and number of log-spaced frequencies of :func:`ride_response`.
DEFAULT_BAND = (0.1, 50.0)
DEFAULT_POINTS = 2000
ACCELERATION_UNIT = "m/s^2"
_RAIL_GROUND = re.compile(r"(?P<body>[A-Za-z][A-Za-z0-9_]*?)_rail(?P<side>[LR]?)\.(?P<axis>r?[xyz])\Z")
# (axis, side) of a rail ground -> coefficient of each component
_RAIL_MIXING = {
    ("z", ""): {"vertical": 1.0},
    ("z", "L"): {"vertical": 1.0, "cross_level": -0.5},
    ("z", "R"): {"vertical": 1.0, "cross_level": 0.5},
    ("y", ""): {"alignment": 1.0},
    ("y", "L"): {"alignment": 1.0, "gauge": 0.5},
    ("y", "R"): {"alignment": 1.0, "gauge": -0.5},
}
# displacement of a point at r = (lx, ly, lz): t + theta x r, per axis
_ROTATION_TERMS = {0: (("ry", 1, 2), ("rz", -1, 1)), 1: (("rz", 1, 0), ("rx", -1, 2)), 2: (("rx", 1, 1), ("ry", -1, 0))}

def _model(vehicle: VehicleModel) -> Model:
    """The vehicle's model (ride analyses need its points and bodies)."""
    if vehicle.model is None:
        raise InputError("the ride analysis needs the vehicle's model (build it with express.numeric.statespace.load_vehicle)")
    return vehicle.model


def output_points(vehicle: VehicleModel) -> tuple:
    """The model's output points (none without rail data)."""
    rail = _model(vehicle).rail
    return rail.outputs if rail is not None else ()



@dataclass(frozen=True)
class RailInputs:
    """The inputs of a vehicle the track drives.

    Attributes
    ----------
    names : tuple of str
        Driven inputs (``W1.yR``, ``W1_railL.z``, ...).
    columns : numpy.ndarray of int, shape (K,)
        Their indices in ``vehicle.inputs``.
    positions : numpy.ndarray, shape (K,)
        Station ``x`` [m] of the wheelset or body of each.
    mixing : numpy.ndarray, shape (K, len(COMPONENTS))
        Coefficient of each track component in each input.
    rail_grounds : dict of str to (str, str)
        Rail ground id -> (body, side ``""``, ``"L"`` or ``"R"``).
    undriven : tuple of str
        Inputs left at zero.
    """

    names: tuple[str, ...]
    columns: NDArray[np.int64]
    positions: FloatArray
    mixing: FloatArray
    rail_grounds: dict[str, tuple[str, str]]
    undriven: tuple[str, ...]

    def delays(self, speed: float) -> FloatArray:
        """``tau_k = (max x - x_k) / v`` [s] of each driven input."""
        return (self.positions.max() - self.positions) / speed if self.positions.size else self.positions


def _value(vehicle: VehicleModel, expression: Any, what: str) -> float:
    try:
        return expression_value(expression, vehicle.values)
    except (KeyError, ValueError) as error:
        raise InputError(f"{what}: {error}") from None


def _wheelset_grounds(vehicle: VehicleModel) -> dict[str, tuple[str, str]]:
    """Grounds that hold one rail wheelset and nothing else, whatever their names:
    ground id -> (wheelset, side) (e.g. the Manchester vehicle's ``T1_GF`` under ``W1``).
    Such a ground is that wheelset's rail ground for both rails (side ``""``), or for the
    left (``"L"``) or right (``"R"``) rail when every point of it lies on that side
    (``y > 0`` or ``y < 0``)."""
    model = _model(vehicle)
    ground_ids = {ground.id for ground in model.grounds}
    hosts = {point.id: point.host for point in model.points}
    wheelsets = {w.name for w in vehicle.wheelsets}
    held: dict[str, set[str]] = {}
    for element in model.elements:
        ends = (hosts.get(element.s_end), hosts.get(element.t_end))
        for here, there in (ends, ends[::-1]):
            if here in ground_ids and there not in ground_ids:
                held.setdefault(here, set()).add(str(there))
    found = {}
    for ground, bodies in held.items():
        if len(bodies) == 1 and bodies <= wheelsets:
            lateral = [_value(vehicle, point.offset[1], f"point {point.id}") for point in model.points if point.host == ground]
            side = "L" if lateral and min(lateral) > 0 else "R" if lateral and max(lateral) < 0 else ""
            found[ground] = (next(iter(bodies)), side)
    return found


def rail_inputs(vehicle: VehicleModel) -> RailInputs:
    """Which inputs of ``vehicle`` the track drives, with what, from where (module docstring)."""
    model = _model(vehicle)
    bodies = {body.id: body for body in model.bodies} if model is not None else {}
    stations = {w.name: w.station for w in vehicle.wheelsets}
    irregularity = {f"{w.name}.yR": w.name for w in vehicle.wheelsets}
    under_wheelsets = _wheelset_grounds(vehicle)
    names, columns, positions, rows, undriven = [], [], [], [], []
    grounds: dict[str, tuple[str, str]] = {}
    for column, name in enumerate(vehicle.inputs):
        mix: dict[str, float] | None = None
        ground, _, axis = name.partition(".")
        match = _RAIL_GROUND.match(name)
        if name in irregularity:
            mix, position = {"alignment": 1.0}, stations[irregularity[name]]
        elif (match and match["body"] in bodies) or ground in under_wheelsets:
            body_id, side = (match["body"], match["side"]) if match and match["body"] in bodies else under_wheelsets[ground]
            grounds[ground] = (body_id, side)
            mix = _RAIL_MIXING.get((axis, side))
            position = _value(vehicle, bodies[body_id].position[0], f"body {body_id} position")
        if mix is None:
            undriven.append(name)
            continue
        names.append(name)
        columns.append(column)
        positions.append(position)
        rows.append([mix.get(component, 0.0) for component in COMPONENTS])
    return RailInputs(
        tuple(names), np.array(columns, dtype=np.int64), np.array(positions, dtype=float),
        np.array(rows, dtype=float).reshape(len(names), len(COMPONENTS)), grounds, tuple(undriven),
    )


# --- outputs -----------------------------------------------------------------------------


@dataclass
class _Rows:
    """Output rows ``y = (D0 + i w D1 - w^2 D2) q + (E0 + i w E1) u``, built one by one."""

    n: int
    m: int
    names: list[str] = field(default_factory=list)
    units: list[str] = field(default_factory=list)
    rows: list[tuple[np.ndarray, ...]] = field(default_factory=list)

    def add(self, name: str, unit: str, **parts: np.ndarray) -> None:
        zero_q, zero_u = np.zeros(self.n), np.zeros(self.m)
        self.names.append(name)
        self.units.append(unit)
        self.rows.append(tuple(parts.get(k, zero_q) for k in ("d0", "d1", "d2"))
                         + tuple(parts.get(k, zero_u) for k in ("e0", "e1")))

    def matrices(self) -> tuple[np.ndarray, ...]:
        return tuple(np.array([row[i] for row in self.rows]).reshape(len(self.rows), -1) for i in range(5))


def _dof_row(vehicle: VehicleModel, coefficients: Mapping[str, Any], what: str) -> np.ndarray:
    """A row over q from ``{dof: expression}``; refuses DOFs removed by pins."""
    row = np.zeros(vehicle.n)
    for dof, coefficient in coefficients.items():
        if dof not in vehicle.dofs:
            raise InputError(f"{what}: moves with {dof}, which a pin eliminates; ride outputs need "
                             "bodies whose DOFs are kept")
        row[vehicle.dofs.index(dof)] += _value(vehicle, coefficient, what)
    return row


def point_rows(vehicle: VehicleModel, body_id: str, offset, what: str, point: str | None = None) -> dict[str, np.ndarray]:
    """Rows over q of the displacement of a point on a body (``offset`` [m], parameter
    expressions), for each axis along which the body's DOFs move it; on a flexible body
    the modes move the point too (``point``: the CP or output name its shapes are given at,
    :mod:`express.model.modal_body`).

    Raises
    ------
    InputError
        If one of those DOFs was eliminated by a pin.
    """
    model = _model(vehicle)
    body = model.body(body_id)
    rows = {}
    for axis, name in enumerate(AXES):
        terms: dict[str, Any] = {}
        if name in body.dofs:
            terms[f"{body_id}.{name}"] = 1
        for rotation, sign, component in _ROTATION_TERMS[axis]:
            if rotation in body.dofs:
                terms[f"{body_id}.{rotation}"] = sign * offset[component]
        if point is not None and model.flexible:
            terms.update(modal_motion(model, body_id, point, offset, axis))
        row = _dof_row(vehicle, terms, what)
        if np.any(row != 0):
            rows[name] = row
    return rows


_AT_TANGENT = (ElementKind.PARALLEL, ElementKind.FRICTION, ElementKind.CHARACTERISTIC)


def _wheel_load_rows(vehicle: VehicleModel, inputs: RailInputs, rows: _Rows) -> dict[str, tuple[str, ...]]:
    """``<W>.dQL``, ``<W>.dQR`` from the z elements between the vehicle and the rail grounds."""
    model = _model(vehicle)
    n, m = vehicle.n, rows.m
    hosts = {point.id: point.host for point in model.points}
    points = {point.id: point for point in model.points}
    loads: dict[str, dict[str, np.ndarray]] = {}  # body -> side -> [k dq, c dq, k du, c du]
    # a friction element or characteristic: its tangent is its stiffness (or damping); a
    # linearised vehicle's equivalent changes them as it changes K and C
    seen = {e.element: (e.stiffness - (e.tangent if e.matrix == "K" else 0.0),
                        e.damping - (e.tangent if e.matrix == "C" else 0.0)) for e in getattr(vehicle, "elements", ())}
    for element in model.elements:
        on_ground = [hosts.get(end) in inputs.rail_grounds for end in (element.s_end, element.t_end)]
        if on_ground[0] == on_ground[1] or element.rotational or element.direction != 2 or element.vector is not None:
            continue
        what = f"element {element.id} (to a rail ground)"
        if element.kind not in _AT_TANGENT:
            raise InputError(f"{what}: a series or clearance element cannot carry the wheel load in a ride analysis")
        body, side = inputs.rail_grounds[hosts[element.s_end if on_ground[0] else element.t_end]]
        if not side:  # one ground under both wheels: the side of the element's wheel end (+y left)
            lateral = _value(vehicle, points[element.t_end if on_ground[0] else element.s_end].offset[1], what)
            side = "L" if lateral > 0 else "R" if lateral < 0 else ""
        delta_q, delta_u = np.zeros(n), np.zeros(m)
        for end, sign in ((element.s_end, 1.0), (element.t_end, -1.0)):
            dofs, ground_inputs = end_motion(model, end, element.direction, False)
            delta_q += sign * _dof_row(vehicle, dofs, what)
            for name, coefficient in ground_inputs.items():
                delta_u[vehicle.inputs.index(name)] += sign * _value(vehicle, coefficient, what)
        # the element's force on its vehicle end, + up: -(k d + c d') on S, +(k d + c d') on T
        on_vehicle = -1.0 if on_ground[1] else 1.0
        k_seen, c_seen = seen.get(element.id, (0.0, 0.0))
        k = on_vehicle * (_value(vehicle, element.stiffness, what) + k_seen)
        c = on_vehicle * (_value(vehicle, element.damping, what) + c_seen)
        parts = loads.setdefault(body, {}).setdefault(side, np.zeros(2 * (n + m)))
        parts += np.concatenate([k * delta_q, c * delta_q, k * delta_u, c * delta_u])
    for body, by_side in loads.items():
        shared = by_side.get("", np.zeros(2 * (n + m)))  # elements on the centre line: half to each wheel
        for side in ("L", "R"):
            row = 0.5 * shared + by_side.get(side, np.zeros(2 * (n + m)))
            rows.add(f"{body}.dQ{side}", "N", d0=row[:n], d1=row[n:2 * n], e0=row[2 * n:2 * n + m], e1=row[2 * n + m:])
    return dict.fromkeys(loads, ("L", "R"))


def _output_rows(vehicle: VehicleModel, inputs: RailInputs, speed: float) -> tuple[_Rows, dict, dict]:
    rows = _Rows(vehicle.n, len(vehicle.inputs))
    directions: dict[str, tuple[str, ...]] = {}
    for point in output_points(vehicle):
        by_axis = point_rows(vehicle, point.body, point.offset, f"output {point.name}", point.name)
        directions[point.name] = tuple(by_axis)
        for axis, row in by_axis.items():
            rows.add(f"{point.name}.a{axis}", ACCELERATION_UNIT, d2=row)
    for w in vehicle.wheelsets:
        lateral, yaw = np.zeros(vehicle.n), np.zeros(vehicle.n)
        lateral[w.y], yaw[w.psi] = -w.f2 / speed, w.f2
        rows.add(f"{w.name}.Y", "N", d0=yaw, d1=lateral)
        relative, rail = np.zeros(vehicle.n), np.zeros(len(vehicle.inputs))
        relative[w.y], rail[vehicle.inputs.index(f"{w.name}.yR")] = 1.0, -1.0
        rows.add(f"{w.name}.y_rel", "m", d0=relative, e0=rail)
    sides = _wheel_load_rows(vehicle, inputs, rows)
    for element in nonlinear_rows(vehicle):  # what the statistical linearisation reads
        unit = "rad" if element.rotational else "m"
        rows.add(f"{element.element}.deflection", unit, d0=element.gradient, e0=element.inputs)
        rows.add(f"{element.element}.rate", f"{unit}/s", d1=element.gradient, e1=element.inputs)
    return rows, directions, sides


# --- response ----------------------------------------------------------------------------


@dataclass(frozen=True, repr=False)
class RideResponse(DataRecord):
    """Stationary random response of a vehicle on a track, one-sided PSDs in Hz.

    Attributes
    ----------
    frequencies : numpy.ndarray, shape (F,)
        [Hz].
    speed : float
        [m/s].
    components : tuple of str
        Track components that drive the vehicle (order of the last axis of ``transfer``).
    input_psd : dict of str to numpy.ndarray
        Temporal PSD [m^2/Hz] of each component in ``components``.
    names, units : tuple of str
        Outputs (module docstring) and their SI units.
    transfer : numpy.ndarray, complex, shape (F, len(names), len(components))
        Response of each output to each component [unit/m], delays included.
    psd : numpy.ndarray, shape (F, len(names))
        ``sum_j |transfer_j|^2 G_j`` [unit^2/Hz].
    directions : dict of str to tuple of str
        Axes in which each output point can move.
    wheel_sides : dict of str to tuple of str
        Bodies with dynamic wheel loads, and the sides.
    notes : tuple of str
        What the analysis left out (undriven inputs, components the model cannot feel).
    """

    frequencies: FloatArray
    speed: float
    components: tuple[str, ...]
    input_psd: dict[str, FloatArray]
    names: tuple[str, ...]
    units: tuple[str, ...]
    transfer: NDArray[np.complex128] = field(repr=False)
    psd: FloatArray = field(repr=False)
    directions: dict[str, tuple[str, ...]]
    wheel_sides: dict[str, tuple[str, ...]]
    notes: tuple[str, ...] = ()

    def to_xarray(self):
        """The response as an :class:`xarray.Dataset` over ``frequency`` [Hz], ``output``
        and ``component`` (:func:`express.analysis.result_data.ride_dataset`)."""
        from express.analysis.result_data import ride_dataset

        return ride_dataset(self)

    def to_pandas(self):
        """The PSDs as a :class:`pandas.DataFrame` indexed by ``frequency [Hz]``, one column
        per output ``<name> [<unit>^2/Hz]``."""
        columns = {"frequency": self.frequencies, **{n: self.psd[:, i] for i, n in enumerate(self.names)}}
        units = {"frequency": "Hz", **{n: f"({u})^2/Hz" if u else "1/Hz" for n, u in zip(self.names, self.units, strict=True)}}
        return columns_frame(columns, units, index="frequency")

    def _summary(self) -> list[str]:
        f = self.frequencies
        return [f"{len(self.names)} outputs, components {', '.join(self.components)}, at {self.speed:.3f} m/s",
                f"{f.size} frequencies {f[0]:g}-{f[-1]:g} Hz" if f.size else "no frequencies"]

    def index(self, name: str) -> int:
        try:
            return self.names.index(name)
        except ValueError:
            raise KeyError(f"unknown ride output {name!r}; known: {', '.join(self.names)}") from None

    def psd_of(self, name: str) -> FloatArray:
        """One-sided PSD of an output [unit^2/Hz], shape (F,)."""
        return self.psd[:, self.index(name)]

    def rms(self, name: str) -> float:
        """RMS of an output over the frequency grid [unit]."""
        return float(spectral_rms(self.frequencies, self.psd_of(name)))

    def covariance(self, first: str, second: str) -> float:
        """``integral Re G_12 df``, ``G_12 = sum_j H_1j conj(H_2j) G_j`` [unit_1 unit_2]."""
        h1, h2 = self.transfer[:, self.index(first)], self.transfer[:, self.index(second)]
        weights = np.stack([self.input_psd[c] for c in self.components], axis=1)
        cross = np.sum((h1 * np.conj(h2)).real * weights, axis=1)
        return float(np.trapezoid(cross, self.frequencies))


def felt_components(vehicle: VehicleModel) -> tuple[str, ...]:
    """The track components that reach ``vehicle``: through its rail inputs, and the cross
    level at its contact springs where no rail ground takes it (:func:`_height_inputs`)."""
    inputs = rail_inputs(vehicle)
    springs = contact_springs(vehicle) is not None
    return tuple(c for j, c in enumerate(COMPONENTS)
                 if (inputs.names and np.any(inputs.mixing[:, j] != 0)) or (c == "cross_level" and springs))


def _height_inputs(vehicle: VehicleModel, inputs: RailInputs, outputs: list[str]) -> HeightInputs | None:
    """The cross level at the contact springs (:mod:`express.analysis.time.rail_heights`)
    when no rail ground takes it, as a time run takes it; None otherwise."""
    if inputs.names and np.any(inputs.mixing[:, COMPONENTS.index("cross_level")] != 0):
        return None
    return height_inputs(vehicle, COMPONENTS, outputs)


def _speed(vehicle: VehicleModel, speed: float | None) -> float:
    v = float(vehicle.speed if speed is None else si_argument(speed, "speed", "speed"))
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"ride: the speed must be > 0 m/s, got {v!r}" + (" (the model has none)" if speed is None else ""))
    return v


def linear_instability(vehicle: VehicleModel, speed: float) -> str | None:
    """Why the linear model has no stationary response at ``speed`` [m/s] (the unstable
    mode, :func:`express.analysis.frequency.frequency.require_stable`), None when it has one."""
    try:
        require_stable(vehicle, speed)
    except AnalysisError as error:
        return str(error).split(": its response to a sinusoid")[0]
    return None


def _check_stable(vehicle: VehicleModel, v: float) -> None:
    """:func:`linear_instability`'s reason as the error of a random excitation: above the
    critical speed a free motion grows, so no stationary response (and no PSD) exists."""
    reason = linear_instability(vehicle, v)
    if reason is not None:
        raise AnalysisError(f"ride: {vehicle.equations.name}: {reason}: its response to a random track grows "
                            "without bound, there is no stationary response (PSD, RMS, comfort) to report")


def _undriven_notes(vehicle: VehicleModel, inputs: RailInputs) -> list[str]:
    """One line per kind of input left at zero."""
    layout = vehicle.layout
    if layout is None:
        return []
    kinds = (
        ("flange penetrations (linear model: no flange contact)", set(layout.flange)),
        ("curvature and cant (straight track)", set(layout.curvature) | set(layout.cant)),
    )
    notes, rest = [], list(inputs.undriven)
    for what, names in kinds:
        found = [name for name in rest if name in names]
        rest = [name for name in rest if name not in names]
        if found:
            notes.append(f"left at zero: {what}: {', '.join(found)}")
    if rest:
        notes.append(f"left at zero: inputs the track does not drive (not rail grounds, docs/ride.md): {', '.join(rest)}")
    return notes


def ride_response(
    vehicle: VehicleModel,
    spectra: Mapping[str, Any],
    speed: float | None = None,
    frequencies: ArrayLike | None = None,
) -> RideResponse:
    """PSDs of the ride outputs of ``vehicle`` running at ``speed`` on a random track.

    Parameters
    ----------
    vehicle : VehicleModel
        With rail data (wheelsets; ``[rail.outputs]`` for the accelerations).
    spectra : mapping of str to TrackSpectrum
        Spatial spectrum per component of :data:`express.rail.track.spectra.COMPONENTS`
        (anything with ``psd(Omega)`` [m^2/(rad/m)]); e.g. :func:`track_class_spectra`.
    speed : float, str or pint.Quantity, optional
        [m/s] > 0 (a number is SI; a quantity carries its unit, ``"120 km/h"``); the
        model's own speed by default.
    frequencies : array_like, optional
        [Hz] > 0, increasing (numbers, or quantities: ``"5 rad/s"`` is 0.796 Hz); default :data:`DEFAULT_POINTS` log-spaced over
        :data:`DEFAULT_BAND`.

    Raises
    ------
    InputError
        Bad speed, frequencies, component names or spectrum values (negative PSD).
    AnalysisError
        The vehicle is unstable at that speed, or ``i w I - A`` is singular.
    """
    if vehicle.model is None or vehicle.model.rail is None or not vehicle.wheelsets:
        raise InputError("ride: the model has no rail data (no [rail] section with wheelsets)")
    v = _speed(vehicle, speed)
    f = check_frequencies(np.geomspace(*DEFAULT_BAND, DEFAULT_POINTS) if frequencies is None
                          else si_arguments(frequencies, "frequency", "frequencies"), "ride_response", positive=True)
    unknown = [name for name in spectra if name not in COMPONENTS]
    if unknown:
        raise InputError("; ".join(f"ride: unknown track component {name!r}{did_you_mean(name, COMPONENTS)}" for name in unknown)
                         + f" (known: {', '.join(COMPONENTS)})")
    inputs = rail_inputs(vehicle)
    notes = _undriven_notes(vehicle, inputs)
    rows, directions, sides = _output_rows(vehicle, inputs, v)
    heights = _height_inputs(vehicle, inputs, rows.names)
    mixing = inputs.mixing if heights is None else np.vstack([inputs.mixing, heights.mixing])
    used = []
    for j, component in enumerate(COMPONENTS):
        felt = bool(np.any(mixing[:, j] != 0))
        if component in spectra and felt:
            used.append(component)
        elif component in spectra:
            notes.append(f"{component}: the model has no input it drives (rail grounds, docs/ride.md)")
        elif felt:
            notes.append(f"{component}: no spectrum given (e.g. a table without that column): left at zero")
    if heights is not None and "cross_level" in used:
        notes.append("cross_level: imposed at the wheels' contact springs (one ground under both rails of a wheelset; "
                     "docs/track.md)")
    input_psd = {c: check_psd(spatial_to_temporal(spectra[c].psd, f, v), f.size, f"ride ({c} spectrum)") for c in used}
    a = vehicle.state_matrix(v)
    _check_stable(vehicle, v)
    w = 2.0 * math.pi * f
    n_f, n_j = f.size, len(used)
    mixing = mixing[:, [COMPONENTS.index(c) for c in used]]  # (K, J)
    d0, d1, d2, e0, e1 = rows.matrices()
    columns = inputs.columns
    b, bd = vehicle.input_matrix(v)[:, columns], vehicle.input_rate_matrix(v)[:, columns]
    e0, e1, positions = e0[:, columns], e1[:, columns], inputs.positions
    if heights is not None:  # the cross level at the contact springs: one more input per wheel
        b, bd = np.hstack([b, heights.b]), np.hstack([bd, heights.bd])
        e0, e1 = np.hstack([e0, heights.e0]), np.hstack([e1, heights.e1])
        positions = np.concatenate([positions, heights.positions])
    delays = (positions.max() - positions) / v if positions.size else positions
    # u_j at the driven inputs k: T[k, j] exp(-i w tau_k), laid out (K, F*J) for plain matrix products
    u = np.asarray(np.exp(-1j * np.outer(delays, w))[:, :, None] * mixing[:, None, :], dtype=np.complex128)
    u = u.reshape(-1, n_f * n_j)
    s = np.repeat(1j * w, n_j)  # i w for every (frequency, component) column
    try:
        y = coordinate_response(a, b, bd, (d0, d1, d2), u, s, f, vehicle.n)
    except np.linalg.LinAlgError as error:
        raise AnalysisError(f"ride: {error}") from None
    y = y + e0 @ u + (e1 @ u) * s
    transfer = y.reshape(-1, n_f, n_j).transpose(1, 0, 2)
    weights = np.stack([input_psd[c] for c in used], axis=1) if used else np.zeros((n_f, 0))
    psd = np.sum((transfer.real**2 + transfer.imag**2) * weights[:, None, :], axis=2)
    return RideResponse(f, v, tuple(used), input_psd, tuple(rows.names), tuple(rows.units), transfer, psd,
                        directions, sides, tuple(notes))
