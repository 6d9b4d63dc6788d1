"""Comfort indices: Sperling's ride index Wz and EN 12299's simplified mean comfort N_MV.

Both come from spectra (one-sided PSDs [(m/s^2)^2/Hz], :mod:`.spectral`) or from
sampled time histories [m/s^2].

Sperling's Wz
-------------
For one harmonic of peak amplitude ``a`` [cm/s^2] at frequency f, Sperling's index is
``Wz = (a^3 B(f)^3)^(1/10) = (a B(f))^0.3`` with the weighting B of
:func:`.weighting.sperling_weighting` (this is the older ``0.896 (a^3 F(f) / f)^(1/10)``
with its tabulated frequency factor F replaced by the continuous B).  Several harmonics
combine as ``Wz = (sum_i Wz_i^10)^(1/10)`` (:func:`sperling_index_harmonics`).  For a
random signal the index is taken on the energy: a harmonic of RMS ``a_rms`` [m/s^2] has
peak ``100 sqrt(2) a_rms`` cm/s^2, so, summing the weighted mean square over the
spectrum::

    Wz = ( (100 sqrt 2)^2 integral B(f)^2 G_a(f) df )^0.15
       = 4.417 ( integral B(f)^2 G_a(f) df )^(1/6.67)          G_a in (m/s^2)^2/Hz

over Sperling's band 0.5-30 Hz (:data:`SPERLING_BAND`).  For a single harmonic both
rules agree exactly.  This energy ("r.m.s.") form is the one that does not depend on the
analysis length or frequency resolution (Deng, Zhou, Thompson et al., *Analysis of the
consistency of the Sperling index for rail vehicles based on different algorithms*,
Vehicle System Dynamics 59 (2021), doi:10.1080/00423114.2019.1677923); the cube-sum rule
applied to FFT lines is not, so :func:`sperling_index_time` uses the energy form too.

EN 12299 mean comfort, simplified method
----------------------------------------
``N_MV = 6 sqrt( (a_XP95^Wd)^2 + (a_YP95^Wd)^2 + (a_ZP95^Wb)^2 )`` where ``a_iP95^W`` is
the 95th percentile of the RMS values over consecutive 5-s windows (60 of them in the
standard's 5-minute test zone) of the acceleration weighted by W (Wd longitudinal and
lateral, Wb vertical; :mod:`.weighting`) [m/s^2].

From a spectrum (:func:`mean_comfort_spectral`) the weighted signal is taken as a
stationary Gaussian process of variance ``sigma^2 = int |W|^2 G df``.  Its mean square
over a window of T = 5 s is a random variable of mean ``sigma^2`` and variance
(exact for a Gaussian process, R the autocorrelation of the weighted signal)::

    Var = (4 / T) integral_0^T (1 - tau / T) R(tau)^2 d tau,
    R(tau) = integral_0^inf |W|^2 G cos(2 pi f tau) df

and is approximated by a scaled chi-square variable with ``nu = 2 sigma^4 / Var``
degrees of freedom (Satterthwaite's approximation; for a band-limited white noise of
bandwidth B it gives Bendat & Piersol's ``nu = 2 B T``: *Random Data*, Wiley, chapter on
the statistical errors of mean-square estimates).  Hence::

    a_P95 = sigma sqrt( chi2_0.95(nu) / nu )

``method="rms"`` uses ``a_P95 = sigma`` instead (the window-to-window scatter ignored).
The tests check the Gaussian estimate against the percentile of 5-s windows of a long
seeded realisation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from express.analysis.ride.spectral import check_frequencies, check_psd, spectral_variance
from express.analysis.ride.weighting import WB, WD, FrequencyWeighting, sperling_weighting, weigh_time_history
from express.base.diagnostics import InputError

__all__ = [
    "EN12299_WINDOW",
    "SPERLING_BAND",
    "SPERLING_CONSTANT",
    "MeanComfort",
    "mean_comfort",
    "mean_comfort_spectral",
    "p95_from_spectrum",
    "sperling_index",
    "sperling_index_harmonics",
    "sperling_index_time",
    "window_rms",
]

FloatArray = NDArray[np.float64]

#: ``(100 sqrt 2)^0.3 = 4.417``: m/s^2 RMS to cm/s^2 peak inside Sperling's 0.3 power.
SPERLING_CONSTANT = (100.0 * math.sqrt(2.0)) ** 0.3
#: Frequency band of Sperling's index [Hz].
SPERLING_BAND = (0.5, 30.0)
#: EN 12299 RMS window [s].
EN12299_WINDOW = 5.0


# --- Sperling ----------------------------------------------------------------------------


def sperling_index(
    frequencies: ArrayLike,
    psd: ArrayLike,
    direction: str = "vertical",
    band: tuple[float, float] = SPERLING_BAND,
) -> float:
    """Sperling's Wz from a one-sided acceleration PSD (module docstring).

    Parameters
    ----------
    frequencies : array_like, shape (F,)
        [Hz], strictly increasing.
    psd : array_like, shape (F,)
        ``G_a`` [(m/s^2)^2/Hz], >= 0.
    direction : {"vertical", "lateral"}
    band : (float, float)
        Integration band [Hz]; default 0.5-30 Hz.

    Examples
    --------
    A mean square of 0.01 (m/s^2)^2 in a narrow band at 2 Hz, and a 2 Hz harmonic of
    the same RMS (peak 0.1 sqrt 2 m/s^2):

    >>> f = np.array([1.99, 2.0, 2.01]); g = np.array([0.0, 1.0, 0.0])
    >>> round(sperling_index(f, g), 3), round(sperling_index_harmonics([2.0], [0.1 * 2**0.5]), 3)
    (1.909, 1.909)
    """
    f = check_frequencies(frequencies, "sperling_index")
    g = check_psd(psd, f.size, "sperling_index")
    weighted = sperling_weighting(f, direction) ** 2 * g
    return float(SPERLING_CONSTANT * float(spectral_variance(f, weighted, band)) ** 0.15)


def sperling_index_harmonics(frequencies: ArrayLike, amplitudes: ArrayLike, direction: str = "vertical") -> float:
    """Sperling's Wz of a sum of harmonics: ``(sum_i (100 a_i B(f_i))^3)^(1/10)``.

    Parameters
    ----------
    frequencies : array_like, shape (n,)
        [Hz] > 0.
    amplitudes : array_like, shape (n,)
        Peak amplitudes ``a_i`` [m/s^2] (not RMS).
    direction : {"vertical", "lateral"}
    """
    f = np.asarray(frequencies, dtype=float)
    a = np.abs(np.asarray(amplitudes, dtype=float))
    if f.shape != a.shape or f.ndim != 1 or not (np.all(np.isfinite(f)) and np.all(np.isfinite(a))) or np.any(f <= 0):
        raise InputError(
            "sperling_index_harmonics: frequencies (> 0 Hz) and amplitudes must be finite, 1-D, same length"
        )
    return float(np.sum((100.0 * a * sperling_weighting(f, direction)) ** 3) ** 0.1)


def _periodogram(signal: ArrayLike, sampling_rate: float, where: str) -> tuple[FloatArray, FloatArray, float]:
    x = np.asarray(signal, dtype=float)
    problems = []
    if x.ndim != 1 or x.size < 4:
        problems.append(f"signal must be 1-D with at least 4 samples, got shape {x.shape}")
    elif not np.all(np.isfinite(x)):
        problems.append("signal has non-finite values")
    if not (isinstance(sampling_rate, (int, float)) and math.isfinite(sampling_rate) and sampling_rate > 0):
        problems.append(f"sampling_rate must be > 0 Hz, got {sampling_rate!r}")
    if problems:
        raise InputError("\n".join(f"{where}: {p}" for p in problems))
    n = x.size
    spectrum = np.fft.rfft(x - x.mean())
    power = 2.0 * np.abs(spectrum) ** 2 / (n * sampling_rate)
    power[0] /= 2.0
    if n % 2 == 0:
        power[-1] /= 2.0
    return np.asarray(np.fft.rfftfreq(n, d=1.0 / sampling_rate), dtype=float), power, sampling_rate / n


def sperling_index_time(
    signal: ArrayLike,
    sampling_rate: float,
    direction: str = "vertical",
    band: tuple[float, float] = SPERLING_BAND,
) -> float:
    """Sperling's Wz of a sampled acceleration [m/s^2], energy form over FFT lines.

    ``Wz = 4.417 (sum_k B(f_k)^2 G_k df)^0.15`` over the lines ``f_k`` in ``band``, with
    the periodogram ``G_k`` of the whole record (mean removed), so that ``sum_k G_k df``
    is the record's mean square (Parseval).
    """
    f, g, df = _periodogram(signal, sampling_rate, "sperling_index_time")
    inside = (f >= band[0]) & (f <= band[1])
    energy = float(np.sum(sperling_weighting(f[inside], direction) ** 2 * g[inside]) * df)
    return float(SPERLING_CONSTANT * energy**0.15)


# --- EN 12299 ----------------------------------------------------------------------------


@dataclass(frozen=True)
class MeanComfort:
    """EN 12299 simplified mean comfort.

    Attributes
    ----------
    n_mv : float
        ``N_MV`` (dimensionless; < 1.5 very comfortable ... > 4.5 very uncomfortable).
    a_xp95, a_yp95, a_zp95 : float
        95th percentiles of the 5-s RMS of the Wd-, Wd- and Wb-weighted accelerations
        [m/s^2].
    method : str
        ``"time"``, ``"gaussian"`` or ``"rms"``.
    """

    n_mv: float
    a_xp95: float
    a_yp95: float
    a_zp95: float
    method: str


def _n_mv(p95: list[float], method: str) -> MeanComfort:
    ax, ay, az = p95
    return MeanComfort(6.0 * math.sqrt(ax**2 + ay**2 + az**2), ax, ay, az, method)


def window_rms(signal: ArrayLike, sampling_rate: float, window: float = EN12299_WINDOW) -> FloatArray:
    """RMS over consecutive, non-overlapping windows [unit of ``signal``].

    A trailing part shorter than one window is left out.

    Parameters
    ----------
    signal : array_like, shape (N,)
    sampling_rate : float
        [Hz].
    window : float
        [s]; must hold at least one sample, and the record at least one window.
    """
    x = np.asarray(signal, dtype=float)
    per = round(window * sampling_rate)
    if x.ndim != 1 or per < 1 or x.size < per:
        raise InputError(
            f"window_rms: need a 1-D signal of at least one {window} s window ({per} samples), got shape {x.shape}"
        )
    count = x.size // per
    return np.sqrt(np.mean(x[: count * per].reshape(count, per) ** 2, axis=1))


def mean_comfort(
    ax: ArrayLike, ay: ArrayLike, az: ArrayLike, sampling_rate: float, window: float = EN12299_WINDOW
) -> MeanComfort:
    """EN 12299 ``N_MV`` from floor acceleration time histories [m/s^2] (unweighted).

    Each history is weighted (Wd, Wd, Wb; :func:`.weighting.weigh_time_history`), cut
    into consecutive ``window`` s pieces, and the 95th percentile of their RMS values is
    taken (``numpy.percentile``, linear interpolation between order statistics).
    """
    p95 = []
    for signal, weighting in ((ax, WD), (ay, WD), (az, WB)):
        weighted = weigh_time_history(signal, sampling_rate, weighting)
        p95.append(float(np.percentile(window_rms(weighted, sampling_rate, window), 95.0)))
    return _n_mv(p95, method="time")


def p95_from_spectrum(
    frequencies: ArrayLike,
    psd: ArrayLike,
    window: float = EN12299_WINDOW,
    method: str = "gaussian",
) -> float:
    """95th percentile of the ``window``-s RMS of a stationary Gaussian signal.

    Parameters
    ----------
    frequencies : array_like, shape (F,)
        [Hz], strictly increasing.
    psd : array_like, shape (F,)
        One-sided PSD of the (already weighted) signal [x^2/Hz]; interpolated linearly.
    window : float
        T [s].
    method : {"gaussian", "rms"}
        Module docstring.
    """
    f = check_frequencies(frequencies, "p95_from_spectrum")
    g = check_psd(psd, f.size, "p95_from_spectrum")
    if method not in ("gaussian", "rms"):
        raise InputError(f"p95_from_spectrum: method must be 'gaussian' or 'rms', got {method!r}")
    if not (isinstance(window, (int, float)) and math.isfinite(window) and window > 0):
        raise InputError(f"p95_from_spectrum: window must be > 0 s, got {window!r}")
    variance = float(spectral_variance(f, g))
    if method == "rms" or variance == 0.0:
        return math.sqrt(variance)
    # autocorrelation on a uniform grid df = 1/(8T): R periodic over 8T, far beyond T;
    # the grid stops where the rest of the spectrum holds less than 1e-9 of the variance
    df = 1.0 / (8.0 * window)
    tail = variance - np.concatenate([[0.0], np.cumsum(np.diff(f) * (g[1:] + g[:-1]) / 2)])
    f_top = float(f[np.argmax(tail <= 1e-9 * variance)]) if np.any(tail <= 1e-9 * variance) else float(f[-1])
    n_f = max(16, math.ceil(f_top / df) + 2)
    fine = np.arange(n_f) * df
    g_fine = np.interp(fine, f, g, left=0.0, right=0.0)
    n_t = 2 * (n_f - 1)
    # trapezoidal rule in f: R(tau_n) = sum_k w_k G_k df cos(2 pi f_k tau_n), w = 1/2 at the ends
    r = np.fft.irfft(g_fine * df, n=n_t) * (n_t / 2.0)
    dtau = 1.0 / (n_t * df)
    m = math.floor(window / dtau)
    tau = np.arange(m + 1) * dtau
    integrand = (1.0 - tau / window) * r[: m + 1] ** 2
    var_ms = 4.0 / window * float(np.sum(integrand[1:] + integrand[:-1]) * dtau / 2.0)
    sigma2 = float(r[0])  # the same quadrature as R, so that nu is consistent
    nu = 2.0 * sigma2**2 / var_ms
    return math.sqrt(variance * stats.chi2.ppf(0.95, nu) / nu)


def mean_comfort_spectral(
    frequencies: ArrayLike,
    psd_x: ArrayLike,
    psd_y: ArrayLike,
    psd_z: ArrayLike,
    window: float = EN12299_WINDOW,
    method: str = "gaussian",
) -> MeanComfort:
    """EN 12299 ``N_MV`` from one-sided PSDs of the floor accelerations [(m/s^2)^2/Hz].

    The PSDs are unweighted; Wd, Wd and Wb are applied here as ``|W|^2 G``.
    """
    f = check_frequencies(frequencies, "mean_comfort_spectral")
    p95 = []
    for name, psd, weighting in (("x", psd_x, WD), ("y", psd_y, WD), ("z", psd_z, WB)):
        g = check_psd(psd, f.size, f"mean_comfort_spectral (psd_{name})")
        p95.append(p95_from_spectrum(f, _weighted(weighting, f, g), window, method))
    return _n_mv(p95, method=method)


def _weighted(weighting: FrequencyWeighting, f: FloatArray, g: FloatArray) -> FloatArray:
    return weighting.magnitude(f) ** 2 * g
