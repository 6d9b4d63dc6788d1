"""Published power spectral densities of track irregularity, with exact band integrals.

This module owns the spectra a random irregularity is drawn from
(:class:`~express.rail.track.irregularity.SpectrumIrregularity`): the US FRA alignment
spectrum of track classes 5 and 6 and the ORE B176 / ERRI alignment spectrum (low and
high level), and the registry that gives them the names used in track files.

Every spectrum is a :class:`TrackSpectrum`: a one-sided PSD ``S(Omega)``
[m^2/(rad/m)] in the wavenumber ``Omega`` [rad/m] >= 0, so that the variance of the
irregularity over a band is the integral of ``S`` over that band, and that integral in
closed form (:meth:`TrackSpectrum.variance`).

Adding a spectrum (another component, e.g. vertical profile, cross-level or gauge, or
other classes, e.g. AAR): write a frozen dataclass deriving from :class:`TrackSpectrum`
with a ``name`` field, its :attr:`~TrackSpectrum.component`, :meth:`~TrackSpectrum.psd`
and the antiderivative :meth:`~TrackSpectrum.primitive`; then
:func:`register_spectrum` its instances under the names a track file uses.
:func:`get_spectrum` looks names up per component (``"alignment"`` by default).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike

from ._common import FloatArray

__all__ = [
    "COMPONENTS",
    "ERRI_HIGH",
    "ERRI_LOW",
    "FRA_CLASS_5",
    "FRA_CLASS_6",
    "SPECTRA",
    "SPECTRA_BY_COMPONENT",
    "AlignmentSpectrum",
    "ERRIAlignmentSpectrum",
    "FRAAlignmentSpectrum",
    "TrackSpectrum",
    "get_spectrum",
    "register_spectrum",
]

#: Irregularity components a spectrum can describe. Only ``"alignment"`` (lateral,
#: ``yR``) is used by the track today.
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
    return name.strip().lower().replace("-", "_").replace(" ", "_")


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
    ValueError
        If the component is unknown or the name is already taken by another spectrum.
    """
    if spectrum.component not in SPECTRA_BY_COMPONENT:
        raise ValueError(f"unknown component {spectrum.component!r} (known: {', '.join(COMPONENTS)})")
    table = SPECTRA_BY_COMPONENT[spectrum.component]
    key = _key(key)
    if table.get(key, spectrum) is not spectrum:
        raise ValueError(f"{spectrum.component} spectrum {key!r} is already registered")
    table[key] = spectrum


for _name, _spectrum in (("fra5", FRA_CLASS_5), ("fra6", FRA_CLASS_6),
                         ("erri_low", ERRI_LOW), ("erri_high", ERRI_HIGH)):
    register_spectrum(_name, _spectrum)


def get_spectrum(name: str, component: str = "alignment") -> TrackSpectrum:
    """Return a registered spectrum by name (case, spaces and ``-``/``_`` ignored).

    Parameters
    ----------
    name : str
        E.g. ``"fra5"``, ``"ERRI-high"``.
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
