"""Published power spectral densities of track irregularity, with exact band integrals.

This module owns the spectra a random irregularity is drawn from
(:class:`~express.rail.track.irregularity.SpectrumIrregularity`): the US FRA alignment
spectrum of track classes 5 and 6 and the ORE B176 / ERRI alignment spectrum (low and
high level), and the registry that gives them the names used in track files.

Every spectrum is a :class:`TrackSpectrum`: a one-sided PSD ``S(Omega)``
[m^2/(rad/m)] in the wavenumber ``Omega`` [rad/m] >= 0, so that the variance of the
irregularity over a band is the integral of ``S`` over that band, and that integral in
closed form (:meth:`TrackSpectrum.variance`).

Vertical profile, cross-level (rail height difference) and gauge spectra, US classes
1-6 as FRA (:data:`FRA_CLASSES`) or AAR (:data:`AAR_CLASSES`) classes (vertical,
alignment, and one form for cross level and gauge), ERRI / ORE B176 low
and high (:data:`ERRI_LEVELS`: all four components) and user tables
(:class:`~express.rail.track.tabulated_spectra.TabulatedSpectrum`) follow the same conventions (end of the module;
``docs/ride.md``); seeded realisations of any of them are the cosine sums of
:class:`~express.rail.track.irregularity.Harmonics`.

Adding a spectrum (another component or other classes): write a frozen dataclass deriving from :class:`TrackSpectrum`
with a ``name`` field, its :attr:`~TrackSpectrum.component`, :meth:`~TrackSpectrum.psd`
and the antiderivative :meth:`~TrackSpectrum.primitive`; then
:func:`register_spectrum` its instances under the names a track file uses.
:func:`get_spectrum` looks names up per component (``"alignment"`` by default).
"""

from __future__ import annotations

import re
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike

from express.base.diagnostics import ArgumentError
from express.rail.track._common import FloatArray

__all__ = [
    "AAR_CLASSES",
    "COMPONENTS",
    "ERRI_HIGH",
    "ERRI_LEVELS",
    "ERRI_LOW",
    "FRA_A_A",
    "FRA_A_V",
    "FRA_CLASSES",
    "FRA_CLASS_5",
    "FRA_CLASS_6",
    "FRA_OMEGA_S",
    "SPECTRA",
    "SPECTRA_BY_COMPONENT",
    "AlignmentSpectrum",
    "ERRIAlignmentSpectrum",
    "ERRICrossLevelSpectrum",
    "ERRIGaugeSpectrum",
    "ERRIVerticalSpectrum",
    "FRAAlignmentSpectrum",
    "FRACrossLevelSpectrum",
    "FRAGaugeSpectrum",
    "FRAVerticalSpectrum",
    "TrackSpectrum",
    "get_spectrum",
    "register_spectrum",
]

#: Irregularity components a spectrum can describe, each a table of a track file
#: (``irregularity`` for the alignment ``yR``; ``docs/track.md``, "Random components").
COMPONENTS = ("alignment", "vertical", "cross_level", "gauge")


class TrackSpectrum(ABC):
    """One-sided PSD of one irregularity component, with its exact band integral.

    Subclasses are frozen dataclasses with a ``name`` field (a label for messages and
    plots) and set the class attribute :attr:`component`.
    """

    #: Which irregularity the spectrum describes, one of :data:`COMPONENTS`.
    component: ClassVar[str] = "alignment"
    name: str

    @abstractmethod
    def psd(self, omega: ArrayLike) -> FloatArray:
        """One-sided PSD [m^2/(rad/m)] at wavenumbers ``omega`` [rad/m]."""

    @abstractmethod
    def primitive(self, omega: FloatArray) -> FloatArray:
        """An antiderivative of :meth:`psd` in ``omega`` [m^2] (for :meth:`variance`)."""

    def variance(self, omega_min: ArrayLike, omega_max: ArrayLike) -> FloatArray | float:
        """Integral of the PSD from ``omega_min`` to ``omega_max`` [rad/m], in m^2, exact.

        Parameters
        ----------
        omega_min, omega_max : array_like
            Band edges [rad/m], broadcast together; a float for scalar edges.
        """
        lo, hi = np.asarray(omega_min, float), np.asarray(omega_max, float)
        out = self.primitive(hi) - self.primitive(lo)
        return float(out) if out.ndim == 0 else out


