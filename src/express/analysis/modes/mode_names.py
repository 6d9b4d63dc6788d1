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
(the participation of :class:`express.analysis.modes.modes.Mode`, rotations times the radius
of gyration) is mostly in the running gear (wheelsets, frames, levers), of which the
wheelsets hold at least :data:`HUNTING_WHEELSET_SHARE`, almost all of it
(:data:`HUNTING_LATERAL_YAW`) lateral and yaw, at a frequency not above
:data:`HUNTING_FREQUENCY_FACTOR` times the kinematic frequency of a free wheelset
``f = v / (2 pi) sqrt(lambda_e / (r0 b))`` (Klingel) when the speed is known.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from express.analysis.modes.mode_energies import (
    STROKE,
    DofGroups,
    group_sums,
    kinetic_shares,
    roll_centres,
    running_sum,
    series_ranking,
    series_shares,
)
from express.model.modal_body import mode_words
from express.model.topology import Topology

__all__ = ["STROKE", "ModeEnergy", "RoleGroups", "generic_names", "kinematic_frequency", "mode_energy", "mode_names"]

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
    """The energy distribution of one mode (module docstring; :func:`mode_names` takes
    many modes at once).

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
    groups = DofGroups.of(dofs)
    vectors = np.asarray(phi)[:, None]
    shares = kinetic_shares(vectors, groups, mass)[:, 0]
    keys = [(groups.bodies[body], direction) for body, direction in zip(groups.body_of, groups.directions, strict=True)]
    kinetic = dict(zip(keys, shares.tolist(), strict=True)) if shares.any() else {}
    series = series_ranking(series_shares(vectors, groups, damping)[:, 0], groups.elements)
    strain = float(np.real(np.conj(phi) @ (stiffness @ phi)))
    kinetic_energy = abs(eigenvalue) ** 2 * float(np.real(np.conj(phi) @ (mass @ phi)))
    ratio = kinetic_energy / strain if strain > 0 else float("inf")
    heights = roll_centres(vectors, groups)[:, 0]
    roll_centre = {groups.bodies[body]: float(height) for body, height in zip(groups.roll[0], heights, strict=True)
                   if height == height}
    return ModeEnergy(kinetic, series, ratio, roll_centre)


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
    return "/".join(words.get(d) or mode_words(d) for d in chosen)


def _is_sway(parts: dict[str, float]) -> bool:
    """Lateral and roll are the two largest directions, each with at least
    :data:`SWAY_SHARE` of the kinetic energy."""
    total = sum(parts.values()) or 1.0
    top = sorted(parts, key=lambda d: -parts[d])[:2]
    return set(top) == {"y", "rx"} and min(parts["y"], parts["rx"]) >= SWAY_SHARE * total


class RoleGroups:
    """The DOFs and bodies of a rail vehicle by role, for naming its modes (built once
    per vehicle; the index arrays on first use).

    Parameters
    ----------
    groups : DofGroups
    roles : Topology
        The role of every body (a body it does not list is a car body).
    """

    def __init__(self, groups: DofGroups, roles: Topology) -> None:
        self.groups = groups
        self.roles = roles
        self._place_cache: dict[tuple[tuple[int, ...], bool], tuple[list[str], np.ndarray | None, list[int]]] = {}

    def role(self, body: str) -> str:
        """``"wheelset"``, ``"lever"``, ``"bogie"`` or ``"body"``."""
        return self.roles.role.get(body, "body")

    @cached_property
    def kinds(self) -> tuple[str, ...]:
        """The roles of the bodies with DOFs, sorted."""
        return tuple(sorted({self.role(body) for body in self.groups.bodies}))

    @cached_property
    def body_kind(self) -> np.ndarray:
        """Index into :attr:`kinds` of every body of :attr:`DofGroups.bodies`."""
        return np.array([self.kinds.index(self.role(body)) for body in self.groups.bodies], dtype=np.intp)

    @cached_property
    def row_role(self) -> np.ndarray:
        """The role of every row (DOF with mass), as an array of str."""
        return np.array([self.role(body) for body in self.groups.bodies] or [""])[self.groups.body_of]

    @cached_property
    def kind_directions(self) -> tuple[tuple[np.ndarray, np.ndarray, tuple[str, ...]], ...]:
        """For every kind: its rows, their direction (index) and the directions in the
        order of their first row."""
        out = []
        for kind in self.kinds:
            rows = np.flatnonzero(self.row_role == kind)
            names = tuple(dict.fromkeys(self.groups.directions[i] for i in rows))
            labels = np.array([names.index(self.groups.directions[i]) for i in rows], dtype=np.intp)
            out.append((rows, labels, names))
        return tuple(out)

    @cached_property
    def hunting_rows(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Masks over the rows: running gear (not a car body), wheelsets, and their
        lateral and yaw DOFs."""
        wheelset = self.row_role == "wheelset"
        lateral_yaw = np.array([direction in ("y", "rz") for direction in self.groups.directions], dtype=bool)
        return self.row_role != "body", wheelset, wheelset & lateral_yaw

    @cached_property
    def sway_rolls(self) -> np.ndarray:
        """Columns of :attr:`DofGroups.roll` whose body is a car body."""
        return np.flatnonzero(self.body_kind[self.groups.roll[0]] == self.kinds.index("body")) if "body" in self.kinds \
            else np.zeros(0, dtype=np.intp)

    def places(self, shares: np.ndarray, bodies: np.ndarray, kind: str) -> list[str]:
        """Where each mode's subject is: which bogie (running gear) or which car body of
        several, from the shares of ``bodies`` (indices into :attr:`DofGroups.bodies`,
        shape (b,); ``shares`` (b, m)); ``""`` when it is not one place."""
        m = shares.shape[1]
        if kind == "body" and sum(1 for role in self.roles.role.values() if role == "body") < 2:
            return [""] * m
        names, labels, candidates = self._places(tuple(bodies.tolist()), kind == "body")
        sums = shares if labels is None else group_sums(shares, labels, len(names))
        if not candidates:
            return [""] * m
        total = running_sum(sums)
        top = np.asarray(candidates)[np.argmax(sums[candidates], axis=0)]
        leads = (sums[top, np.arange(m)] >= 0.75 * total).tolist()
        if kind == "body":
            return [names[t] if lead else "all car bodies" for t, lead in zip(top.tolist(), leads, strict=True)]
        several = ("both bogies" if len(self.roles.bogies) == 2 else "all bogies") if len(candidates) >= 2 else ""
        return ["" if t_total <= 0 else self.roles.bogie_label(names[t]) if lead else several
                for t, lead, t_total in zip(top.tolist(), leads, total.tolist(), strict=True)]

    def _places(self, bodies: tuple[int, ...], each: bool) -> tuple[list[str], np.ndarray | None, list[int]]:
        """The places ``bodies`` can be: each body, or their bogies; how the bodies add
        to them (None: each its own) and those that name a place, sorted by name
        (kept: a few sets of bodies per vehicle)."""
        if (bodies, each) not in self._place_cache:
            self._place_cache[(bodies, each)] = self._places_of(bodies, each)
        return self._place_cache[(bodies, each)]

    def _places_of(self, bodies: tuple[int, ...], each: bool) -> tuple[list[str], np.ndarray | None, list[int]]:
        names = [self.groups.bodies[i] for i in bodies]
        if each:
            return names, None, sorted(range(len(names)), key=names.__getitem__)
        group_of = [self.roles.group(body) for body in names]
        names = list(dict.fromkeys(group_of))
        labels = np.array([names.index(group) for group in group_of], dtype=np.intp)
        return names, labels, [i for i in sorted(range(len(names)), key=names.__getitem__) if names[i]]


