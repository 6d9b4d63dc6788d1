"""What the numerical analyses read of a vehicle's model, as names and numbers.

The analyses of a :class:`~express.numeric.statespace.VehicleModel` need, besides its
matrices, a few facts of the model it came from: the role of every body (the mode
labels), the radius of gyration of every rotation (the participation of a mode), the
lateral displacement of the rail output points (``frf``).  :func:`facts_of` computes
them from the symbolic model at the vehicle's values; :func:`facts_data` and
:func:`read_facts` write them as data and read them back, checked, for the
derivation cache: a vehicle read back from the cache carries them, so that a warm
command never loads the symbolic model (nor SymPy).

Examples
--------
>>> from express.io import load_model
>>> model = load_model("examples/forced-steering.toml")
>>> facts = facts_of(model, model.values())
>>> facts.topology.role["L1"], round(facts.gyration["CB.rz"], 3)
('lever', 6.055)
>>> read_facts(facts_data(facts)) == facts
True
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from express.model.modal_body import modal_coordinates, modal_motion
from express.model.topology import Topology, classify_bodies
from express.numeric.program import ProgramError, checked_list, checked_strings

if TYPE_CHECKING:
    from express.model.records import Model

__all__ = ["OutputPoint", "VehicleFacts", "facts_data", "facts_of", "read_facts"]

_ROTATIONS = {"rx": 0, "ry": 1, "rz": 2}


@dataclass(frozen=True)
class OutputPoint:
    """A rail output point (``[rail.outputs]``) and its lateral displacement.

    Attributes
    ----------
    name : str
    body : str
        The body it sits on.
    lateral : tuple of (str, float)
        ``u_y = sum(c q[dof])`` in the body's track frame: ``(dof, c)`` for the body's
        ``y`` (1), ``rz`` (``lx`` [m]) and ``rx`` (``-lz`` [m]) DOFs it has.
    """

    name: str
    body: str
    lateral: tuple[tuple[str, float], ...]

    def row(self, dofs: tuple[str, ...]) -> list[float]:
        """The coefficients of ``u_y`` over ``dofs`` (0 for the DOFs it does not use)."""
        row = [0.0] * len(dofs)
        for dof, coefficient in self.lateral:
            if dof in dofs:
                row[dofs.index(dof)] += coefficient
        return row


@dataclass(frozen=True)
class VehicleFacts:
    """The facts of a model the numerical analyses use (module docstring).

    Attributes
    ----------
    source : str
        The model file, for messages.
    parameters : tuple of str
        Every parameter of the model, sorted.
    topology : Topology
        The role of every body (:func:`express.model.topology.classify_bodies`, the
        bogies ordered by station at the values).
    gyration : dict of str to float
        Rotation DOF -> the body's radius of gyration ``sqrt(I / m)`` [m], where mass and
        inertia are known and positive; a flexible body's modal coordinate -> ``1/sqrt(m)``
        [1/sqrt(kg)], the RMS displacement over the body per unit of a mass-normalised mode.
    outputs : tuple of OutputPoint
        The rail output points, in the model's order.
    stuck : tuple of str
        The friction elements, which the linear analyses see stuck (their pre-slip springs
        in ``K``: the tangent at the static state), in the model's order.
    tangents : tuple of (str, str)
        The nonlinear characteristics, which the linear analyses see as their tangents at
        the static state, and the matrix each goes into (``"K"`` or ``"C"``), in the
        model's order.
    """

    source: str
    parameters: tuple[str, ...]
    topology: Topology
    gyration: dict[str, float]
    outputs: tuple[OutputPoint, ...] = ()
    stuck: tuple[str, ...] = ()
    tangents: tuple[tuple[str, str], ...] = ()


def facts_of(model: Model, values: Mapping[str, float]) -> VehicleFacts:
    """The facts of ``model`` at ``values`` (SI, every parameter)."""
    from express.model.parameters import expression_value

    def number(expression: Any) -> float | None:
        try:
            return expression_value(expression, values)
        except (KeyError, TypeError, ValueError):
            return None

    topology = classify_bodies(model, lambda body: number(model.body(body).position[0]) or 0.0)
    gyration = {}
    for body in model.bodies:
        mass = number(body.mass)
        for dof in body.dofs:
            if dof in _ROTATIONS:
                inertia = number(body.inertia[_ROTATIONS[dof]])
                if mass is not None and inertia is not None and mass > 0 and inertia > 0:
                    gyration[f"{body.id}.{dof}"] = math.sqrt(inertia / mass)
        if mass is not None and mass > 0:  # a mass-normalised mode: RMS displacement 1/sqrt(m) per unit
            for name in modal_coordinates(model, body.id):
                gyration[name] = 1.0 / math.sqrt(mass)
    outputs = []
    for point in model.rail.outputs if model.rail is not None else ():
        body = model.body(point.body)
        lx, lz = expression_value(point.offset[0], values), expression_value(point.offset[2], values)
        lateral = tuple((f"{body.id}.{dof}", c) for dof, c in (("y", 1.0), ("rz", lx), ("rx", -lz)) if dof in body.dofs)
        if model.flexible:  # the modes of a flexible body move the point too
            offset = tuple(expression_value(v, values) for v in point.offset)
            lateral += tuple((dof, expression_value(c, values))
                             for dof, c in modal_motion(model, body.id, point.name, offset, 1).items())
        outputs.append(OutputPoint(point.name, point.body, lateral))
    stuck = tuple(e.id for e in model.elements if getattr(e, "sliding", False))
    tangents = tuple((e.id, "C" if e.characteristic.velocity else "K") for e in model.elements
                     if e.characteristic is not None)
    return VehicleFacts(model.source, tuple(sorted(model.parameters)), topology, gyration, tuple(outputs), stuck,
                        tangents)


def facts_data(facts: VehicleFacts) -> dict[str, Any]:
    """``facts`` as JSON-ready data."""
    topology = facts.topology
    return {
        "source": facts.source,
        "parameters": list(facts.parameters),
        "role": dict(topology.role),
        "bogie_of": dict(topology.bogie_of),
        "lever_partner": dict(topology.lever_partner),
        "bogies": list(topology.bogies),
        "gyration": dict(facts.gyration),
        "outputs": [[point.name, point.body, [list(pair) for pair in point.lateral]] for point in facts.outputs],
        "stuck": list(facts.stuck),
        "tangents": [list(pair) for pair in facts.tangents],
    }


def read_facts(data: Any) -> VehicleFacts:
    """The facts of :func:`facts_data`'s data, every field checked.

    Raises
    ------
    ProgramError
        For data that is not such facts (a damaged or foreign cache entry).
    """
    if not isinstance(data, dict):
        raise ProgramError("bad vehicle facts")
    topology = Topology(_texts(data.get("role")), _texts(data.get("bogie_of")), _texts(data.get("lever_partner")),
                        tuple(checked_strings(data.get("bogies"))))
    gyration = data.get("gyration")
    if not (isinstance(gyration, dict) and all(_number(v) for v in gyration.values())):
        raise ProgramError("bad vehicle facts")
    outputs = []
    for item in checked_list(data.get("outputs")):
        if not (isinstance(item, list) and len(item) == 3 and isinstance(item[0], str) and isinstance(item[1], str)):
            raise ProgramError("bad output point")
        pairs = checked_list(item[2])
        if not all(isinstance(p, list) and len(p) == 2 and isinstance(p[0], str) and _number(p[1]) for p in pairs):
            raise ProgramError("bad output point")
        outputs.append(OutputPoint(item[0], item[1], tuple((p[0], float(p[1])) for p in pairs)))
    source = data.get("source")
    if not isinstance(source, str):
        raise ProgramError("bad vehicle facts")
    tangents = checked_list(data.get("tangents", []))
    if not all(isinstance(p, list) and len(p) == 2 and isinstance(p[0], str) and p[1] in ("K", "C") for p in tangents):
        raise ProgramError("bad vehicle facts")
    return VehicleFacts(source, tuple(checked_strings(data.get("parameters"))), topology, dict(gyration), tuple(outputs),
                        tuple(checked_strings(data.get("stuck"))), tuple((p[0], p[1]) for p in tangents))


def _number(value: Any) -> bool:
    return type(value) in (int, float) and math.isfinite(value)




def _texts(value: Any) -> dict[str, str]:
    if not (isinstance(value, dict) and all(isinstance(k, str) and isinstance(v, str) for k, v in value.items())):
        raise ProgramError("expected a mapping of texts")
    return dict(value)
