"""Lateral track irregularity (alignment) ``yR(s)`` as data.

This module owns the irregularities a :class:`~express.rail.track.geometry.Track`
carries: none (:class:`NoIrregularity`), a sinusoid (:class:`SinusoidIrregularity`), a
measured profile interpolated from a table (:class:`ProfileIrregularity`) and a random
profile drawn from a published spectrum (:class:`SpectrumIrregularity`, spectra in
:mod:`express.rail.track.spectra`).

The same classes carry the track's other components (vertical level, cross level,
gauge: :class:`~express.rail.track.geometry.Track`, ``docs/track.md``, "Track components"),
with ``value`` in metres of that component. ``yR`` [m] is the lateral displacement of the
track, positive to the LEFT (y left);
``s`` [m] the distance along the track. Every irregularity is defined for every ``s``
(it is not cut at the ends of the track) and has ``value(s)`` (also ``irr(s)``) and
``rate(s) = d yR / ds`` [m/m], for a float (float out) or an array.

Limits (checked when a record is made, so that no work starts on absurd input):
:data:`MAX_LATERAL_IRREGULARITY` on amplitudes and tabulated values,
:data:`MAX_HARMONICS` on the cosines of a spectrum realisation, :data:`MAX_SAMPLES` on
:meth:`SpectrumIrregularity.tabulate`.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from express.base.diagnostics import ArgumentError
from express.rail.track._common import FieldProblem, FloatArray, as_input, as_output, is_finite_number, raise_if
from express.rail.track.spectra import SPECTRA, TrackSpectrum, get_spectrum

__all__ = [
    "MAX_HARMONICS",
    "MAX_LATERAL_IRREGULARITY",
    "MAX_SAMPLES",
    "Harmonics",
    "Irregularity",
    "NoIrregularity",
    "ProfileIrregularity",
    "SinusoidIrregularity",
    "SpectrumIrregularity",
]

#: Largest |yR| [m] accepted for an amplitude or a tabulated value. Real alignment
#: errors are millimetres; 0.1 m is ten flange clearances, so a larger value is a unit
#: mistake (millimetres written as metres).
MAX_LATERAL_IRREGULARITY = 0.1
#: Most cosines in one spectrum realisation, ``period * (1/wavelength_min -
#: 1/wavelength_max)``. Evaluating yR costs work in proportion to harmonics times
#: points (the default realisation has 3250 harmonics).
MAX_HARMONICS = 200_000
#: Most points :meth:`SpectrumIrregularity.tabulate` makes.
MAX_SAMPLES = 10_000_000


class Irregularity(ABC):
    """Lateral track irregularity ``yR(s)`` [m] (alignment), y positive to the left.

    Subclasses are callable: ``irr(s)`` is ``irr.value(s)``.
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
        arr, scalar = as_input(s)
        return as_output(np.zeros_like(arr), scalar)

    def rate(self, s: ArrayLike) -> FloatArray | float:
        return self.value(s)


@dataclass(frozen=True)
class SinusoidIrregularity(Irregularity):
    """Sinusoidal alignment ``yR = amplitude * sin(2 pi s / wavelength + phase)``.

    Parameters
    ----------
    amplitude : float
        Amplitude [m], ``|amplitude| <=`` :data:`MAX_LATERAL_IRREGULARITY`.
    wavelength : float
        Wavelength [m], > 0.
    phase : float
        Phase [rad] at s = 0; default 0.
    """

    amplitude: float
    wavelength: float
    phase: float = 0.0

    @staticmethod
    def field_problems(amplitude: Any, wavelength: Any, phase: Any = 0.0) -> list[FieldProblem]:
        """``(field, message)`` for every bad value (empty if none)."""
        out: list[FieldProblem] = []
        if not is_finite_number(amplitude):
            out.append(("amplitude", f"'amplitude' must be a finite number of metres, got {amplitude!r}"))
        elif abs(amplitude) > MAX_LATERAL_IRREGULARITY:
            out.append(("amplitude", f"'amplitude' must be at most {MAX_LATERAL_IRREGULARITY} m in size, "
                                     f"got {amplitude!r} m (millimetres written as metres?)"))
        if not is_finite_number(wavelength) or wavelength <= 0:
            out.append(("wavelength", f"'wavelength' must be > 0 m, got {wavelength!r}"))
        if not is_finite_number(phase):
            out.append(("phase", f"'phase' must be a finite number, got {phase!r}"))
        return out

    def __post_init__(self) -> None:
        raise_if(self.field_problems(self.amplitude, self.wavelength, self.phase), "SinusoidIrregularity")

    def value(self, s: ArrayLike) -> FloatArray | float:
        arr, scalar = as_input(s)
        k = 2.0 * np.pi / self.wavelength
        return as_output(self.amplitude * np.sin(k * arr + self.phase), scalar)

    def rate(self, s: ArrayLike) -> FloatArray | float:
        arr, scalar = as_input(s)
        k = 2.0 * np.pi / self.wavelength
        return as_output(self.amplitude * k * np.cos(k * arr + self.phase), scalar)


