"""Track geometry and lateral track irregularity, as data.

This module owns the description of the track a vehicle runs on:

* the **layout**: a list of segments (:class:`Straight`, :class:`Transition`,
  :class:`Curve`) and the functions of the distance ``s`` along the track that the rail
  modules need: signed curvature ``rho(s)``, its rate, signed cant ``S(s)``, its rate
  (:class:`Track`);
* the **lateral irregularity** ``yR(s)`` (:class:`NoIrregularity`,
  :class:`SinusoidIrregularity`, :class:`ProfileIrregularity` read from a CSV file,
  :class:`SpectrumIrregularity` drawn from a published alignment spectrum);
* the **exact plane geometry** of the centreline (heading, ``(X, Y)``, offset of the
  track ahead of a point from the tangent there), against which the small-curvature
  approximations used by the vehicle model are checked;
* **track files** in TOML (:func:`load_track`, :func:`track_from_dict`), with errors that
  name the file, line and item (:class:`TrackError`);
* the paper's test curve (:func:`paper_curve`).

Conventions (``docs/track.md``, ``/work/shared/design/rail.md``): x forward, y left,
z up; distances in metres from the start of the track. The signed curvature ``rho`` is
positive for a curve to the LEFT; the signed cant ``S`` (rail height difference, metres)
is positive when the track is rolled toward the centre of a left curve, so a normally
canted right curve has ``rho < 0`` and ``S < 0``. Before the start (``s < 0``) and after
the end (``s >= length``) the track is straight with no cant. Curvature, cant and their
rates are right-continuous: at a joint they take the value of the segment that starts
there.

Nothing here evaluates text as code; TOML is parsed with :mod:`tomllib` (``tomli`` on
Python 3.10).
"""

from __future__ import annotations

import math
import re
from abc import ABC, abstractmethod
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]

__all__ = [
    "Straight",
    "Transition",
    "Curve",
    "Segment",
    "Track",
    "Irregularity",
    "NoIrregularity",
    "SinusoidIrregularity",
    "ProfileIrregularity",
    "SpectrumIrregularity",
    "FRAAlignmentSpectrum",
    "ERRIAlignmentSpectrum",
    "FRA_CLASS_5",
    "FRA_CLASS_6",
    "ERRI_LOW",
    "ERRI_HIGH",
    "SPECTRA",
    "get_spectrum",
    "AlignmentSpectrum",
    "TRANSITION_SHAPES",
    "DIRECTIONS",
    "UNITS",
    "TrackError",
    "paper_curve",
    "read_profile_csv",
    "load_track",
    "track_from_dict",
]

FloatArray = NDArray[np.float64]

#: Transition shapes: ``"linear"`` (clothoid: curvature and cant linear in s) and
#: ``"sine"`` (half-wave sine ramp, ``(1 - cos(pi s / L)) / 2``).
TRANSITION_SHAPES = ("linear", "sine")
#: Curve directions.
DIRECTIONS = ("left", "right")

_CONST, _LINEAR, _SINE = 0, 1, 2
_SHAPE_CODE = {"linear": _LINEAR, "sine": _SINE}


def _is_number(x: Any) -> bool:
    return isinstance(x, (int, float, np.integer, np.floating)) and not isinstance(x, bool)


def _finite(x: Any) -> bool:
    return _is_number(x) and math.isfinite(float(x))


def _as_output(values: FloatArray, scalar: bool) -> FloatArray | float:
    return float(values) if scalar else values


def _as_input(s: ArrayLike) -> tuple[FloatArray, bool]:
    arr = np.asarray(s, dtype=float)
    return arr, arr.ndim == 0


# ---------------------------------------------------------------------------------------
# Segments
# ---------------------------------------------------------------------------------------


def _length_problems(length: Any) -> list[str]:
    if not _finite(length):
        return [f"'length' must be a finite number of metres, got {length!r}"]
    if length <= 0:
        return [f"'length' must be > 0 m, got {length!r}"]
    return []


@dataclass(frozen=True)
class Straight:
    """Straight track: zero curvature, zero cant.

    Parameters
    ----------
    length : float
        Length along the track [m], > 0.
    """

    length: float

    @staticmethod
    def problems(length: Any) -> list[str]:
        """Return what is wrong with these field values (empty if nothing)."""
        return _length_problems(length)

    def __post_init__(self) -> None:
        _raise_if(self.problems(self.length), "Straight")


@dataclass(frozen=True)
class Transition:
    """Transition curve: curvature and cant ramp between the neighbouring segments.

    The start values are those at the end of the previous segment and the end values
    those at the start of the next one (zero, straight track, when the transition is
    first or last). Two transitions may not follow each other.

    Parameters
    ----------
    length : float
        Length along the track [m], > 0.
    shape : {"linear", "sine"}
        ``"linear"``: curvature and cant vary linearly with s (clothoid, linear cant
        ramp). ``"sine"``: they follow ``v0 + (v1 - v0) (1 - cos(pi u)) / 2`` with
        ``u = (s - s0) / length``, the half-wave sine ramp used in Japan, whose rate is
        zero at both ends.
    """

    length: float
    shape: str = "linear"

    @staticmethod
    def problems(length: Any, shape: Any = "linear") -> list[str]:
        """Return what is wrong with these field values (empty if nothing)."""
        out = _length_problems(length)
        if shape not in TRANSITION_SHAPES:
            out.append(f"'shape' must be one of {', '.join(TRANSITION_SHAPES)}, got {shape!r}")
        return out

    def __post_init__(self) -> None:
        _raise_if(self.problems(self.length, self.shape), "Transition")


@dataclass(frozen=True)
class Curve:
    """Circular curve of constant radius and cant.

    Parameters
    ----------
    length : float
        Length along the track [m], > 0.
    radius : float
        Radius [m], > 0.
    direction : {"left", "right"}
        Direction the track turns, seen in the direction of travel (+x).
    cant : float
        Cant as the rail height difference S [m] (outer rail above inner rail), toward
        the centre of the curve; default 0. A negative value is adverse cant.
    """

    length: float
    radius: float
    direction: str
    cant: float = 0.0

    @staticmethod
    def problems(length: Any, radius: Any, direction: Any, cant: Any = 0.0) -> list[str]:
        """Return what is wrong with these field values (empty if nothing)."""
        out = _length_problems(length)
        if not _finite(radius):
            out.append(f"'radius' must be a finite number of metres, got {radius!r}")
        elif radius <= 0:
            out.append(f"'radius' must be > 0 m, got {radius!r}")
        if direction not in DIRECTIONS:
            out.append(f"'direction' must be 'left' or 'right', got {direction!r}")
        if not _finite(cant):
            out.append(f"'cant' must be a finite number of metres, got {cant!r}")
        return out

    def __post_init__(self) -> None:
        _raise_if(self.problems(self.length, self.radius, self.direction, self.cant), "Curve")

    @property
    def curvature(self) -> float:
        """Signed curvature rho [1/m]: ``+1/radius`` to the left, ``-1/radius`` right."""
        return (1.0 if self.direction == "left" else -1.0) / self.radius

    @property
    def signed_cant(self) -> float:
        """Signed cant S [m]: ``+cant`` in a left curve, ``-cant`` in a right curve."""
        return self.cant if self.direction == "left" else -self.cant


