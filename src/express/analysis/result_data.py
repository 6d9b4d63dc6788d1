"""The analyses' larger result records as :class:`xarray.Dataset` (issue 35, item 2):
the wheel/rail outputs, the steady curving state, the time history of a run, the ride
response, the results of a study and the critical speed's sensitivities.

Each record's ``to_xarray()`` calls the function here (so that the analysis modules keep
their size); every variable has CF-style ``units`` and ``long_name`` attributes, the
dimensions are labelled (``time``, ``dof``, ``wheelset``, ``side``, ``frequency``,
``output``, ``component``, ``point``, ``parameter``).  The records are only read, never
imported at module level, so no analysis module depends on this one's imports.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from express.base.data import variable, xarray

__all__ = ["ride_dataset", "sensitivity_dataset", "simulation_dataset", "steady_curving_dataset", "study_dataset",
           "wheel_rail_variables"]

#: The per-wheel quantities of :class:`~express.analysis.curving.outputs.WheelRailOutputs`:
#: attribute -> (variable name, unit, long name).
_PER_WHEEL = (
    ("vertical_load", "Q", "N", "vertical wheel load"),
    ("lateral_force", "Y", "N", "lateral wheel/rail force in the track plane, +y left"),
    ("y_over_q", "YQ", "1", "derailment quotient Y/Q (guiding force over Q)"),
    ("longitudinal_force", "Fx", "N", "longitudinal creep force, +x forward"),
    ("contact_position", "u", "m", "lateral contact position on the rail"),
    ("contact_angle", "gamma", "rad", "contact angle"),
    ("frictional_power", "Tgamma", "N", "frictional power per distance rolled T gamma"),
    ("wear_rate", "wear", "ug/m/mm^2", "USFD wear rate"),
    ("rcf_damage", "rcf", "1", "Burstow RCF damage index"),
)


#: Long names of a time run's outputs by name prefix (longest first; the name itself otherwise).
_OUTPUT_NAMES = (
    ("Ytot", "total lateral force from the rails on the wheelset"), ("YQ", "derailment quotient Y/Q"),
    ("Y", "lateral wheel/rail force"), ("Q", "vertical wheel load"), ("SY", "track shift force"),
    ("aoa", "angle of attack"), ("Fx", "longitudinal creep force"), ("gamma", "contact angle"),
    ("flanging", "flange contact"), ("flange", "flange force"), ("dy", "flange penetration"),
    ("dQQ0", "largest wheel unloading"), ("psi_TW", "wheelset yaw relative to its bogie"),
    ("theta_", "steering lever rotation"), ("rho", "track curvature at the leading wheelset"),
    ("S", "cant at the leading wheelset"), ("stop_", "bump stop force"), ("Tgamma", "frictional power"),
    ("wear", "USFD wear rate"), ("rcf", "Burstow RCF damage index"), ("u", "lateral contact position on the rail"),
)


def _long_name(name: str) -> str:
    return next((f"{text} ({name})" for prefix, text in _OUTPUT_NAMES if name.startswith(prefix)), name)


def _wheelset_names(count: int) -> list[int]:
    return list(range(1, count + 1))


def wheel_rail_variables(outputs: Any, time_dim: str | None) -> tuple[dict[str, tuple], dict[str, Any]]:
    """The variables and coordinates of a ``WheelRailOutputs`` (``time_dim`` None: one
    instant, the first dimension dropped)."""

    def cut(values: np.ndarray) -> np.ndarray:
        return np.asarray(values)[0] if time_dim is None else np.asarray(values)

    lead: tuple[str, ...] = () if time_dim is None else (time_dim,)
    data: dict[str, tuple] = {}
    for attribute, name, unit, long_name in _PER_WHEEL:
        values = getattr(outputs, attribute)
        if values is not None:
            data[name] = variable(cut(values), (*lead, "wheelset", "side"), unit, long_name)
    data["flanging"] = variable(cut(outputs.flange_contact), (*lead, "wheelset", "side"), "1", "flange contact")
    data["SY"] = variable(cut(outputs.track_shift_force), (*lead, "wheelset"), "N", "track shift force Y_L + Y_R")
    data["aoa"] = variable(cut(outputs.angle_of_attack), (*lead, "wheelset"), "rad", "angle of attack")
    data["dQQ0"] = variable(cut(outputs.vehicle_unloading), lead, "1", "largest wheel unloading (Q0 - Q) / Q0")
    data["Q0"] = variable(np.asarray(outputs.static_load), ("wheelset",), "N", "static wheel load")
    coords = {"wheelset": ("wheelset", _wheelset_names(outputs.wheelsets), {"long_name": "wheelset number"}),
              "side": ("side", ["L", "R"], {"long_name": "wheel side (left, right)"})}
    return data, coords


def steady_curving_dataset(result: Any) -> Any:
    """A :class:`~express.analysis.curving.steady.SteadyCurving` as a dataset: the
    wheel/rail outputs over (wheelset, side), the coordinates ``q`` over ``dof``, the
    derived angles and the curve's scalars."""
    xr = xarray()
    data, coords = wheel_rail_variables(result.wheel_rail, None)
    units = result.units()
    data["q"] = variable(np.asarray(result.q, float), "dof", "m or rad (dof_units)", "coordinates from the track")
    coords["dof"] = list(result.dofs)
    coords["dof_units"] = ("dof", [units[d] for d in result.dofs])
    data["radius"] = variable(result.curve.radius, (), "m", "curve radius")
    data["cant"] = variable(result.curve.cant, (), "m", "cant")
    data["speed"] = variable(result.speed, (), "m/s", "speed")
    data["a_q"] = variable(result.unbalanced_acceleration, (), "m/s^2", "cant deficiency in the track plane")
    data["residual"] = variable(result.residual, (), "1", "relative residual of the equations")
    data["growth"] = variable(np.nan if result.growth is None else result.growth, (), "1/s",
                              "largest real part of the linearised equations")
    for name, value in result.derived.items():
        data[name] = variable(float(value), (), "rad", "derived angle")
    return xr.Dataset(data, coords=coords, attrs={"contact": result.contact, "loads": result.wheel_rail.loads,
                                                  "direction": result.curve.direction,
                                                  "iterations": result.iterations})


