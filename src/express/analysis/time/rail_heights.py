"""Rail heights at the wheels' contact springs: the cross level of a model with one ground
under both rails of a wheelset.

Such a ground (the bundled wagon's and Manchester car's ``GF``, ``GR``) has one vertical
input, which the track's vertical level drives; its cross level ``c = z_R - z_L``
(``docs/track.md``, "Track components") cannot reach the wheels through it. It is
imposed where it acts, at each wheel's own vertical contact spring
(:func:`express.rail.vertical_contact.vertical_contacts`): the (left, right) rail raised by
``r = (-c/2, +c/2)`` adds ``kappa r`` to the spring's deflection, ``kappa`` the spring's
coefficient on its ground's vertical input (-1 for a spring from the wheel to the rail), so
the vehicle takes the generalized forces and each wheel the load change::

    f  = -sum_wheels (k_z kappa r + c_z kappa r') d        (d: the deflection's row over q)
    dQ = -(k_z kappa r + c_z kappa r')

the same equations as a ground under each rail (``tests/test_time_rail_heights.py`` runs
both and compares them). In the state equations ``f`` enters through ``G``
(:class:`express.assembly.first_order.StateForm`) as the track's inputs enter through
``B`` and ``Bd``: ``B_r = G P_r``, ``Bd_r = G Pd_r`` with ``P_r = -d k_z kappa`` and
``Pd_r = -d c_z kappa`` (one column per wheel).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from express.base.caches import IdentityCache
from express.numeric.statespace import VehicleModel
from express.rail.track import Track
from express.rail.vertical_contact import vertical_contacts

__all__ = ["ContactSprings", "HeightInputs", "RailHeights", "contact_springs", "height_inputs", "rail_heights"]


@dataclass(frozen=True)
class ContactSprings:
    """The vertical contact springs of every wheel, flattened wheelset by wheelset (left,
    right): ``S = 2 n_wheelsets`` columns.

    Attributes
    ----------
    rows : numpy.ndarray, shape (S, n)
        Each spring's deflection over the coordinates [m per unit].
    stiffness, damping : numpy.ndarray, shape (S,)
        ``k_z`` [N/m] and ``c_z`` [N s/m].
    kappa : numpy.ndarray, shape (S,)
        The deflection's coefficient on its ground's vertical input.
    """

    rows: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    kappa: np.ndarray

    @property
    def forcing(self) -> np.ndarray:
        """``P_r = -d k_z kappa``: generalized forces per metre of rail height, shape (n, S)."""
        return -(self.rows * (self.stiffness * self.kappa)[:, None]).T

    @property
    def forcing_rate(self) -> np.ndarray:
        """``Pd_r = -d c_z kappa``: per metre per second of its rate, shape (n, S)."""
        return -(self.rows * (self.damping * self.kappa)[:, None]).T


def contact_springs(vehicle: VehicleModel) -> ContactSprings | None:
    """The contact springs through which a rail height reaches the wheels, or None unless
    every wheel stands on a vertical spring to a ground with a vertical input (``<G>.z``)."""
    return _SPRINGS.get_or_make((vehicle,), lambda: _contact_springs(vehicle))


_SPRINGS: IdentityCache[ContactSprings | None] = IdentityCache(8)


def _contact_springs(vehicle: VehicleModel) -> ContactSprings | None:
    if vehicle.model is None or not vehicle.wheelsets:
        return None
    pairs = vertical_contacts(vehicle.model, vehicle.values, [w.name for w in vehicle.wheelsets], vehicle.dofs,
                              vehicle.inputs)
    every = [spring for pair in pairs for spring in pair]
    if any(spring is None for spring in every):
        return None
    vertical = np.array([name.endswith(".z") for name in vehicle.inputs], dtype=bool)
    kappa = np.array([float(np.sum(spring.inputs[vertical])) for spring in every])  # type: ignore[union-attr]
    if np.any(kappa == 0.0):
        return None
    return ContactSprings(
        np.array([spring.dofs for spring in every], dtype=float),  # type: ignore[union-attr]
        np.array([spring.stiffness for spring in every], dtype=float),  # type: ignore[union-attr]
        np.array([spring.damping for spring in every], dtype=float),  # type: ignore[union-attr]
        kappa,
    )


@dataclass(frozen=True)
class RailHeights:
    """The rail heights under every wheel along a run (module docstring).

    Attributes
    ----------
    heights, rates : numpy.ndarray, shape (N, S)
        ``r`` [m] and ``r'`` [m/s] of each wheel's rail (wheelset by wheelset, left then
        right) at every instant.
    springs : ContactSprings
    """

    heights: np.ndarray
    rates: np.ndarray
    springs: ContactSprings

    def load_changes(self) -> np.ndarray:
        """``dQ = -(k_z kappa r + c_z kappa r')`` [N], shape (N, n_wheelsets, 2)."""
        s = self.springs
        change = -(self.heights * s.stiffness * s.kappa + self.rates * s.damping * s.kappa)
        return change.reshape(change.shape[0], -1, 2)

    def forces(self) -> np.ndarray:
        """The generalized forces ``f`` on the coordinates at every instant, shape (N, n)."""
        return self.heights @ self.springs.forcing.T + self.rates @ self.springs.forcing_rate.T


def rail_heights(vehicle: VehicleModel, track: Track, distance: np.ndarray, speed: float) -> RailHeights | None:
    """The cross level's rail heights under the wheels with the leading wheelset at each
    ``distance`` [m] and the rates at ``speed`` [m/s]; None when the track carries no cross
    level or the model's springs cannot take it (:func:`contact_springs`)."""
    springs = contact_springs(vehicle) if "cross_level" in track.applied_components else None
    if springs is None:
        return None
    stations = np.array([w.station for w in vehicle.wheelsets], dtype=float)
    s = (np.asarray(distance, dtype=float)[:, None] - (stations.max() - stations)[None, :]).ravel()
    component = track.component("cross_level")
    shape = (np.size(distance), stations.size)
    half = 0.5 * np.asarray(component.value(s), dtype=float).reshape(shape)
    half_rate = 0.5 * speed * np.asarray(component.rate(s), dtype=float).reshape(shape)
    side = np.array([-1.0, 1.0])  # left rail down, right rail up for c > 0
    heights = (half[:, :, None] * side).reshape(shape[0], -1)
    rates = (half_rate[:, :, None] * side).reshape(shape[0], -1)
    return RailHeights(heights, rates, springs)


@dataclass(frozen=True)
class HeightInputs:
    """The rail heights as further inputs of the frequency domain (``express ride``), one
    per wheel (``S`` columns, the order of :class:`ContactSprings`).

    Attributes
    ----------
    b, bd : numpy.ndarray, shape (N, S)
        ``G P_r`` and ``G Pd_r``: their columns of the state equations' ``B`` and ``Bd``.
    e0, e1 : numpy.ndarray, shape (n_outputs, S)
        Their part of the outputs ``y = ... + (E0 + i w E1) u``: ``-k_z kappa`` and
        ``-c_z kappa`` in the rows ``<W>.dQL``, ``<W>.dQR`` of each wheel's own load.
    mixing : numpy.ndarray, shape (S, n_components)
        ``-1/2`` (left) and ``+1/2`` (right) in the column of the cross level.
    positions : numpy.ndarray, shape (S,)
        The wheels' stations [m].
    """

    b: np.ndarray
    bd: np.ndarray
    e0: np.ndarray
    e1: np.ndarray
    mixing: np.ndarray
    positions: np.ndarray


def height_inputs(vehicle: VehicleModel, components: tuple[str, ...], outputs: tuple[str, ...] | list[str]) -> HeightInputs | None:
    """The cross level at the contact springs as inputs of the frequency domain, None when
    the model's springs cannot take it (:func:`contact_springs`).

    Parameters
    ----------
    vehicle : VehicleModel
    components : tuple of str
        The track components in the order of the mixing's columns.
    outputs : sequence of str
        The output names; the rows ``<W>.dQL``, ``<W>.dQR`` take each wheel's load change.
    """
    springs = contact_springs(vehicle)
    if springs is None:
        return None
    count = springs.kappa.size
    mixing = np.zeros((count, len(components)))
    mixing[:, components.index("cross_level")] = np.tile([-0.5, 0.5], count // 2)
    e0, e1 = np.zeros((len(outputs), count)), np.zeros((len(outputs), count))
    rows = {name: i for i, name in enumerate(outputs)}
    for j, wheel in enumerate(f"{w.name}.dQ{side}" for w in vehicle.wheelsets for side in "LR"):
        if wheel in rows:
            e0[rows[wheel], j] = -springs.stiffness[j] * springs.kappa[j]
            e1[rows[wheel], j] = -springs.damping[j] * springs.kappa[j]
    force = vehicle.form.force
    positions = np.repeat([w.station for w in vehicle.wheelsets], 2).astype(float)
    return HeightInputs(force @ springs.forcing, force @ springs.forcing_rate, e0, e1, mixing, positions)