@dataclass(frozen=True)
class FRAAlignmentSpectrum(TrackSpectrum):
    """US FRA alignment spectrum of one track class.

    ``S(Omega) = k A_a Omega_c^2 / ((Omega^2 + Omega_c^2) Omega^2)`` [m^2/(rad/m)],
    one-sided in the wavenumber ``Omega`` [rad/m] > 0.

    Parameters
    ----------
    name : str
        Label.
    A_a : float
        Roughness coefficient [m^2 rad/m] (published in cm^2 rad/m: multiply by 1e-4).
    omega_c : float
        Cut-off wavenumber [rad/m]; 0.8245.
    k : float
        Scale factor, 0.25 in the published form (dimensionless).

    Notes
    -----
    Constants (classes 5 and 6, see :data:`FRA_CLASS_5`, :data:`FRA_CLASS_6`): the
    table of A_a, Omega_c = 0.8245 rad/m and k = 0.25 usually quoted from Garg &
    Dukkipati, *Dynamics of Railway Vehicle Systems* (Academic Press, 1984), derived
    from the FRA measurements of Hamid et al., *Analytical Descriptions of Track
    Geometry Variations*, FRA report DOT/FRA/ORD-83/03 (1983): A_a = 0.0762 (class 5)
    and 0.0339 (class 6) cm^2 rad/m. The same table (with the 1e-4 conversion to
    m^2 rad/m) appears in public simulation code; the primary report itself was not
    available to check. S diverges as Omega -> 0, so a band must exclude Omega = 0.
    """

    component: ClassVar[str] = "alignment"
    name: str
    A_a: float
    omega_c: float = 0.8245
    k: float = 0.25

    def psd(self, omega: ArrayLike) -> FloatArray:
        """One-sided PSD [m^2/(rad/m)] at wavenumbers ``omega`` [rad/m] > 0."""
        w = np.asarray(omega, dtype=float)
        return self.k * self.A_a * self.omega_c**2 / ((w**2 + self.omega_c**2) * w**2)

    def primitive(self, omega: FloatArray) -> FloatArray:
        """Antiderivative [m^2]: S = k A (1/w^2 - 1/(w^2 + wc^2)) integrates to this."""
        w = np.asarray(omega, dtype=float)
        return self.k * self.A_a * (-1.0 / w - np.arctan(w / self.omega_c) / self.omega_c)


@dataclass(frozen=True)
class ERRIAlignmentSpectrum(TrackSpectrum):
    """ORE B176 / ERRI alignment spectrum.

    ``S(Omega) = A Omega_c^2 / ((Omega^2 + Omega_r^2) (Omega^2 + Omega_c^2))``
    [m^2/(rad/m)], one-sided in ``Omega`` [rad/m] >= 0.

    Parameters
    ----------
    name : str
        Label.
    A : float
        Level [m rad]: 2.119e-7 (low), 6.125e-7 (high).
    omega_c : float
        0.8246 rad/m.
    omega_r : float
        0.0206 rad/m.

    Notes
    -----
    ORE B176 (ERRI B176, report RP1, 1989), as used e.g. by GENSYS and SIMPACK. The
    "high" level was checked against the GENSYS manual (program TRC_IPSD, "ORE B176
    high level" lateral PSD tabulated in m^2/(1/m) = 2 pi S(Omega)): this formula gives
    2.319e-4 at 0.02 1/m and 6.161e-6 at 0.1 1/m against the tabulated 2.3194e-4 and
    6.1608e-6.
    """

    component: ClassVar[str] = "alignment"
    name: str
    A: float
    omega_c: float = 0.8246
    omega_r: float = 0.0206

    def psd(self, omega: ArrayLike) -> FloatArray:
        """One-sided PSD [m^2/(rad/m)] at wavenumbers ``omega`` [rad/m] >= 0."""
        w = np.asarray(omega, dtype=float)
        wc, wr = self.omega_c, self.omega_r
        return self.A * wc**2 / ((w**2 + wr**2) * (w**2 + wc**2))

    def primitive(self, omega: FloatArray) -> FloatArray:
        """Antiderivative [m^2], from the partial fractions of S in w^2."""
        w = np.asarray(omega, dtype=float)
        wc, wr = self.omega_c, self.omega_r
        c = self.A * wc**2 / (wc**2 - wr**2)
        return c * (np.arctan(w / wr) / wr - np.arctan(w / wc) / wc)


#: Any alignment spectrum (kept for code written against the single-module track).
AlignmentSpectrum = TrackSpectrum