def _profile_problems(distance: FloatArray, yr: FloatArray) -> list[FieldProblem]:
    if distance.shape != yr.shape:
        return [("yr", f"distance and yr differ in length ({distance.size} and {yr.size})")]
    if distance.size < 2:
        return [("distance", f"need at least two points, got {distance.size}")]
    if not (np.all(np.isfinite(distance)) and np.all(np.isfinite(yr))):
        return [("distance", "distance and yr must be finite")]
    if np.any(np.diff(distance) <= 0):
        return [("distance", "distance must be strictly increasing")]
    if np.max(np.abs(yr)) > MAX_LATERAL_IRREGULARITY:
        return [("yr", f"|yr| reaches {np.max(np.abs(yr)):.6g} m, more than {MAX_LATERAL_IRREGULARITY} m "
                       "(millimetres written as metres?)")]
    return []


@dataclass(frozen=True, eq=False)
class ProfileIrregularity(Irregularity):
    """Tabulated (measured) alignment, linearly interpolated.

    Outside the tabulated range the end values are held (a constant lateral offset,
    which does not excite the vehicle), so that no step appears at the ends.

    Parameters
    ----------
    distance : array_like, shape (n,)
        Distances s [m], strictly increasing, n >= 2.
    yr : array_like, shape (n,)
        yR [m] at those distances, ``|yr| <=`` :data:`MAX_LATERAL_IRREGULARITY`.
    source : str
        Where the data came from (file name), for messages.
    """

    distance: FloatArray
    yr: FloatArray
    source: str = "<array>"

    @staticmethod
    def field_problems(distance: ArrayLike, yr: ArrayLike) -> list[FieldProblem]:
        """``(field, message)`` for every bad value (empty if none)."""
        return _profile_problems(np.ravel(np.asarray(distance, dtype=float)), np.ravel(np.asarray(yr, dtype=float)))

    def __post_init__(self) -> None:
        raise_if(self.field_problems(self.distance, self.yr), f"ProfileIrregularity from {self.source}")

    def _samples(self) -> tuple[FloatArray, FloatArray]:
        return np.ravel(np.asarray(self.distance, dtype=float)), np.ravel(np.asarray(self.yr, dtype=float))

    def value(self, s: ArrayLike) -> FloatArray | float:
        arr, scalar = as_input(s)
        distance, yr = self._samples()
        return as_output(np.interp(arr, distance, yr), scalar)

    def rate(self, s: ArrayLike) -> FloatArray | float:
        arr, scalar = as_input(s)
        distance, yr = self._samples()
        slopes = np.diff(yr) / np.diff(distance)
        i = np.clip(np.searchsorted(distance, arr, side="right") - 1, 0, slopes.size - 1)
        out = np.where((arr >= distance[0]) & (arr < distance[-1]), slopes[i], 0.0)
        return as_output(out, scalar)


