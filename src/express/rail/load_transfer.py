"""Quasi-static wheel loads of a lateral-only model in a steady canted curve (an estimate).

A model whose wheelsets have no vertical or roll coordinates cannot compute its wheel
loads; this module estimates them from the statics of the vehicle as a set of rigid
masses standing on its wheelsets (``docs/curving.md``, "Wheel loads of a lateral-only
model").  In a curve of signed curvature ``rho`` [1/m] with signed cant ``S`` [m] over
the cant base ``G`` [m] (cant angle ``phi``, ``sin(phi) = S / G``), a mass ``m`` feels,
per unit mass, in the track plane and normal to it::

    a_y = g sin(phi) - v**2 rho cos(phi)      (lateral, +y to the left; -a_y is the cant deficiency)
    a_n = g cos(phi) + v**2 rho sin(phi)      (normal, pressing into the track)

Each body's mass is shared among the wheelsets that carry it (:func:`load_shares`).  The
moments about the track's centreline at rail level of the body's lateral force
``m a_y`` at its height ``h`` and of its normal force ``m a_n`` at its lateral
offset ``y_c`` from the track centre (the body's displacement in the suspension, its
"suspension roll") are carried by wheelset ``j`` whose contact points are ``2 b0``
apart::

    Q_left + Q_right = sum_i s_ij m_i a_n
    Q_left - Q_right = sum_i s_ij m_i (a_y h_i + a_n y_i) / b0_j

so with no offsets each wheel of wheelset j changes by ``m a h / (2 b0)`` (``a`` the
cant deficiency), toward the outer rail; cant excess (``a_y > 0`` in a left curve)
moves load to the inner rail.  The offset ``y_i`` is measured from the track centre line
under the body's wheelsets: in a curve a body's coordinate is its displacement from the
track centre at its own station, and a car body on an undeflected suspension lies on the
chord between its bogies, ``rho (lT**2 + a**2) / 2`` inside it
(:func:`support_line_offsets`; ``docs/curving.md``, "Statics of a canted curve").  Neglected: the heights of the lateral contact forces
above rail level (contact angle), the roll of the wheelset itself, dynamic load changes,
track twist.  Only the static part of the load is exact; the difference is an estimate.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from express.base.diagnostics import ArgumentError
from express.model.parameters import expression_value
from express.model.records import Model
from express.model.topology import classify_bodies

__all__ = [
    "BodyLoads",
    "WheelLoads",
    "body_loads",
    "load_shares",
    "support_line_offsets",
    "track_plane_accelerations",
    "wheel_loads",
]

FloatArray = NDArray[np.float64]


def track_plane_accelerations(speed: ArrayLike, curvature: ArrayLike, cant: ArrayLike, cant_base: float,
                              gravity: float) -> tuple[FloatArray | float, FloatArray | float]:
    """Lateral and normal acceleration of the load per unit mass in the track plane.

    Parameters
    ----------
    speed : float or array_like
        Forward speed v [m/s].
    curvature : float or array_like
        Signed curvature rho [1/m], positive for a curve to the left.
    cant : float or array_like
        Signed cant S [m] (rail height difference), positive when the track is rolled
        toward the centre of a left curve.
    cant_base : float
        Distance G between the rails' contact points the cant is measured over [m].
    gravity : float
        g [m/s^2].

    Returns
    -------
    lateral, normal : float or numpy.ndarray
        ``a_y = g sin(phi) - v**2 rho cos(phi)`` [m/s^2], positive to the left (the
        negative of the cant deficiency in a left curve), and
        ``a_n = g cos(phi) + v**2 rho sin(phi)`` [m/s^2].

    Raises
    ------
    ArgumentError
        For a cant not smaller than the cant base.

    Examples
    --------
    >>> a_y, a_n = track_plane_accelerations(0.0, 0.0, 0.0, 1.5, 9.81)
    >>> float(a_y), float(a_n)
    (0.0, 9.81)
    """
    sin_phi = np.asarray(cant, dtype=float) / float(cant_base)
    if np.any(np.abs(sin_phi) >= 1.0):
        raise ArgumentError(f"the cant must be smaller than the cant base {cant_base} m")
    cos_phi = np.sqrt(1.0 - sin_phi**2)
    centripetal = np.asarray(speed, dtype=float) ** 2 * np.asarray(curvature, dtype=float)
    lateral = gravity * sin_phi - centripetal * cos_phi
    normal = gravity * cos_phi + centripetal * sin_phi
    if lateral.ndim == 0:
        return float(lateral), float(normal)
    return lateral, normal


@dataclass(frozen=True)
class BodyLoads:
    """The masses of a vehicle and how its wheelsets carry them.

    Attributes
    ----------
    bodies : tuple of str
        Body ids, as in the model.
    mass : numpy.ndarray, shape (n_bodies,)
        [kg].
    height : numpy.ndarray, shape (n_bodies,)
        Height of each body's centre above rail level [m].
    shares : numpy.ndarray, shape (n_bodies, n_wheelsets)
        Fraction of each body's weight on each wheelset (rows sum to 1).
    half_base : numpy.ndarray, shape (n_wheelsets,)
        b0, half the distance between the contact points of each wheelset [m].
    """

    bodies: tuple[str, ...]
    mass: FloatArray
    height: FloatArray
    shares: FloatArray
    half_base: FloatArray

    def static_loads(self, gravity: float) -> FloatArray:
        """Static load Q0 of each wheel of each wheelset [N], shape (n_wheelsets,)."""
        return 0.5 * gravity * (self.mass @ self.shares)


@dataclass(frozen=True)
class WheelLoads:
    """Vertical loads Q of the wheels [N], left and right, shape (..., n_wheelsets)."""

    left: FloatArray
    right: FloatArray

    @property
    def total(self) -> FloatArray:
        """``Q_left + Q_right`` of each wheelset [N]."""
        return self.left + self.right

    @property
    def difference(self) -> FloatArray:
        """``Q_left - Q_right`` of each wheelset [N]."""
        return self.left - self.right


def wheel_loads(loads: BodyLoads, lateral: ArrayLike, normal: ArrayLike,
                offsets: ArrayLike | None = None) -> WheelLoads:
    """Quasi-static wheel loads (see the module docstring).

    Parameters
    ----------
    loads : BodyLoads
    lateral, normal : float or array_like, broadcastable to (..., n_bodies)
        ``a_y`` and ``a_n`` of :func:`track_plane_accelerations` [m/s^2]: one value,
        or one per body at its station (``(N, n_bodies)`` for a time history; a value
        per instant is ``a[:, None]``).
    offsets : array_like, shape (..., n_bodies), optional
        Lateral displacement of each body's centre from the track centre line under its
        wheelsets [m] (:func:`support_line_offsets`; zero by default: the rigid-vehicle
        estimate).

    Returns
    -------
    WheelLoads
        Each of shape (..., n_wheelsets).

    Examples
    --------
    A 10 t mass 1 m above rail on one wheelset (b0 = 0.75 m) at 1 m/s^2 of cant
    deficiency puts ``m a h / (2 b0) = 6.67 kN`` more on the outer wheel:

    >>> one = BodyLoads(("B",), np.array([1e4]), np.array([1.0]), np.ones((1, 1)), np.array([0.75]))
    >>> q = wheel_loads(one, -1.0, 9.81)
    >>> round(float(q.right[0] - q.left[0]) / 2, 1)
    6666.7
    """
    count = loads.mass.size
    a_y = np.broadcast_to(np.asarray(lateral, dtype=float), np.broadcast_shapes(np.shape(lateral), (count,)))
    a_n = np.broadcast_to(np.asarray(normal, dtype=float), np.broadcast_shapes(np.shape(normal), (count,)))
    weights = loads.mass[:, None] * loads.shares  # (n_bodies, n_wheelsets)
    total = a_n @ weights
    moment = (a_y * loads.height) @ weights
    if offsets is not None:
        moment = moment + (a_n * np.asarray(offsets, dtype=float)) @ weights
    difference = moment / loads.half_base
    return WheelLoads(0.5 * (total + difference), 0.5 * (total - difference))


def support_line_offsets(shares: ArrayLike, stations: ArrayLike, wheelset_stations: ArrayLike,
                         curvature: ArrayLike) -> FloatArray:
    """Lateral offset of the track centre line under each body's wheelsets from the track
    centre at the body's own station [m], +y (to the inside of a left curve).

    The track centre at station ``x`` lies ``rho (x - x_i)**2 / 2`` to the inside of the
    tangent at the body's station ``x_i``; weighted with the body's lever-rule shares
    (whose moment about ``x_i`` vanishes) that is the chord::

        e_i = rho_i / 2 sum_j s_ij (x_j - x_i)**2

    Parameters
    ----------
    shares : array_like, shape (n_bodies, n_wheelsets)
        :func:`load_shares`.
    stations : array_like, shape (n_bodies,)
        Each body's station x [m].
    wheelset_stations : array_like, shape (n_wheelsets,)
        Each wheelset's station [m].
    curvature : array_like, broadcastable to (..., n_bodies)
        Signed curvature at each body's station [1/m].

    Returns
    -------
    numpy.ndarray, shape (..., n_bodies)

    Examples
    --------
    A car body between two bogies 19 m apart (wheelbase 2.56 m) in R 600 m: its centre on
    an undeflected suspension lies ``(9.5**2 + 1.28**2) / 1200`` = 76.6 mm inside:

    >>> x = np.array([-10.78, -8.22, 8.22, 10.78])
    >>> round(float(support_line_offsets(np.full((1, 4), 0.25), [0.0], x, 1 / 600)[0]), 4)
    0.0766
    """
    spread = np.asarray(shares, dtype=float) * (np.asarray(wheelset_stations, dtype=float)[None, :]
                                                - np.asarray(stations, dtype=float)[:, None]) ** 2
    return 0.5 * np.asarray(curvature, dtype=float) * spread.sum(axis=1)


def _lever_shares(station: float, supports: Sequence[float]) -> FloatArray:
    """Shares of a load at ``station`` among ``supports`` (stations [m]): the lever rule
    for two, equal for one, the least-norm solution of ``sum w = 1, sum w x = station``
    for more (exact for a beam on two supports)."""
    x = np.asarray(supports, dtype=float)
    if x.size == 1:
        return np.ones(1)
    centre = x.mean()
    spread = float(np.sum((x - centre) ** 2))
    if spread == 0.0:
        return np.full(x.size, 1.0 / x.size)
    return 1.0 / x.size + (station - centre) * (x - centre) / spread


def load_shares(model: Model, values: Mapping[str, float]) -> FloatArray:
    """Fraction of each body's weight on each wheelset, shape (n_bodies, n_wheelsets).

    A wheelset carries itself; a bogie (and a steering lever on it) is shared among its
    wheelsets by the lever rule on their stations; any other body (a car body) is shared
    among the supports — the bogies, and the wheelsets hung from no bogie — by the
    lever rule on their stations, and each bogie's part among its wheelsets as before.
    """
    if model.rail is None:
        raise ArgumentError(f"{model.source}: the model has no [rail] data")
    wheelsets = [w.body for w in model.rail.wheelsets]
    station = {body.id: expression_value(body.position[0], values) for body in model.bodies}
    topology = classify_bodies(model)
    under: dict[str, list[int]] = {}
    for j, wheelset in enumerate(wheelsets):
        under.setdefault(topology.bogie_of.get(wheelset, wheelset), []).append(j)

    def spread(body_station: float, support: str) -> FloatArray:
        row = np.zeros(len(wheelsets))
        columns = under[support]
        row[columns] = _lever_shares(body_station, [station[wheelsets[j]] for j in columns])
        return row

    supports = list(under)
    shares = np.zeros((len(model.bodies), len(wheelsets)))
    for i, body in enumerate(model.bodies):
        group = topology.group(body.id)
        if body.id in wheelsets:
            shares[i, wheelsets.index(body.id)] = 1.0
        elif group in under:
            shares[i] = spread(station[body.id], group)
        else:
            parts = _lever_shares(station[body.id], [station[s] for s in supports])
            shares[i] = sum((part * spread(station[s], s) for part, s in zip(parts, supports, strict=True)),
                            np.zeros(len(wheelsets)))
    return shares


def body_loads(model: Model, values: Mapping[str, float], half_base: ArrayLike) -> BodyLoads:
    """The :class:`BodyLoads` of ``model`` at the parameter ``values`` (SI).

    Parameters
    ----------
    model : Model
        A model with rail data; each body's height is the third component of its
        position [m above rail].
    values : mapping of str to float
        Parameter values.
    half_base : array_like, shape (n_wheelsets,)
        b0 of each wheelset [m].
    """
    mass = np.array([expression_value(body.mass, values) for body in model.bodies])
    height = np.array([expression_value(body.position[2], values) for body in model.bodies])
    base = np.asarray(half_base, dtype=float)
    if not np.all(base > 0) or not all(math.isfinite(b) for b in base):
        raise ArgumentError(f"half the contact base b0 must be positive, got {base}")
    return BodyLoads(tuple(body.id for body in model.bodies), mass, height, load_shares(model, values), base)