#: FRA class 5, alignment: A_a = 0.0762 cm^2 rad/m = 7.62e-6 m^2 rad/m.
FRA_CLASS_5 = FRAAlignmentSpectrum("FRA class 5 alignment", A_a=0.0762e-4)
#: FRA class 6, alignment: A_a = 0.0339 cm^2 rad/m = 3.39e-6 m^2 rad/m.
FRA_CLASS_6 = FRAAlignmentSpectrum("FRA class 6 alignment", A_a=0.0339e-4)
#: ORE B176 / ERRI low level: A = 2.119e-7 m rad.
ERRI_LOW = ERRIAlignmentSpectrum("ERRI B176 low", A=2.119e-7)
#: ORE B176 / ERRI high level: A = 6.125e-7 m rad.
ERRI_HIGH = ERRIAlignmentSpectrum("ERRI B176 high", A=6.125e-7)

#: Spectra by component, then by the names accepted in track files.
SPECTRA_BY_COMPONENT: dict[str, dict[str, TrackSpectrum]] = {component: {} for component in COMPONENTS}
#: Alignment spectra by the names accepted in track files (``fra5``, ``erri_low``, ...).
SPECTRA: dict[str, TrackSpectrum] = SPECTRA_BY_COMPONENT["alignment"]


def _key(name: str) -> str:
    """``"FRA-5"``, ``"fra 5"``, ``"fra5"`` -> ``"fra5"``; ``"ERRI-high"`` -> ``"erri_high"``."""
    key = name.strip().lower().replace("-", "_").replace(" ", "_")
    return re.sub(r"(?<=[a-z])_(?=[0-9])", "", key)


def register_spectrum(key: str, spectrum: TrackSpectrum) -> None:
    """Make ``spectrum`` available to :func:`get_spectrum` (and track files) as ``key``.

    Parameters
    ----------
    key : str
        Name in files, normalised like :func:`get_spectrum` does (lower case, ``_``).
    spectrum : TrackSpectrum
        Filed under its :attr:`~TrackSpectrum.component`.

    Raises
    ------
    ArgumentError
        If the component is unknown or the name is already taken by another spectrum.
    """
    if spectrum.component not in SPECTRA_BY_COMPONENT:
        raise ArgumentError(f"unknown component {spectrum.component!r} (known: {', '.join(COMPONENTS)})")
    table = SPECTRA_BY_COMPONENT[spectrum.component]
    key = _key(key)
    if table.get(key, spectrum) is not spectrum:
        raise ArgumentError(f"{spectrum.component} spectrum {key!r} is already registered")
    table[key] = spectrum


for _name, _spectrum in (("fra5", FRA_CLASS_5), ("fra6", FRA_CLASS_6),
                         ("erri_low", ERRI_LOW), ("erri_high", ERRI_HIGH)):
    register_spectrum(_name, _spectrum)


def get_spectrum(name: str, component: str = "alignment") -> TrackSpectrum:
    """Return a registered spectrum by name (case, spaces and ``-``/``_`` ignored).

    Parameters
    ----------
    name : str
        E.g. ``"fra5"``, ``"FRA-5"``, ``"ERRI-high"``.
    component : str
        One of :data:`COMPONENTS`; default ``"alignment"``.

    Raises
    ------
    KeyError
        If the name is unknown; the message lists the known names.
    """
    table = SPECTRA_BY_COMPONENT.get(component, {})
    key = _key(name)
    if key not in table:
        known = ", ".join(table) or "none"
        raise KeyError(f"unknown spectrum {name!r} (known {component} spectra: {known})")
    return table[key]


# ---------------------------------------------------------------------------------------
# Vertical, cross-level and gauge spectra; user tables (issue 14, ride)
# ---------------------------------------------------------------------------------------
#
# Conventions as above: one-sided in Omega [rad/m], variance = integral of S. Cross level
# is the height difference between the rails [m] (the quantity of the cant, see
# docs/track.md), not an angle; gauge is the gauge deviation [m].


def _fra_primitive(k_a: float, omega_c: float, w: FloatArray) -> FloatArray:
    # k A wc^2 / ((w^2 + wc^2) w^2) = k A (1/w^2 - 1/(w^2 + wc^2))
    return k_a * (-1.0 / w - np.arctan(w / omega_c) / omega_c)


