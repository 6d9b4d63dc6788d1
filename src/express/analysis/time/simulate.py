"""Curving simulation: a vehicle running along a track (paper Fig. 9).

The state-space model is driven by the track seen at every station (curvature,
cant, lateral irregularity and their rates, the rear stations delayed behind the
leading wheelset), with flange contact and creep saturation fed back at every step.
Results are indexed by ``d1``, the leading wheelset's distance along the track.

Derived quantities (``rail.md``).  With the paper's dead-band wheel/rail model:

``Y{n}``
    Lateral force from the rail on the flanging wheel of wheelset n [N], the quantity
    the paper plots (横圧, its ``Q``): the flange force plus that wheel's half of the lateral creep
    force (both wheels have the same creep coefficients and lateral creepage), positive
    to the left.  Without flange contact it is half the wheelset's creep force.
``Ytot{n}``
    Total lateral force from the rails on wheelset n [N] (creep plus flange).
``YQ{n}``
    Derailment quotient ``Y / Q0`` of the flanging wheel, ``Q0`` the static wheel load
    (the paper's ``Q / P``).

One meaning per name across the contact models (issue 35): ``Q`` is always a vertical
wheel load, ``Y`` a lateral force.  The dead-band outputs were called ``Q{n}``, ``Qtot{n}``
and ``QP{n}`` before; :data:`express.analysis.time.output_names.RENAMED` maps the old names to the new ones.
``flange{n}``, ``dy{n}``
    The flange force ``-kR dy`` [N] and the flange penetration ``dy`` [m].

With the contact from profile tables, instead of those, the quantities engineers sign
a vehicle off with (:mod:`express.analysis.curving.outputs`, ``docs/contact.md``): per
wheel (``L``, ``R``) the vertical load ``Q{n}{s}`` [N] (``options["wheel_loads"]``:
``"dynamic"`` from the model's vertical contact springs, or a ``"quasi-static estimate"``
of the load transfer for a lateral-only model), the lateral force ``Y{n}{s}`` [N] in the
track plane, ``YQ{n}{s}``, the longitudinal creep force ``Fx{n}{s}`` [N], the contact
position ``u{n}{s}`` [m] and angle ``gamma{n}{s}`` [rad], the flange-contact flag
``flanging{n}{s}``; per wheelset the track shift force ``SY{n}`` [N] and the angle of
attack ``aoa{n}`` [rad]; per vehicle the wheel unloading ``dQQ0``.  Always:

``psi_TW{n}``
    Yaw of wheelset n relative to its bogie frame [rad] (the steering angle; the ideal
    radial value is ``a / R``).
``theta_<lever>``
    Rotation of each steering lever [rad] (bodies carrying a pin's virtual DOF).
``stop_<element>``
    Force of each bump stop (clearance element, :mod:`express.forces.bump_stops`) [N; N m for
    a rotational one], zero inside its gap.

Series (Maxwell) elements make the state ``[q; q_D']`` (:mod:`express.assembly.first_order`);
``q_dot`` of their damper strokes comes from the first-order equations.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from express.analysis.curving.outputs import WheelRailOutputs
from express.analysis.time.force_elements import contact_tables_of, run_forces
from express.analysis.time.integrator import DenseSteps, discretize, march
from express.analysis.time.output_names import OutputTable
from express.analysis.time.sparse_march import Route, SparseSteps, choose_route, sparse_steps
from express.analysis.time.track_inputs import TrackInputs, rail_layout, station_index, track_inputs
from express.base.data import DataRecord, columns_frame
from express.base.diagnostics import ArgumentError
from express.base.threads import limited_blas
from express.forces.bump_stops import BumpStopElement, clearance_force, clearances_of
from express.forces.characteristic import CharacteristicElement
from express.forces.friction import FrictionElement
from express.model.modal_body import coordinate_unit
from express.model.topology import Topology, classify_bodies
from express.numeric.statespace import VehicleModel
from express.rail.nonlinear import wheelset_forces
from express.rail.options import DEFAULT_CREEP_LAW, ContactModel, CreepLaw
from express.rail.track import Track

__all__ = [
    "SimulationResult", "TrackInputs", "bogie_of_wheelsets", "contact_tables_of", "lever_bodies", "output_unit",
    "running_speed", "simulate",
    "track_inputs",
]


@dataclass(repr=False)
class SimulationResult(DataRecord):
    """Time histories of a simulation.

    Attributes
    ----------
    time : numpy.ndarray, shape (N,)
        [s].
    distance : numpy.ndarray, shape (N,)
        ``d1``, distance of the leading wheelset along the track [m].
    dofs : tuple of str
    q, q_dot : numpy.ndarray, shape (N, n)
        Generalized coordinates [m, rad] and velocities.
    outputs : dict of str to numpy.ndarray, each shape (N,)
        Derived quantities (see the module docstring) and ``rho1`` (curvature at the
        leading wheelset, 1/m), ``S1`` (cant there, m).
    speed : float
        [m/s].
    options : dict
        ``flange``, ``saturation``, ``dt``; with the contact tables ``contact`` and
        ``wheel_loads`` (where the wheel loads Q come from).
    wheel_rail : WheelRailOutputs, optional
        The per-wheel, per-wheelset and per-vehicle wheel/rail quantities of a run with
        the contact tables (:class:`~express.analysis.curving.outputs.WheelRailOutputs`);
        their columns are in ``outputs`` too.
    output_units : dict of str to str
        The SI unit of the force elements' outputs, as each element states it (the other
        outputs' units follow their names, :func:`output_unit`).
    """

    time: np.ndarray
    distance: np.ndarray
    dofs: tuple[str, ...]
    q: np.ndarray
    q_dot: np.ndarray
    outputs: dict[str, np.ndarray]
    speed: float
    options: dict = field(default_factory=dict)
    wheel_rail: WheelRailOutputs | None = None
    output_units: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.outputs, OutputTable):
            self.outputs = OutputTable(self.outputs)

    def series(self) -> dict[str, np.ndarray]:
        """Every column: time, d1, each DOF, each DOF rate (``<dof>_dot``), outputs."""
        columns = {"time": self.time, "d1": self.distance}
        for i, dof in enumerate(self.dofs):
            columns[dof] = self.q[:, i]
        for i, dof in enumerate(self.dofs):
            columns[f"{dof}_dot"] = self.q_dot[:, i]
        columns.update(self.outputs)
        return columns

    def to_xarray(self):
        """The time history as an :class:`xarray.Dataset` over ``time`` [s]
        (:func:`express.analysis.result_data.simulation_dataset`)."""
        from express.analysis.result_data import simulation_dataset

        return simulation_dataset(self)

    def to_pandas(self):
        """The time history as a :class:`pandas.DataFrame` of :meth:`series`, indexed by
        ``time [s]``, units in the column names."""
        return columns_frame(self.series(), self.units(), index="time")

    def _summary(self) -> list[str]:
        t = self.time
        span = f"{t[0]:g}-{t[-1]:g} s, {t.size} instants" if t.size else "no instants"
        return [f"{span} at {self.speed:.3f} m/s, dt {self.options.get('dt', float('nan')):g} s",
                f"{len(self.dofs)} DOFs, {len(self.outputs)} outputs"]

    def max_abs(self) -> dict[str, float]:
        """Largest absolute value of every derived output (SI units), by name (an
        :class:`~express.analysis.time.output_names.OutputTable`: an old name is refused
        with the new one)."""
        return OutputTable({name: float(np.max(np.abs(values))) for name, values in self.outputs.items()})

    def units(self) -> dict[str, str]:
        """SI unit of every column of :meth:`series` (``""`` for dimensionless ones)."""
        units = {"time": "s", "d1": "m"}
        for dof in self.dofs:
            units[dof] = coordinate_unit(dof)
        for dof in self.dofs:
            units[f"{dof}_dot"] = f"{units[dof]}/s"
        for name in self.outputs:
            units[name] = self.output_units.get(name, output_unit(name))
        return units

    def to_csv(self) -> str:
        """CSV text: a header of column names with their SI units (``time_s``, ``Q1_N``,
        :func:`express.io.text_formats.column_name`), then one row per time step."""
        from express.io.text_formats import csv_text

        return csv_text(self.series(), self.units())

    def save(self, path: str | Path) -> None:
        """Save as ``.csv``, ``.npz`` or ``.mat`` (by suffix), written whole or not at
        all through :mod:`express.io.output` (``"-"``: CSV on standard output)."""
        from express.io.output import mat_bytes, npz_bytes, write_bytes, write_text

        suffix = "" if str(path) == "-" else Path(path).suffix.lower()
        if suffix not in ("", ".csv", ".npz", ".mat") or (suffix == "" and str(path) != "-"):
            raise ArgumentError(f"{path}: unknown result format {suffix!r} (use .csv, .npz or .mat)")
        if suffix in ("", ".csv"):
            write_text(path, self.to_csv())
        elif suffix == ".npz":
            write_bytes(path, npz_bytes(_safe_keys(self.series()), compress=True))
        else:
            write_bytes(path, mat_bytes(_safe_keys(self.series()), compress=True))


#: Units of the derived outputs by name prefix (longest prefixes first).
_OUTPUT_UNITS = (
    ("Tgamma", "N"), ("wear", "ug/m/mm^2"), ("rcf", ""), ("Q", "N"), ("flanging", ""), ("flange", "N"), ("NL", "N"), ("NR", "N"),
    ("psi_TW", "rad"), ("theta_", "rad"), ("dy", "m"), ("dQQ0", ""), ("rho", "1/m"), ("SY", "N"), ("S", "m"),
    ("stop_", "N"), ("YQ", ""), ("Y", "N"), ("Fx", "N"), ("gamma", "rad"), ("aoa", "rad"), ("u", "m"),
)


def output_unit(name: str) -> str:
    """SI unit of a derived output by its name (``""`` for ratios, flags and unknown names)."""
    return next((unit for prefix, unit in _OUTPUT_UNITS if name.startswith(prefix)), "")


def _safe_keys(columns: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    return {name.replace(".", "_"): values for name, values in columns.items()}


def lever_bodies(vehicle: VehicleModel) -> list[str]:
    """The steering levers (:func:`express.model.topology.classify_bodies`), in pin order."""
    topology = _topology(vehicle)
    return list(topology.levers) if topology is not None else []


def _lever_rotation(vehicle: VehicleModel, body: str) -> str:
    for rotation in ("ry", "rz", "rx"):
        if f"{body}.{rotation}" in vehicle.dofs:
            return f"{body}.{rotation}"
    raise ArgumentError(body)


def bogie_of_wheelsets(vehicle: VehicleModel) -> dict[str, str]:
    """The bogie each wheelset is suspended from (:func:`express.model.topology.classify_bodies`)."""
    topology = _topology(vehicle)
    return dict(topology.bogie_of) if topology is not None else {}


def _topology(vehicle: VehicleModel) -> Topology | None:
    """The roles of the vehicle's bodies: from the facts a vehicle read back from the
    derivation cache carries (the model file is not read again), else from its model."""
    if vehicle.origin.facts is not None:
        return vehicle.origin.facts.topology
    return classify_bodies(vehicle.model) if vehicle.model is not None else None


def _terminal_progress(stream=None):
    stream = sys.stderr if stream is None else stream
    if not stream.isatty():
        return None

    def show(fraction: float) -> None:
        width = 40
        filled = round(fraction * width)
        stream.write(f"\rsimulating [{'#' * filled}{'.' * (width - filled)}] {fraction:4.0%}")
        if fraction >= 1.0:
            stream.write("\n")
        stream.flush()

    return show


@limited_blas
def simulate(
    vehicle: VehicleModel,
    track: Track,
    *,
    speed: float | None = None,
    dt: float = 0.005,
    start: float = 0.0,
    end: float | None = None,
    flange: bool = True,
    saturation: bool = True,
    initial_state: np.ndarray | None = None,
    progress: bool | None = None,
    clearances: bool | None = None,
    contact: ContactModel | None = None,
    creep_law: CreepLaw = DEFAULT_CREEP_LAW,
    route: Route = "auto",
) -> SimulationResult:
    """Run ``vehicle`` along ``track``.

    Parameters
    ----------
    vehicle : VehicleModel
        Numerical vehicle with rail data.
    track : Track
        Curvature, cant and irregularity along the track.
    speed : float or quantity, optional
        [m/s] (a number is SI; ``"95 km/h"`` or a :class:`pint.Quantity` with its unit);
        by default the track's own speed (a track file's or a named track's line
        speed), else the model's, as ``express simulate`` chooses; ``options["speed_from"]``
        says which (``"given"``, ``"track"``, ``"model"``).
    dt : float or quantity
        Time step [s] (the linear part is exact; the step limits how finely the
        flange and saturation feedback is followed).
    start, end : float or quantity
        Leading-wheelset distance at the start and end [m]; ``end`` defaults to the
        track length.
    flange, saturation : bool
        Include flange contact and creep saturation (both on, as in the paper's Fig. 9).
    initial_state : numpy.ndarray, shape (N,), optional
        The state ``[q; q']`` at the start (zero by default); with series elements
        ``[q; q_D']`` (:mod:`express.assembly.first_order`), N = ``vehicle.form.size``.
    progress : bool, optional
        Show a progress bar; by default only when standard error is a terminal.
    clearances : bool, optional
        Include the bump stops (clearance elements); by default unless both
        ``flange`` and ``saturation`` are off (a linear run).
    contact : {"tables", "deadband"}, optional
        The nonlinear wheel/rail contact: ``"tables"`` looks the contact up in the
        profiles' tables (:mod:`express.forces.contact`; the default when the
        model's conicity comes from profiles), ``"deadband"`` is the flange spring and
        creep saturation of :mod:`express.rail.nonlinear`.  A linear run (``flange`` and
        ``saturation`` off) uses neither.
    creep_law : {"table", "fastsim", "polach"}
        The creep law of the contact tables (default ``"table"``, the tables of the exact
        theory; ``docs/contact.md``).
    route : {"auto", "dense", "sparse"}
        How the linear part of a step is taken (the same exact discretization and time
        step either way): dense matrices ``exp(A dt)`` and its hold integrals, or their
        action on the state from the sparse ``A`` (:mod:`express.analysis.time.sparse_march`,
        results equal to rounding); ``"auto"`` chooses the sparse one for large sparse
        models (:func:`~express.analysis.time.sparse_march.choose_route`).

    Returns
    -------
    SimulationResult
        ``options["route"]`` is ``"sparse"`` when the sparse route was taken.
    """
    from express.base.arguments import si_argument

    if not isinstance(track, Track):
        raise ArgumentError(f"track must be a Track (express.load_track(\"R400\") or a track file), "
                            f"got {type(track).__name__}")
    v, speed_from = running_speed(vehicle, track, None if speed is None else si_argument(speed, "speed", "speed"))
    dt = si_argument(dt, "time", "dt")
    start = si_argument(start, "length", "start")
    end = track.length if end is None else si_argument(end, "length", "end")
    if end <= start:
        raise ArgumentError(f"end ({end} m) must lie beyond start ({start} m)")
    steps = int(np.ceil((end - start) / (v * dt)))
    time = np.arange(steps + 1) * dt
    distance = start + v * time
    inputs = track_inputs(vehicle, track, distance, v)
    n = vehicle.n
    tables = contact_tables_of(vehicle, contact, creep_law) if (flange or saturation) else None
    run = run_forces(vehicle, inputs, v, tables=tables, flange=flange, saturation=saturation,
                     clearances=flange or saturation if clearances is None else clearances)
    forces = run.forces
    _check_step(forces, vehicle, dt)
    if run.wheel_loads == "dynamic":
        _check_contact_damping(vehicle)
    a = vehicle.state_matrix(v)
    selector = forces.selector()
    linear = (_dense_steps if choose_route(a, route) == "dense" else _sparse_steps)(vehicle, a, v, dt, inputs, selector)
    size = vehicle.form.size
    x0 = np.zeros(size) if initial_state is None else np.asarray(initial_state, dtype=float)
    if x0.shape != (size,):
        raise ArgumentError(f"initial_state must have shape ({size},), got {x0.shape}")
    show = _terminal_progress() if progress is None else (_terminal_progress() if progress else None)
    states, history = march(linear, x0, forces, progress=show)
    q = states[:, :n]
    # feedback forces act on massive coordinates only: they do not enter q_F'
    q_dot = _velocities(vehicle, states, inputs, sparse=isinstance(linear, SparseSteps))
    outputs = derived_outputs(vehicle, q, q_dot, inputs, v, flange=flange, saturation=saturation,
                              deadband=tables is None)
    record = None
    if tables is not None:
        from express.analysis.time.contact_march import contact_wheel_outputs

        assert run.wheel_loads is not None
        record = contact_wheel_outputs(vehicle, history, q, run.wheel_loads)
        outputs.update(record.columns())
    outputs.update(forces.outputs(states, history))
    options: dict[str, object] = {"flange": flange, "saturation": saturation, "dt": dt, "speed_from": speed_from}
    if isinstance(linear, SparseSteps):
        options["route"] = "sparse"
    if tables is not None:
        options["contact"] = f"tables ({creep_law})"
        options["wheel_loads"] = run.wheel_loads
    if forces.of_kind(BumpStopElement):
        options["clearances"] = True
    if forces.of_kind(FrictionElement):
        options["friction"] = "slipping (spring-slider)"
    if forces.of_kind(CharacteristicElement):
        options["characteristics"] = "piecewise linear (the tables)"
    return SimulationResult(time, distance, vehicle.dofs, q, q_dot, outputs, v, options, record, forces.output_units())


def running_speed(vehicle: VehicleModel, track: Track, speed: float | None) -> tuple[float, str]:
    """The speed of a run [m/s] and where it comes from: ``speed`` if given, else the
    track's own, else the model's (the command line's rule, ``express simulate``)."""
    if speed is not None:
        v, source = float(speed), "given"
    elif getattr(track, "speed", None) is not None:
        v, source = float(track.speed), "track"  # type: ignore[arg-type]
    else:
        v, source = float(vehicle.speed), "model"
    if not v > 0:
        raise ArgumentError(f"speed must be positive, got {v}")
    return v, source


def _check_step(forces, vehicle: VehicleModel, dt: float) -> None:
    """One warning when the step does not resolve a force element's stiffest feedback
    (a friction element's pre-slip spring while it slips, a characteristic's change of
    slope): the run is not converged."""
    resolved = forces.resolved_step(vehicle.mass)
    if resolved is not None and dt > resolved:
        import warnings

        kinds = {element.kind for element in forces.elements if element.resolved_step(vehicle.mass) is not None}
        what = " and ".join(text for kind, text in (
            ("friction", "the friction elements' pre-slip springs while they slip"),
            ("characteristic", "the characteristics' changes of slope")) if kind in kinds) or "the force elements"
        warnings.warn(f"the time step {dt * 1e3:g} ms does not resolve {what} "
                      f"(at most {resolved * 1e3:.3g} ms): the run is not converged in the step; "
                      "use a smaller dt (--dt)", UserWarning, stacklevel=3)


def _check_contact_damping(vehicle: VehicleModel) -> None:
    """One warning when the wheels stand on vertical contact springs without damping:
    the wheelsets' vertical and roll modes on them (150-200 Hz on the bundled S1002 car)
    are then undamped, and the creep forces, proportional to the loads, can drive them
    (a friction-driven flutter that a step fine enough to follow them shows; ``docs/
    contact.md``, "Dynamic wheel loads")."""
    from express.rail.vertical_contact import vertical_contacts

    assert vehicle.model is not None
    springs = vertical_contacts(vehicle.model, vehicle.values, [w.name for w in vehicle.wheelsets], vehicle.dofs,
                                vehicle.inputs)
    bare = [spring.element for pair in springs for spring in pair if spring is not None and not spring.damping > 0]
    if bare:
        import warnings

        warnings.warn(f"the vertical contact elements under the wheels ({', '.join(bare)}) have no damping: the "
                      "wheelsets' vertical and roll modes on them are undamped and the creep forces can drive them, "
                      "so the run may not converge as the step is refined; give them the track's damping "
                      "(docs/contact.md, \"Dynamic wheel loads\")", UserWarning, stacklevel=3)


def _dense_steps(vehicle: VehicleModel, a: np.ndarray, v: float, dt: float, inputs: TrackInputs,
                 selector: np.ndarray) -> DenseSteps:
    """The dense matrices of the step (:func:`express.analysis.time.integrator.discretize`)."""
    phi, gamma0, gamma1 = discretize(a, dt)
    # drive[k] = gamma0 e[k] + gamma1 (e[k+1] - e[k]) with e = B u + Bd u'
    b, bd = vehicle.input_matrix(v), vehicle.input_rate_matrix(v)
    early, late = (gamma0 - gamma1), gamma1
    drive = (
        inputs.u[:-1] @ (early @ b).T
        + inputs.u[1:] @ (late @ b).T
        + inputs.u_rate[:-1] @ (early @ bd).T
        + inputs.u_rate[1:] @ (late @ bd).T
    )
    if inputs.rail is not None:  # the rail heights at the contact springs, e += G f
        springs, g = inputs.rail.springs, vehicle.form.force
        for values, forcing in ((inputs.rail.heights, springs.forcing), (inputs.rail.rates, springs.forcing_rate)):
            drive += values[:-1] @ (early @ g @ forcing).T + values[1:] @ (late @ g @ forcing).T
    return DenseSteps(*(np.ascontiguousarray(m) for m in (phi, drive, gamma0 @ selector, gamma1 @ selector)))


def _sparse_steps(vehicle: VehicleModel, a: np.ndarray, v: float, dt: float, inputs: TrackInputs,
                  selector: np.ndarray) -> SparseSteps:
    """The sparse route's step (:mod:`express.analysis.time.sparse_march`): the forcing
    ``e = B u + Bd u'`` at every step from the sparse input matrices."""
    from scipy.sparse import csr_matrix

    b, bd = csr_matrix(vehicle.input_matrix(v)), csr_matrix(vehicle.input_rate_matrix(v))
    forcing = (b @ inputs.u.T + bd @ inputs.u_rate.T).T
    if inputs.rail is not None:
        forcing = forcing + (csr_matrix(vehicle.form.force) @ inputs.rail.forces().T).T
    return sparse_steps(a, dt, forcing, selector)


def _velocities(vehicle: VehicleModel, states: np.ndarray, inputs: TrackInputs, *, sparse: bool) -> np.ndarray:
    """``q'`` of every coordinate at every step (:meth:`express.assembly.first_order.
    FirstOrderForm.velocities`); on the sparse route from the sparse velocity rows (mostly
    picking a velocity out of the state)."""
    form = vehicle.form
    if not sparse:
        return form.velocities(states, inputs.u, inputs.u_rate)
    from scipy.sparse import csr_matrix

    result = (csr_matrix(form.velocity) @ states.T).T
    if form.first_order.size:
        result = result + (csr_matrix(form.velocity_input) @ inputs.u.T + csr_matrix(form.velocity_rate) @ inputs.u_rate.T).T
    return np.ascontiguousarray(result)


def derived_outputs(vehicle: VehicleModel, q, q_dot, inputs: TrackInputs, speed: float, *, flange=True, saturation=True,
                    deadband=True):
    """The derived quantities of ``rail.md`` from the state histories; ``deadband``
    False leaves out the dead-band model's wheel/rail forces (``Y{n}``, ``YQ{n}``,
    ``Ytot{n}``, ``flange{n}``, ``dy{n}``: a run with the contact tables has its own)."""
    ws = vehicle.wheelsets
    iy = [w.y for w in ws]
    ipsi = [w.psi for w in ws]
    forces = wheelset_forces(
        q[:, iy], q[:, ipsi], q_dot[:, iy], q_dot[:, ipsi], inputs.y_rail, inputs.rho_wheelsets,
        speed, ws, flange=flange, saturation=saturation,
    )
    outputs: dict[str, np.ndarray] = {
        "rho1": inputs.rho_wheelsets[:, 0],
        "S1": inputs.u[:, list(vehicle.inputs).index(rail_layout(vehicle).cant[station_index(vehicle, ws[0].name)])],
    }
    bogies = bogie_of_wheelsets(vehicle)
    for j, wheelset in enumerate(ws, start=1):
        if deadband:
            wheel = forces["flange"][:, j - 1] + 0.5 * forces["lateral_creep"][:, j - 1]
            outputs[f"Y{j}"] = wheel
            outputs[f"YQ{j}"] = wheel / wheelset.wheel_load
            outputs[f"Ytot{j}"] = forces["lateral"][:, j - 1]
            outputs[f"flange{j}"] = forces["flange"][:, j - 1]
            outputs[f"dy{j}"] = forces["dy"][:, j - 1]
        bogie = bogies.get(wheelset.name)
        if bogie is not None:
            # each body's yaw is measured from the track at its own station: add the
            # turn of the track between the bogie and the wheelset stations
            bogie_station = station_index(vehicle, bogie)
            turn = 0.5 * (inputs.rho_wheelsets[:, j - 1] + inputs.rho_stations[:, bogie_station]) * (
                wheelset.station - vehicle.station_positions[bogie_station]
            )
            outputs[f"psi_TW{j}"] = q[:, wheelset.psi] - q[:, vehicle.dof_index(f"{bogie}.rz")] + turn
    for lever in lever_bodies(vehicle):
        outputs[f"theta_{lever}"] = q[:, vehicle.dof_index(_lever_rotation(vehicle, lever))]
    return outputs


def continuous_rhs(
    vehicle: VehicleModel,
    track: Track,
    *,
    speed: float | None = None,
    start: float = 0.0,
    flange: bool = True,
    saturation: bool = True,
):
    """The same equations as :func:`simulate` as a plain right-hand side ``f(t, x)``.

    For reference integrations with ``scipy.integrate.solve_ivp`` (tests and the
    simulation benchmark's baseline): no discretization, inputs evaluated at ``t``.
    """
    v = float(vehicle.speed if speed is None else speed)
    a = vehicle.state_matrix(v)
    n = vehicle.n
    ws = vehicle.wheelsets
    data = clearances_of(vehicle.equations, vehicle.values, vehicle.dofs) if (flange or saturation) else None
    stop_rows = data.gradient if data is not None else np.zeros((0, n))
    columns = [vehicle.form.force[:, w.y] for w in ws] + [vehicle.form.force[:, w.psi] for w in ws]
    columns += [vehicle.form.force @ row for row in stop_rows]
    selector = np.column_stack(columns)
    iy = [w.y for w in ws]
    ipsi = [w.psi for w in ws]

    def rhs(t: float, x: np.ndarray) -> np.ndarray:
        inputs = track_inputs(vehicle, track, np.array([start + v * t]), v)
        q = x[:n]
        q_dot = vehicle.form.velocities(x, inputs.u[0], inputs.u_rate[0])
        forces = wheelset_forces(
            q[iy], q[ipsi], q_dot[iy], q_dot[ipsi], inputs.y_rail[0], inputs.rho_wheelsets[0], v, ws,
            flange=flange, saturation=saturation,
        )
        z = [forces["flange"] + forces["lateral_correction"], forces["yaw_correction"]]
        if data is not None and data.count:
            delta = stop_rows @ q + data.inputs @ inputs.u[0]
            z.append(-clearance_force(delta, data.gap, data.stiffness, data.progressive))
        return a @ x + inputs.drive(vehicle, v)[0] + selector @ np.concatenate(z)

    return rhs