#: Any segment of a track.
Segment = Union[Straight, Transition, Curve]


def _raise_if(problems: list[str], what: str) -> None:
    if problems:
        raise ValueError(f"{what}: " + "; ".join(problems))


# ---------------------------------------------------------------------------------------
# Irregularities
# ---------------------------------------------------------------------------------------


class Irregularity(ABC):
    """Lateral track irregularity ``yR(s)`` [m] (alignment), y positive to the left.

    Subclasses are callable: ``irr(s)`` is ``irr.value(s)``. Every irregularity is
    defined for every s (it is not cut at the track's ends).
    """

    @abstractmethod
    def value(self, s: ArrayLike) -> FloatArray | float:
        """Lateral irregularity yR [m] at distances ``s`` [m]."""

    @abstractmethod
    def rate(self, s: ArrayLike) -> FloatArray | float:
        """Derivative d yR / ds [m/m] at distances ``s`` [m]."""

    def __call__(self, s: ArrayLike) -> FloatArray | float:
        return self.value(s)


@dataclass(frozen=True)
class NoIrregularity(Irregularity):
    """Perfect alignment: ``yR = 0``."""

    def value(self, s: ArrayLike) -> FloatArray | float:
        arr, scalar = _as_input(s)
        return _as_output(np.zeros_like(arr), scalar)

    def rate(self, s: ArrayLike) -> FloatArray | float:
        return self.value(s)


@dataclass(frozen=True)
class SinusoidIrregularity(Irregularity):
    """Sinusoidal alignment ``yR = amplitude * sin(2 pi s / wavelength + phase)``.

    Parameters
    ----------
    amplitude : float
        Amplitude [m].
    wavelength : float
        Wavelength [m], > 0.
    phase : float
        Phase [rad] at s = 0; default 0.
    """

    amplitude: float
    wavelength: float
    phase: float = 0.0

    def __post_init__(self) -> None:
        problems = []
        if not _finite(self.amplitude):
            problems.append(f"'amplitude' must be a finite number, got {self.amplitude!r}")
        if not _finite(self.wavelength) or self.wavelength <= 0:
            problems.append(f"'wavelength' must be > 0 m, got {self.wavelength!r}")
        if not _finite(self.phase):
            problems.append(f"'phase' must be a finite number, got {self.phase!r}")
        _raise_if(problems, "SinusoidIrregularity")

    def value(self, s: ArrayLike) -> FloatArray | float:
        arr, scalar = _as_input(s)
        k = 2.0 * np.pi / self.wavelength
        return _as_output(self.amplitude * np.sin(k * arr + self.phase), scalar)

    def rate(self, s: ArrayLike) -> FloatArray | float:
        arr, scalar = _as_input(s)
        k = 2.0 * np.pi / self.wavelength
        return _as_output(self.amplitude * k * np.cos(k * arr + self.phase), scalar)


@dataclass(frozen=True, eq=False)
class ProfileIrregularity(Irregularity):
    """Tabulated (measured) alignment, linearly interpolated.

    Outside the tabulated range the end values are held (a constant lateral offset,
    which does not excite the vehicle), so that no step appears at the ends.

    Parameters
    ----------
    distance : array_like
        Distances s [m], strictly increasing, at least two points.
    yr : array_like
        yR [m] at those distances.
    source : str
        Where the data came from (file name), for messages.
    """

    distance: FloatArray
    yr: FloatArray
    source: str = "<array>"

    def __post_init__(self) -> None:
        d = np.array(self.distance, dtype=float).ravel()
        v = np.array(self.yr, dtype=float).ravel()
        problems = []
        if d.shape != v.shape:
            problems.append(f"distance and yr differ in length ({d.size} and {v.size})")
        elif d.size < 2:
            problems.append(f"need at least two points, got {d.size}")
        elif not (np.all(np.isfinite(d)) and np.all(np.isfinite(v))):
            problems.append("distance and yr must be finite")
        elif np.any(np.diff(d) <= 0):
            problems.append("distance must be strictly increasing")
        _raise_if(problems, f"ProfileIrregularity from {self.source}")
        d.setflags(write=False)
        v.setflags(write=False)
        object.__setattr__(self, "distance", d)
        object.__setattr__(self, "yr", v)

    def value(self, s: ArrayLike) -> FloatArray | float:
        arr, scalar = _as_input(s)
        return _as_output(np.interp(arr, self.distance, self.yr), scalar)

    def rate(self, s: ArrayLike) -> FloatArray | float:
        arr, scalar = _as_input(s)
        slopes = np.diff(self.yr) / np.diff(self.distance)
        i = np.clip(np.searchsorted(self.distance, arr, side="right") - 1, 0, slopes.size - 1)
        out = np.where((arr >= self.distance[0]) & (arr < self.distance[-1]), slopes[i], 0.0)
        return _as_output(out, scalar)


# --- Published alignment spectra ------------------------------------------------------


