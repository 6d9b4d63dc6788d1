"""Names of the modes of a vehicle from the distribution of their energy.

A mode ``q(t) = Re(phi exp(lambda t))`` of the linear vehicle carries, over a cycle,

* **kinetic energy** ``T = |lambda|^2 / 2 phi^H M phi``, split over the bodies and their
  directions by ``T_i = Re(conj(phi_i) (M phi)_i)`` (summed over the DOFs of one body
  and one direction; with a diagonal mass matrix, ``m_i |phi_i|^2``);
* **strain energy** ``V = 1/2 Re(phi^H K phi)``;
* **dissipated power** ``1/2 |lambda|^2 Re(phi^H C(v) phi)``, of which a series
  (Maxwell) element's damper takes ``c |phi_s|^2`` through its stroke ``s``.

The name's subject is the kind of body that holds the largest kinetic energy (car body,
bogie frame, wheelset, steering lever, :mod:`express.model.topology`); its motion the
directions that hold at least :data:`MOTION_SHARE` of that kind's kinetic energy
(lateral, bounce, roll, pitch, yaw, longitudinal; a car body's lateral and roll
together are *lower sway* when it rolls about a point below its centre of gravity,
*upper sway* above). A series element's stroke has no mass, so it never names a mode:
its share of the dissipated power is listed against its element
(:attr:`ModeEnergy.series`).

*Hunting* is kept for the kinematic motion of the wheelsets, a pattern of displacement
rather than of energy (a car body holds much of the kinetic energy of a bogie's hunting
by its mass alone): an oscillation with damping ratio below 0.5 whose displacement
(the participation of :class:`express.analysis.modes.Mode`, rotations times the radius
of gyration) is mostly in the running gear (wheelsets, frames, levers), of which the
wheelsets hold at least :data:`HUNTING_WHEELSET_SHARE`, almost all of it
(:data:`HUNTING_LATERAL_YAW`) lateral and yaw, at a frequency not above
:data:`HUNTING_FREQUENCY_FACTOR` times the kinematic frequency of a free wheelset
``f = v / (2 pi) sqrt(lambda_e / (r0 b))`` (Klingel) when the speed is known.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from express.assembly.equations import STROKE  # a series element's stroke: <element>.stroke
from express.model.topology import Topology

__all__ = ["STROKE", "ModeEnergy", "generic_name", "kinematic_frequency", "mode_energy", "mode_name"]

#: A direction names the motion when it holds at least this share of the subject's
#: kinetic energy (at most two directions are named).
MOTION_SHARE = 0.2
#: A car body sways (lateral and roll) when both hold at least this share of its
#: kinetic energy.
SWAY_SHARE = 0.1
#: Share of the displacement the wheelsets must hold for hunting.
HUNTING_WHEELSET_SHARE = 0.2
#: Share of the wheelsets' displacement that must be lateral and yaw for hunting.
HUNTING_LATERAL_YAW = 0.8
#: Hunting is at most this factor times Klingel's kinematic frequency.
HUNTING_FREQUENCY_FACTOR = 1.5

_WORDS = {"x": "longitudinal", "y": "lateral", "z": "bounce", "rx": "roll", "ry": "pitch", "rz": "yaw"}
_WHEELSET_WORDS = {**_WORDS, "z": "vertical"}
_SUBJECTS = {"body": "car body", "bogie": "bogie frame", "wheelset": "wheelset", "lever": "steering lever"}


@dataclass(frozen=True)
class ModeEnergy:
    """How one mode's energy is distributed.

    Attributes
    ----------
    kinetic : dict of (str, str) to float
        ``(body, direction)`` -> share of the kinetic energy [-]; the shares sum to 1
        (empty when nothing with mass moves).
    series : tuple of (str, float)
        Series elements with their share of the dissipated power [-], largest first.
    kinetic_to_strain : float
        ``T / V`` [-] (1 at resonance of an undamped oscillation; inf without strain).
    roll_centre : dict of str to float
        Body -> height [m] above its reference point of the line it rolls about,
        ``Re(phi_y / phi_rx)`` (bodies with lateral and roll DOFs that roll).
    """

    kinetic: dict[tuple[str, str], float]
    series: tuple[tuple[str, float], ...]
    kinetic_to_strain: float
    roll_centre: dict[str, float]

    def by_body(self) -> dict[str, float]:
        """Body -> its share of the kinetic energy."""
        shares: dict[str, float] = {}
        for (body, _), share in self.kinetic.items():
            shares[body] = shares.get(body, 0.0) + share
        return shares


def mode_energy(phi: np.ndarray, eigenvalue: complex, dofs: Sequence[str], mass: np.ndarray,
                damping: np.ndarray, stiffness: np.ndarray) -> ModeEnergy:
    """The energy distribution of one mode (module docstring).

    Parameters
    ----------
    phi : numpy.ndarray, shape (n,)
        Displacement part of the eigenvector (complex).
    eigenvalue : complex
        ``lambda`` [1/s].
    dofs : sequence of str
        Names ``body.direction`` (``element.stroke`` for a series element), length n.
    mass, damping, stiffness : numpy.ndarray, shape (n, n)
        ``M``, ``C(v)`` and ``K`` at the mode's speed.
    """
    kinetic_parts = np.real(np.conj(phi) * (mass @ phi))
    groups: dict[tuple[str, str], float] = {}
    for value, dof in zip(kinetic_parts, dofs, strict=True):
        body, _, direction = dof.partition(".")
        if direction != STROKE:
            groups[(body, direction)] = groups.get((body, direction), 0.0) + float(value)
    groups = {key: max(value, 0.0) for key, value in groups.items()}
    total = sum(groups.values())
    kinetic = {key: value / total for key, value in groups.items()} if total > 0 else {}
    dissipated = float(np.real(np.conj(phi) @ (damping @ phi)))
    series = []
    for i, dof in enumerate(dofs):
        element, _, direction = dof.partition(".")
        if direction == STROKE and dissipated > 0:
            series.append((element, float(damping[i, i] * abs(phi[i]) ** 2 / dissipated)))
    series.sort(key=lambda item: -item[1])
    strain = float(np.real(np.conj(phi) @ (stiffness @ phi)))
    kinetic_energy = abs(eigenvalue) ** 2 * float(np.real(np.conj(phi) @ (mass @ phi)))
    ratio = kinetic_energy / strain if strain > 0 else float("inf")
    index = {dof: i for i, dof in enumerate(dofs)}
    roll_centre = {}
    for dof in dofs:
        body, _, direction = dof.partition(".")
        if direction == "rx" and f"{body}.y" in index and abs(phi[index[dof]]) > 0:
            roll_centre[body] = float(np.real(phi[index[f"{body}.y"]] / phi[index[dof]]))
    return ModeEnergy(kinetic, tuple(series), ratio, roll_centre)


def kinematic_frequency(speed: float, conicity: float, r0: float, b: float) -> float:
    """Klingel's kinematic frequency of a free wheelset [Hz].

    ``f = v / (2 pi) sqrt(lambda_e / (r0 b))``: speed ``v`` [m/s], equivalent conicity
    ``lambda_e`` [-], rolling radius ``r0`` [m], half distance ``b`` [m] between the
    contact points. nan when an argument is not positive.

    Examples
    --------
    >>> round(kinematic_frequency(55.0, 0.15, 0.46, 0.75), 3)
    5.772
    """
    if not (speed > 0 and conicity > 0 and r0 > 0 and b > 0):
        return float("nan")
    return speed / (2.0 * np.pi) * float(np.sqrt(conicity / (r0 * b)))


def _motion(parts: dict[str, float], words: dict[str, str]) -> str:
    total = sum(parts.values()) or 1.0
    chosen = [d for d in sorted(parts, key=lambda d: -parts[d]) if parts[d] >= MOTION_SHARE * total][:2]
    return "/".join(words.get(d, d) for d in chosen)


def _is_sway(parts: dict[str, float]) -> bool:
    """Lateral and roll are the two largest directions, each with at least
    :data:`SWAY_SHARE` of the kinetic energy."""
    total = sum(parts.values()) or 1.0
    top = sorted(parts, key=lambda d: -parts[d])[:2]
    return set(top) == {"y", "rx"} and min(parts["y"], parts["rx"]) >= SWAY_SHARE * total


def _where(shares: dict[str, float], roles: Topology, kind: str) -> str:
    """Which bogie (running gear) or which car body (of several) the subject is."""
    if kind == "body":
        bodies = [b for b, r in roles.role.items() if r == "body"]
        if len(bodies) < 2:
            return ""
        top = max(sorted(shares), key=lambda b: shares[b])
        return top if shares[top] >= 0.75 * sum(shares.values()) else "all car bodies"
    by_group: dict[str, float] = {}
    for body, share in shares.items():
        group = roles.group(body)
        by_group[group] = by_group.get(group, 0.0) + share
    total = sum(by_group.values())
    named = [g for g in by_group if g]
    if not named or total <= 0:
        return ""
    top = max(sorted(named), key=lambda g: by_group[g])
    if by_group[top] >= 0.75 * total:
        return roles.bogie_label(top)
    if len(named) >= 2:
        return "both bogies" if len(roles.bogies) == 2 else "all bogies"
    return ""


def _is_hunting(displacement: dict[tuple[str, str], float], roles: Topology, frequency: float,
                damping_ratio: float, kinematic_hz: float | None) -> bool:
    if not (frequency > 0 and damping_ratio < 0.5):
        return False
    if kinematic_hz is not None and kinematic_hz == kinematic_hz and frequency > HUNTING_FREQUENCY_FACTOR * kinematic_hz:
        return False
    gear = wheels = lateral_yaw = 0.0
    for (body, direction), share in displacement.items():
        role = roles.role.get(body, "body")
        if role != "body":
            gear += share
        if role == "wheelset":
            wheels += share
            lateral_yaw += share if direction in ("y", "rz") else 0.0
    return gear >= 0.5 and wheels >= HUNTING_WHEELSET_SHARE and lateral_yaw >= HUNTING_LATERAL_YAW * wheels


def mode_name(energy: ModeEnergy, displacement: dict[tuple[str, str], float], roles: Topology,
              frequency: float, damping_ratio: float, kinematic_hz: float | None = None) -> str:
    """Name a mode of a rail vehicle from its energy (module docstring).

    Parameters
    ----------
    energy : ModeEnergy
    displacement : dict of (str, str) to float
        ``(body, direction)`` -> share of the displacement (participation), for hunting.
    roles : Topology
        The role of every body.
    frequency : float
        Damped frequency [Hz] (0 for a real eigenvalue).
    damping_ratio : float
        [-].
    kinematic_hz : float, optional
        Kinematic frequency of the wheelsets [Hz] (:func:`kinematic_frequency`).

    Returns
    -------
    str
        E.g. ``"hunting, front bogie"``, ``"car body lower sway"``,
        ``"wheelset vertical, both bogies"``, ``"bogie frame yaw, non-oscillatory"``.
    """
    suffix = "" if frequency > 0 else ", non-oscillatory"
    if not energy.kinetic:
        names = ", ".join(element for element, _ in energy.series[:2])
        return f"series element relaxation ({names}){suffix}" if names else f"static{suffix}"
    by_role: dict[str, float] = {}
    for (body, _), share in energy.kinetic.items():
        role = roles.role.get(body, "body")
        by_role[role] = by_role.get(role, 0.0) + share
    kind = max(sorted(by_role), key=lambda r: by_role[r])
    body_shares = {b: s for b, s in energy.by_body().items() if roles.role.get(b, "body") == kind}
    place = _where(body_shares, roles, kind)
    located = f", {place}" if place else ""
    if _is_hunting(displacement, roles, frequency, damping_ratio, kinematic_hz):
        gear: dict[str, float] = {}
        for (body, _), share in displacement.items():
            if roles.role.get(body, "body") != "body":
                gear[body] = gear.get(body, 0.0) + share
        place = _where(gear, roles, "gear")
        return f"hunting, {place}" if place else "hunting"
    if kind == "wheelset" and frequency <= 0:
        return f"wheelset creep{located}{suffix}"
    parts: dict[str, float] = {}
    for (body, direction), share in energy.kinetic.items():
        if body in body_shares:
            parts[direction] = parts.get(direction, 0.0) + share
    motion = _motion(parts, _WHEELSET_WORDS if kind == "wheelset" else _WORDS)
    if kind == "body" and _is_sway(parts):
        heights = [energy.roll_centre[b] for b in body_shares if b in energy.roll_centre]
        if heights:
            motion = "lower sway" if min(heights, key=abs) < 0 else "upper sway"
    return f"{_SUBJECTS.get(kind, kind)} {motion}{located}{suffix}"


def generic_name(energy: ModeEnergy, frequency: float) -> str:
    """Name of a mode of a model without rail data: the bodies holding at least 15 % of
    its kinetic energy (at most three) with their main direction, e.g.
    ``"B1 yaw, B2 pitch"``."""
    suffix = "" if frequency > 0 else ", non-oscillatory"
    if not energy.kinetic:
        names = ", ".join(element for element, _ in energy.series[:2])
        return f"series element relaxation ({names}){suffix}" if names else f"static{suffix}"
    totals = energy.by_body()
    chosen = [b for b in sorted(totals, key=lambda b: -totals[b]) if totals[b] >= 0.15][:3] or list(totals)[:1]
    parts = []
    for body in chosen:
        directions = {d: s for (b, d), s in energy.kinetic.items() if b == body}
        direction = max(sorted(directions), key=lambda d: directions[d])
        parts.append(f"{body} {_WORDS.get(direction, direction)}")
    return ", ".join(parts) + suffix
