"""Modes of the linear vehicle: eigenvalue records, participation and labels.

A mode is one eigenvalue of ``A(v)`` with what moves in it: the participation share of
every DOF (rotations weighed by the body's radius of gyration, so that radians compare
with metres), the series elements' share of its dissipated power, and a name from the
distribution of its energy over the bodies and directions
(:mod:`express.analysis.modes.mode_names`): hunting, wheelset, bogie frame, steering lever or
car-body modes.  :func:`modes_of` builds them; :mod:`express.analysis.stability.stability` finds the modes
at a speed and the critical speed.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from express.analysis.modes.mode_energies import (
    DofGroups,
    RowProduct,
    group_sums,
    kinetic_shares,
    participation,
    roll_centres,
    series_ranking,
    series_shares,
    top_columns,
)
from express.analysis.modes.mode_names import RoleGroups, generic_names, kinematic_frequency, mode_names
from express.base.data import DataRecord, variable, xarray
from express.base.units import KMH
from express.model.topology import Topology
from express.numeric.statespace import VehicleModel

__all__ = ["DOMINANT_COUNT", "STABILITY_RTOL", "EigenResult", "Mode", "modes_of", "stability_threshold"]

#: Relative stability threshold: a mode counts as unstable when its real part exceeds
#: this times the spectrum's scale (its largest ``|lambda|``, at least 1 1/s). About the
#: square root of the machine epsilon: rounding moves a simple eigenvalue by about
#: ``eps |A|``, but a double one (the free lateral motion of a wheelset whose creep
#: forces vanish, a Young's modulus of 1e-300 Pa) by ``sqrt(eps) |A|`` (docs/reliability.md).
STABILITY_RTOL = 1e-8


def stability_threshold(eigenvalues) -> float:
    """The real part [1/s] above which an eigenvalue of this spectrum is unstable:
    :data:`STABILITY_RTOL` times ``max(1, max |lambda|)``.

    Examples
    --------
    >>> f"{stability_threshold([-0.5 + 20j, 6.7e-7, -316.0]):.3g}"
    '3.16e-06'
    """
    values = np.abs(np.asarray(eigenvalues, dtype=complex))
    return STABILITY_RTOL * max(1.0, float(values.max()) if values.size else 1.0)

#: Number of DOFs listed in :attr:`Mode.dominant`.
DOMINANT_COUNT = 4
#: Length [m] by which a rotation [rad] is multiplied before it is compared with a
#: translation [m] when the body's mass or inertia is unknown (or zero).
REFERENCE_LENGTH = 1.0

_MOTION_WORDS = {"x": "longitudinal", "y": "sway", "z": "bounce", "rx": "roll", "ry": "pitch", "rz": "yaw"}
_FRAME_WORDS = {"x": "longitudinal", "y": "lateral", "z": "vertical", "rx": "roll", "ry": "pitch", "rz": "yaw"}


# ---------------------------------------------------------------------------------------
# Modes
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Mode:
    """One eigenvalue of ``A(v)`` and what moves in it.

    Attributes
    ----------
    eigenvalue : complex
        ``lambda = Re + j Im`` [1/s]; the free motion is ``exp(lambda t)``. Only the
        member with ``Im >= 0`` of a conjugate pair is kept.
    frequency_hz : float
        Damped natural frequency ``Im / (2 pi)`` [Hz] (0 for a real eigenvalue).
    damping_ratio : float
        ``-Re / |lambda|`` [-]: positive when the mode decays, negative when it grows,
        0 for a zero eigenvalue.
    dominant : tuple of (str, float)
        Up to :data:`DOMINANT_COUNT` DOFs with the largest share of the displacement part
        ``phi`` of the eigenvector, largest first, with their share in [0, 1]:
        ``share_i = |l_i phi_i|^2 / sum_j |l_j phi_j|^2`` with ``l = 1`` for a
        translation and, for a rotation, ``l`` = the body's radius of gyration about
        that axis, ``sqrt(I / m)`` [m], so that radians compare with metres (a rotation
        counts as the displacement of the body's inertia-equivalent point: 0.65 m for a
        wheelset's yaw, 6 m for the car body's). The shares of all DOFs sum to 1, so
        those listed sum to at most 1.
    kind : str
        Short label of the mode (see :meth:`describe`), e.g. ``"hunting, front bogie"``.
    body_shares : tuple of (str, float)
        Share of every body (sum of its DOFs' shares), largest first.
    series : tuple of (str, float)
        Series (Maxwell) elements with their share of the mode's dissipated power [-],
        largest first (:mod:`express.analysis.modes.mode_names`). Their strokes have no mass:
        they are never among :attr:`dominant` nor the subject of :attr:`kind`.

    Examples
    --------
    >>> mode = Mode(complex(-0.5, 20.0), 20.0 / (2 * np.pi), 0.025,
    ...             (("W1.y", 0.4), ("W2.y", 0.3), ("T1.rz", 0.2)), "hunting, front bogie")
    >>> mode.describe()
    'hunting, front bogie (W1.y, W2.y, T1.rz)'
    >>> round(mode.frequency_hz, 3), mode.stable
    (3.183, True)
    """

    eigenvalue: complex
    frequency_hz: float
    damping_ratio: float
    dominant: tuple[tuple[str, float], ...]
    kind: str = ""
    series: tuple[tuple[str, float], ...] = field(default=(), repr=False)
    #: the bodies and their shares of the displacement, in the order of their first DOF
    #: (sorted into :attr:`body_shares` when asked: thousands of modes of a long train
    #: would each sort a thousand bodies)
    _bodies: tuple[tuple[str, ...], np.ndarray] | None = field(default=None, repr=False, compare=False)

    @cached_property
    def body_shares(self) -> tuple[tuple[str, float], ...]:
        """Share of every body (sum of its DOFs' shares), largest first (ties in the
        order of the bodies' first DOF)."""
        if self._bodies is None:
            return ()
        names, shares = self._bodies
        order = np.argsort(-shares, kind="stable")
        return tuple(zip([names[i] for i in order], shares[order].tolist(), strict=True))

    @property
    def real(self) -> float:
        """Real part of the eigenvalue [1/s] (growth rate when positive)."""
        return float(self.eigenvalue.real)

    @property
    def imag(self) -> float:
        """Imaginary part of the eigenvalue [rad/s]."""
        return float(self.eigenvalue.imag)

    @property
    def stable(self) -> bool:
        """True when the real part is negative."""
        return self.real < 0.0

    @property
    def natural_frequency_hz(self) -> float:
        """Undamped natural frequency ``|lambda| / (2 pi)`` [Hz] of an oscillatory mode
        (for a real eigenvalue, its rate ``|lambda| / (2 pi)``)."""
        return abs(self.eigenvalue) / (2.0 * np.pi)

    def describe(self) -> str:
        """Short human label: :attr:`kind` and the DOFs that dominate.

        The DOFs listed are those of :attr:`dominant` with at least 10 % of the
        displacement (at most three; at least the first), then the series elements
        with at least 10 % of the dissipated power (:attr:`series`, at most two).

        Returns
        -------
        str
            E.g. ``"hunting, front bogie (W1.y, W2.y, T1.rz)"`` or
            ``"car body sway/roll (CB.y, CB.rx)"``.
        """
        names = [name for name, share in self.dominant[:3] if share >= 0.1] or [
            name for name, _ in self.dominant[:1]
        ]
        series = [f"{element} {share:.0%}" for element, share in self.series[:2] if share >= 0.1]
        if series:
            names.append("series dampers " + " ".join(series))
        kind = self.kind or "mode"
        return f"{kind} ({', '.join(names)})" if names else kind


@dataclass(frozen=True, repr=False)
class EigenResult(DataRecord):
    """Every mode of the vehicle at one speed.

    Attributes
    ----------
    speed : float
        [m/s]; nan for a model without rail data (its modes do not depend on it).
    modes : tuple of Mode
        One per conjugate pair (and one per real eigenvalue), sorted by descending real
        part: ``modes[0]`` is the least stable.
    eigenvalues : numpy.ndarray, shape (N,)
        Every eigenvalue of ``A`` [1/s], both members of each conjugate pair, sorted by
        descending real part, then descending imaginary part (empty when not given).

    Examples
    --------
    >>> from express.io import load_model
    >>> from express.numeric.statespace import vehicle_model
    >>> from express.analysis.stability.stability import eigen_analysis
    >>> car = vehicle_model(load_model("examples/conventional.toml"))
    >>> result = eigen_analysis(car, 30.0)
    >>> result.stable, len(result.modes) <= 2 * car.n
    (True, True)
    >>> sorted(result.rows()[0])
    ['damping_ratio', 'description', 'frequency_hz', 'imag', 'real']
    """

    speed: float
    modes: tuple[Mode, ...]
    eigenvalues: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=complex), repr=False, compare=False)

    @property
    def speed_kmh(self) -> float:
        """Speed [km/h] (nan for a model without rail data)."""
        return self.speed / KMH

    @property
    def max_real(self) -> float:
        """Largest real part [1/s]."""
        return max(mode.real for mode in self.modes)

    @property
    def threshold(self) -> float:
        """Real part [1/s] above which a mode counts as unstable (:func:`stability_threshold`)."""
        return stability_threshold([mode.eigenvalue for mode in self.modes])

    @property
    def stable(self) -> bool:
        """True when no mode grows: every real part at most :attr:`threshold` (a real part
        of rounding size, relative to the spectrum's scale, is not an instability)."""
        return self.max_real <= self.threshold

    def rows(self) -> list[dict[str, float | str]]:
        """One dict per mode, least stable first, for printing or CSV.

        Keys: ``real`` [1/s], ``imag`` [rad/s], ``frequency_hz`` [Hz],
        ``damping_ratio`` [-], ``description`` (:meth:`Mode.describe`).
        """
        return [
            {
                "real": mode.real,
                "imag": mode.imag,
                "frequency_hz": mode.frequency_hz,
                "damping_ratio": mode.damping_ratio,
                "description": mode.describe(),
            }
            for mode in self.modes
        ]

    def to_pandas(self):
        """The modes as a :class:`pandas.DataFrame`, units in the column names, mode
        numbers (1 = least stable) as the index."""
        import pandas as pd

        frame = pd.DataFrame(
            [{"Re [1/s]": m.real, "Im [rad/s]": m.imag, "f [Hz]": m.frequency_hz, "damping ratio [-]": m.damping_ratio,
              "mode": m.kind, "dominant DOFs": ", ".join(f"{d} {s:.0%}" for d, s in m.dominant[:3])}
             for m in self.modes],
            index=pd.RangeIndex(1, len(self.modes) + 1, name="mode number"),
        )
        where = (f"at {self.speed:.3f} m/s ({self.speed_kmh:.1f} km/h)" if self.speed == self.speed
                 else "(no rail data: independent of the speed)")
        frame.attrs["title"] = f"eigenvalues {where}"
        return frame

    def to_xarray(self):
        """The modes as an :class:`xarray.Dataset` over ``mode`` (1 = least stable):
        ``real`` [1/s], ``imag`` [rad/s], ``frequency`` [Hz], ``damping_ratio`` [1],
        ``kind`` and ``description``; the ``speed`` [m/s] as an attribute (nan without rail data)."""
        xr = xarray()
        modes = self.modes
        data = {
            "real": variable(np.array([m.real for m in modes], float), "mode", "1/s", "real part of the eigenvalue"),
            "imag": variable(np.array([m.imag for m in modes], float), "mode", "rad/s",
                             "imaginary part of the eigenvalue"),
            "frequency": variable(np.array([m.frequency_hz for m in modes], float), "mode", "Hz", "frequency"),
            "damping_ratio": variable(np.array([m.damping_ratio for m in modes], float), "mode", "1", "damping ratio"),
            "kind": variable(np.array([m.kind for m in modes], dtype=object), "mode", "", "mode name"),
            "description": variable(np.array([m.describe() for m in modes], dtype=object), "mode", "",
                                    "mode name and dominant DOFs"),
        }
        return xr.Dataset(data, coords={"mode": ("mode", np.arange(1, len(modes) + 1), {"long_name": "mode number"})},
                          attrs={"speed": self.speed, "speed_units": "m/s", "stable": int(self.stable)})

    def _summary(self) -> list[str]:
        where = (f"at {self.speed:.3f} m/s ({self.speed_kmh:.1f} km/h)" if self.speed == self.speed
                 else "(no rail data)")
        lines = [f"{len(self.modes)} modes {where}, {'stable' if self.stable else 'UNSTABLE'}"]
        lines += [f"{m.real:+.4g} {m.imag:+.4g}j 1/s, {m.frequency_hz:.3g} Hz: {m.describe()}"[:110]
                  for m in self.modes[:3]]
        return lines + (["..."] if len(self.modes) > 3 else [])

    def _repr_html_(self) -> str:
        """The table in a notebook (:meth:`to_pandas`)."""
        frame = self.to_pandas()
        return f"<p>{frame.attrs['title']}</p>" + frame.to_html(float_format=lambda x: f"{x:.4g}")

    def table(self) -> str:
        """The rows as aligned text (one line per mode)."""
        where = (f"at {self.speed:.3f} m/s ({self.speed_kmh:.1f} km/h)" if self.speed == self.speed
                 else "(no rail data: independent of the speed)")
        lines = [f"eigenvalues {where}",
                 f"{'Re [1/s]':>12} {'Im [rad/s]':>12} {'f [Hz]':>9} {'zeta':>8}  mode"]
        for row in self.rows():
            lines.append(
                f"{row['real']:12.4f} {row['imag']:12.4f} {row['frequency_hz']:9.3f} "
                f"{row['damping_ratio']:8.4f}  {row['description']}"
            )
        return "\n".join(lines)