@dataclass(frozen=True)
class FRAAlignmentSpectrum:
    """US FRA alignment spectrum of one track class.

    ``S(Omega) = k A_a Omega_c^2 / ((Omega^2 + Omega_c^2) Omega^2)`` [m^2/(rad/m)],
    one-sided in the wavenumber ``Omega`` [rad/m] >= 0, so that the variance of yR over
    a band is the integral of S over that band.

    Parameters
    ----------
    name : str
        Label.
    A_a : float
        Roughness coefficient [m^2 rad/m] (published in cm^2 rad/m: multiply by 1e-4).
    omega_c : float
        Cut-off wavenumber [rad/m].
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

    name: str
    A_a: float
    omega_c: float = 0.8245
    k: float = 0.25

    def psd(self, omega: ArrayLike) -> FloatArray:
        """One-sided PSD [m^2/(rad/m)] at wavenumbers ``omega`` [rad/m] > 0."""
        w = np.asarray(omega, dtype=float)
        return self.k * self.A_a * self.omega_c**2 / ((w**2 + self.omega_c**2) * w**2)

    def _primitive(self, w: FloatArray) -> FloatArray:
        # S = k A (1/w^2 - 1/(w^2 + wc^2))
        return self.k * self.A_a * (-1.0 / w - np.arctan(w / self.omega_c) / self.omega_c)

    def variance(self, omega_min: ArrayLike, omega_max: ArrayLike) -> FloatArray | float:
        """Integral of the PSD from ``omega_min`` to ``omega_max`` (> 0) [m^2], exact."""
        lo, hi = np.asarray(omega_min, float), np.asarray(omega_max, float)
        out = self._primitive(hi) - self._primitive(lo)
        return float(out) if out.ndim == 0 else out


@dataclass(frozen=True)
class ERRIAlignmentSpectrum:
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

    name: str
    A: float
    omega_c: float = 0.8246
    omega_r: float = 0.0206

    def psd(self, omega: ArrayLike) -> FloatArray:
        """One-sided PSD [m^2/(rad/m)] at wavenumbers ``omega`` [rad/m] >= 0."""
        w = np.asarray(omega, dtype=float)
        wc, wr = self.omega_c, self.omega_r
        return self.A * wc**2 / ((w**2 + wr**2) * (w**2 + wc**2))

    def _primitive(self, w: FloatArray) -> FloatArray:
        wc, wr = self.omega_c, self.omega_r
        c = self.A * wc**2 / (wc**2 - wr**2)
        return c * (np.arctan(w / wr) / wr - np.arctan(w / wc) / wc)

    def variance(self, omega_min: ArrayLike, omega_max: ArrayLike) -> FloatArray | float:
        """Integral of the PSD from ``omega_min`` to ``omega_max`` [m^2], exact."""
        lo, hi = np.asarray(omega_min, float), np.asarray(omega_max, float)
        out = self._primitive(hi) - self._primitive(lo)
        return float(out) if out.ndim == 0 else out


AlignmentSpectrum = Union[FRAAlignmentSpectrum, ERRIAlignmentSpectrum]

#: FRA class 5, alignment: A_a = 0.0762 cm^2 rad/m = 7.62e-6 m^2 rad/m.
FRA_CLASS_5 = FRAAlignmentSpectrum("FRA class 5 alignment", A_a=0.0762e-4)
#: FRA class 6, alignment: A_a = 0.0339 cm^2 rad/m = 3.39e-6 m^2 rad/m.
FRA_CLASS_6 = FRAAlignmentSpectrum("FRA class 6 alignment", A_a=0.0339e-4)
#: ORE B176 / ERRI low level: A = 2.119e-7 m rad.
ERRI_LOW = ERRIAlignmentSpectrum("ERRI B176 low", A=2.119e-7)
#: ORE B176 / ERRI high level: A = 6.125e-7 m rad.
ERRI_HIGH = ERRIAlignmentSpectrum("ERRI B176 high", A=6.125e-7)

#: Spectra by the names accepted in track files.
SPECTRA: dict[str, AlignmentSpectrum] = {
    "fra5": FRA_CLASS_5,
    "fra6": FRA_CLASS_6,
    "erri_low": ERRI_LOW,
    "erri_high": ERRI_HIGH,
}


def get_spectrum(name: str) -> AlignmentSpectrum:
    """Return a spectrum of :data:`SPECTRA` by name (case and ``-``/``_`` ignored).

    Raises
    ------
    KeyError
        If the name is unknown; the message lists the known names.
    """
    key = name.strip().lower().replace("-", "_").replace(" ", "_")
    if key not in SPECTRA:
        raise KeyError(f"unknown spectrum {name!r} (known: {', '.join(SPECTRA)})")
    return SPECTRA[key]


@dataclass(frozen=True)
class SpectrumIrregularity(Irregularity):
    """Random alignment with a published spectrum: a sum of cosines, random phases.

    ``yR(s) = sum_k a_k cos(Omega_k s + phi_k)`` with ``Omega_k = 2 pi k / period`` for
    every integer k whose wavenumber lies in the band
    ``[2 pi / wavelength_max, 2 pi / wavelength_min]``, amplitudes
    ``a_k = sqrt(2 * integral of S over the bin of Omega_k)`` (bins of width
    ``2 pi / period`` centred on ``Omega_k``, the outer two reaching the band edges;
    integrated exactly) and phases ``phi_k`` uniform in ``[0, 2 pi)`` from
    ``numpy.random.default_rng(seed)``.
    The profile repeats every ``period`` metres, and its mean square over one period is
    exactly the integral of S over the band (the band variance).

    Parameters
    ----------
    spectrum : FRAAlignmentSpectrum or ERRIAlignmentSpectrum or str
        The spectrum, or its name in :data:`SPECTRA` (``"fra5"``, ``"fra6"``,
        ``"erri_low"``, ``"erri_high"``).
    seed : int
        Seed of the phases; the same seed gives the same profile. Default 0.
    wavelength_min, wavelength_max : float
        Wavelength band [m]; default 3 m to 120 m (the wavelengths that excite the
        lateral modes of a vehicle at ordinary speeds; the FRA spectrum diverges at long
        wavelengths, so some upper bound is needed).
    period : float
        Length after which the profile repeats [m]; default 10 km.
    """

    spectrum: AlignmentSpectrum
    seed: int = 0
    wavelength_min: float = 3.0
    wavelength_max: float = 120.0
    period: float = 10_000.0
    #: Wavenumbers Omega_k [rad/m], amplitudes a_k [m] and phases phi_k [rad].
    wavenumbers: FloatArray = field(init=False, repr=False, compare=False)
    amplitudes: FloatArray = field(init=False, repr=False, compare=False)
    phases: FloatArray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if isinstance(self.spectrum, str):
            try:
                object.__setattr__(self, "spectrum", get_spectrum(self.spectrum))
            except KeyError as exc:
                raise ValueError(f"SpectrumIrregularity: {exc.args[0]}") from None
        problems = []
        lmin, lmax, period = self.wavelength_min, self.wavelength_max, self.period
        if not isinstance(self.seed, (int, np.integer)) or isinstance(self.seed, bool) or self.seed < 0:
            problems.append(f"'seed' must be a non-negative integer, got {self.seed!r}")
        if not (_finite(lmin) and lmin > 0):
            problems.append(f"'wavelength_min' must be > 0 m, got {lmin!r}")
        if not (_finite(lmax) and lmax > 0):
            problems.append(f"'wavelength_max' must be > 0 m, got {lmax!r}")
        if not (_finite(period) and period > 0):
            problems.append(f"'period' must be > 0 m, got {period!r}")
        if not problems:
            if lmin >= lmax:
                problems.append(f"'wavelength_min' ({lmin}) must be < 'wavelength_max' ({lmax})")
            elif period < lmax:
                problems.append(f"'period' ({period}) must be >= 'wavelength_max' ({lmax})")
        _raise_if(problems, "SpectrumIrregularity")

        w_lo, w_hi = 2 * np.pi / lmax, 2 * np.pi / lmin
        dw = 2 * np.pi / period
        k = np.arange(math.ceil(w_lo / dw - 1e-12), math.floor(w_hi / dw + 1e-12) + 1)
        if k.size == 0:
            raise ValueError("SpectrumIrregularity: no wavenumber of the period in the band")
        w = k * dw
        # bins between midpoints; the outer bins reach the band edges
        edges = np.concatenate([[w_lo], 0.5 * (w[:-1] + w[1:]), [w_hi]])
        power = np.asarray(self.spectrum.variance(edges[:-1], edges[1:]), dtype=float)
        rng = np.random.default_rng(int(self.seed))
        phases = rng.uniform(0.0, 2 * np.pi, size=w.size)
        for name, arr in (("wavenumbers", w), ("amplitudes", np.sqrt(2 * power)), ("phases", phases)):
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    @property
    def band_variance(self) -> float:
        """Integral of the PSD over the band [m^2] (= mean square over one period)."""
        w_lo, w_hi = 2 * np.pi / self.wavelength_max, 2 * np.pi / self.wavelength_min
        return float(self.spectrum.variance(w_lo, w_hi))

    def _sum(self, s: ArrayLike, derivative: bool) -> FloatArray | float:
        arr, scalar = _as_input(s)
        flat = arr.ravel()
        out = np.empty_like(flat)
        chunk = max(1, 2_000_000 // self.wavenumbers.size)
        for i in range(0, flat.size, chunk):
            arg = np.outer(flat[i : i + chunk], self.wavenumbers) + self.phases
            if derivative:
                out[i : i + chunk] = -np.sin(arg) @ (self.amplitudes * self.wavenumbers)
            else:
                out[i : i + chunk] = np.cos(arg) @ self.amplitudes
        return _as_output(out.reshape(arr.shape), scalar)

    def value(self, s: ArrayLike) -> FloatArray | float:
        return self._sum(s, derivative=False)

    def rate(self, s: ArrayLike) -> FloatArray | float:
        return self._sum(s, derivative=True)

    def tabulate(self, start: float, stop: float, step: float = 0.25) -> ProfileIrregularity:
        """Sample the profile into a :class:`ProfileIrregularity` (fast to evaluate).

        Parameters
        ----------
        start, stop : float
            Range of s [m] to cover (``stop`` included).
        step : float
            Sampling step [m]; keep it well below ``wavelength_min`` (default 0.25 m).
        """
        n = max(2, math.ceil((stop - start) / step) + 1)
        d = np.linspace(start, start + (n - 1) * step, n)
        return ProfileIrregularity(d, self.value(d), source=f"{self.spectrum.name}, seed {self.seed}")


# ---------------------------------------------------------------------------------------
# Track
# ---------------------------------------------------------------------------------------

# Gauss-Legendre rule used to integrate the heading into the centreline.
_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)
#: Longest piece of track integrated with one Gauss-Legendre rule [m].
_PIECE = 10.0


def _ramp(shape: FloatArray, u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Ramp f(u), its derivative f'(u) and its integral F(u) = int_0^u f, per shape code."""
    lin, sine = shape == _LINEAR, shape == _SINE
    f = np.where(lin, u, np.where(sine, 0.5 * (1 - np.cos(np.pi * u)), 0.0))
    df = np.where(lin, 1.0, np.where(sine, 0.5 * np.pi * np.sin(np.pi * u), 0.0))
    big_f = np.where(lin, 0.5 * u**2, np.where(sine, 0.5 * u - np.sin(np.pi * u) / (2 * np.pi), 0.0))
    return f, df, big_f