def simulation_dataset(result: Any) -> Any:
    """A :class:`~express.analysis.time.simulate.SimulationResult` as a dataset over
    ``time`` [s] (``distance`` [m] a coordinate along it): ``q`` and ``q_dot`` over
    (time, dof) and each derived output (its unit from the run)."""
    xr = xarray()
    units = result.units()
    data: dict[str, tuple] = {
        "q": variable(np.asarray(result.q, float), ("time", "dof"), "m or rad (dof_units)", "generalized coordinates"),
        "q_dot": variable(np.asarray(result.q_dot, float), ("time", "dof"), "m/s or rad/s (dof_units per s)",
                          "generalized velocities"),
    }
    for name, values in result.outputs.items():
        data[name] = variable(np.asarray(values), "time", units.get(name, "") or "1", _long_name(name))
    coords = {"time": ("time", np.asarray(result.time, float), {"units": "s", "long_name": "time"}),
              "distance": ("time", np.asarray(result.distance, float),
                           {"units": "m", "long_name": "distance of the leading wheelset along the track"}),
              "dof": list(result.dofs), "dof_units": ("dof", [units[d] for d in result.dofs])}
    attrs = {"speed": result.speed, "speed_units": "m/s",
             **{str(k): (v if isinstance(v, (int, float, str)) else str(v)) for k, v in result.options.items()}}
    attrs = {k: (int(v) if isinstance(v, bool) else v) for k, v in attrs.items()}
    return xr.Dataset(data, coords=coords, attrs=attrs)


def ride_dataset(result: Any) -> Any:
    """A :class:`~express.analysis.ride.vehicle.RideResponse` as a dataset over
    ``frequency`` [Hz]: ``psd`` (frequency x output), ``transfer`` (frequency x output x
    component, complex) and ``input_psd`` (frequency x component), each output's unit in
    the ``units`` coordinate."""
    xr = xarray()
    components = list(result.components)
    inputs = (np.stack([result.input_psd[c] for c in components], axis=1) if components
              else np.zeros((len(result.frequencies), 0)))
    data = {
        "psd": variable(np.asarray(result.psd, float), ("frequency", "output"), "unit^2/Hz (units)",
                        "one-sided PSD of the output"),
        "transfer": variable(np.asarray(result.transfer), ("frequency", "output", "component"), "unit/m (units)",
                             "response of the output to the track component"),
        "input_psd": variable(inputs, ("frequency", "component"), "m^2/Hz", "temporal PSD of the track component"),
        "rms": variable(np.array([result.rms(n) for n in result.names], float), "output", "unit (units)",
                        "RMS of the output"),
    }
    coords = {"frequency": ("frequency", np.asarray(result.frequencies, float), {"units": "Hz", "long_name": "frequency"}),
              "output": list(result.names), "units": ("output", list(result.units)), "component": components}
    return xr.Dataset(data, coords=coords, attrs={"speed": result.speed, "speed_units": "m/s",
                                                  "notes": "; ".join(result.notes)})


def study_dataset(columns: Mapping[str, Any], units: Mapping[str, str]) -> Any:
    """The columns of a study's results (``read_table``) as a dataset over ``point``,
    each with its unit (``"1"`` for a pure number)."""
    xr = xarray()
    data: dict[str, tuple] = {}
    for name, values in columns.items():
        if name == "error":
            data[name] = variable(np.asarray(values, dtype=object), "point", "", "error message ('' for none)")
        else:
            data[name] = variable(np.asarray(values, float), "point", units.get(name, "") or "1", name)
    count = len(next(iter(columns.values()))) if columns else 0
    return xr.Dataset(data, coords={"point": ("point", np.arange(count), {"long_name": "point number"})})


def sensitivity_dataset(result: Any) -> Any:
    """A :class:`~express.analysis.study.sensitivity.CriticalSpeedSensitivity` as a
    dataset over ``parameter``: ``value`` (SI), ``derivative`` [m/s per parameter unit]
    and ``elasticity`` [1]; the critical speed [m/s] and frequency [Hz] as scalars."""
    xr = xarray()
    rows = result.sensitivities
    data = {
        "value": variable(np.array([s.value for s in rows], float), "parameter", "SI", "parameter value"),
        "derivative": variable(np.array([s.derivative for s in rows], float), "parameter",
                               "m/s per SI unit of the parameter", "derivative of the critical speed"),
        "elasticity": variable(np.array([s.elasticity for s in rows], float), "parameter", "1",
                               "relative change of the critical speed per relative change of the parameter"),
        "critical_speed": variable(result.critical_speed, (), "m/s", "critical speed (exact crossing)"),
        "frequency": variable(result.frequency, (), "Hz", "frequency of the crossing mode"),
    }
    return xr.Dataset(data, coords={"parameter": [s.name for s in rows]})