@dataclass(frozen=True, eq=False)
class Harmonics:
    """The cosines of a spectrum realisation: ``yR = sum_k a_k cos(Omega_k s + phi_k)``.

    Attributes
    ----------
    spectrum : TrackSpectrum
        The spectrum drawn from.
    wavenumbers : ndarray, shape (n,)
        ``Omega_k`` [rad/m].
    amplitudes : ndarray, shape (n,)
        ``a_k`` [m].
    phases : ndarray, shape (n,)
        ``phi_k`` [rad].
    """

    spectrum: TrackSpectrum
    wavenumbers: FloatArray
    amplitudes: FloatArray
    phases: FloatArray

    @classmethod
    def draw(cls, spectrum: TrackSpectrum, seed: int, wavelength_min: float, wavelength_max: float,
             period: float) -> Harmonics:
        """Draw the harmonics of :class:`SpectrumIrregularity` (see there); arrays read-only."""
        w_lo, w_hi = 2 * np.pi / wavelength_max, 2 * np.pi / wavelength_min
        dw = 2 * np.pi / period
        w = _harmonic_numbers(period, wavelength_min, wavelength_max) * dw
        # bins between midpoints; the outer bins reach the band edges
        edges = np.concatenate([[w_lo], 0.5 * (w[:-1] + w[1:]), [w_hi]])
        power = np.asarray(spectrum.variance(edges[:-1], edges[1:]), dtype=float)
        phases = np.random.default_rng(int(seed)).uniform(0.0, 2 * np.pi, size=w.size)
        amplitudes = np.sqrt(2 * power)
        for arr in (w, amplitudes, phases):
            arr.setflags(write=False)
        return cls(spectrum, w, amplitudes, phases)

    def evaluate(self, s: FloatArray, derivative: bool = False) -> FloatArray:
        """``sum_k a_k cos(Omega_k s + phi_k)`` [m], or its derivative in s [m/m].

        Parameters
        ----------
        s : ndarray, shape (p,)
            Distances [m].
        derivative : bool
            If true, ``-sum_k a_k Omega_k sin(Omega_k s + phi_k)``.

        Returns
        -------
        ndarray, shape (p,)

        Notes
        -----
        The sum is ``Re sum_k c_k exp(i Omega_k s)`` with ``c_k = a_k exp(i phi_k)``
        (times ``i Omega_k`` for the derivative). When the wavenumbers are consecutive
        multiples of one step ``dw`` (every drawn realisation), blocks of 64 of them share
        ``exp(i Omega_b s)`` and the rest is a polynomial in ``exp(i dw s)`` summed by
        Horner's rule: the same sum, exact to rounding, at about a fifth of the cost of
        one cosine per term. Otherwise the cosines are summed directly.
        """
        s = np.asarray(s, dtype=float)
        coefficients = self.amplitudes * np.exp(1j * self.phases)
        if derivative:
            coefficients = 1j * self.wavenumbers * coefficients
        w = self.wavenumbers
        if w.size >= 2 and np.allclose(np.diff(w), w[1] - w[0], rtol=1e-9, atol=0.0):
            return _sum_progression(s, w[0], w[1] - w[0], coefficients)
        out = np.empty_like(s)
        chunk = max(1, 2_000_000 // max(w.size, 1))  # bounds the (chunk, n) temporary to 32 MB
        for i in range(0, s.size, chunk):
            out[i : i + chunk] = (np.exp(1j * np.outer(s[i : i + chunk], w)) @ coefficients).real
        return out


def _sum_progression(s: FloatArray, w0: float, dw: float, coefficients: np.ndarray) -> FloatArray:
    """``Re sum_k c_k exp(i (w0 + k dw) s)``, k = 0..n-1, by blocks of Horner sums."""
    n = coefficients.size
    size = min(64, n)
    blocks = -(-n // size)
    padded = np.zeros(blocks * size, dtype=complex)
    padded[:n] = coefficients
    table = padded.reshape(blocks, size)  # table[b, m] is c_{b size + m}
    block_start = w0 + dw * size * np.arange(blocks)
    out = np.empty_like(s)
    chunk = max(1, 500_000 // blocks)  # bounds each (chunk, blocks) temporary to 8 MB
    for i in range(0, s.size, chunk):
        part = s[i : i + chunk]
        step = np.exp(1j * dw * part)[:, None]
        total = np.broadcast_to(table[:, -1], (part.size, blocks)).copy()
        for m in range(size - 2, -1, -1):
            total *= step
            total += table[:, m]
        out[i : i + chunk] = (np.exp(1j * np.outer(part, block_start)) * total).sum(axis=1).real
    return out


def _harmonic_numbers(period: float, wavelength_min: float, wavelength_max: float) -> FloatArray:
    """The k with ``2 pi k / period`` in the band (as floats); check the count first."""
    first = math.ceil(period / wavelength_max - 1e-12)
    last = math.floor(period / wavelength_min + 1e-12)
    return np.arange(first, last + 1, dtype=float)


def _spectrum_problems(spectrum: Any, seed: Any, wavelength_min: Any, wavelength_max: Any,
                       period: Any) -> list[FieldProblem]:
    out: list[FieldProblem] = []
    if isinstance(spectrum, str):
        try:
            get_spectrum(spectrum)
        except KeyError as exc:
            out.append(("spectrum", str(exc.args[0])))
    elif not isinstance(spectrum, TrackSpectrum):
        out.append(("spectrum", f"'spectrum' must be one of {', '.join(SPECTRA)} or a TrackSpectrum, "
                                f"got {spectrum!r}"))
    if not isinstance(seed, (int, np.integer)) or isinstance(seed, bool) or seed < 0:
        out.append(("seed", f"'seed' must be a non-negative integer, got {seed!r}"))
    lengths = [(key, f"'{key}' must be > 0 m, got {value!r}")
               for key, value in (("wavelength_min", wavelength_min), ("wavelength_max", wavelength_max),
                                  ("period", period))
               if not (is_finite_number(value) and value > 0)]
    if lengths:
        return out + lengths
    if wavelength_min >= wavelength_max:
        out.append(("wavelength_min", f"'wavelength_min' ({wavelength_min}) must be < 'wavelength_max' "
                                      f"({wavelength_max})"))
    elif period < wavelength_max:
        out.append(("period", f"'period' ({period}) must be >= 'wavelength_max' ({wavelength_max})"))
    else:
        count = period / wavelength_min - period / wavelength_max
        if count > MAX_HARMONICS:
            out.append(("period", f"'period' ({period:g} m) with 'wavelength_min' ({wavelength_min:g} m) and "
                                  f"'wavelength_max' ({wavelength_max:g} m) needs {count:.3g} harmonics, more "
                                  f"than the limit {MAX_HARMONICS}: shorten the period or raise wavelength_min"))
        elif _harmonic_numbers(period, wavelength_min, wavelength_max).size == 0:
            out.append(("period", f"no wavenumber 2 pi k / period of the period {period} m lies in the band "
                                  f"{wavelength_min} m to {wavelength_max} m: lengthen the period"))
    return out


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
    spectrum : TrackSpectrum or str
        The spectrum, or its name in :data:`~express.rail.track.spectra.SPECTRA`
        (``"erri_low"``, ``"erri_high"``, ``"fra1"`` ... ``"fra6"``, ``"aar1"`` ...
        ``"aar6"``); kept as given, the
        spectrum used is :attr:`psd_spectrum`.
    seed : int
        Seed of the phases, >= 0; the same seed gives the same profile. Default 0.
    wavelength_min, wavelength_max : float
        Wavelength band [m]; default 3 m to 120 m (the wavelengths that excite the
        lateral modes of a vehicle at ordinary speeds; the FRA spectrum diverges at long
        wavelengths, so some upper bound is needed).
    period : float
        Length after which the profile repeats [m], >= ``wavelength_max``; default
        10 km. ``period * (1/wavelength_min - 1/wavelength_max)``, the number of
        cosines, may not exceed :data:`MAX_HARMONICS`.

    Raises
    ------
    ArgumentError
        Naming every bad field, before any harmonic is drawn.
    """

    spectrum: TrackSpectrum | str
    seed: int = 0
    wavelength_min: float = 3.0
    wavelength_max: float = 120.0
    period: float = 10_000.0

    @staticmethod
    def field_problems(spectrum: Any, seed: Any = 0, wavelength_min: Any = 3.0, wavelength_max: Any = 120.0,
                       period: Any = 10_000.0) -> list[FieldProblem]:
        """``(field, message)`` for every bad value (empty if none), bounds included."""
        return _spectrum_problems(spectrum, seed, wavelength_min, wavelength_max, period)

    def __post_init__(self) -> None:
        raise_if(self.field_problems(self.spectrum, self.seed, self.wavelength_min, self.wavelength_max,
                                     self.period), "SpectrumIrregularity")

    @property
    def psd_spectrum(self) -> TrackSpectrum:
        """The spectrum itself (looked up when :attr:`spectrum` is a name)."""
        return get_spectrum(self.spectrum) if isinstance(self.spectrum, str) else self.spectrum

    @cached_property
    def harmonics(self) -> Harmonics:
        """The drawn cosines (computed on first use, then kept)."""
        return Harmonics.draw(self.psd_spectrum, int(self.seed), self.wavelength_min, self.wavelength_max,
                              self.period)

    @property
    def wavenumbers(self) -> FloatArray:
        """Wavenumbers ``Omega_k`` [rad/m]."""
        return self.harmonics.wavenumbers

    @property
    def amplitudes(self) -> FloatArray:
        """Amplitudes ``a_k`` [m]."""
        return self.harmonics.amplitudes

    @property
    def phases(self) -> FloatArray:
        """Phases ``phi_k`` [rad]."""
        return self.harmonics.phases

    @property
    def band_variance(self) -> float:
        """Integral of the PSD over the band [m^2] (= mean square over one period)."""
        w_lo, w_hi = 2 * np.pi / self.wavelength_max, 2 * np.pi / self.wavelength_min
        return float(self.psd_spectrum.variance(w_lo, w_hi))

    def _sum(self, s: ArrayLike, derivative: bool) -> FloatArray | float:
        arr, scalar = as_input(s)
        out = self.harmonics.evaluate(arr.ravel(), derivative=derivative)
        return as_output(out.reshape(arr.shape), scalar)

    def value(self, s: ArrayLike) -> FloatArray | float:
        return self._sum(s, derivative=False)

    def rate(self, s: ArrayLike) -> FloatArray | float:
        return self._sum(s, derivative=True)

    def tabulate(self, start: float, stop: float, step: float = 0.25) -> ProfileIrregularity:
        """Sample the profile into a :class:`ProfileIrregularity` (fast to evaluate).

        Parameters
        ----------
        start, stop : float
            Range of s [m] to cover (``stop`` included), ``stop > start``.
        step : float
            Sampling step [m], > 0; keep it well below ``wavelength_min`` (default
            0.25 m). At most :data:`MAX_SAMPLES` points.

        Raises
        ------
        ArgumentError
            For a bad range or step, or too many points.
        """
        if not (is_finite_number(start) and is_finite_number(stop) and stop > start):
            raise ArgumentError(f"tabulate: need finite start < stop, got {start!r} and {stop!r}")
        if not (is_finite_number(step) and step > 0):
            raise ArgumentError(f"tabulate: 'step' must be > 0 m, got {step!r}")
        count = (stop - start) / step + 1
        if count > MAX_SAMPLES:
            raise ArgumentError(f"tabulate: {count:.3g} points from {start:g} m to {stop:g} m every {step:g} m, "
                             f"more than the limit {MAX_SAMPLES}: use a larger step")
        n = max(2, math.ceil((stop - start) / step) + 1)
        d = np.linspace(start, start + (n - 1) * step, n)
        d.setflags(write=False)
        yr = np.asarray(self.value(d), dtype=float)
        yr.setflags(write=False)
        return ProfileIrregularity(d, yr, source=f"{self.psd_spectrum.name}, seed {self.seed}")