def _pole_sum_primitive(scale: float, poles: tuple[float, ...], numerator_x: bool, w: FloatArray) -> FloatArray:
    """Antiderivative of ``scale * x^m / prod_i (x + p_i^2)`` in w, ``x = w^2``, m = 1 or 0.

    Partial fractions in x (distinct ``p_i``): ``sum_i r_i / (x + p_i^2)`` with
    ``r_i = (-p_i^2)^m / prod_(j != i) (p_j^2 - p_i^2)``, and
    ``integral dw / (w^2 + p^2) = atan(w / p) / p``.
    """
    out = np.zeros_like(w)
    for i, p in enumerate(poles):
        residue = (-(p**2)) if numerator_x else 1.0
        for j, q in enumerate(poles):
            if j != i:
                residue /= q**2 - p**2
        out = out + residue * np.arctan(w / p) / p
    return scale * out


@dataclass(frozen=True)
class FRAVerticalSpectrum(TrackSpectrum):
    """US FRA vertical profile (surface) spectrum of one track class.

    ``S(Omega) = k A_v Omega_c^2 / ((Omega^2 + Omega_c^2) Omega^2)`` [m^2/(rad/m)], the
    form of :class:`FRAAlignmentSpectrum`, with ``k = 0.25``, ``Omega_c = 0.8245`` rad/m
    and A_v [m^2 rad/m] = (1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339) x 1e-4 for
    classes 1 to 6 (published in cm^2 rad/m; same sources as the alignment spectrum;
    the A_v column also appears in public simulation code). Diverges at Omega -> 0.
    """

    component: ClassVar[str] = "vertical"
    name: str
    A_v: float
    omega_c: float = 0.8245
    k: float = 0.25

    def psd(self, omega: ArrayLike) -> FloatArray:
        """One-sided PSD [m^2/(rad/m)] at wavenumbers ``omega`` [rad/m] > 0."""
        w = np.asarray(omega, dtype=float)
        return self.k * self.A_v * self.omega_c**2 / ((w**2 + self.omega_c**2) * w**2)

    def primitive(self, omega: FloatArray) -> FloatArray:
        """Antiderivative [m^2]."""
        return _fra_primitive(self.k * self.A_v, self.omega_c, np.asarray(omega, dtype=float))


@dataclass(frozen=True)
class FRACrossLevelSpectrum(TrackSpectrum):
    """US FRA cross-level spectrum of one track class (rail height difference).

    ``S(Omega) = 4 k A_v Omega_c^2 / ((Omega^2 + Omega_c^2) (Omega^2 + Omega_s^2))``
    [m^2/(rad/m)], finite at Omega = 0, with the class's A_v (as in
    :class:`FRAVerticalSpectrum`), ``k = 0.25``, ``Omega_c = 0.8245`` rad/m and
    ``Omega_s`` [rad/m] = 0.6046, 0.9308, 0.8520, 1.1312, 0.8209, 0.4380 for classes
    1 to 6.

    Notes
    -----
    Form and Omega_s as tabulated with the other FRA constants in Garg & Dukkipati
    (1984) after Hamid et al. (1983); the Omega_s column could not be checked against a
    second public source here. The form is that of the ERRI / DB cross level
    (:class:`ERRICrossLevelSpectrum`) without its long-wavelength roll-off.
    """

    component: ClassVar[str] = "cross_level"
    name: str
    A_v: float
    omega_s: float
    omega_c: float = 0.8245
    k: float = 0.25

    def __post_init__(self) -> None:
        if not (self.omega_s > 0 and self.omega_c > 0 and self.omega_s != self.omega_c):
            raise ArgumentError(f"{self.name}: need omega_s, omega_c > 0 and distinct")

    def psd(self, omega: ArrayLike) -> FloatArray:
        """One-sided PSD [m^2/(rad/m)] at wavenumbers ``omega`` [rad/m] >= 0."""
        w = np.asarray(omega, dtype=float)
        return 4 * self.k * self.A_v * self.omega_c**2 / ((w**2 + self.omega_c**2) * (w**2 + self.omega_s**2))

    def primitive(self, omega: FloatArray) -> FloatArray:
        """Antiderivative [m^2], by partial fractions in Omega^2."""
        scale = 4 * self.k * self.A_v * self.omega_c**2
        return _pole_sum_primitive(scale, (self.omega_c, self.omega_s), False, np.asarray(omega, dtype=float))