def _hunting(displacement: np.ndarray, naming: RoleGroups, frequency: np.ndarray, damping_ratio: np.ndarray,
             kinematic_hz: float | None) -> np.ndarray:
    """Which modes are hunting (module docstring), from the displacement shares (k, m)."""
    possible = (frequency > 0) & (damping_ratio < 0.5)
    if kinematic_hz is not None and kinematic_hz == kinematic_hz:
        possible &= ~(frequency > HUNTING_FREQUENCY_FACTOR * kinematic_hz)
    gear, wheels, kinematic = (running_sum(displacement[mask]) for mask in naming.hunting_rows)
    return possible & (gear >= 0.5) & (wheels >= HUNTING_WHEELSET_SHARE) & (kinematic >= HUNTING_LATERAL_YAW * wheels)


def _relaxation(series: tuple[tuple[str, float], ...], suffix: str) -> str:
    """The name of a mode in which nothing with mass moves."""
    names = ", ".join(element for element, _ in series[:2])
    return f"series element relaxation ({names}){suffix}" if names else f"static{suffix}"


def mode_names(kinetic: np.ndarray, series: Sequence[tuple[tuple[str, float], ...]], rolls: np.ndarray,
               displacement: np.ndarray, naming: RoleGroups, frequency: np.ndarray, damping_ratio: np.ndarray,
               kinematic_hz: float | None = None) -> list[str]:
    """Name modes of a rail vehicle from their energy (module docstring).

    Parameters
    ----------
    kinetic : numpy.ndarray, shape (k, m)
        Every DOF's share of the kinetic energy (:func:`~express.analysis.modes.mode_energies.kinetic_shares`).
    series : sequence of tuple of (str, float)
        Every mode's series elements with their share of the dissipated power, largest first.
    rolls : numpy.ndarray, shape (r, m)
        Roll centres (:func:`~express.analysis.modes.mode_energies.roll_centres`).
    displacement : numpy.ndarray, shape (k, m)
        Every DOF's share of the displacement (participation), for hunting.
    naming : RoleGroups
    frequency : numpy.ndarray, shape (m,)
        Damped frequency [Hz] (0 for a real eigenvalue).
    damping_ratio : numpy.ndarray, shape (m,)
        [-].
    kinematic_hz : float, optional
        Kinematic frequency of the wheelsets [Hz] (:func:`kinematic_frequency`).

    Returns
    -------
    list of str
        E.g. ``"hunting, front bogie"``, ``"car body lower sway"``,
        ``"wheelset vertical, both bogies"``, ``"bogie frame yaw, non-oscillatory"``.
    """
    groups, m = naming.groups, kinetic.shape[1]
    kind_of = np.argmax(group_sums(kinetic, naming.body_kind[groups.body_of], len(naming.kinds)), axis=0)
    by_body = group_sums(kinetic, groups.body_of, len(groups.bodies))
    places = {}
    for index, kind in enumerate(naming.kinds):
        bodies = np.flatnonzero(naming.body_kind == index)
        places[kind] = naming.places(by_body[bodies], bodies, kind)
    hunting = _hunting(displacement, naming, frequency, damping_ratio, kinematic_hz)
    gear = np.flatnonzero(naming.body_kind != naming.kinds.index("body")) if "body" in naming.kinds \
        else np.arange(len(groups.bodies))
    hunting_places = naming.places(group_sums(displacement, groups.body_of, len(groups.bodies))[gear], gear, "gear")
    parts = [group_sums(kinetic[rows], labels, len(names)).T.tolist()
             for rows, labels, names in naming.kind_directions]
    sway = rolls[naming.sway_rolls]
    has_kinetic: list[bool] = np.any(kinetic, axis=0).tolist()
    names = []
    for k in range(m):
        suffix = "" if frequency[k] > 0 else ", non-oscillatory"
        kind = naming.kinds[kind_of[k]]
        located = f", {places[kind][k]}" if places[kind][k] else ""
        if not has_kinetic[k]:
            names.append(_relaxation(series[k], suffix))
        elif hunting[k]:
            names.append(f"hunting, {hunting_places[k]}" if hunting_places[k] else "hunting")
        elif kind == "wheelset" and not frequency[k] > 0:
            names.append(f"wheelset creep{located}{suffix}")
        else:
            directions = dict(zip(naming.kind_directions[kind_of[k]][2], parts[kind_of[k]][k], strict=True))
            motion = _motion(directions, _WHEELSET_WORDS if kind == "wheelset" else _WORDS)
            heights = sway[:, k][sway[:, k] == sway[:, k]]
            if kind == "body" and _is_sway(directions) and heights.size:
                motion = "lower sway" if heights[np.argmin(np.abs(heights))] < 0 else "upper sway"
            names.append(f"{_SUBJECTS.get(kind, kind)} {motion}{located}{suffix}")
    return names