@dataclass(frozen=True)
class Track:
    """A track: segments one after the other, plus a lateral irregularity.

    The segments start at s = 0. Methods taking ``s`` accept floats or arrays and are
    vectorized (a float in, a float out). Before s = 0 and from s = ``length`` on, the
    track is straight, without cant, continuing the tangent at the end.

    Parameters
    ----------
    segments : sequence of Straight, Transition, Curve
        The layout, in order. No two transitions may follow each other.
    irregularity : Irregularity
        Lateral irregularity yR(s); default none.
    speed : float or None
        Nominal running speed [m/s] from the track file, if any (informative; the track
        itself does not use it).
    """

    segments: tuple[Segment, ...] = ()
    irregularity: Irregularity = field(default_factory=NoIrregularity)
    speed: float | None = None

    def __post_init__(self) -> None:
        segs = tuple(self.segments)
        object.__setattr__(self, "segments", segs)
        problems = []
        for i, seg in enumerate(segs, 1):
            if not isinstance(seg, (Straight, Transition, Curve)):
                problems.append(f"segment {i} is not a Straight, Transition or Curve: {seg!r}")
        for i in range(1, len(segs)):
            if isinstance(segs[i - 1], Transition) and isinstance(segs[i], Transition):
                problems.append(
                    f"segments {i} and {i + 1} are both transitions (a transition takes its "
                    "end values from its neighbours)"
                )
        if not isinstance(self.irregularity, Irregularity):
            problems.append(f"irregularity is not an Irregularity: {self.irregularity!r}")
        if self.speed is not None and not (_finite(self.speed) and self.speed > 0):
            problems.append(f"speed must be > 0 m/s, got {self.speed!r}")
        _raise_if(problems, "Track")
        self._build()

    # --- tables ---------------------------------------------------------------------

    def _build(self) -> None:
        segs = self.segments
        n = len(segs)
        lengths = np.array([float(sg.length) for sg in segs])
        starts = np.concatenate([[0.0], np.cumsum(lengths)])

        def end_values(sg: Segment | None) -> tuple[float, float]:
            return (sg.curvature, sg.signed_cant) if isinstance(sg, Curve) else (0.0, 0.0)

        shape = np.zeros(n, dtype=int)
        rho0, rho1, cant0, cant1 = (np.zeros(n) for _ in range(4))
        for i, sg in enumerate(segs):
            if isinstance(sg, Transition):
                shape[i] = _SHAPE_CODE[sg.shape]
                rho0[i], cant0[i] = end_values(segs[i - 1] if i > 0 else None)
                rho1[i], cant1[i] = end_values(segs[i + 1] if i + 1 < n else None)
            else:
                rho0[i], cant0[i] = rho1[i], cant1[i] = end_values(sg)
        # heading at the segment starts: exact integral of the curvature
        heading = np.zeros(n + 1)
        if n:
            _, _, big_f = _ramp(shape, np.ones(n))
            heading[1:] = np.cumsum(lengths * (rho0 + (rho1 - rho0) * big_f))
        tables = dict(
            _n=n, _starts=starts, _lengths=lengths, _shape=shape, _rho0=rho0, _rho1=rho1,
            _cant0=cant0, _cant1=cant1, _heading0=heading,
        )
        for key, val in tables.items():
            object.__setattr__(self, key, val)
        self._build_centreline()

    def _build_centreline(self) -> None:
        knots = [0.0]
        for a, length in zip(self._starts[:-1], self._lengths):
            m = max(1, math.ceil(length / _PIECE))
            knots.extend(a + length * np.arange(1, m + 1) / m)
        knots_arr = np.array(knots)
        x = np.zeros(knots_arr.size)
        y = np.zeros(knots_arr.size)
        if knots_arr.size > 1:
            dx, dy = self._integrate_tangent(knots_arr[:-1], knots_arr[1:])
            x[1:], y[1:] = np.cumsum(dx), np.cumsum(dy)
        object.__setattr__(self, "_knots", knots_arr)
        object.__setattr__(self, "_knot_x", x)
        object.__setattr__(self, "_knot_y", y)

    def _integrate_tangent(self, a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Integral of (cos, sin)(heading) from a to b, both in the same knot piece."""
        half = 0.5 * (b - a)
        t = (0.5 * (a + b))[..., None] + half[..., None] * _GL_X
        th = self._heading_inside(t)
        return half * (np.cos(th) @ _GL_W), half * (np.sin(th) @ _GL_W)

    # --- evaluation -----------------------------------------------------------------

    @property
    def length(self) -> float:
        """Total length of the segments [m]."""
        return float(self._starts[-1])

    @property
    def boundaries(self) -> FloatArray:
        """Distances of the segment joints [m], from 0 to ``length`` (n + 1 values)."""
        return self._starts.copy()

    def _locate(self, s: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Segment index, local coordinate u in [0, 1] and inside-mask for each s."""
        inside = (s >= 0.0) & (s < self.length)
        k = np.clip(np.searchsorted(self._starts, s, side="right") - 1, 0, max(self._n - 1, 0))
        if self._n == 0:
            return k, np.zeros_like(s), inside
        u = np.clip((s - self._starts[k]) / self._lengths[k], 0.0, 1.0)
        return k, u, inside

    def _profile(self, s: ArrayLike, start: FloatArray, end: FloatArray, rate: bool):
        arr, scalar = _as_input(s)
        if self._n == 0:
            return _as_output(np.zeros_like(arr), scalar)
        k, u, inside = self._locate(arr)
        f, df, _ = _ramp(self._shape[k], u)
        jump = end[k] - start[k]
        val = jump * df / self._lengths[k] if rate else start[k] + jump * f
        return _as_output(np.where(inside, val, 0.0), scalar)

    def geometry(self, s: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Curvature, its rate, cant and its rate at ``s`` in one pass (arrays).

        The same values as :meth:`curvature`, :meth:`curvature_rate`, :meth:`cant` and
        :meth:`cant_rate`, locating each ``s`` in its segment once (for simulations).
        """
        arr = np.asarray(s, dtype=float)
        if self._n == 0:
            zeros = np.zeros_like(arr)
            return zeros, zeros, zeros, zeros
        k, u, inside = self._locate(arr)
        f, df, _ = _ramp(self._shape[k], u)
        length = self._lengths[k]
        out = []
        for start, end in ((self._rho0, self._rho1), (self._cant0, self._cant1)):
            jump = end[k] - start[k]
            out.append(np.where(inside, start[k] + jump * f, 0.0))
            out.append(np.where(inside, jump * df / length, 0.0))
        return out[0], out[1], out[2], out[3]

    def curvature(self, s: ArrayLike) -> FloatArray | float:
        """Signed curvature rho(s) [1/m], > 0 for a curve to the left."""
        return self._profile(s, self._rho0, self._rho1, rate=False)

    def curvature_rate(self, s: ArrayLike) -> FloatArray | float:
        """d rho / ds [1/m^2] (zero outside the transitions)."""
        return self._profile(s, self._rho0, self._rho1, rate=True)

    def cant(self, s: ArrayLike) -> FloatArray | float:
        """Signed cant S(s) [m], > 0 when rolled toward the centre of a left curve."""
        return self._profile(s, self._cant0, self._cant1, rate=False)

    def cant_rate(self, s: ArrayLike) -> FloatArray | float:
        """d S / ds [m/m] (zero outside the transitions)."""
        return self._profile(s, self._cant0, self._cant1, rate=True)

    def lateral_irregularity(self, s: ArrayLike) -> FloatArray | float:
        """Lateral irregularity yR(s) [m] (y left)."""
        return self.irregularity.value(s)

    def lateral_irregularity_rate(self, s: ArrayLike) -> FloatArray | float:
        """d yR / ds [m/m]."""
        return self.irregularity.rate(s)

    def with_irregularity(self, irregularity: Irregularity) -> Track:
        """The same layout with another irregularity."""
        return replace(self, irregularity=irregularity)

    # --- exact geometry -------------------------------------------------------------

    def _heading_inside(self, s: FloatArray) -> FloatArray:
        """Heading for 0 <= s <= length (clipped), exact."""
        if self._n == 0:
            return np.zeros_like(s)
        k, u, _ = self._locate(np.clip(s, 0.0, self.length))
        _, _, big_f = _ramp(self._shape[k], u)
        rho0, rho1 = self._rho0[k], self._rho1[k]
        return self._heading0[k] + self._lengths[k] * (rho0 * u + (rho1 - rho0) * big_f)

    def heading(self, s: ArrayLike) -> FloatArray | float:
        """Heading theta(s) [rad] of the centreline tangent from +X, = int_0^s rho.

        Exact (closed form per segment). 0 before the start, constant after the end.
        """
        arr, scalar = _as_input(s)
        return _as_output(self._heading_inside(arr), scalar)

    def centreline(self, s: ArrayLike) -> tuple[FloatArray | float, FloatArray | float]:
        """Plane coordinates (X, Y) [m] of the centreline at distance s.

        X along the initial tangent, Y to its left; the start is the origin. The heading
        is integrated with a 16-point Gauss-Legendre rule on pieces of at most 10 m
        inside one segment (where the heading is smooth), accurate to about 1e-12 m.
        Before the start and after the end the centreline is straight.
        """
        arr, scalar = _as_input(s)
        length = self.length
        sc = np.clip(arr, 0.0, length)
        j = np.clip(np.searchsorted(self._knots, sc, side="right") - 1, 0, max(self._knots.size - 2, 0))
        if self._knots.size > 1:
            dx, dy = self._integrate_tangent(self._knots[j], sc)
        else:
            dx = dy = np.zeros_like(sc)
        x = self._knot_x[j] + dx
        y = self._knot_y[j] + dy
        th_end = self._heading0[-1]
        before, after = arr < 0.0, arr > length
        x = np.where(before, arr, np.where(after, x + (arr - length) * np.cos(th_end), x))
        y = np.where(after, y + (arr - length) * np.sin(th_end), np.where(before, 0.0, y))
        return _as_output(x, scalar), _as_output(y, scalar)

    def lateral_offset_exact(self, s: ArrayLike, lx: ArrayLike) -> FloatArray | float:
        """Offset [m] of the centreline point at s + lx from the tangent line at s.

        Measured perpendicular to the tangent at s, positive to the left: the natural
        geometric sign, so the track ahead (or behind) in a left curve is at about
        ``+rho lx^2 / 2``. The vehicle model's lateral displacement of a connection
        point ``lx`` ahead of a body at station s, relative to the track at the point's
        own station, is MINUS this (``-rho lx^2 / 2`` to first order).

        Parameters
        ----------
        s : array_like
            Station of the tangent [m].
        lx : array_like
            Distance along the track to the point, positive ahead [m]; broadcast with s.
        """
        s_arr, lx_arr = np.broadcast_arrays(np.asarray(s, float), np.asarray(lx, float))
        scalar = s_arr.ndim == 0
        x0, y0 = self.centreline(s_arr)
        x1, y1 = self.centreline(s_arr + lx_arr)
        th = self._heading_inside(s_arr)
        out = -(np.asarray(x1) - x0) * np.sin(th) + (np.asarray(y1) - y0) * np.cos(th)
        return _as_output(np.asarray(out, dtype=float), scalar)

    def lateral_offset_first_order(self, s: ArrayLike, lx: ArrayLike) -> FloatArray | float:
        """First-order offset ``rho(s) lx^2 / 2`` [m] (sign of :meth:`lateral_offset_exact`)."""
        s_arr, lx_arr = np.broadcast_arrays(np.asarray(s, float), np.asarray(lx, float))
        out = np.asarray(self.curvature(s_arr)) * lx_arr**2 / 2
        return _as_output(out, s_arr.ndim == 0)

    def lateral_offset_second_order(self, s: ArrayLike, lx: ArrayLike) -> FloatArray | float:
        """Offset ``rho(s) lx^2 / 2 + rho'(s) lx^3 / 6`` [m], with the curvature rate."""
        s_arr, lx_arr = np.broadcast_arrays(np.asarray(s, float), np.asarray(lx, float))
        out = (np.asarray(self.curvature(s_arr)) * lx_arr**2 / 2
               + np.asarray(self.curvature_rate(s_arr)) * lx_arr**3 / 6)
        return _as_output(out, s_arr.ndim == 0)

    def lateral_offset_two_station(self, s: ArrayLike, lx: ArrayLike) -> FloatArray | float:
        """Offset ``lx^2 (rho(s) / 3 + rho(s + lx) / 6)`` [m] from two curvatures.

        The offset to first order in rho is ``int_0^lx (lx - t) rho(s + t) dt``; this
        rule is exact for it when rho is linear between s and s + lx (a clothoid), needs
        no curvature rate, and uses only the curvature at the body's station and at the
        point's station.
        """
        s_arr, lx_arr = np.broadcast_arrays(np.asarray(s, float), np.asarray(lx, float))
        out = lx_arr**2 * (np.asarray(self.curvature(s_arr)) / 3
                           + np.asarray(self.curvature(s_arr + lx_arr)) / 6)
        return _as_output(out, s_arr.ndim == 0)


def paper_curve(
    direction: str = "left",
    *,
    lead_in: float = 50.0,
    lead_out: float | None = None,
    shape: str = "sine",
    radius: float = 400.0,
    cant: float = 0.095,
    transition_length: float = 95.0,
    curve_length: float = 170.0,
    irregularity: Irregularity | None = None,
    speed: float | None = 120.0 / 3.6,
) -> Track:
    """The curve of the paper's Fig. 9 (Tanifuji & Suzuki 2001, section 4.3).

    Straight ``lead_in``, transition 95 m, circular curve R = 400 m of 170 m with
    95 mm cant, transition 95 m, straight ``lead_out``: 460 m with the default 50 m
    straights. The paper gives neither the lengths of the straights nor the direction
    nor the transition shape ("curvature and cant change smoothly"); the defaults here
    are 50 m, LEFT (so rho > 0, as plotted in Fig. 9) and the half-wave sine ramp.

    Parameters
    ----------
    direction : {"left", "right"}
        Direction of the curve; default ``"left"``.
    lead_in : float
        Straight before the first transition [m], >= 0 (0: none); default 50.
    lead_out : float or None
        Straight after the second transition [m]; default: same as ``lead_in``.
    shape : {"sine", "linear"}
        Transition shape; default ``"sine"``.
    radius, cant, transition_length, curve_length : float
        [m]; defaults 400, 0.095, 95, 170.
    irregularity : Irregularity or None
        Default none.
    speed : float or None
        Nominal speed [m/s]; default 120 km/h, the speed of Fig. 9.

    Returns
    -------
    Track
    """
    lead_out = lead_in if lead_out is None else lead_out
    segments: list[Segment] = []
    if lead_in > 0:
        segments.append(Straight(lead_in))
    segments += [
        Transition(transition_length, shape),
        Curve(curve_length, radius, direction, cant),
        Transition(transition_length, shape),
    ]
    if lead_out > 0:
        segments.append(Straight(lead_out))
    return Track(tuple(segments), NoIrregularity() if irregularity is None else irregularity, speed)


# ---------------------------------------------------------------------------------------
# Files
# ---------------------------------------------------------------------------------------


class TrackError(ValueError):
    """Bad track input. The message lists every problem found, each with its place.

    Attributes
    ----------
    source : str
        File (or other source) the input came from.
    problems : list of str
        One line per problem: ``<file>:<line>: <item>: <what is wrong>``.
    """

    def __init__(self, source: str, problems: Sequence[str]):
        self.source = source
        self.problems = list(problems)
        count = f"{len(self.problems)} problem" + ("s" if len(self.problems) != 1 else "")
        super().__init__(f"invalid track input {source} ({count}):\n  " + "\n  ".join(self.problems))


_NUMBER_UNIT = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z/]+)\s*$")
#: Units accepted in strings such as ``"95 mm"``, by dimension, with their SI factor.
UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "mm": 1e-3, "km": 1e3},
    "speed": {"m/s": 1.0, "km/h": 1.0 / 3.6},
    "angle": {"rad": 1.0, "deg": math.pi / 180.0},
}
_SI_UNIT = {"length": "m", "speed": "m/s", "angle": "rad"}


