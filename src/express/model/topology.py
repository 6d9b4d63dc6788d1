"""What each body of a vehicle is: wheelset, bogie, steering lever or car body.

One classifier for every stage that needs the running gear's structure: the mode
labels of the stability analysis, the derived outputs of a simulation (lever angles,
bogie yaw), drawings.  It reads only the model's topology (bodies, connection points,
elements, pins) and the wheelset list of its rail data; stations (x positions) come
from the caller, who knows the parameter values.

Rules
-----
* a **wheelset** is a body listed in the rail data;
* a **lever** is a body that hosts the virtual connection point of a pinned joint and
  has a rotation DOF; its *partner* is the host of the joint's other point;
* the **bogie** of a wheelset is the body with a yaw DOF, other than a wheelset or a
  lever, that shares the most elements with it (ties broken by id);
* every other body is a **car body** (``"body"``).

Examples
--------
>>> from express.io import load_model
>>> model = load_model("examples/forced-steering.toml")
>>> topology = classify_bodies(model)
>>> topology.bogie_of["W1"], topology.role["L1"], topology.role["CB"]
('T1', 'lever', 'body')
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from express.model.records import Model

__all__ = ["Topology", "classify_bodies"]

ROTATIONS = ("rx", "ry", "rz")


@dataclass(frozen=True)
class Topology:
    """The role of every body of a model.

    Attributes
    ----------
    role : dict of str to str
        Body id -> ``"wheelset"``, ``"lever"``, ``"bogie"`` or ``"body"``.
    bogie_of : dict of str to str
        Wheelset id -> the bogie it is suspended from (wheelsets without one absent).
    lever_partner : dict of str to str
        Lever id -> the body its pin joins it to (``""`` for a ground), in pin order.
    bogies : tuple of str
        Bogie ids, front (largest station) first.
    """

    role: dict[str, str]
    bogie_of: dict[str, str]
    lever_partner: dict[str, str]
    bogies: tuple[str, ...]

    @property
    def levers(self) -> tuple[str, ...]:
        """Lever ids in pin order."""
        return tuple(self.lever_partner)

    def group(self, body: str) -> str:
        """The bogie a running-gear body belongs to (``""`` for none)."""
        role = self.role.get(body)
        if role == "bogie":
            return body
        if role == "wheelset":
            return self.bogie_of.get(body, "")
        if role == "lever":
            partner = self.lever_partner[body]
            return partner if partner in self.bogies else ""
        return ""

    def bogie_label(self, bogie: str) -> str:
        """``"front bogie"``/``"rear bogie"`` for a two-bogie car, else ``"bogie <id>"``."""
        if len(self.bogies) == 2:
            return "front bogie" if bogie == self.bogies[0] else "rear bogie"
        return f"bogie {bogie}"


def classify_bodies(model: Model, station: Callable[[str], float] | None = None) -> Topology:
    """Classify the bodies of ``model`` (see the module docstring for the rules).

    Parameters
    ----------
    model : Model
    station : callable, optional
        Body id -> its station x [m], used to order the bogies front to back; without
        it the bogies keep the model's order.
    """
    bodies = {body.id: body for body in model.bodies}
    wheelsets = [w.body for w in model.rail.wheelsets] if model.rail is not None else []
    host = {point.id: point.host for point in model.points}
    lever_partner: dict[str, str] = {}
    for pin in model.pins:
        lever, partner = host.get(pin.virtual), host.get(pin.non_virtual)
        if lever in bodies and lever not in lever_partner and any(r in bodies[lever].dofs for r in ROTATIONS):
            lever_partner[lever] = partner if partner in bodies else ""
    running_gear = set(wheelsets)
    counts: dict[str, dict[str, int]] = {wheelset: {} for wheelset in wheelsets}
    for element in model.elements:  # the elements between a wheelset and another body
        ends = {host.get(element.s_end), host.get(element.t_end)}
        if len(ends) != 2:
            continue
        for wheelset in [end for end in ends if end in running_gear and end is not None]:
            (other,) = ends - {wheelset}
            if other in bodies and other not in running_gear and other not in lever_partner and "rz" in bodies[other].dofs:
                counts[wheelset][other] = counts[wheelset].get(other, 0) + 1
    bogie_of: dict[str, str] = {}
    for wheelset in wheelsets:
        found = counts[wheelset]
        if found:
            bogie_of[wheelset] = max(sorted(found), key=lambda body: found[body])
    frames = set(bogie_of.values())
    order = [b.id for b in model.bodies if b.id in frames]
    bogies = tuple(sorted(order, key=lambda b: -station(b)) if station is not None else order)
    role = {}
    for body_id in bodies:
        if body_id in running_gear:
            role[body_id] = "wheelset"
        elif body_id in lever_partner:
            role[body_id] = "lever"
        elif body_id in frames:
            role[body_id] = "bogie"
        else:
            role[body_id] = "body"
    return Topology(role, bogie_of, lever_partner, bogies)