# Body roles for the labels
# ---------------------------------------------------------------------------------------


def _roles(vehicle: VehicleModel) -> Topology:
    """The role of every body (:func:`express.model.topology.classify_bodies`, through
    :attr:`VehicleModel.facts <express.numeric.statespace.VehicleModel.facts>`)."""
    return vehicle.facts.topology


def _dof_lengths(vehicle: VehicleModel) -> np.ndarray:
    """``l_i`` of :attr:`Mode.dominant`: 1 for translations, the radius of gyration
    ``sqrt(I / m)`` [m] for rotations (:data:`REFERENCE_LENGTH` where unknown)."""
    gyration = vehicle.facts.gyration
    lengths = np.ones(vehicle.n)
    for i, dof in enumerate(vehicle.dofs):
        if dof.partition(".")[2] in ("rx", "ry", "rz"):
            lengths[i] = gyration.get(dof, REFERENCE_LENGTH)
        elif dof in gyration:  # a flexible body's mode: 1/sqrt(m) (express.numeric.facts)
            lengths[i] = gyration[dof]
    return lengths


@dataclass(frozen=True)
class _Layout:
    """What :func:`modes_of` needs of a vehicle besides its matrices, built once per vehicle."""

    groups: DofGroups
    naming: RoleGroups | None  # None without rail data
    lengths: np.ndarray
    mass: RowProduct
    dominant_dofs: np.ndarray  # the DOFs with mass, as an object array