def _quantity(value: Any, dimension: str) -> float:
    """A number (SI) or a string ``"<number> <unit>"``; raises ValueError with the reason."""
    if _is_number(value):
        if not math.isfinite(float(value)):
            raise ValueError(f"must be finite, got {value!r}")
        return float(value)
    if isinstance(value, str):
        m = _NUMBER_UNIT.match(value)
        units = UNITS[dimension]
        if not m:
            raise ValueError(
                f"{value!r} is not a number with a unit (write e.g. 12.5 for SI "
                f"{_SI_UNIT[dimension]}, or \"12.5 {next(iter(units))}\")"
            )
        number, unit = m.groups()
        if unit not in units:
            raise ValueError(f"unit {unit!r} in {value!r} is not a {dimension} unit ({', '.join(units)})")
        return float(number) * units[unit]
    raise ValueError(f"must be a number or a string with a unit, got {type(value).__name__} {value!r}")


class _Lines:
    """Line numbers of tables and keys in the TOML text (best effort, never required)."""

    _HEADER = re.compile(r"^\s*(\[\[?)\s*([A-Za-z0-9_\-\"' .]+?)\s*(\]\]?)\s*(#.*)?$")
    _KEY = re.compile(r"^\s*([A-Za-z0-9_\-]+)\s*=")

    def __init__(self, text: str | None):
        self.tables: dict[tuple, int] = {}
        self.keys: dict[tuple, int] = {}
        if not text:
            return
        table: tuple = ("",)
        n_segments = 0
        for lineno, line in enumerate(text.splitlines(), 1):
            head = self._HEADER.match(line)
            if head:
                name = head.group(2).strip().strip("\"'")
                if head.group(1) == "[[" and name == "segment":
                    n_segments += 1
                    table = ("segment", n_segments)
                else:
                    table = (name,)
                self.tables.setdefault(table, lineno)
                continue
            key = self._KEY.match(line)
            if key:
                self.keys.setdefault((*table, key.group(1)), lineno)

    def line(self, table: tuple, key: str | None = None) -> int | None:
        if key is not None and (*table, key) in self.keys:
            return self.keys[(*table, key)]
        return self.tables.get(table)


