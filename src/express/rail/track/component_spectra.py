"""The track's components as random processes: their seeds and their band-limited spectra.

This module owns what ties a track's random components together, in the time domain and
in the frequency domain (``docs/track.md``, "Random components"; ``docs/ride.md``):

* :func:`component_seed`: the seed of each component derived from one track seed, so that
  the components of one track are drawn from different random streams (uncorrelated);
* :class:`BandLimitedSpectrum`: a spectrum cut to a wavenumber band, the expected PSD of a
  realisation (:class:`~express.rail.track.irregularity.SpectrumIrregularity`) drawn over
  that band;
* :func:`track_spectra`: the spectrum of every random component of a
  :class:`~express.rail.track.geometry.Track`, for the frequency-domain ride, and a note
  for every component that is a deterministic or measured shape instead.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from express.base.diagnostics import ArgumentError
from express.rail.track._common import FloatArray
from express.rail.track.geometry import TRACK_COMPONENTS, Track
from express.rail.track.irregularity import NoIrregularity, SpectrumIrregularity
from express.rail.track.spectra import TrackSpectrum

__all__ = ["BandLimitedSpectrum", "component_seed", "track_spectra"]

#: Relative tolerance of the band edges of :meth:`BandLimitedSpectrum.psd`.
_EDGE = 1e-12


def component_seed(seed: int, component: str) -> int:
    """The seed of one component's phases, derived from the track's ``seed``.

    The alignment takes ``seed`` itself (so a file written before the other components
    could be random draws the same alignment); vertical level, cross level and gauge take
    the first 32-bit word of ``numpy.random.SeedSequence([seed, i])`` with ``i`` their
    index in :data:`~express.rail.track.geometry.TRACK_COMPONENTS` (1, 2, 3). Different
    seeds give independent phase streams of ``numpy.random.default_rng``, so the
    components of one track are uncorrelated (in expectation over the phases; a finite
    realisation has a sample cross-correlation of about ``1/sqrt(N_eff)``, see
    ``docs/track.md``).

    Parameters
    ----------
    seed : int
        The track's seed, >= 0.
    component : str
        One of :data:`~express.rail.track.geometry.TRACK_COMPONENTS`.

    Returns
    -------
    int
        >= 0.

    Raises
    ------
    ArgumentError
        For a negative or non-integer seed or an unknown component.
    """
    if not isinstance(seed, (int, np.integer)) or isinstance(seed, bool) or seed < 0:
        raise ArgumentError(f"component_seed: 'seed' must be a non-negative integer, got {seed!r}")
    if component not in TRACK_COMPONENTS:
        raise ArgumentError(f"component_seed: unknown component {component!r} (known: {', '.join(TRACK_COMPONENTS)})")
    index = TRACK_COMPONENTS.index(component)
    if index == 0:
        return int(seed)
    return int(np.random.SeedSequence([int(seed), index]).generate_state(1)[0])


@dataclass(frozen=True)
class BandLimitedSpectrum(TrackSpectrum):
    """``base`` inside the band ``[omega_min, omega_max]`` [rad/m], zero outside.

    The expected PSD of a realisation drawn over that band, whose mean square over a
    period is ``base.variance(omega_min, omega_max)``; :meth:`variance` over any band is
    that of the overlap, exactly.

    Parameters
    ----------
    base : TrackSpectrum
        The spectrum; its component is this one's.
    omega_min, omega_max : float
        Band edges [rad/m], ``0 < omega_min < omega_max``.
    """

    base: TrackSpectrum
    omega_min: float
    omega_max: float

    def __post_init__(self) -> None:
        if not (np.isfinite(self.omega_min) and np.isfinite(self.omega_max) and 0 < self.omega_min < self.omega_max):
            raise ArgumentError(f"BandLimitedSpectrum: need 0 < omega_min < omega_max, got {self.omega_min!r} "
                                f"and {self.omega_max!r}")

    @property
    def name(self) -> str:  # type: ignore[override]
        """The base spectrum's name with the band in wavelengths."""
        return (f"{self.base.name}, wavelengths {2 * np.pi / self.omega_max:.4g}-"
                f"{2 * np.pi / self.omega_min:.4g} m")

    @property
    def component(self) -> str:  # type: ignore[override]
        """The base spectrum's component."""
        return self.base.component

    def psd(self, omega: ArrayLike) -> FloatArray:
        """``base.psd`` [m^2/(rad/m)] inside the band, 0 outside; the edges are inside to a
        relative 1e-12 (a frequency grid from ``v / wavelength`` meets them to rounding)."""
        w = np.asarray(omega, dtype=float)
        inside = (w >= self.omega_min * (1 - _EDGE)) & (w <= self.omega_max * (1 + _EDGE))
        return np.where(inside, self.base.psd(np.clip(w, self.omega_min, self.omega_max)), 0.0)

    def primitive(self, omega: FloatArray) -> FloatArray:
        """``base.primitive`` of ``omega`` clipped to the band [m^2]."""
        return np.asarray(self.base.primitive(np.clip(np.asarray(omega, dtype=float), self.omega_min,
                                                      self.omega_max)), dtype=float)


def track_spectra(track: Track) -> tuple[dict[str, TrackSpectrum], tuple[str, ...]]:
    """The spectrum of every random component of ``track``, each cut to its band.

    Parameters
    ----------
    track : Track

    Returns
    -------
    spectra : dict of str to BandLimitedSpectrum
        By component (:data:`~express.rail.track.geometry.TRACK_COMPONENTS`), for each
        component that is a :class:`~express.rail.track.irregularity.SpectrumIrregularity`:
        its spectrum over its wavelength band.
    notes : tuple of str
        One per component that is a deterministic or measured shape (it has no spectrum).
    """
    spectra: dict[str, TrackSpectrum] = {}
    notes = []
    for name in TRACK_COMPONENTS:
        component = track.component(name)
        if isinstance(component, SpectrumIrregularity):
            spectra[name] = BandLimitedSpectrum(component.psd_spectrum, 2 * np.pi / component.wavelength_max,
                                                2 * np.pi / component.wavelength_min)
        elif not isinstance(component, NoIrregularity):
            notes.append(f"{name}: the track file gives a {type(component).__name__} (a deterministic or measured "
                         "shape, not a spectrum): left at zero in the frequency domain")
    return spectra, tuple(notes)