@dataclass(frozen=True)
class FRAGaugeSpectrum(FRACrossLevelSpectrum):
    """US FRA gauge spectrum of one track class [m^2/(rad/m)]: the cross-level form and
    constants of :class:`FRACrossLevelSpectrum`, for the gauge deviation [m].

    Notes
    -----
    The US class spectra are tabulated for "cross level and gauge" together, one PSD
    ``4 k A_v Omega_c^2 / ((Omega^2 + Omega_c^2)(Omega^2 + Omega_s^2))`` for both (Zhai,
    *Vehicle-Track Coupled Dynamics*, Springer 2020, the US track spectra; the same in
    public implementations of those spectra, e.g. a MATLAB script of the classes 5 and 6
    labelled "cross level and gauge irregularity" with A_v = 0.2095 and 0.0339 cm^2 rad/m,
    Omega_s = 0.8209 and 0.4380 rad/m, the constants held here).  Hamid et al. (1983)
    fitted gauge separately; their own gauge constants were not found in public material.
    """

    component: ClassVar[str] = "gauge"


@dataclass(frozen=True)
class ERRIVerticalSpectrum(ERRIAlignmentSpectrum):
    """ORE B176 / ERRI vertical profile spectrum: the form of
    :class:`ERRIAlignmentSpectrum` with ``A_v`` = 4.032e-7 (low) or 1.080e-6 (high)
    m rad (ORE B176; the same constants in several public simulation codes).
    """

    component: ClassVar[str] = "vertical"


@dataclass(frozen=True)
class ERRICrossLevelSpectrum(TrackSpectrum):
    """ERRI / DB ("German") cross-level spectrum, as a rail height difference [m].

    ``S(Omega) = 4 A_v Omega_c^2 Omega^2 / ((Omega^2 + Omega_r^2) (Omega^2 + Omega_c^2)
    (Omega^2 + Omega_s^2))`` [m^2/(rad/m)], with the vertical level A_v and
    Omega_c = 0.8246, Omega_r = 0.0206, Omega_s = 0.4380 rad/m.

    Notes
    -----
    Published (DB high-speed spectra that extend ORE B176 to cross level and gauge) as
    the PSD of the cross-level *angle*, ``A_v b^-2 Omega_c^2 Omega^2 / (...)``
    [1/(rad/m)], b = 0.75 m the half distance between the rail centres; the height
    difference ``2 b x angle`` has ``(2 b)^2`` times that PSD, the factor 4 here (and
    b drops out).
    """

    component: ClassVar[str] = "cross_level"
    name: str
    A: float
    omega_c: float = 0.8246
    omega_r: float = 0.0206
    omega_s: float = 0.4380
    factor: ClassVar[float] = 4.0

    def psd(self, omega: ArrayLike) -> FloatArray:
        """One-sided PSD [m^2/(rad/m)] at wavenumbers ``omega`` [rad/m] >= 0."""
        w2 = np.asarray(omega, dtype=float) ** 2
        den = (w2 + self.omega_r**2) * (w2 + self.omega_c**2) * (w2 + self.omega_s**2)
        return self.factor * self.A * self.omega_c**2 * w2 / den

    def primitive(self, omega: FloatArray) -> FloatArray:
        """Antiderivative [m^2], by partial fractions in Omega^2."""
        scale = self.factor * self.A * self.omega_c**2
        poles = (self.omega_r, self.omega_c, self.omega_s)
        return _pole_sum_primitive(scale, poles, True, np.asarray(omega, dtype=float))


@dataclass(frozen=True)
class ERRIGaugeSpectrum(ERRICrossLevelSpectrum):
    """ERRI / DB ("German") gauge spectrum [m^2/(rad/m)]:
    ``A_g Omega_c^2 Omega^2 / ((Omega^2 + Omega_r^2) (Omega^2 + Omega_c^2) (Omega^2 +
    Omega_s^2))``, A_g = 5.32e-8 (low) or 1.032e-7 (high) m rad (constants as in one
    public simulation code; not checked against a second source).
    """

    component: ClassVar[str] = "gauge"
    factor: ClassVar[float] = 1.0


#: FRA roughness coefficients per class 1..6 [m^2 rad/m] (published in cm^2 rad/m).
FRA_A_V = (1.2107e-4, 1.0181e-4, 0.6816e-4, 0.5376e-4, 0.2095e-4, 0.0339e-4)
FRA_A_A = (3.3634e-4, 1.2107e-4, 0.4128e-4, 0.3027e-4, 0.0762e-4, 0.0339e-4)
#: FRA cross-level corner wavenumbers Omega_s per class 1..6 [rad/m].
FRA_OMEGA_S = (0.6046, 0.9308, 0.8520, 1.1312, 0.8209, 0.4380)