class _Problems:
    """Collects problems as ``<source>:<line>: <item>: <message>``, sorted by line."""

    def __init__(self, source: str, lines: _Lines):
        self.source, self.lines = source, lines
        self._entries: list[tuple[int, int, str]] = []

    def __len__(self) -> int:
        return len(self._entries)

    def add(self, table: tuple, item: str, message: str, key: str | None = None) -> None:
        line = self.lines.line(table, key)
        where = f"{self.source}:{line}" if line else self.source
        self._entries.append((line or 0, len(self._entries), f"{where}: {item}: {message}"))

    @property
    def items(self) -> list[str]:
        """The problems, those without a line first, then by line."""
        return [text for _, _, text in sorted(self._entries)]


_TOP_KEYS = {"speed", "segment", "irregularity", "name", "description"}
_SEGMENT_KEYS = {
    "straight": {"type", "length"},
    "transition": {"type", "length", "shape"},
    "curve": {"type", "length", "radius", "direction", "cant"},
}
_IRREGULARITY_KEYS = {
    "none": {"type"},
    "sinusoid": {"type", "amplitude", "wavelength", "phase"},
    "csv": {"type", "file"},
    "spectrum": {"type", "spectrum", "seed", "wavelength_min", "wavelength_max", "period"},
}


def _get(table: Mapping, key: str, dimension: str, problems: _Problems, where: tuple,
         item: str, default: Any = ..., positive: bool = False) -> Any:
    """Read a quantity; record a problem and return None when missing or bad."""
    if key not in table:
        if default is ...:
            problems.add(where, item, f"missing '{key}'")
            return None
        return default
    try:
        value = _quantity(table[key], dimension)
    except ValueError as exc:
        problems.add(where, item, f"'{key}' {exc}", key)
        return None
    if positive and value <= 0:
        unit = _SI_UNIT[dimension]
        problems.add(where, item, f"'{key}' must be > 0 {unit}, got {table[key]!r}", key)
        return None
    return value


