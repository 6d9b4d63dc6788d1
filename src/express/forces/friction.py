"""Friction elements: Coulomb friction with a pre-slip spring, a force element of the time
domain (issue 31, item 1).

A friction element is a spring ``k`` (its ``stiffness``, the pre-slip stiffness) in series
with a slider that slips when the spring's force reaches the friction limit ``L``
(``friction = mu N`` in the model file, constant; or ``mu N`` with ``N`` the load another
element carries, below).  The slider's position ``s`` is the
element's internal state; with the deflection ``delta = g . q + h . u``::

    F = k (delta - s),   |F| <= L;   s moves only while |F| = L  (then F = L sign(delta'))

which is the exact rate-independent law (elastic–perfectly plastic): stick and slip
without smoothing.  In the march it is the *return mapping* at every kept state: the
trial force ``k (delta - s)`` beyond ``+-L`` moves the slider to ``delta -+ L/k``.  The
predictor's trial state updates nothing (:func:`express.forces.law.force_law`'s
``commit``).  Sources: the series spring–slider (Jenkin) element as used for friction
dampers in rail vehicles (e.g. the Lenoir link) in Iwnicki (ed.), *Handbook of Railway
Vehicle Dynamics*, 2nd ed., ch. on suspension components; its hysteresis loop is the
parallelogram of the elastoplastic element, area ``4 L (X - L/k)`` per cycle of amplitude
``X > L/k`` (tested).

How the linear analyses see it: **stuck** — the pre-slip spring alone, in ``K`` (and any
``damping`` of the element in ``C``, in parallel with the friction branch) — which is the
tangent at the static state.  The force element therefore feeds back the difference from
the stuck spring, ``z = -F + k delta = k s`` along ``g``; a run in which nothing slips is
exactly the linear run.

The element reads the coordinates of each deflection, acts along ``g``, has one internal
state per element (its slider), its compiled law is :class:`FrictionLaw`, its
linearisation is ``dz/d(delta) = 0`` stuck and ``k`` slipping, and it reports
``friction_<element>`` (the force ``F`` [N; N m rotational]) and ``slip_<element>`` (the
slider's position ``s`` [m; rad]).

**A limit that follows a load** (``friction = { mu = ..., of = "W" }``; a torque ``{ mu,
of, radius }``: ``mu r N``): ``L = mu max(0, N)``, ``N = sense (N0 + k r)`` — ``N0`` the
static force of the element ``W`` (gravity's and its preload, :mod:`express.assembly.
friction_loads`), ``r`` its deflection and ``k r`` its dynamic force (a characteristic's
``F(r) - F(0)``), ``sense`` the sign of ``N0``, so that ``N`` is the load as it carries it
statically, falling to zero (and the limit with it) when it unloads: lift-off.  The march
evaluates ``L`` from the state at every kept and trial state (:func:`load_limit`); the
linear analyses still see the element stuck.  It then also reports ``limit_<element>``
(``L`` [N; N m]).  The laws: a Lenoir link's friction force is ``mu`` times a share of its
axlebox spring's load, set by the link's inclination (Iwnicki (ed.), *Handbook of Railway
Vehicle Dynamics*, the chapter on suspension components); a centre bowl's or side bearer's
torque is ``mu r N`` (a flat disc of radius ``R`` under uniform pressure: ``r = 2R/3``).

**A pair in a plane** (``friction = { ..., plane = "<partner>" }``: two elements along x
and y between the same points, the same ``k``): the trial force ``t = k (d - s)`` is a
vector; the sliders stick while ``|t| <= L`` (the first's limit), else they are returned
onto the circle along ``t``, ``s = d - (L/|t|) t/k`` (:func:`plane_mapping`); in pure x
motion the pair is the 1-D element exactly.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np
from numba import njit, types
from numba.extending import overload

from express.base.caches import IdentityCache
from express.base.kernels import kernel
from express.forces.characteristic import table_force
from express.forces.element import ForceElement, sparse_rows
from express.forces.law import force_law
from express.model.parameters import expression_value

__all__ = ["RESOLVED", "FollowedLoads", "FrictionElement", "FrictionLaw", "LoadLaw", "followed_loads", "friction_elements_of",
           "load_limit", "map_sliders", "plane_mapping",
           "return_mapping"]

#: ``w dt`` of the pre-slip frequency a step may reach and still resolve the slip phase.
RESOLVED = 0.02


class LoadLaw(NamedTuple):
    """The loads the friction limits follow: ``r = offset[k, f] + sum coefficient[f, :]
    x[places[f, :]]`` the followed element's deflection, ``N = sense (static + k r)`` (a
    spring, ``counts[f] == 0``) or ``sense (static + F(r) - F(0))`` (a characteristic,
    breakpoints ``xs``, ``fs``; ``F(0)`` is ``zero``) [N]; ``factor`` ``mu`` (``mu r``),
    0 for a constant limit."""

    factor: np.ndarray
    places: np.ndarray
    coefficient: np.ndarray
    offset: np.ndarray
    static: np.ndarray
    sense: np.ndarray
    stiffness: np.ndarray
    xs: np.ndarray
    fs: np.ndarray
    counts: np.ndarray
    zero: np.ndarray


class FrictionLaw(NamedTuple):
    """Friction elements for the compiled march: deflection ``offset[k, f] + sum
    coefficient[f, :] x[places[f, :]]``, pre-slip ``stiffness`` [N/m], ``limit`` [N]
    (rotational: N m/rad, N m), the committed slider positions ``slider`` [m] (changed in
    place when committing); forces into ``z[first:]``.  An element with ``factor[f] > 0``
    slips at ``factor[f] max(0, N)`` instead (:class:`LoadLaw`)."""

    first: int
    places: np.ndarray
    coefficient: np.ndarray
    offset: np.ndarray
    stiffness: np.ndarray
    limit: np.ndarray
    slider: np.ndarray
    load: LoadLaw
    partner: np.ndarray


@kernel
def load_limit(x, k, load, f, limit):
    """The friction limit of element ``f`` at state ``x`` and step ``k``: ``limit`` when
    constant, else ``factor max(0, N)`` (:class:`LoadLaw`; zero at lift-off)."""
    if load.factor[f] == 0.0:
        return limit
    r = load.offset[k, f]
    for i in range(load.places.shape[1]):
        r += load.coefficient[f, i] * x[load.places[f, i]]
    if load.counts[f] > 0:
        force, _ = table_force(load.xs, load.fs, f, load.counts[f], r)
        dynamic = force - load.zero[f]
    else:
        dynamic = load.stiffness[f] * r
    normal = load.sense[f] * (load.static[f] + dynamic)
    return load.factor[f] * normal if normal > 0.0 else 0.0


@kernel
def return_mapping(delta, slider, stiffness, limit):
    """The slider's position after the deflection ``delta`` from ``slider`` (stick, or slip
    to the friction limit)."""
    force = stiffness * (delta - slider)
    if force > limit:
        return delta - limit / stiffness
    if force < -limit:
        return delta + limit / stiffness
    return slider


@njit(cache=True)
def map_sliders(delta, slider, stiffness, limit, partner):
    """Every element's slider after the deflections ``delta`` (n_f,) from ``slider``, the
    pairs in a plane together (:func:`friction_forces`'s mappings), with the limits
    ``limit`` (n_f,): a new array."""
    found = slider.copy()
    for f in range(delta.size):
        p = partner[f]
        if p == -1:
            found[f] = return_mapping(delta[f], slider[f], stiffness[f], limit[f])
        elif p >= 0:
            found[f], found[p] = plane_mapping(delta[f], delta[p], slider[f], slider[p], stiffness[f], limit[f])
    return found


@njit(cache=True)
def _replay(delta, slider, stiffness, limit, partner, out):
    """The committed slider positions at every kept state (the march's return mappings
    again, in the same order, with the limits ``limit[k, f]``): ``out[k, f]``."""
    for k in range(delta.shape[0]):
        slider = map_sliders(delta[k], slider, stiffness, limit[k], partner)
        out[k] = slider


@kernel
def plane_mapping(dx, dy, sx, sy, stiffness, limit):
    """The sliders of a friction pair in a plane after the deflections ``(dx, dy)`` from
    ``(sx, sy)``: stuck while the trial force ``k (d - s)`` lies within the circle of
    radius ``limit``, else returned onto it along the trial force (exact, no smoothing)."""
    tx, ty = stiffness * (dx - sx), stiffness * (dy - sy)
    size = np.sqrt(tx * tx + ty * ty)
    if size <= limit:
        return sx, sy
    scale = limit / size
    return dx - scale * tx / stiffness, dy - scale * ty / stiffness


@kernel
def _deflection(x, k, law, f):
    delta = law.offset[k, f]
    for i in range(law.places.shape[1]):
        delta += law.coefficient[f, i] * x[law.places[f, i]]
    return delta


@kernel
def friction_forces(x, k, law, z, commit):
    """``z = k s`` of every friction element (the module docstring) into ``z[law.first:]``;
    a pair in a plane (``partner[f] >= 0``; its partner ``-2``) is mapped by its first."""
    for f in range(law.limit.size):
        p = law.partner[f]
        if p == -2:
            continue
        delta = _deflection(x, k, law, f)
        limit = load_limit(x, k, law.load, f, law.limit[f])
        if p < 0:
            slider = return_mapping(delta, law.slider[f], law.stiffness[f], limit)
            if commit:
                law.slider[f] = slider
            z[law.first + f] = law.stiffness[f] * slider
            continue
        sx, sy = plane_mapping(delta, _deflection(x, k, law, p), law.slider[f], law.slider[p], law.stiffness[f], limit)
        if commit:
            law.slider[f], law.slider[p] = sx, sy
        z[law.first + f], z[law.first + p] = law.stiffness[f] * sx, law.stiffness[p] * sy


@overload(force_law)
def _friction_law(x, k, law, z, record, commit):
    if isinstance(law, types.BaseNamedTuple) and law.instance_class is FrictionLaw:
        return lambda x, k, law, z, record, commit: friction_forces(x, k, law, z, commit)
    return None


@kernel
def _normals(r, stiffness, xs, fs, counts, zero, static, sense, normal, slope):
    """``N = sense (N0 + k r)`` or ``sense (N0 + F(r) - F(0))`` and ``dN/dr`` of every
    element (column) at every state (row) of ``r`` (K, n_f), into ``normal`` and ``slope``
    (:class:`FollowedLoads`)."""
    for i in range(r.shape[0]):
        for f in range(r.shape[1]):
            if counts[f] > 0:
                force, gradient = table_force(xs, fs, f, counts[f], r[i, f])
                dynamic = force - zero[f]
            else:
                dynamic, gradient = stiffness[f] * r[i, f], stiffness[f]
            normal[i, f] = sense[f] * (static[f] + dynamic)
            slope[i, f] = sense[f] * gradient


@dataclass(frozen=True)
class FollowedLoads:
    """The loads ``N`` the friction limits follow (:class:`LoadLaw`), in NumPy.

    Attributes
    ----------
    factor : numpy.ndarray, shape (n_f,)
        ``mu`` [-] (rotational ``mu r`` [m]); 0 for an element with a constant limit.
    rows : numpy.ndarray, shape (n_f, N)
        The followed element's deflection over the state.
    offset : numpy.ndarray, shape (steps + 1, n_f)
        Its part from the inputs at every step.
    static, sense, stiffness : numpy.ndarray, shape (n_f,)
        ``N0`` [N] (tension positive), the sign of ``N0``, the spring's ``k`` [N/m].
    xs, fs : numpy.ndarray, shape (n_f, P)
        A characteristic's breakpoints (padded); ``counts`` (n_f,) 0 for a spring.
    """

    factor: np.ndarray
    rows: np.ndarray
    offset: np.ndarray
    static: np.ndarray
    sense: np.ndarray
    stiffness: np.ndarray
    xs: np.ndarray
    fs: np.ndarray
    counts: np.ndarray

    @staticmethod
    def none(n_f: int, size: int, steps: int) -> FollowedLoads:
        """Every limit constant."""
        zeros = np.zeros(n_f)
        return FollowedLoads(zeros, np.zeros((n_f, size)), np.zeros((steps, n_f)), zeros, zeros, zeros,
                             np.zeros((n_f, 2)), np.zeros((n_f, 2)), np.zeros(n_f, dtype=np.int64))

    @cached_property
    def zero(self) -> np.ndarray:
        """``F(0)`` of each characteristic (0 for a spring)."""
        return np.array([table_force(self.xs, self.fs, f, int(c), 0.0)[0] if c > 0 else 0.0
                         for f, c in enumerate(self.counts)])

    def law(self) -> LoadLaw:
        places, coefficient = sparse_rows(self.rows)
        contiguous = [np.ascontiguousarray(a, dtype=float) for a in
                      (self.factor, self.static, self.sense, self.stiffness, self.xs, self.fs)]
        factor, static, sense, stiffness, xs, fs = contiguous
        return LoadLaw(factor, places, coefficient, np.ascontiguousarray(self.offset, dtype=float), static, sense,
                       stiffness, xs, fs, np.ascontiguousarray(self.counts, dtype=np.int64), self.zero)

    def normal(self, states: np.ndarray, first: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """``(N, dN/dr)`` at the states (K, N) of steps ``first, first + 1, ...``, each (K, n_f)."""
        r = np.ascontiguousarray(states @ self.rows.T + self.offset[first: first + states.shape[0]])
        normal, slope = np.empty_like(r), np.empty_like(r)
        _normals(r, self.stiffness, self.xs, self.fs, self.counts, self.zero, self.static, self.sense, normal, slope)
        return normal, slope

    def limits(self, states: np.ndarray, constant: np.ndarray, first: int = 0) -> np.ndarray:
        """The friction limits at the states (K, N), shape (K, n_f) (:func:`load_limit`)."""
        normal = self.normal(states, first)[0]
        return np.where(self.factor > 0, self.factor * np.maximum(normal, 0.0), constant)


class FrictionElement(ForceElement):
    """The friction elements of a vehicle along a run (module docstring).

    Parameters
    ----------
    names : tuple of str
        The elements' ids.
    gradient : numpy.ndarray, shape (n_f, n)
        ``g`` of each deflection over the coordinates.
    input_gradient : numpy.ndarray, shape (n_f, m)
        ``h`` of each deflection over the inputs.
    stiffness, limit : numpy.ndarray, shape (n_f,)
        Pre-slip stiffness [N/m; N m/rad] and friction limit [N; N m] (a limit that
        follows a load: ignored, see ``loads``).
    force : numpy.ndarray, shape (N, n)
        How a generalized force enters the state equation (``FirstOrderForm.force``).
    u : numpy.ndarray, shape (steps + 1, m)
        The inputs at every step.
    rotational : tuple of bool
        Whether each element acts on a rotation (its outputs' units).
    loads : FollowedLoads, optional
        The loads the limits follow (default: every limit constant).
    """

    kind = "friction"

    def __init__(self, names: tuple[str, ...], gradient: np.ndarray, input_gradient: np.ndarray,
                 stiffness: np.ndarray, limit: np.ndarray, force: np.ndarray, u: np.ndarray,
                 rotational: tuple[bool, ...], loads: FollowedLoads | None = None, partner: np.ndarray | None = None):
        self.ids, self.gradient, self.input_gradient, self.rotational = names, gradient, input_gradient, rotational
        self.stiffness, self.limit, self.force, self.u = stiffness, limit, force, u
        self.rows = np.zeros((len(names), force.shape[0]))
        self.rows[:, : gradient.shape[1]] = gradient
        self.offset = np.ascontiguousarray(u @ input_gradient.T, dtype=float)
        self.loads = loads if loads is not None else FollowedLoads.none(len(names), force.shape[0], u.shape[0])
        #: Pairs in a plane: ``partner[f]`` the second of the pair ``f`` leads, -2 for a
        #: second, -1 alone.
        self.partner = np.full(len(names), -1, dtype=np.int64) if partner is None else np.asarray(partner, np.int64)
        #: The slider positions the NumPy forces start from (the steady solver's state).
        self.slider = np.zeros(len(names))
        #: Held: the NumPy forces keep every slider where it is (every element stuck; the
        #: steady solver's equilibrium for given sliders, ``analysis/curving/transition.py``).
        self.frozen = False
        self.states = len(names)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"friction_{name}" for name in self.ids)

    @property
    def reads(self) -> np.ndarray:
        return np.flatnonzero(np.any(self.rows != 0, axis=0) | np.any(self.loads.rows != 0, axis=0))

    def directions(self) -> np.ndarray:
        n = self.gradient.shape[1]
        return np.column_stack([self.force[:, :n] @ row for row in self.gradient])

    def law(self, first: int) -> FrictionLaw:
        index, coefficient = sparse_rows(self.rows)
        return FrictionLaw(first, index, coefficient, self.offset, np.ascontiguousarray(self.stiffness, dtype=float),
                           np.ascontiguousarray(self.limit, dtype=float), self.slider.copy(), self.loads.law(),
                           self.partner)

    def deflections(self, x: np.ndarray, k: int) -> np.ndarray:
        """The deflections at state ``x`` and step ``k``."""
        return self.gradient @ x[: self.gradient.shape[1]] + self.input_gradient @ self.u[k]

    def limits_at(self, x: np.ndarray, k: int) -> np.ndarray:
        """The friction limits at state ``x`` and step ``k`` [N; N m], shape (n_f,)."""
        return self.loads.limits(x[None, :], self.limit, k)[0]

    def _sliders(self, delta: np.ndarray, limits: np.ndarray) -> np.ndarray:
        return map_sliders(np.ascontiguousarray(delta, dtype=float), self.slider, np.ascontiguousarray(self.stiffness, float),
                           np.ascontiguousarray(limits, dtype=float), self.partner)

    def beyond(self, x: np.ndarray, k: int, tolerance: float = 1e-9) -> np.ndarray:
        """Which elements' spring force at ``x``, their sliders held, exceeds its limit by
        more than ``tolerance`` of it (a pair in a plane by its circle): shape (n_f,) bool."""
        trial = self.stiffness * (self.deflections(x, k) - self.slider)
        size = np.abs(trial)
        for f, p in enumerate(self.partner):
            if p >= 0:
                size[f] = size[p] = float(np.hypot(trial[f], trial[p]))
        limits = self.limits_at(x, k)
        lead = {int(p): f for f, p in enumerate(self.partner) if p >= 0}  # a pair's second: its first's limit
        return size > np.array([limits[lead.get(f, f)] for f in range(size.size)]) * (1 + tolerance)

    def return_mapped(self, x: np.ndarray, k: int) -> np.ndarray:
        """The sliders after the march's return mapping at ``x`` (shape (n_f,) [m; rad]);
        :attr:`slider` unchanged."""
        return self._sliders(self.deflections(x, k), self.limits_at(x, k))

    def forces(self, x: np.ndarray, k: int) -> np.ndarray:
        if self.frozen:
            return self.stiffness * self.slider
        return self.stiffness * self._sliders(self.deflections(x, k), self.limits_at(x, k))

    def slopes(self, x: np.ndarray, k: int, forces: np.ndarray) -> np.ndarray:
        """Stuck (or :attr:`frozen`): 0; slipping (the slider follows the deflection):
        ``k g``, less the limit's own slope ``sign(F) dL/dx`` when it follows a load."""
        if self.frozen:
            return np.zeros_like(self.rows)
        delta, limits = self.deflections(x, k), self.limits_at(x, k)
        trial = self.stiffness * (delta - self.slider)
        size, direction = np.abs(trial), np.sign(trial)
        for f, p in enumerate(self.partner):  # a pair: the trial force's size and direction in the plane
            if p >= 0:
                size[f] = size[p] = float(np.hypot(trial[f], trial[p]))
                if size[f] > 0:
                    direction[f], direction[p] = trial[f] / size[f], trial[p] / size[f]
        slipping = size > limits
        slopes = np.where(slipping, self.stiffness, 0.0)[:, None] * self.rows
        for f, p in enumerate(self.partner):  # dF/d(delta) = L/|t| (I - t t^T) k on the circle
            if p >= 0 and slipping[f]:
                pair = np.array([f, p])
                tangent = np.eye(2) - np.outer(direction[pair], direction[pair])
                slopes[pair] -= limits[f] / size[f] * self.stiffness[f] * tangent @ self.rows[pair]
        normal, rate = self.loads.normal(x[None, :], k)
        lead = {int(p): f for f, p in enumerate(self.partner) if p >= 0}  # a pair's second: its first's limit
        for f in range(self.partner.size):
            first = lead.get(f, f)
            if slipping[f] and self.loads.factor[first] > 0 and normal[0, first] > 0:
                slopes[f] -= direction[f] * self.loads.factor[first] * rate[0, first] * self.loads.rows[first]
        return slopes

    def resolved_step(self, mass: np.ndarray) -> float | None:
        """While slipping the element feeds its pre-slip stiffness back explicitly: the step
        must resolve ``w = sqrt(ks g M^-1 g)``; :data:`RESOLVED` of a period of it (the free
        decay's error is 1.5e-4 of 4 F/k at w dt = 0.012, 4.5e-3 at 0.05)."""
        inverse = np.linalg.solve(mass, self.gradient.T)  # M^-1 g^T, (n, n_f)
        compliance = np.einsum("fi,if->f", self.gradient, inverse)
        omega = np.sqrt(self.stiffness * np.maximum(compliance, 0.0))
        largest = float(np.max(omega)) if omega.size else 0.0
        return RESOLVED / largest if largest > 0 else None

    def history_of(self, states: np.ndarray, limits: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The sliders and forces at every kept state, the march's return mapping replayed:
        ``(slider, force)``, each shape (steps + 1, n_f); ``limits`` the friction limits at
        the states when already known (``FollowedLoads.limits``)."""
        delta = np.ascontiguousarray(states @ self.rows.T + self.offset[: states.shape[0]])
        sliders = np.zeros_like(delta)
        if limits is None:
            limits = self.loads.limits(states, self.limit)
        limits = np.ascontiguousarray(limits, dtype=float)  # a pair: its first's
        _replay(delta, self.slider.copy(), np.ascontiguousarray(self.stiffness, dtype=float), limits, self.partner,
                sliders)
        return sliders, self.stiffness * (delta - sliders)

    def outputs(self, states: np.ndarray, history: np.ndarray) -> dict[str, np.ndarray]:
        limits = self.loads.limits(states, self.limit)
        sliders, forces = self.history_of(states, limits)
        found = {}
        for f, name in enumerate(self.ids):
            found[f"friction_{name}"] = forces[:, f]
            found[f"slip_{name}"] = sliders[:, f]
            if self.loads.factor[f] > 0:
                found[f"limit_{name}"] = limits[:, f]
        return found

    def output_units(self) -> dict[str, str]:
        units = {}
        for f, (name, rotational) in enumerate(zip(self.ids, self.rotational, strict=True)):
            units[f"friction_{name}"] = "N*m" if rotational else "N"
            units[f"slip_{name}"] = "rad" if rotational else "m"
            if self.loads.factor[f] > 0:
                units[f"limit_{name}"] = "N*m" if rotational else "N"
        return units


class _TermNumbers(NamedTuple):
    """A friction element term's expressions evaluated at the vehicle's values."""

    gradient: dict[str, float]
    inputs: dict[str, float]
    values: dict[str, float]


#: The friction terms' numbers already evaluated, by equations and values.
_NUMBERS: IdentityCache[list[_TermNumbers]] = IdentityCache(16)


def _term_numbers(vehicle, terms) -> list[_TermNumbers]:
    """The numbers of ``terms`` at ``vehicle.values``, kept for the same equations and
    values (a study's runs and a benchmark's repeats evaluate them once)."""
    values = vehicle.values

    def evaluate() -> list[_TermNumbers]:
        def numbers(expressions: dict) -> dict[str, float]:
            return {key: expression_value(value, values) for key, value in expressions.items()}

        return [_TermNumbers(numbers(t.gradient), numbers(t.inputs), numbers(t.values)) for t in terms]

    return _NUMBERS.get_or_make((vehicle.equations,), evaluate, tuple(sorted(values.items())))


def friction_elements_of(vehicle, u: np.ndarray) -> FrictionElement | None:
    """The friction elements of ``vehicle`` (a :class:`~express.numeric.statespace.VehicleModel`)
    along the inputs ``u`` (steps + 1, m), or None when it has none."""
    equations = vehicle.equations
    terms = [t for t in equations.element_terms if t.kind == "friction"]
    if not terms:
        return None
    numbers = _term_numbers(vehicle, terms)
    column = {dof: i for i, dof in enumerate(vehicle.dofs)}  # a stroke left out by the vehicle: no column
    n, m = len(vehicle.dofs), len(equations.inputs)
    gradient, inputs = np.zeros((len(terms), n)), np.zeros((len(terms), m))
    for f, number in enumerate(numbers):
        for dof, value in number.gradient.items():
            if dof in column:
                gradient[f, column[dof]] = value
        for name, value in number.inputs.items():
            inputs[f, equations.inputs.index(name)] = value
    stiffness = np.array([number.values["stiffness"] for number in numbers])
    limit = np.array([number.values["friction"] for number in numbers])
    kinds = {e.id: e.rotational for e in vehicle.model.elements} if vehicle.model is not None else {}
    loads = None
    if any("load_static" in t.values for t in terms):
        loads = followed_loads(vehicle, terms, u)
        limit = np.where(loads.factor > 0, 0.0, limit)
    names = tuple(t.element for t in terms)
    planes = {e.id: e.friction_plane for e in vehicle.model.elements} if vehicle.model is not None else {}
    partner = np.full(len(terms), -1, dtype=np.int64)
    for f, name in enumerate(names):
        if planes.get(name) in names:
            partner[f], partner[names.index(planes[name])] = names.index(planes[name]), -2
    return FrictionElement(names, gradient, inputs, stiffness, limit, vehicle.form.force, u,
                           tuple(kinds.get(t.element, False) for t in terms), loads, partner)


def followed_loads(vehicle, terms, u: np.ndarray) -> FollowedLoads:
    """The :class:`FollowedLoads` of the friction element terms ``terms`` (the ``load_*``
    values of :mod:`express.assembly.friction_loads`)."""
    equations = vehicle.equations
    evaluated = _term_numbers(vehicle, terms)
    column = {dof: i for i, dof in enumerate(vehicle.dofs)}
    n_f, size = len(terms), vehicle.form.size
    found = FollowedLoads.none(n_f, size, u.shape[0])
    rows, offset = found.rows.copy(), found.offset.copy()
    factor, static, stiffness = np.zeros(n_f), np.zeros(n_f), np.zeros(n_f)
    counts = np.array([sum(1 for key in t.values if key.startswith("load_x")) for t in terms], dtype=np.int64)
    width = max(2, int(counts.max()))
    xs, fs = np.zeros((n_f, width)), np.zeros((n_f, width))
    for f, term in enumerate(terms):
        if "load_static" not in term.values:
            continue
        number = {key: value for key, value in evaluated[f].values.items() if key.startswith("load")}
        factor[f], static[f] = evaluated[f].values["friction"], number["load_static"]
        stiffness[f] = number["load_stiffness"] if counts[f] == 0 else 0.0
        h = np.zeros(len(equations.inputs))
        for key, value in number.items():
            if key.startswith("load_g:") and key[7:] in column:
                rows[f, column[key[7:]]] = value
            elif key.startswith("load_h:"):
                h[equations.inputs.index(key[7:])] = value
        offset[:, f] = u @ h
        for i in range(int(counts[f])):
            xs[f, i], fs[f, i] = number[f"load_x{i}"], number[f"load_f{i}"]
        xs[f, counts[f]:], fs[f, counts[f]:] = xs[f, max(counts[f] - 1, 0)], fs[f, max(counts[f] - 1, 0)]
    return FollowedLoads(factor, rows, offset, static, np.sign(static), stiffness, xs, fs, counts)