#: FRA spectra of classes 1..6 by component (alignment classes 5 and 6 are FRA_CLASS_5, _6).
FRA_CLASSES: dict[str, tuple[TrackSpectrum, ...]] = {
    "vertical": tuple(FRAVerticalSpectrum(f"FRA class {c} vertical", A_v=a) for c, a in enumerate(FRA_A_V, 1)),
    "alignment": (*(FRAAlignmentSpectrum(f"FRA class {c} alignment", A_a=a) for c, a in enumerate(FRA_A_A[:4], 1)),
                  FRA_CLASS_5, FRA_CLASS_6),
    "cross_level": tuple(FRACrossLevelSpectrum(f"FRA class {c} cross level", A_v=a, omega_s=s)
                         for c, (a, s) in enumerate(zip(FRA_A_V, FRA_OMEGA_S, strict=True), 1)),
    "gauge": tuple(FRAGaugeSpectrum(f"FRA class {c} gauge", A_v=a, omega_s=s)
                   for c, (a, s) in enumerate(zip(FRA_A_V, FRA_OMEGA_S, strict=True), 1)),
}
#: The same six US classes under the name AAR (see :data:`AAR_CLASSES`).
AAR_CLASSES: dict[str, tuple[TrackSpectrum, ...]] = {
    "vertical": tuple(FRAVerticalSpectrum(f"AAR class {c} vertical", A_v=a) for c, a in enumerate(FRA_A_V, 1)),
    "alignment": tuple(FRAAlignmentSpectrum(f"AAR class {c} alignment", A_a=a) for c, a in enumerate(FRA_A_A, 1)),
    "cross_level": tuple(FRACrossLevelSpectrum(f"AAR class {c} cross level", A_v=a, omega_s=s)
                         for c, (a, s) in enumerate(zip(FRA_A_V, FRA_OMEGA_S, strict=True), 1)),
    "gauge": tuple(FRAGaugeSpectrum(f"AAR class {c} gauge", A_v=a, omega_s=s)
                   for c, (a, s) in enumerate(zip(FRA_A_V, FRA_OMEGA_S, strict=True), 1)),
}
"""The US six-class spectra as "AAR classes": the constants of :data:`FRA_CLASSES`.

The spectra of US track classes 1-6 (FRA track safety classes; measurements analysed
by Hamid et al., DOT/FRA/ORD-83/03, 1983) are tabulated once, with A_v, A_a,
Omega_s, Omega_c and k, in Garg & Dukkipati (1984); later work quotes that one table
as the "FRA" or the "AAR" (Association of American Railroads) class spectra. No
separate AAR constants were found, so ``AAR-k`` is the FRA class k spectrum under the
other name (its own objects, labelled "AAR class k ...", for messages and plots).
"""
#: ERRI / ORE B176 (and DB) spectra by component and level.
ERRI_LEVELS: dict[str, dict[str, TrackSpectrum]] = {
    "alignment": {"low": ERRI_LOW, "high": ERRI_HIGH},
    "vertical": {"low": ERRIVerticalSpectrum("ERRI B176 low vertical", A=4.032e-7),
                 "high": ERRIVerticalSpectrum("ERRI B176 high vertical", A=1.080e-6)},
    "cross_level": {"low": ERRICrossLevelSpectrum("ERRI/DB low cross level", A=4.032e-7),
                    "high": ERRICrossLevelSpectrum("ERRI/DB high cross level", A=1.080e-6)},
    "gauge": {"low": ERRIGaugeSpectrum("ERRI/DB low gauge", A=5.32e-8),
              "high": ERRIGaugeSpectrum("ERRI/DB high gauge", A=1.032e-7)},
}

# Every component's classes get registry names (alignment's ERRI levels and FRA classes 5
# and 6 are registered above under the same names).
_new: TrackSpectrum
for _component in ("alignment", "vertical", "cross_level", "gauge"):
    for _level, _new in ERRI_LEVELS[_component].items():
        register_spectrum(f"erri_{_level}", _new)
    for _class, _new in enumerate(FRA_CLASSES.get(_component, ()), 1):
        register_spectrum(f"fra{_class}", _new)
    for _class, _new in enumerate(AAR_CLASSES.get(_component, ()), 1):
        register_spectrum(f"aar{_class}", _new)
