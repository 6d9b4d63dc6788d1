"""Comfort frequency weightings: EN 12299 / ISO 2631 (Wb, Wc, Wd, Wk) and Sperling's B(f).

This module owns the weighting filters as their defining transfer functions and their
application to time histories.  Every weighting of ISO 2631-1 / ISO 8041 (and so of
EN 12299, which takes them from EN ISO 8041) is the product of four blocks in the
Laplace variable ``s`` [rad/s], with ``w_i = 2 pi f_i``::

    high-pass       H_h(s) = s^2 / (s^2 + w1 s / Q1 + w1^2)                (none if f1 = 0)
    low-pass        H_l(s) = w2^2 / (s^2 + w2 s / Q2 + w2^2)                (none if f2 = inf)
    a-v transition  H_t(s) = (1 + s / w3) / (1 + s / (Q4 w4) + s^2 / w4^2)  (f3, f4 may be inf)
    upward step     H_s(s) = (w5 / w6)^2 (1 + s/(Q5 w5) + s^2/w5^2) / (1 + s/(Q6 w6) + s^2/w6^2)
                    (= (s^2 + w5 s/Q5 + w5^2) / (s^2 + w6 s/Q6 + w6^2); none if f5 = f6 = inf)
    W(s) = K H_h H_l H_t H_s

with ``Q1 = Q2 = 1/sqrt(2)`` (second-order Butterworth band limits).  The parameters
(Hz) are those of ISO 8041 (table of the weightings' parameters, reproduced in public
instrument manuals, e.g. the Larson Davis HVM200 reference manual, table 3.1):

======  ====  ===  ====  ====  ====  ====  ====  ====  ====  =====
name    f1    f2   f3    f4    Q4    f5    Q5    f6    Q6    K
======  ====  ===  ====  ====  ====  ====  ====  ====  ====  =====
Wb      0.4   100  16    16    0.55  2.5   0.9   4     0.95  1.024
Wc      0.4   100  8     8     0.63  inf   -     inf   -     1
Wd      0.4   100  2     2     0.63  inf   -     inf   -     1
Wk      0.4   100  12.5  12.5  0.63  2.37  0.91  3.35  0.91  1
======  ====  ===  ====  ====  ====  ====  ====  ====  ====  =====

EN 12299 uses Wd for the longitudinal and lateral floor accelerations, Wb for the
vertical one and Wc for the seat back; Wk (ISO 2631-1, vertical seat) is kept because
ISO 2631-1 tabulates it, which checks the upward-step block that Wb shares.  (BS 6841
writes Wb's step with unit-gain polynomials and ``K = 0.4``; ``0.4 (4/2.5)^2 = 1.024``
is the same filter.)  These four are what the simplified method of EN 12299 (mean
comfort N_MV) needs.

Sperling's weightings (Sperling & Betzhold, 1956; the form used e.g. in GB 5599 and
in Forstberg, *Ride comfort and motion sickness in tilting trains*, KTH, 2000) are
amplitude factors of the frequency ``f`` [Hz]::

    B_z(f) = 0.588 sqrt( (1.911 f^2 + (0.25 f^2)^2)
                         / ((1 - 0.277 f^2)^2 + (1.563 f - 0.0368 f^3)^2) )    (vertical)
    B_y(f) = 1.25 B_z(f)                                                      (lateral)

``B_z`` is the modulus of ``0.588 (1.911^0.5 p + 0.25 p^2) / (1 + 1.563 p + 0.277 p^2
+ 0.0368 p^3)`` at ``p = i f`` (f in Hz, not rad/s): :func:`sperling_transfer`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.fft import next_fast_len

from express.base.diagnostics import InputError

__all__ = [
    "WB",
    "WC",
    "WD",
    "WEIGHTINGS",
    "WK",
    "FrequencyWeighting",
    "get_weighting",
    "sperling_transfer",
    "sperling_weighting",
    "weigh_time_history",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

_BUTTERWORTH_Q = 1.0 / math.sqrt(2.0)


@dataclass(frozen=True)
class FrequencyWeighting:
    """One ISO 8041 / ISO 2631 frequency weighting, as its parameters.

    Parameters
    ----------
    name : str
        ``"Wb"``, ``"Wd"``, ...
    f1, f2 : float
        High-pass and low-pass corner frequencies [Hz]; ``f1 = 0`` means no high-pass,
        ``f2 = inf`` no low-pass.
    f3, f4, Q4 : float
        Acceleration-velocity transition [Hz, Hz, -]; ``inf`` removes the matching term.
    f5, Q5, f6, Q6 : float
        Upward step [Hz, -, Hz, -]; ``f5 = f6 = inf`` means no step.
    K : float
        Gain (dimensionless).
    Q1, Q2 : float
        Quality factors of the band limits, ``1/sqrt(2)``.
    """

    name: str
    f1: float
    f2: float
    f3: float = math.inf
    f4: float = math.inf
    Q4: float = 1.0
    f5: float = math.inf
    Q5: float = 1.0
    f6: float = math.inf
    Q6: float = 1.0
    K: float = 1.0
    Q1: float = _BUTTERWORTH_Q
    Q2: float = _BUTTERWORTH_Q

    def __post_init__(self) -> None:
        problems = []
        for key in ("f1", "f2", "f3", "f4", "f5", "f6"):
            value = getattr(self, key)
            if not (isinstance(value, (int, float)) and not math.isnan(value) and value >= 0):
                problems.append(f"{key} must be a frequency >= 0 Hz (or inf), got {value!r}")
        for key in ("Q1", "Q2", "Q4", "Q5", "Q6", "K"):
            value = getattr(self, key)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                problems.append(f"{key} must be a finite number > 0, got {value!r}")
        if not problems and math.isinf(self.f5) != math.isinf(self.f6):
            problems.append("f5 and f6 must both be finite (an upward step) or both inf (none)")
        if not problems and (math.isinf(self.f1) or self.f2 == 0 or self.f4 == 0 or self.f3 == 0):
            problems.append("f1 must be finite and f2, f3, f4 > 0")
        if problems:
            raise InputError("\n".join(f"weighting {self.name}: {p}" for p in problems))

    def blocks(self, s: ArrayLike) -> dict[str, NDArray[Any]]:
        """The four blocks H_h, H_l, H_t, H_s at the Laplace values ``s`` [rad/s].

        Returns
        -------
        dict of str to numpy.ndarray, complex, shape of ``s``
            Keys ``"high_pass"``, ``"low_pass"``, ``"transition"``, ``"step"``.
        """
        s = np.asarray(s, dtype=complex)
        one: NDArray[Any] = np.ones(s.shape, dtype=complex)
        high: NDArray[Any]
        low: NDArray[Any]
        den: NDArray[Any]
        step: NDArray[Any]
        two_pi = 2.0 * math.pi
        if self.f1 > 0:
            w1 = two_pi * self.f1
            high = s**2 / (s**2 + w1 * s / self.Q1 + w1**2)
        else:
            high = one
        if math.isfinite(self.f2):
            w2 = two_pi * self.f2
            low = w2**2 / (s**2 + w2 * s / self.Q2 + w2**2)
        else:
            low = one
        num = one + (s / (two_pi * self.f3) if math.isfinite(self.f3) else 0.0)
        if math.isfinite(self.f4):
            w4 = two_pi * self.f4
            den = one + s / (self.Q4 * w4) + (s / w4) ** 2
        else:
            den = one
        transition = num / den
        if math.isfinite(self.f5):
            w5, w6 = two_pi * self.f5, two_pi * self.f6
            step = (
                (w5 / w6) ** 2 * (one + s / (self.Q5 * w5) + (s / w5) ** 2) / (one + s / (self.Q6 * w6) + (s / w6) ** 2)
            )
        else:
            step = one
        return {"high_pass": high, "low_pass": low, "transition": transition, "step": step}

    def transfer(self, s: ArrayLike) -> ComplexArray:
        """``W(s) = K H_h H_l H_t H_s`` at the Laplace values ``s`` [rad/s] (complex)."""
        b = self.blocks(s)
        return self.K * b["high_pass"] * b["low_pass"] * b["transition"] * b["step"]

    def response(self, frequencies: ArrayLike) -> ComplexArray:
        """Complex frequency response ``W(i 2 pi f)`` at ``frequencies`` [Hz]."""
        f = np.asarray(frequencies, dtype=float)
        return self.transfer(2j * math.pi * f)

    def magnitude(self, frequencies: ArrayLike) -> FloatArray:
        """``|W(i 2 pi f)|`` at ``frequencies`` [Hz] (dimensionless)."""
        return np.abs(self.response(frequencies))

    def polynomials(self) -> tuple[FloatArray, FloatArray]:
        """Numerator and denominator of ``W(s)`` in descending powers of ``s`` [rad/s].

        For :mod:`scipy.signal` (``freqs``, ``lti``, ``bilinear``).
        """
        two_pi = 2.0 * math.pi
        num, den = np.array([self.K]), np.array([1.0])
        if self.f1 > 0:
            w1 = two_pi * self.f1
            num, den = np.polymul(num, [1.0, 0.0, 0.0]), np.polymul(den, [1.0, w1 / self.Q1, w1**2])
        if math.isfinite(self.f2):
            w2 = two_pi * self.f2
            num, den = np.polymul(num, [w2**2]), np.polymul(den, [1.0, w2 / self.Q2, w2**2])
        if math.isfinite(self.f3):
            num = np.polymul(num, [1.0 / (two_pi * self.f3), 1.0])
        if math.isfinite(self.f4):
            w4 = two_pi * self.f4
            den = np.polymul(den, [1.0 / w4**2, 1.0 / (self.Q4 * w4), 1.0])
        if math.isfinite(self.f5):
            w5, w6 = two_pi * self.f5, two_pi * self.f6
            num = np.polymul(num, [1.0, w5 / self.Q5, w5**2])
            den = np.polymul(den, [1.0, w6 / self.Q6, w6**2])
        return np.asarray(num, dtype=float), np.asarray(den, dtype=float)

    def slowest_decay(self) -> float:
        """Smallest ``-Re(pole)`` of ``W(s)`` [1/s]: how slowly its impulse response dies."""
        poles = np.roots(self.polynomials()[1])
        return float(np.min(-poles.real))


#: EN 12299 vertical floor weighting (ISO 2631-4 / ISO 8041 Wb).
WB = FrequencyWeighting("Wb", f1=0.4, f2=100.0, f3=16.0, f4=16.0, Q4=0.55, f5=2.5, Q5=0.9, f6=4.0, Q6=0.95, K=1.024)
#: EN 12299 seat-back weighting (ISO 2631-1 Wc).
WC = FrequencyWeighting("Wc", f1=0.4, f2=100.0, f3=8.0, f4=8.0, Q4=0.63)
#: EN 12299 longitudinal and lateral weighting (ISO 2631-1 Wd).
WD = FrequencyWeighting("Wd", f1=0.4, f2=100.0, f3=2.0, f4=2.0, Q4=0.63)
#: ISO 2631-1 vertical seat weighting Wk.
WK = FrequencyWeighting("Wk", f1=0.4, f2=100.0, f3=12.5, f4=12.5, Q4=0.63, f5=2.37, Q5=0.91, f6=3.35, Q6=0.91)

#: The weightings by name.
WEIGHTINGS: dict[str, FrequencyWeighting] = {w.name: w for w in (WB, WC, WD, WK)}


def get_weighting(name: str) -> FrequencyWeighting:
    """Return a weighting of :data:`WEIGHTINGS` by name (``"Wb"``, ``"wd"``, ...).

    Raises
    ------
    InputError
        Unknown name; the message lists the known ones.
    """
    for key, weighting in WEIGHTINGS.items():
        if key.lower() == str(name).strip().lower():
            return weighting
    raise InputError(f"unknown weighting {name!r} (known: {', '.join(WEIGHTINGS)})")


# --- Sperling --------------------------------------------------------------------------

_SPERLING_GAIN = {"vertical": 0.588, "lateral": 1.25 * 0.588}


def _direction(direction: str) -> str:
    key = str(direction).strip().lower()
    key = {"z": "vertical", "y": "lateral", "x": "lateral"}.get(key, key)
    if key not in _SPERLING_GAIN:
        raise InputError(f"unknown Sperling direction {direction!r} (use 'vertical' or 'lateral')")
    return key


def sperling_transfer(frequencies: ArrayLike, direction: str = "vertical") -> ComplexArray:
    """Sperling's weighting as a rational function of ``p = i f`` (complex).

    ``0.588 (sqrt(1.911) p + 0.25 p^2) / (1 + 1.563 p + 0.277 p^2 + 0.0368 p^3)``,
    times 1.25 for ``direction="lateral"``; its modulus is :func:`sperling_weighting`.
    """
    p = 1j * np.asarray(frequencies, dtype=float)
    gain = _SPERLING_GAIN[_direction(direction)]
    return gain * (math.sqrt(1.911) * p + 0.25 * p**2) / (1.0 + 1.563 * p + 0.277 * p**2 + 0.0368 * p**3)


def sperling_weighting(frequencies: ArrayLike, direction: str = "vertical") -> FloatArray:
    """Sperling's amplitude weighting ``B(f)`` (module docstring) at ``frequencies`` [Hz].

    Parameters
    ----------
    frequencies : array_like
        [Hz], >= 0.
    direction : {"vertical", "lateral"}
        ``"z"`` and ``"y"`` (or ``"x"``) are accepted too.

    Examples
    --------
    >>> round(float(sperling_weighting(5.0)), 4)
    0.8128
    """
    f = np.asarray(frequencies, dtype=float)
    gain = _SPERLING_GAIN[_direction(direction)]
    num = 1.911 * f**2 + (0.25 * f**2) ** 2
    den = (1.0 - 0.277 * f**2) ** 2 + (1.563 * f - 0.0368 * f**3) ** 2
    return gain * np.sqrt(num / den)


# --- Time histories ---------------------------------------------------------------------


def weigh_time_history(signal: ArrayLike, sampling_rate: float, weighting: FrequencyWeighting) -> FloatArray:
    """Filter a sampled signal by a weighting's analogue response, in the frequency domain.

    The signal (taken as zero before its start) is zero-padded, multiplied by
    ``W(i 2 pi f)`` at the FFT frequencies and transformed back; the padding is long
    enough for the weighting's impulse response to die out (14 time constants of its
    slowest pole, ``e^-14 < 1e-6``), so the result is the analogue filter's response to
    the sampled signal started from rest, with no frequency warping (unlike a bilinear
    digital filter) up to the Nyquist frequency.  The samples are read as a band-limited
    signal, so where the record stops abruptly its last fraction of a second rings
    slightly (relative errors of order 1e-4).

    Parameters
    ----------
    signal : array_like, shape (N,) or (N, m)
        Samples along axis 0 [any unit; the result has the same].
    sampling_rate : float
        [Hz], > 0.
    weighting : FrequencyWeighting

    Returns
    -------
    numpy.ndarray, shape of ``signal``
    """
    x = np.asarray(signal, dtype=float)
    problems = []
    if x.ndim not in (1, 2) or x.shape[0] < 2:
        problems.append(f"signal must have shape (N,) or (N, m) with N >= 2, got {x.shape}")
    elif not np.all(np.isfinite(x)):
        problems.append("signal has non-finite values")
    if not (isinstance(sampling_rate, (int, float)) and math.isfinite(sampling_rate) and sampling_rate > 0):
        problems.append(f"sampling_rate must be > 0 Hz, got {sampling_rate!r}")
    if problems:
        raise InputError("\n".join(f"weigh_time_history: {p}" for p in problems))
    n = x.shape[0]
    tail = math.ceil(14.0 / weighting.slowest_decay() * sampling_rate)
    n_fft = next_fast_len(n + tail, real=True)
    spectrum = np.fft.rfft(x, n=n_fft, axis=0)
    f = np.fft.rfftfreq(n_fft, d=1.0 / sampling_rate)
    h = weighting.response(f)
    if x.ndim == 2:
        h = h[:, None]
    return np.fft.irfft(spectrum * h, n=n_fft, axis=0)[:n]
