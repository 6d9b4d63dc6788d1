"""Steady-state curving: the equilibrium of the nonlinear vehicle in a constant curve.

In a curve of constant radius and cant, at constant speed, every coordinate measured
from the track (``docs/rail.md``) is constant, so the state ``x`` of the time march
(:mod:`express.analysis.time.simulate`) solves (``docs/curving.md``, "Steady state")::

    0 = A(v) x + B(v) u + S z(x)

with ``u`` the curvature and cant at every station, ``z`` the nonlinear wheel/rail forces
(the contact tables' forces less their linear part, or the dead-band flange and creep
saturation) and the bump stops, ``S`` the columns they act through — the same equations
the time march integrates, with the time derivative zero.  They are solved by
pseudo-transient continuation (:func:`_pseudo_transient`: implicit Euler steps of growing
size, Newton's method in the limit) from the linear steady state ``-A^-1 B u``, with the
Jacobian ``A + S dz/dx``: ``A`` exact (from the symbolic M, C, K), ``dz/dx`` by
differences in the few wheelset and bump-stop coordinates ``z`` depends on.  Where the
iteration stalls at a jump of the contact, the time march itself settles the state
(:meth:`SteadyCurvingSolver._settle`; its fixed point solves the same equations).
Everything but ``u`` is built once per vehicle and speed (:class:`SteadyCurvingSolver`),
so a sweep costs some tens of milliseconds per curve.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from express.analysis.curving.curves import (
    MAX_UNBALANCED_ACCELERATION,
    CurveError,
    SteadyCurve,
    curves_of_track,
    track_problems,
)
from express.analysis.curving.measure import wheel_rail_outputs
from express.analysis.curving.outputs import WheelRailOutputs
from express.analysis.curving.step_solver import StepSolver
from express.analysis.time.force_elements import contact_tables_of, run_forces
from express.analysis.time.simulate import derived_outputs
from express.analysis.time.track_inputs import TrackInputs
from express.base.data import DataRecord, columns_frame
from express.base.diagnostics import ArgumentError
from express.forces.element import ForceSet
from express.model.modal_body import coordinate_unit
from express.model.parameters import expression_value
from express.numeric.statespace import VehicleModel
from express.rail.options import DEFAULT_CREEP_LAW, ContactModel, CreepLaw

__all__ = [
    "MAX_UNBALANCED_ACCELERATION",
    "CurveError",
    "NoSteadyStateError",
    "SteadyCurve",
    "SteadyCurving",
    "SteadyCurvingSolver",
    "curves_of_track",
    "steady_curving",
    "track_problems",
]

#: Relative residual the solution must reach (of the curve's forcing ``|B u|``); the
#: iteration goes on to 1e-11 when it can.  Where a contact jumps between two points
#: (profiles with two-point contact) the equations are discontinuous and the iteration
#: may end between 1e-11 and this.
_TOLERANCE = 1e-6
#: Relative residual below which the iteration's result is not polished by a time march.
_SETTLED = 1e-9


class NoSteadyStateError(CurveError):
    """A curve that can be run but in which the solver finds no equilibrium (where
    :func:`express.analysis.curving.settled.curving_or_settled` runs the vehicle into it
    instead)."""


@dataclass(frozen=True, repr=False)
class SteadyCurving(DataRecord):
    """The steady state of a vehicle in a constant curve.

    Attributes
    ----------
    curve : SteadyCurve
    speed : float
        [m/s].
    unbalanced_acceleration : float
        Cant deficiency in the track plane [m/s^2] (negative: excess).
    dofs : tuple of str
    q : numpy.ndarray, shape (n,)
        Coordinates from the track [m, rad].
    state : numpy.ndarray, shape (N,)
        The state of the time march.
    wheel_rail : WheelRailOutputs
        One instant.
    derived : dict of str to float
        Wheelset yaw in its bogie ``psi_TW{n}`` and lever angles ``theta_<lever>`` [rad].
    contact : str
        The contact model used.
    iterations : int
        Evaluations of the equations.
    residual : float
        ``|A x + B u + S z| / |B u|`` at the solution.
    growth : float or None
        The largest real part of the eigenvalues of the equations linearised at the
        state, ``A + G dz/dx`` (the time march's own tangent) [1/s]: negative for a stable
        equilibrium; None where not computed (more than :data:`STABILITY_STATES` states).
        With friction elements, stuck at their sliders (small motions stick).
    path : str
        With friction elements, how the state was reached (its sliders): through the
        curve's transition (:mod:`express.analysis.curving.transition`) or loaded from
        rest; empty without friction (the equilibrium is unique).
    """

    curve: SteadyCurve
    speed: float
    unbalanced_acceleration: float
    dofs: tuple[str, ...]
    q: np.ndarray
    state: np.ndarray
    wheel_rail: WheelRailOutputs
    derived: dict[str, float] = field(default_factory=dict)
    contact: str = ""
    iterations: int = 0
    residual: float = 0.0
    growth: float | None = None
    path: str = ""

    @property
    def stable(self) -> bool | None:
        """Whether the equilibrium is stable (``growth < 0``; None when not computed)."""
        return None if self.growth is None else self.growth < 0.0

    def columns(self) -> dict[str, float]:
        """The curve, then every output: ``R``, ``cant``, ``speed``, ``a_q``, the
        wheel/rail outputs (:meth:`WheelRailOutputs.columns`), the derived angles and
        each coordinate."""
        out = {"R": self.curve.radius, "cant": self.curve.cant, "speed": self.speed,
               "a_q": self.unbalanced_acceleration}
        out.update({name: float(values[0]) for name, values in self.wheel_rail.columns().items()})
        out.update(self.derived)
        out.update({dof: float(value) for dof, value in zip(self.dofs, self.q, strict=True)})
        return out

    def to_xarray(self):
        """The state as an :class:`xarray.Dataset`: wheel/rail outputs over (wheelset,
        side), ``q`` over ``dof``, the curve's scalars
        (:func:`express.analysis.result_data.steady_curving_dataset`)."""
        from express.analysis.result_data import steady_curving_dataset

        return steady_curving_dataset(self)

    def to_pandas(self):
        """The state as a one-row :class:`pandas.DataFrame` of :meth:`columns` (the
        command's row), units in the column names."""
        return columns_frame(self.columns(), self.units())

    def _summary(self) -> list[str]:
        w = self.wheel_rail
        return [f"R {self.curve.radius:g} m, cant {self.curve.cant:g} m, {self.speed:.3f} m/s, "
                f"a_q {self.unbalanced_acceleration:.3f} m/s^2, contact {self.contact}",
                f"max |aoa| {np.abs(w.angle_of_attack).max() * 1e3:.3g} mrad, max Y/Q {np.nanmax(w.y_over_q):.3g}, "
                f"max |SY| {np.abs(w.track_shift_force).max() / 1e3:.3g} kN"]

    def units(self) -> dict[str, str]:
        """SI unit of every column of :meth:`columns`."""
        units = {"R": "m", "cant": "m", "speed": "m/s", "a_q": "m/s^2", **self.wheel_rail.units()}
        units.update(dict.fromkeys(self.derived, "rad"))
        units.update({dof: coordinate_unit(dof) for dof in self.dofs})
        return units


class SteadyCurvingSolver:
    """The steady-state equations of one vehicle at one speed, built once.

    Parameters
    ----------
    vehicle : VehicleModel
        With rail data.
    speed : float, optional
        [m/s]; the model's speed by default.
    contact : {"tables", "deadband"}, optional
        As :func:`express.analysis.time.simulate.simulate` (tables when the model's contact
        comes from profiles).
    creep_law : {"table", "fastsim", "polach"}
        Creep law of the contact tables (default ``"table"``, the tables of the exact
        theory; ``docs/contact.md``).
    flange, saturation : bool
        The dead-band model's flange contact and creep saturation (both off: the
        linear steady state).
    path : {"transition", "rest"}
        With friction elements, the state reached through the curve's transition (a
        time march into it, then the exact equilibrium on its sliders;
        :mod:`express.analysis.curving.transition`) or loaded from rest (the sliders at
        rest, one step).
    """

    def __init__(self, vehicle: VehicleModel, speed: float | None = None, *, contact: ContactModel | None = None,
                 creep_law: CreepLaw = DEFAULT_CREEP_LAW, flange: bool = True, saturation: bool = True,
                 path: str = "transition"):
        if path not in ("transition", "rest"):
            raise ArgumentError(f"path must be 'transition' or 'rest', got {path!r}")
        self.path = path
        if vehicle.layout is None or vehicle.model is None or vehicle.model.rail is None:
            raise ArgumentError("the model has no rail data: add a [rail] section to run it in a curve")
        self.vehicle = vehicle
        self.speed = float(vehicle.speed if speed is None else speed)
        self.flange, self.saturation = flange, saturation
        self.contact_option, self.creep_law = contact, creep_law
        nonlinear_run = flange or saturation
        self.tables = contact_tables_of(vehicle, contact, creep_law) if nonlinear_run else None
        self.contact = (f"tables ({creep_law})" if self.tables is not None
                        else "dead-band" if nonlinear_run else "linear")
        v = self.speed
        self.a, self.b = vehicle.state_matrix(v), vehicle.input_matrix(v)
        self.cant_base = expression_value(vehicle.model.rail.cant_base, vehicle.values)
        self.gravity = expression_value(vehicle.model.rail.gravity, vehicle.values)
        ws = vehicle.wheelsets
        self.iy = np.array([w.y for w in ws])
        self.ipsi = np.array([w.psi for w in ws])
        self._held: tuple[TrackInputs, ForceSet] | None = None
        self.selector = self._forces(self.inputs(SteadyCurve(math.inf))).selector()
        self.sparse_a = self.sparse_selector = None  # a long train's J is kept sparse (step_solver.py)
        if StepSolver(self.a.shape[0]).sparse:
            from scipy import sparse

            self.sparse_a, self.sparse_selector = sparse.csr_matrix(self.a), sparse.csr_matrix(self.selector)

    def inputs(self, curve: SteadyCurve) -> TrackInputs:
        """The track inputs of ``curve`` at every station (one instant)."""
        vehicle = self.vehicle
        layout = vehicle.layout
        assert layout is not None
        names = list(vehicle.inputs)
        u = np.zeros((1, len(names)))
        for station in layout.stations:
            u[0, names.index(station.curvature_input)] = curve.curvature
            u[0, names.index(station.cant_input)] = curve.signed_cant
        count = len(vehicle.wheelsets)
        return TrackInputs(u, np.zeros_like(u), np.zeros((1, count)), np.full((1, count), curve.curvature),
                           np.full((1, len(layout.stations)), curve.curvature))

    def _forces(self, inputs: TrackInputs) -> ForceSet:
        """The run's force elements on ``inputs`` (one instant,
        :func:`express.analysis.time.force_elements.run_forces`), kept for the last inputs."""
        if self._held is not None and self._held[0] is inputs:
            return self._held[1]
        nonlinear_run = self.flange or self.saturation
        forces = run_forces(self.vehicle, inputs, self.speed, tables=self.tables, flange=self.flange,
                            saturation=self.saturation, clearances=nonlinear_run).forces
        self._held = (inputs, forces)
        return forces

    def force_set(self, inputs: TrackInputs) -> ForceSet:
        """The nonlinear force elements on ``inputs`` (one instant), as the equations use
        them: ``z = force_set(inputs).forces(x, 0)``, acting through :attr:`selector`."""
        return self._forces(inputs)

    def feedback(self, x: np.ndarray, inputs: TrackInputs) -> np.ndarray:
        """``z(x)``: the nonlinear forces fed back, as the time march computes them: the
        wheel/rail forces of every wheelset (lateral, then yaw) and the bump stops."""
        return self._forces(inputs).forces(x, 0)

    def _equations(self, inputs: TrackInputs):
        forcing = self.b @ inputs.u[0]
        nonlinear_run = self.flange or self.saturation

        def equations(x: np.ndarray) -> tuple[np.ndarray, Any]:
            if not nonlinear_run:
                return self.a @ x + forcing, self.a if self.sparse_a is None else self.sparse_a
            forces = self._forces(inputs)
            z = forces.forces(x, 0)
            slopes = forces.slopes(x, 0, z)
            if self.sparse_a is None:
                jacobian = self.a + self.selector @ slopes
            else:
                from scipy import sparse

                jacobian = self.sparse_a + self.sparse_selector @ sparse.csr_matrix(slopes)
            return self.a @ x + forcing + self.selector @ z, jacobian

        return equations, forcing

    def solve(self, curve: SteadyCurve, start: np.ndarray | None = None) -> SteadyCurving:
        """The steady state in ``curve`` (from ``start``, else the linear steady state).

        Raises
        ------
        CurveError
            For a curve that cannot be run (:meth:`SteadyCurve.problems`) or without a
            steady state (the solver does not converge, a wheel leaves its contact table).
        """
        problems = curve.problems(self.speed, self.cant_base, self.gravity)
        if problems:
            raise CurveError("\n".join(problems))
        inputs = self.inputs(curve)
        friction = self._friction(inputs)
        if friction is not None:
            return self._through_transition(curve, inputs, friction)
        equations, forcing = self._equations(inputs)
        try:
            linear = StepSolver(forcing.size).solve(self.a if self.sparse_a is None else self.sparse_a, -forcing)
        except np.linalg.LinAlgError as error:
            raise CurveError("the vehicle has a free coordinate (A is singular): it has no steady state") from error
        scale = max(float(np.linalg.norm(forcing)), 1e-300)
        x, evaluations, residual = _pseudo_transient(equations, linear if start is None else start, scale)
        if not residual < _TOLERANCE and start is not None:  # a neighbour's state can lie in another regime
            x, more, residual = _pseudo_transient(equations, linear, scale)
            evaluations += more
        if not residual < _SETTLED:  # stalled at a jump of the contact: let the time march settle it
            settled = self._settle(curve, x)
            settled_residual = float(np.linalg.norm(equations(settled)[0])) / scale
            if settled_residual < residual:
                x, residual = settled, settled_residual
        if not residual < _TOLERANCE:
            raise NoSteadyStateError(f"no steady state in R = {curve.radius:g} m with {curve.cant * 1e3:g} mm cant at "
                             f"{self.speed * 3.6:.1f} km/h: the vehicle cannot follow this curve (relative residual "
                             f"{residual:.1e} after {evaluations} steps; an unstable vehicle has no steady state)")
        return self._result(curve, x, inputs, evaluations, residual, _growth(equations(x)[1]))

    def _friction(self, inputs: TrackInputs):
        """The friction elements of a nonlinear run on ``inputs`` the path decides (None:
        none, ``path = "rest"`` or the linear steady state)."""
        from express.forces.friction import FrictionElement

        if self.path != "transition" or not (self.flange or self.saturation):
            return None
        found = self._forces(inputs).of_kind(FrictionElement)
        return found[0] if found else None

    def resolved_dt(self) -> float:
        """The step [s] of a time run of this vehicle that resolves its force elements
        (:func:`express.analysis.curving.transition.resolved_dt`)."""
        from express.analysis.curving.transition import resolved_dt

        return resolved_dt(self._forces(self.inputs(SteadyCurve(math.inf))), self.vehicle.mass)

    def _through_transition(self, curve: SteadyCurve, inputs: TrackInputs, friction) -> SteadyCurving:
        """The state reached through the transition (:mod:`express.analysis.curving.transition`)."""
        from express.analysis.curving.transition import hold_sliders, march_into

        state, friction.slider[:], path = march_into(
            self.vehicle, curve, self.speed, self.resolved_dt(), friction.ids, contact=self.contact_option,
            creep_law=self.creep_law, flange=self.flange, saturation=self.saturation)
        equations, forcing = self._equations(inputs)
        scale = max(float(np.linalg.norm(forcing)), 1e-300)
        x, evaluations, residual, rounds = hold_sliders(equations, friction, state, scale, _pseudo_transient)
        if not residual < _TOLERANCE or friction.beyond(x, 0).any():
            raise NoSteadyStateError(f"no steady state in R = {curve.radius:g} m with {curve.cant * 1e3:g} mm cant at "
                                     f"{self.speed * 3.6:.1f} km/h {path}: relative residual {residual:.1e} after "
                                     f"{rounds} rounds of the sliders held ({evaluations} steps)")
        friction.frozen = True  # the tangent of small motions: every element sticks
        try:
            growth = _growth(equations(x)[1])
        finally:
            friction.frozen = False
        result = self._result(curve, x, inputs, evaluations, residual, growth)
        return replace(result, path=f"{path} ({rounds} round(s) of the sliders held and returned)")

    def _settle(self, curve: SteadyCurve, x: np.ndarray, seconds: float = 10.0, rounds: int = 8) -> np.ndarray:
        """The time march (:func:`express.analysis.time.simulate.simulate`, the same equations)
        from ``x`` in a long constant curve until the state stops moving (at most ``rounds``
        runs of ``seconds``); its fixed point is the equilibrium (the exact discretisation's
        fixed point solves ``A x + e = 0``).  The Manchester S1002 car at R 357 m, with its
        yaw element turned by the curve, needs 4 rounds to reach rounding level."""
        from express.analysis.time.simulate import simulate
        from express.rail.track import Curve, Track

        stations = [w.station for w in self.vehicle.wheelsets] + list(self.vehicle.station_positions)
        start = max(stations) - min(stations) + 1.0
        travel = self.speed * seconds
        track = Track((Curve(start + rounds * travel + 1.0, curve.radius, curve.direction, curve.cant),))
        for k in range(rounds):
            run = simulate(self.vehicle, track, speed=self.speed, start=start + k * travel,
                           end=start + (k + 1) * travel, initial_state=x, progress=False,
                           contact=self.contact_option, creep_law=self.creep_law, flange=self.flange,
                           saturation=self.saturation)
            moved = float(np.max(np.abs(run.q[-1] - run.q[-min(run.q.shape[0], 200)])))
            x = np.concatenate([run.q[-1], run.q_dot[-1][self.vehicle.form.massive]])  # the state [q; q_D']
            if moved < 1e-12:
                break
        return x

    def _result(self, curve: SteadyCurve, x: np.ndarray, inputs: TrackInputs, iterations: int,
                residual: float, growth: float | None = None) -> SteadyCurving:
        vehicle = self.vehicle
        q = x[: vehicle.n]
        q_dot = vehicle.form.velocities(x[None, :], inputs.u, inputs.u_rate)
        if self.tables is not None:
            self._check_on_tables(x, inputs, curve)
        wheel_rail = wheel_rail_outputs(vehicle, q[None, :], q_dot, inputs, self.speed, contact=self.tables)
        derived = derived_outputs(vehicle, q[None, :], q_dot, inputs, self.speed, flange=self.flange,
                                  saturation=self.saturation)
        angles = {name: float(values[0]) for name, values in derived.items() if name.startswith(("psi_TW", "theta_"))}
        return SteadyCurving(curve, self.speed, curve.unbalanced_acceleration(self.speed, self.cant_base, self.gravity),
                             vehicle.dofs, q.copy(), x.copy(), wheel_rail, angles, self.contact, iterations, residual,
                             growth)

    def _check_on_tables(self, x: np.ndarray, inputs: TrackInputs, curve: SteadyCurve) -> None:
        from express.analysis.time.contact_march import contact_force_history
        from express.rail.contact_forces import OUTPUTS

        n = self.vehicle.n
        assert self.tables is not None
        history = contact_force_history(x[None, :n], self.vehicle.form.velocities(x)[None, :], self.iy, self.ipsi,
                                        inputs.y_rail, inputs.rho_wheelsets, self.speed, self.tables)
        beyond = np.abs(history[0, :, OUTPUTS.index("beyond")])
        if np.any(beyond > 0):
            raise NoSteadyStateError(f"in R = {curve.radius:g} m a wheel runs {1e3 * float(beyond.max()):.1f} mm beyond its "
                             "contact table (flange climb): the vehicle cannot follow this curve")


#: Largest state whose equilibrium's stability is computed (dense eigenvalues).
STABILITY_STATES = 2000


def _growth(tangent) -> float | None:
    """The largest real part of the eigenvalues of ``tangent`` (dense or sparse, N x N)
    [1/s]; None above :data:`STABILITY_STATES` states."""
    if tangent.shape[0] > STABILITY_STATES:
        return None
    dense = tangent.toarray() if hasattr(tangent, "toarray") else np.asarray(tangent)
    return float(np.max(np.linalg.eigvals(dense).real))


def _pseudo_transient(equations, start: np.ndarray, scale: float, steps: int = 1000) -> tuple[np.ndarray, int, float]:
    """Pseudo-transient continuation (Kelley & Keyes 1998, "Convergence analysis of
    pseudo-transient continuation", SIAM J. Numer. Anal. 35): implicit Euler steps of
    ``x' = f(x)`` whose pseudo-time step grows as the residual falls (switched evolution
    relaxation), Newton's method in the limit.  Following the vehicle's own dynamics, it
    finds the equilibrium a time march settles to, and does not stall at the kinks of the
    flange contact where plain Newton steps cycle; when the residual stops falling (large
    steps cycling over a jump of the contact), the largest step is cut tenfold, so the
    iteration falls back toward a damped time march.

    Returns the solution, the number of steps and the relative residual ``|f| / scale``.
    """
    x = np.array(start, dtype=float)
    f, jacobian = equations(x)
    solve = StepSolver(x.size)  # dense, or banded for a long train
    step, largest = 1e-3, 1e6  # [s] of pseudo-time
    residual = best = float(np.linalg.norm(f))
    best_x = x.copy()
    stalled = 0
    for count in range(1, steps + 1):
        x = x + solve(step, jacobian, f)
        f, jacobian = equations(x)
        new = float(np.linalg.norm(f))
        if not np.isfinite(new):
            return x, count, math.inf
        step = min(step * max(residual / max(new, 1e-300), 0.5), largest)
        residual = new
        if residual / scale < 1e-11:
            break
        if residual < 0.9 * best:
            best, stalled, best_x = residual, 0, x.copy()
        else:
            stalled += 1
            if stalled >= 8:
                largest = step = max(step / 10.0, 1e-5)
                stalled = 0
    if residual <= best:
        return x, count, residual / scale
    return best_x, count, best / scale


def steady_curving(vehicle: VehicleModel, curves: SteadyCurve | Iterable[SteadyCurve], *,
                   speeds: float | Sequence[float] | None = None, **options) -> list[SteadyCurving]:
    """Steady states of ``vehicle`` in each curve (at each speed), each solution the start
    of the next.

    Parameters
    ----------
    vehicle : VehicleModel
    curves : SteadyCurve or iterable of SteadyCurve
    speeds : float, quantity or sequence of them, optional
        [m/s] (a number is SI; ``"95 km/h"`` or a :class:`pint.Quantity`): one for all
        curves or one per curve; the model's speed by default.
    **options
        ``contact``, ``creep_law``, ``flange``, ``saturation`` of :class:`SteadyCurvingSolver`.

    Returns
    -------
    list of SteadyCurving
    """
    from express.base.arguments import si_argument

    if isinstance(curves, SteadyCurve):
        curves = [curves]
    elif isinstance(curves, Iterable) and not isinstance(curves, str):
        curves = list(curves)
    else:
        curves = [curves]
    for curve in curves:
        if not isinstance(curve, SteadyCurve):
            raise ArgumentError(f"curves must be a SteadyCurve or a list of them (e.g. SteadyCurve(radius=600.0, "
                                f"cant=0.15)), got {type(curve).__name__} {curve!r:.60}")
    if speeds is None or isinstance(speeds, (int, float, str)) or hasattr(speeds, "units"):
        speeds = [vehicle.speed if speeds is None else si_argument(speeds, "speed", "speeds")] * len(curves)
    else:
        speeds = [si_argument(speed, "speed", "speeds") for speed in speeds]
    if len(speeds) != len(curves):
        raise ArgumentError(f"{len(speeds)} speeds for {len(curves)} curves")
    solvers: dict[float, SteadyCurvingSolver] = {}
    results: list[SteadyCurving] = []
    for curve, speed in zip(curves, speeds, strict=True):
        solver = solvers.get(float(speed))
        if solver is None:
            solver = solvers[float(speed)] = SteadyCurvingSolver(vehicle, speed, **options)
        start = results[-1].state if results and results[-1].curve.direction == curve.direction else None
        results.append(solver.solve(curve, start))
    return results