def generic_names(kinetic: np.ndarray, series: Sequence[tuple[tuple[str, float], ...]], groups: DofGroups,
                  frequency: np.ndarray) -> list[str]:
    """Names of modes of a model without rail data: the bodies holding at least 15 % of
    the kinetic energy (at most three) with their main direction, e.g.
    ``"B1 yaw, B2 pitch"`` (arguments as :func:`mode_names`)."""
    by_body = group_sums(kinetic, groups.body_of, len(groups.bodies))
    rows_of = [sorted(np.flatnonzero(groups.body_of == body), key=lambda i: groups.directions[i])
               for body in range(len(groups.bodies))]
    has_kinetic: list[bool] = np.any(kinetic, axis=0).tolist()
    names = []
    for k in range(kinetic.shape[1]):
        suffix = "" if frequency[k] > 0 else ", non-oscillatory"
        if not has_kinetic[k]:
            names.append(_relaxation(series[k], suffix))
            continue
        totals = by_body[:, k]
        chosen = np.flatnonzero(totals >= 0.15)
        chosen = chosen[np.argsort(-totals[chosen], kind="stable")][:3] if chosen.size else np.zeros(1, dtype=np.intp)
        parts = []
        for body in chosen.tolist():
            rows = rows_of[body]
            direction = groups.directions[rows[int(np.argmax(kinetic[rows, k]))]]
            parts.append(f"{groups.bodies[body]} {_WORDS.get(direction) or mode_words(direction)}")
        names.append(", ".join(parts) + suffix)
    return names