_last_layout: tuple[weakref.ref, _Layout] | None = None


def _layout(vehicle: VehicleModel) -> _Layout:
    """The vehicle's :class:`_Layout`, kept for the last vehicle asked (a critical speed
    asks for the modes of one vehicle at many speeds)."""
    global _last_layout
    last = _last_layout
    if last is not None and last[0]() is vehicle:
        return last[1]
    groups = DofGroups.of(vehicle.dofs)
    rail = vehicle.layout is not None and bool(vehicle.wheelsets)
    layout = _Layout(groups, RoleGroups(groups, _roles(vehicle)) if rail else None, _dof_lengths(vehicle),
                     RowProduct(vehicle.mass), np.array([groups.dofs[i] for i in groups.rows], dtype=object))
    _last_layout = (weakref.ref(vehicle), layout)
    return layout


def modes_of(
    vehicle: VehicleModel, eigenvalues: np.ndarray, eigenvectors: np.ndarray, *, limit: int | None = None,
    speed: float | None = None,
) -> tuple[Mode, ...]:
    """Build the :class:`Mode` records of eigenpairs of ``A`` (state ``[q; q']``).

    Parameters
    ----------
    vehicle : VehicleModel
        Gives the DOF names, the matrices and the body roles for the names.
    eigenvalues : numpy.ndarray, shape (N,)
    eigenvectors : numpy.ndarray, shape (N, N)
        Columns are the eigenvectors, as from :func:`numpy.linalg.eig`.
    limit : int, optional
        Build only the ``limit`` least stable modes.
    speed : float, optional
        The speed [m/s] of ``A``: the creep damping and the wheelsets' kinematic
        frequency for the names (:mod:`express.analysis.modes.mode_names`); the model's own
        speed by default.

    Returns
    -------
    tuple of Mode
        One per conjugate pair (the member with ``Im >= 0``) and per real eigenvalue,
        sorted by descending real part.

    Notes
    -----
    The modes are described together, :data:`_CHUNK` at a time, as arrays over DOFs x
    modes (:mod:`express.analysis.modes.mode_energies`).
    """
    layout = _layout(vehicle)
    speed = vehicle.speed if speed is None else speed
    rail = layout.naming is not None
    damping = vehicle.damping(speed) if rail and speed == speed and speed > 0 else vehicle.damping_base
    kinematic = max((kinematic_frequency(speed, w.conicity, w.r0, w.b) for w in vehicle.wheelsets), default=None)
    keep = np.flatnonzero(eigenvalues.imag >= 0.0)
    order = keep[np.lexsort((-eigenvalues.imag[keep], -eigenvalues.real[keep]))]
    if limit is not None:
        order = order[:limit]
    modes: list[Mode] = []
    for start in range(0, order.size, _CHUNK):
        chosen = order[start : start + _CHUNK]
        modes += _modes(vehicle, layout, eigenvalues[chosen], eigenvectors[: vehicle.n, chosen], damping, kinematic)
    return tuple(modes)


