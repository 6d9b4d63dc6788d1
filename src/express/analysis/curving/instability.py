"""EN 14363's instability criterion of a time run: the sliding rms of the track shift force.

On straight track and in large curves a vehicle is judged unstable when the track shift
force of a wheelset, ``ΣY``, band-pass filtered around the frequency of the instability
``f0`` (``f0 ± 2 Hz``), has a sliding rms over 100 m of track that exceeds half of
Prud'homme's limit, ``(ΣY)lim / 2`` (EN 14363:2005 and UIC 518, the stability test; the
processing as summarised in the GENSYS course notes on UIC 518 / EN 14363, "Acceptance
test": ``ΣY`` instability criterion, filter ``f0 ± 2 Hz``, sliding rms; ``docs/curving.md``):

* ``f0``: the frequency of the largest peak of the spectrum of ``ΣY`` (its mean
  removed) between :data:`BAND_LOW` and :data:`BAND_HIGH`, the band where hunting lies;
* the filter: a 4th-order Butterworth band-pass ``f0 - 2 Hz ... f0 + 2 Hz`` (its lower
  edge at least :data:`BAND_LOW`), run forwards and backwards (zero phase, as an
  off-line evaluation may);
* windows of :data:`WINDOW` metres every :data:`STEP` metres; the rms over a window is
  ``sqrt(mean(x^2))`` of the filtered samples in it (the run's samples are equally
  spaced in time and, at a constant speed, in distance).

A run shorter than one window has no value (None); the standard's percentile treatment of
measured zones is not applied to a simulation (its largest window is reported).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["BAND_HIGH", "BAND_LOW", "HALF_WIDTH", "STEP", "WINDOW", "InstabilityRms", "instability_rms", "sliding_rms"]

#: Length of the sliding window [m] and the spacing of the windows [m].
WINDOW, STEP = 100.0, 10.0
#: Half width of the band-pass around f0 [Hz].
HALF_WIDTH = 2.0
#: Band searched for f0 [Hz] (hunting of rail vehicles: about 1 to 10 Hz).
BAND_LOW, BAND_HIGH = 0.5, 15.0


@dataclass(frozen=True)
class InstabilityRms:
    """The criterion's quantity for one wheelset.

    Attributes
    ----------
    frequency : float
        f0 [Hz], the centre of the band-pass.
    rms : numpy.ndarray, shape (windows,)
        Sliding rms of the filtered ``ΣY`` [N], one per window.
    starts : numpy.ndarray, shape (windows,)
        Distance at the start of each window [m].
    """

    frequency: float
    rms: np.ndarray
    starts: np.ndarray

    @property
    def largest(self) -> float:
        """The largest window's rms [N]."""
        return float(self.rms.max())


def sliding_rms(distance: np.ndarray, values: np.ndarray, window: float = WINDOW, step: float = STEP
                ) -> tuple[np.ndarray, np.ndarray]:
    """``(starts, rms)``: the rms of ``values`` (shape (N,)) over the samples of every
    window ``[s, s + window)`` of ``distance`` (increasing), one every ``step`` metres."""
    distance = np.asarray(distance, dtype=float)
    squares = np.concatenate([[0.0], np.cumsum(np.asarray(values, dtype=float) ** 2)])
    starts = np.arange(distance[0], distance[-1] - window + 1e-9, step)
    first = np.searchsorted(distance, starts, side="left")
    last = np.searchsorted(distance, starts + window, side="left")
    counts = np.maximum(last - first, 1)
    return starts, np.sqrt((squares[last] - squares[first]) / counts)


def instability_rms(distance: np.ndarray, speed: float, shift_force: np.ndarray) -> InstabilityRms | None:
    """The filtered sliding rms of one wheelset's ``ΣY`` (module docstring).

    Parameters
    ----------
    distance : numpy.ndarray, shape (N,)
        Distance run at each (equally spaced) instant [m].
    speed : float
        Running speed [m/s].
    shift_force : numpy.ndarray, shape (N,)
        ``ΣY`` of the wheelset [N].

    Returns
    -------
    InstabilityRms or None
        None for a run shorter than one window or sampled too coarsely for the band.
    """
    from scipy import signal

    distance = np.asarray(distance, dtype=float)
    if distance.size < 2 or distance[-1] - distance[0] < WINDOW or not speed > 0:
        return None
    rate = speed / float(np.median(np.diff(distance)))  # samples per second
    x = np.asarray(shift_force, dtype=float) - float(np.mean(shift_force))
    frequencies = np.fft.rfftfreq(x.size, 1.0 / rate)
    power = np.abs(np.fft.rfft(x * np.hanning(x.size))) ** 2
    band = (frequencies >= BAND_LOW) & (frequencies <= min(BAND_HIGH, 0.4 * rate))
    if not band.any():
        return None
    f0 = float(frequencies[band][np.argmax(power[band])])
    low, high = max(f0 - HALF_WIDTH, BAND_LOW), f0 + HALF_WIDTH
    if high >= 0.5 * rate:
        return None
    sections = signal.butter(4, [low, high], btype="bandpass", fs=rate, output="sos")
    filtered = signal.sosfiltfilt(sections, x)
    starts, rms = sliding_rms(distance, filtered)
    return InstabilityRms(f0, rms, starts) if rms.size and math.isfinite(float(rms.max())) else None
