"""The wheel/rail quantities of a curving result, named as engineers name them.

One record, :class:`WheelRailOutputs`, holds them for a time history (``N`` instants)
or a steady state (``N = 1``); the steady-state solver and the time march both build it,
so their columns are the same (``docs/curving.md``, "Outputs").  Per wheel (``L`` left,
``R`` right; wheelsets numbered from the front, 1, 2, ...):

``Q{n}{s}`` [N]
    vertical wheel load (from the model's vertical contact, or the quasi-static
    estimate of :mod:`express.rail.load_transfer` for a lateral-only model; the
    ``loads`` attribute says which);
``Y{n}{s}`` [N]
    lateral force from the rail on the wheel in the track plane, +y to the left;
``YQ{n}{s}`` [-]
    the derailment quotient: the lateral force toward the track centre (the guiding
    force, ``-Y`` on the left wheel, ``+Y`` on the right) over Q; flange climbing needs
    it large and positive;
``Fx{n}{s}`` [N]
    longitudinal creep force on the wheel, +x forward;
``u{n}{s}`` [m], ``gamma{n}{s}`` [rad]
    lateral contact position on the rail (from its nominal point, +y left) and the
    contact angle (positive, the flank's slope toward the wheel's own flange);
``flanging{n}{s}`` [-]
    1 when the contact angle exceeds :data:`FLANGE_CONTACT_ANGLE` (flange contact), else 0.

With the contact tables (not the dead-band model) each wheel also has, after the
other columns (``docs/wear.md``):

``Tgamma{n}{s}`` [N]
    the contact's frictional power per unit rolling distance, ``|Fx xi + T eta + Mz phi|``
    (the spin moment ``Mz`` of the default table law; FASTSIM and Polach give none);
``wear{n}{s}`` [ug/m/mm^2]
    the USFD wear rate of R8T wheel steel at ``Tgamma / A`` (:func:`express.rail.wear.
    usfd_wear_rate`, ``A`` the Hertz patch's area): mass lost per metre rolled per mm^2
    of contact;
``rcf{n}{s}`` [-]
    Burstow's RCF damage index per passage at ``Tgamma`` (:func:`express.rail.wear.
    burstow_damage`).

Per wheelset: ``SY{n}`` [N], the track shift force ``Y_L + Y_R`` (Prud'homme's ΣY,
+y left); ``aoa{n}`` [rad], the angle of attack (the wheelset's yaw from the track
tangent at its station, positive turning the front to the left). Per vehicle: ``dQQ0``
[-], the largest wheel unloading ``(Q0 - Q) / Q0`` over all wheels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from express.base.diagnostics import ArgumentError
from express.rail.wear import burstow_damage, wear_rate_of_contact
from express.rail.wear_profile import WHEEL_STEEL_DENSITY, usfd_profile_wear

__all__ = ["FLANGE_CONTACT_ANGLE", "SIDES", "WheelRailOutputs", "column_unit"]

FloatArray = NDArray[np.float64]

#: Contact angle beyond which a contact counts as flange contact [rad]: 30 degrees.  The
#: tread of S1002 on 60E1 (1:40) keeps its contact angle below about 10 degrees over the
#: flange clearance; from the flange root on it climbs steeply to the flank's 70 degrees,
#: so any threshold between about 20 and 60 degrees marks the same contacts.
FLANGE_CONTACT_ANGLE = math.radians(30.0)
#: Wheel suffixes, in the order of the last axis of the per-wheel arrays.
SIDES = ("L", "R")


def _per_wheel(values: ArrayLike, name: str) -> FloatArray:
    array = np.asarray(values, dtype=float)
    if array.ndim != 3 or array.shape[2] != 2:
        raise ArgumentError(f"{name} must have shape (instants, wheelsets, 2), got {array.shape}")
    return array


@dataclass(frozen=True)
class WheelRailOutputs:
    """Wheel/rail quantities at ``N`` instants of ``n`` wheelsets (see the module docstring).

    Attributes
    ----------
    vertical_load : numpy.ndarray, shape (N, n, 2)
        Q of each wheel, left then right [N].
    lateral_force : numpy.ndarray, shape (N, n, 2)
        Y in the track plane, +y left [N].
    longitudinal_force : numpy.ndarray, shape (N, n, 2)
        Longitudinal creep force, +x forward [N].
    contact_position : numpy.ndarray, shape (N, n, 2)
        Lateral contact position on the rail [m].
    contact_angle : numpy.ndarray, shape (N, n, 2)
        Contact angle [rad], >= 0 toward the wheel's flange.
    angle_of_attack : numpy.ndarray, shape (N, n)
        Yaw of each wheelset from the track [rad].
    static_load : numpy.ndarray, shape (n,)
        Q0 of each wheel of each wheelset [N].
    loads : str
        Where Q comes from: ``"dynamic"`` (the model's vertical contact),
        ``"quasi-static estimate"`` (:mod:`express.rail.load_transfer`) or ``"static"``.
    frictional_power : numpy.ndarray, shape (N, n, 2), optional
        Tgamma of each contact [N] (the contact tables' runs; ``None`` otherwise).
    patch_area : numpy.ndarray, shape (N, n, 2), optional
        Area of each Hertz patch [m^2], with ``frictional_power``.
    wheel_position, patch_semi_b : numpy.ndarray, shape (N, n, 2), optional
        Each contact's position on the wheel profile from the centred wheelset's contact,
        positive toward the field side [m], and its patch's lateral semi-axis [m] (the
        contact tables' runs): for :meth:`wheel_wear_depth`.
    """

    vertical_load: FloatArray
    lateral_force: FloatArray
    longitudinal_force: FloatArray
    contact_position: FloatArray
    contact_angle: FloatArray
    angle_of_attack: FloatArray
    static_load: FloatArray
    loads: str = "quasi-static estimate"
    frictional_power: FloatArray | None = None
    patch_area: FloatArray | None = None
    wheel_position: FloatArray | None = None
    patch_semi_b: FloatArray | None = None

    def __post_init__(self) -> None:
        shape = _per_wheel(self.vertical_load, "vertical_load").shape
        energy = ("frictional_power", "patch_area", "wheel_position", "patch_semi_b")
        if (self.frictional_power is None) != (self.patch_area is None):
            raise ArgumentError("frictional_power and patch_area come together")
        for name in ("lateral_force", "longitudinal_force", "contact_position", "contact_angle", *energy):
            if name in energy and getattr(self, name) is None:
                continue
            if _per_wheel(getattr(self, name), name).shape != shape:
                raise ArgumentError(f"{name} must have the shape of vertical_load {shape}")
        if np.shape(self.angle_of_attack) != shape[:2]:
            raise ArgumentError(f"angle_of_attack must have shape {shape[:2]}, got {np.shape(self.angle_of_attack)}")
        if np.shape(self.static_load) != shape[1:2] or not np.all(np.asarray(self.static_load) > 0):
            raise ArgumentError(f"static_load must be {shape[1]} positive loads, got {self.static_load!r}")

    @property
    def wheelsets(self) -> int:
        """Number of wheelsets n."""
        return int(self.vertical_load.shape[1])

    @property
    def guiding_force(self) -> FloatArray:
        """Lateral force toward the track centre on each wheel [N], shape (N, n, 2):
        ``-Y`` on the left wheel, ``+Y`` on the right."""
        return self.lateral_force * np.array([-1.0, 1.0])

    @property
    def y_over_q(self) -> FloatArray:
        """Derailment quotient Y/Q of each wheel (guiding force over Q), shape (N, n, 2)."""
        return self.guiding_force / self.vertical_load

    @property
    def flange_contact(self) -> NDArray[np.bool_]:
        """Whether each wheel is in flange contact, shape (N, n, 2)."""
        return self.contact_angle > FLANGE_CONTACT_ANGLE

    @property
    def track_shift_force(self) -> FloatArray:
        """ΣY of each wheelset, ``Y_L + Y_R`` [N], shape (N, n)."""
        return self.lateral_force.sum(axis=2)

    @property
    def wheel_unloading(self) -> FloatArray:
        """``(Q0 - Q) / Q0`` of each wheel, shape (N, n, 2)."""
        q0 = self.static_load[None, :, None]
        return (q0 - self.vertical_load) / q0

    @property
    def vehicle_unloading(self) -> FloatArray:
        """ΔQ/Q0 of the vehicle: the largest wheel unloading at each instant, shape (N,)."""
        return self.wheel_unloading.reshape(self.wheel_unloading.shape[0], -1).max(axis=1)

    def columns(self) -> dict[str, FloatArray]:
        """Every column by name (module docstring), each of shape (N,), in a fixed order."""
        out: dict[str, FloatArray] = {}
        per_wheel = (("Q", self.vertical_load), ("Y", self.lateral_force), ("YQ", self.y_over_q),
                     ("Fx", self.longitudinal_force), ("u", self.contact_position), ("gamma", self.contact_angle),
                     ("flanging", self.flange_contact.astype(float)))
        for j in range(self.wheelsets):
            for prefix, values in per_wheel:
                for k, side in enumerate(SIDES):
                    out[f"{prefix}{j + 1}{side}"] = values[:, j, k]
            out[f"SY{j + 1}"] = self.track_shift_force[:, j]
            out[f"aoa{j + 1}"] = self.angle_of_attack[:, j]
        out["dQQ0"] = self.vehicle_unloading
        if self.frictional_power is not None:
            out.update(self._energy_columns())
        return out

    @property
    def wear_rate(self) -> FloatArray | None:
        """USFD wear rate of each wheel [ug/(m mm^2)], shape (N, n, 2); ``None`` without
        the frictional power."""
        if self.frictional_power is None or self.patch_area is None:
            return None
        return wear_rate_of_contact(self.frictional_power, self.patch_area)

    @property
    def rcf_damage(self) -> FloatArray | None:
        """Burstow's RCF damage index of each wheel [-], shape (N, n, 2); ``None``
        without the frictional power."""
        return None if self.frictional_power is None else burstow_damage(self.frictional_power)

    def wheel_wear_depth(self, rolled: ArrayLike, edges: ArrayLike, radius: float,
                         density: float = WHEEL_STEEL_DENSITY) -> FloatArray:
        """Depth worn off each wheel's profile by the USFD wear rate over the run [m],
        shape (n, 2, M): on the cells ``edges`` (shape (M + 1,)) of the position on the
        wheel profile from the centred wheelset's contact, positive toward the field side
        [m]; ``rolled`` the distance each instant stands for [m], shape (N,)
        (:func:`express.rail.wear_profile.rolled_per_instant` of a run's distances);
        ``radius`` the rolling radius [m]; each patch's mass spread by its Hertz line
        load (``docs/wear.md``)."""
        if self.frictional_power is None or self.wheel_position is None or self.patch_semi_b is None:
            raise ArgumentError("the wear across the profile needs the contact tables' record")
        weights = np.asarray(rolled, dtype=float)
        if weights.shape != self.frictional_power.shape[:1]:
            raise ArgumentError(f"rolled must have shape ({self.frictional_power.shape[0]},), got {weights.shape}")
        assert self.patch_area is not None
        return np.array([[usfd_profile_wear(edges, self.wheel_position[:, j, k], self.patch_semi_b[:, j, k],
                                            self.frictional_power[:, j, k], self.patch_area[:, j, k], weights,
                                            radius=radius, density=density) for k in range(2)]
                         for j in range(self.wheelsets)])

    def at(self, instants: ArrayLike) -> WheelRailOutputs:
        """The outputs at the chosen ``instants`` only (a boolean mask, shape (N,), or
        indices); ``static_load`` and ``loads`` kept."""
        chosen = np.asarray(instants)
        changes = {f.name: getattr(self, f.name)[chosen] for f in fields(self)
                   if isinstance(getattr(self, f.name), np.ndarray) and f.name != "static_load"}
        return replace(self, **changes)

    def _energy_columns(self) -> dict[str, FloatArray]:
        out: dict[str, FloatArray] = {}
        per_wheel = (("Tgamma", self.frictional_power), ("wear", self.wear_rate), ("rcf", self.rcf_damage))
        for j in range(self.wheelsets):
            for prefix, values in per_wheel:
                if values is None:  # a record without the frictional power: no energy columns
                    continue
                for k, side in enumerate(SIDES):
                    out[f"{prefix}{j + 1}{side}"] = values[:, j, k]
        return out

    def units(self) -> dict[str, str]:
        """SI unit of every column of :meth:`columns` (``""`` for ratios and flags)."""
        return {name: column_unit(name) for name in self.columns()}


#: Units of the columns by name prefix (longest prefixes first).
_UNITS = (("Tgamma", "N"), ("wear", "ug/m/mm^2"), ("rcf", ""), ("flanging", ""), ("gamma", "rad"), ("dQQ0", ""), ("aoa", "rad"), ("YQ", ""), ("Fx", "N"), ("SY", "N"),
          ("Q", "N"), ("Y", "N"), ("u", "m"))


def column_unit(name: str) -> str:
    """SI unit of a column of :meth:`WheelRailOutputs.columns`.

    Examples
    --------
    >>> column_unit("YQ1L"), column_unit("SY2"), column_unit("gamma1R")
    ('', 'N', 'rad')
    """
    for prefix, unit in _UNITS:
        if name.startswith(prefix):
            return unit
    raise KeyError(name)