#: Modes described together (arrays of DOFs x modes: memory grows with it).
_CHUNK = 256


def _modes(vehicle: VehicleModel, layout: _Layout, values: np.ndarray, vectors: np.ndarray, damping: np.ndarray,
           kinematic: float | None) -> list[Mode]:
    """:class:`Mode` records of the eigenvalues ``values`` (m,) with the displacement
    parts ``vectors`` (n, m) of their eigenvectors."""
    groups = layout.groups
    eigenvalues = [complex(value) for value in values]
    frequency = [lam.imag / (2.0 * np.pi) for lam in eigenvalues]
    zeta = [float(-lam.real / abs(lam)) if abs(lam) > 0 else 0.0 for lam in eigenvalues]
    by_mode = participation(vectors, groups, layout.lengths)[:, groups.rows]  # (m, k)
    displacement = np.ascontiguousarray(by_mode.T)
    kinetic = kinetic_shares(vectors, groups, layout.mass)
    shares = series_shares(vectors, groups, damping)
    series = [series_ranking(shares[:, k], groups.elements) for k in range(len(eigenvalues))]
    if layout.naming is not None:
        kinds = mode_names(kinetic, series, roll_centres(vectors, groups), displacement, layout.naming,
                           np.array(frequency), np.array(zeta), kinematic)
    else:
        kinds = generic_names(kinetic, series, groups, np.array(frequency))
    dominant = top_columns(by_mode, DOMINANT_COUNT)
    dominant_dofs = layout.dominant_dofs[dominant].tolist()
    dominant_shares = np.take_along_axis(by_mode, dominant, axis=1).tolist()
    by_body = group_sums(displacement, groups.body_of, len(groups.bodies)).T
    return [
        Mode(
            eigenvalue=lam,
            frequency_hz=float(frequency[k]),
            damping_ratio=zeta[k],
            dominant=tuple(zip(dominant_dofs[k], dominant_shares[k], strict=True)),
            kind=kinds[k],
            series=series[k],
            _bodies=(groups.bodies, by_body[k]),
        )
        for k, lam in enumerate(eigenvalues)
    ]