def _get_choice(table: Mapping, key: str, choices: Iterable[str], problems: _Problems,
                where: tuple, item: str, default: Any = ...) -> str | None:
    choices = tuple(choices)
    if key not in table:
        if default is ...:
            problems.add(where, item, f"missing '{key}' (one of {', '.join(choices)})")
            return None
        return default
    value = table[key]
    if value not in choices:
        problems.add(where, item, f"'{key}' must be one of {', '.join(choices)}, got {value!r}", key)
        return None
    return value


def _unknown_keys(table: Mapping, allowed: set, problems: _Problems, where: tuple, item: str) -> None:
    for key in table:
        if key not in allowed:
            problems.add(where, item, f"unknown key '{key}' (allowed: {', '.join(sorted(allowed))})", key)


def _segment_from_dict(i: int, d: Any, problems: _Problems) -> tuple[str | None, Segment | None]:
    """Parse segment ``i`` (1-based); return its type (if known) and the segment (if valid)."""
    where, item = ("segment", i), f"segment {i}"
    if not isinstance(d, Mapping):
        problems.add(where, item, f"must be a table, got {d!r}")
        return None, None
    kind = _get_choice(d, "type", _SEGMENT_KEYS, problems, where, item)
    if kind is None:
        return None, None
    item = f"segment {i} ({kind})"
    _unknown_keys(d, _SEGMENT_KEYS[kind], problems, where, item)
    n_before = len(problems)
    fields: dict[str, Any] = {"length": _get(d, "length", "length", problems, where, item, positive=True)}
    if kind == "straight":
        cls: type = Straight
    elif kind == "transition":
        fields["shape"] = _get_choice(d, "shape", TRANSITION_SHAPES, problems, where, item, default="linear")
        cls = Transition
    else:
        fields["radius"] = _get(d, "radius", "length", problems, where, item, positive=True)
        fields["direction"] = _get_choice(d, "direction", DIRECTIONS, problems, where, item)
        fields["cant"] = _get(d, "cant", "length", problems, where, item, default=0.0)
        cls = Curve
    if len(problems) > n_before:
        return kind, None
    return kind, cls(**fields)


def read_profile_csv(path: str | Path) -> ProfileIrregularity:
    """Read a measured alignment from a CSV file.

    Two columns: distance s [m], yR [m]; separated by commas (or semicolons, tabs,
    spaces). Blank lines and lines starting with ``#`` are skipped; the first other
    line may be a header (any non-numeric first line). Distances must be strictly
    increasing. Values are linearly interpolated (:class:`ProfileIrregularity`).

    Raises
    ------
    TrackError
        Listing every bad row as ``<file>:<line>: <what is wrong>``, or if the file
        cannot be read.
    """
    path = Path(path)
    source = str(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise TrackError(source, [f"{source}: cannot read the file: {exc}"]) from None
    problems: list[str] = []
    rows: list[tuple[int, float, float]] = []
    first_data_line = True
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        cells = [c for c in re.split(r"[,;\s]+", line) if c]
        if len(cells) != 2:
            if first_data_line and not _all_numeric(cells):
                first_data_line = False
                continue  # header
            problems.append(
                f"{source}:{lineno}: expected 2 columns (distance, yR), got {len(cells)}: {line!r}"
            )
            first_data_line = False
            continue
        try:
            d, v = float(cells[0]), float(cells[1])
        except ValueError:
            if first_data_line:
                first_data_line = False
                continue  # header
            problems.append(f"{source}:{lineno}: not a number in {line!r}")
            continue
        first_data_line = False
        if not (math.isfinite(d) and math.isfinite(v)):
            problems.append(f"{source}:{lineno}: values must be finite, got {line!r}")
            continue
        if rows and d <= rows[-1][1]:
            problems.append(
                f"{source}:{lineno}: distance {d} is not greater than {rows[-1][1]} on line {rows[-1][0]}"
            )
            continue
        rows.append((lineno, d, v))
    if not problems and len(rows) < 2:
        problems.append(f"{source}: need at least two data rows, found {len(rows)}")
    if problems:
        raise TrackError(source, problems)
    return ProfileIrregularity([r[1] for r in rows], [r[2] for r in rows], source=source)


def _all_numeric(cells: Sequence[str]) -> bool:
    try:
        [float(c) for c in cells]
    except ValueError:
        return False
    return True


def _irregularity_from_dict(d: Any, problems: _Problems, base_dir: Path) -> Irregularity | None:
    where, item = ("irregularity",), "irregularity"
    if not isinstance(d, Mapping):
        problems.add(where, item, f"must be a table, got {d!r}")
        return None
    kind = _get_choice(d, "type", _IRREGULARITY_KEYS, problems, where, item)
    if kind is None:
        return None
    item = f"irregularity ({kind})"
    _unknown_keys(d, _IRREGULARITY_KEYS[kind], problems, where, item)
    n_before = len(problems)
    if kind == "none":
        return NoIrregularity()
    if kind == "sinusoid":
        amplitude = _get(d, "amplitude", "length", problems, where, item)
        wavelength = _get(d, "wavelength", "length", problems, where, item, positive=True)
        phase = _get(d, "phase", "angle", problems, where, item, default=0.0)
        if len(problems) > n_before:
            return None
        return SinusoidIrregularity(amplitude, wavelength, phase)
    if kind == "csv":
        name = d.get("file")
        if not isinstance(name, str) or not name:
            key = "file" if "file" in d else None
            problems.add(where, item, f"'file' must be the path of a CSV file, got {name!r}", key)
            return None
        path = Path(name)
        if not path.is_absolute():
            path = base_dir / path
        try:
            return read_profile_csv(path)
        except TrackError as exc:
            for message in exc.problems:
                problems.add(where, item, message, "file")
            return None
    # spectrum
    name = d.get("spectrum")
    spectrum = None
    if not isinstance(name, str):
        problems.add(where, item, f"'spectrum' must be one of {', '.join(SPECTRA)}, got {name!r}",
                     "spectrum" if "spectrum" in d else None)
    else:
        try:
            spectrum = get_spectrum(name)
        except KeyError as exc:
            problems.add(where, item, str(exc.args[0]), "spectrum")
    seed = d.get("seed", 0)
    if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
        problems.add(where, item, f"'seed' must be a non-negative integer, got {seed!r}", "seed")
    kwargs = {
        key: _get(d, key, "length", problems, where, item, default=default, positive=True)
        for key, default in (("wavelength_min", 3.0), ("wavelength_max", 120.0), ("period", 10_000.0))
    }
    if len(problems) > n_before:
        return None
    try:
        return SpectrumIrregularity(spectrum, seed, **kwargs)
    except ValueError as exc:
        problems.add(where, item, str(exc).removeprefix("SpectrumIrregularity: "))
        return None


def track_from_dict(
    d: Mapping[str, Any],
    source: str = "<dict>",
    *,
    text: str | None = None,
    base_dir: str | Path | None = None,
) -> Track:
    """Build a :class:`Track` from the parsed content of a track file.

    Parameters
    ----------
    d : mapping
        Parsed TOML: optional ``speed``, ``name``, ``description``; an array of
        ``segment`` tables; an optional ``irregularity`` table (see ``docs/track.md``).
        Quantities are numbers in SI units or strings with a unit (``"95 mm"``,
        ``"400 m"``, ``"120 km/h"``; units m, mm, km, m/s, km/h, and rad, deg for a
        phase).
    source : str
        Name of the file, used in messages.
    text : str, optional
        The TOML text ``d`` was parsed from; only used to give line numbers.
    base_dir : path, optional
        Directory against which a relative CSV ``file`` is resolved; default the
        directory of ``source``.

    Returns
    -------
    Track

    Raises
    ------
    TrackError
        Listing every problem found, each as ``<file>:<line>: segment <i> (<type>):
        <what is wrong>`` (segments are numbered from 1 in file order).
    """
    lines = _Lines(text)
    problems = _Problems(source, lines)
    base = Path(base_dir) if base_dir is not None else Path(source).parent
    top = ("",)
    if not isinstance(d, Mapping):
        raise TrackError(source, [f"{source}: the track must be a table, got {type(d).__name__}"])
    _unknown_keys(d, _TOP_KEYS, problems, top, "track")
    for key in ("name", "description"):
        if key in d and not isinstance(d[key], str):
            problems.add(top, "track", f"'{key}' must be a string", key)
    speed = None
    if "speed" in d:
        speed = _get(d, "speed", "speed", problems, top, "track", positive=True)
    raw_segments = d.get("segment")
    parsed: list[tuple[str | None, Segment | None]] = []
    if raw_segments is None:
        problems.add(top, "track", "no [[segment]] given")
    elif not isinstance(raw_segments, list):
        problems.add(top, "track", "'segment' must be an array of tables ([[segment]])", "segment")
    else:
        parsed = [_segment_from_dict(i, sd, problems) for i, sd in enumerate(raw_segments, 1)]
    kinds = [kind for kind, _ in parsed]
    segments = [seg for _, seg in parsed]
    for i in range(1, len(kinds)):
        if kinds[i - 1] == kinds[i] == "transition":
            problems.add(("segment", i + 1), f"segment {i + 1} (transition)",
                         f"follows another transition (segment {i}); a transition ramps between "
                         "its neighbours, so put a straight or a curve between them")
    irregularity: Irregularity | None = NoIrregularity()
    if "irregularity" in d:
        irregularity = _irregularity_from_dict(d["irregularity"], problems, base)
    if len(problems):
        raise TrackError(source, problems.items)
    return Track(tuple(segments), irregularity, speed)  # type: ignore[arg-type]


def load_track(path: str | Path) -> Track:
    """Read a TOML track file (format in ``docs/track.md``).

    Raises
    ------
    TrackError
        If the file cannot be read or parsed, or describes a bad track; the message
        names the file, the line where known, the item and every problem.
    """
    path = Path(path)
    source = str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise TrackError(source, [f"{source}: cannot read the file: {exc}"]) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        match = re.search(r"line (\d+)", str(exc))
        where = f"{source}:{match.group(1)}" if match else source
        raise TrackError(source, [f"{where}: not valid TOML: {exc}"]) from None
    return track_from_dict(data, source, text=text, base_dir=path.parent)
