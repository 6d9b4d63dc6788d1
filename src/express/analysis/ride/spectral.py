"""Linear random-vibration tools: output spectra, RMS, wheelbase filtering, realisations.

This module owns the generic spectral algebra of the ride analysis; it knows nothing of
vehicles or tracks beyond arrays.

PSD convention
--------------
Every power spectral density here is **one-sided in the frequency f [Hz]**: a stationary
signal x with PSD ``G_x(f)``, f >= 0, has variance ``sigma_x^2 = integral_0^inf G_x df``
(units: x^2/Hz).  The other conventions in use convert as::

    G(f) = 2 S(f)             S two-sided in f:      sigma^2 = int_-inf^inf S(f) df
    G(f) = 4 pi S(w)          S two-sided in w [rad/s]: sigma^2 = int_-inf^inf S(w) dw
    G(f) = (2 pi / v) S(2 pi f / v)   S one-sided in the wavenumber Omega [rad/m] of a
                                      track seen at speed v [m/s] (Omega = w / v)

so the classic result ``sigma_x^2 = pi S0 / (k c)`` for a mass on a spring k and damper c
under a white force of two-sided PSD S0 [N^2/(rad/s)] reads ``G0 / (4 k c)`` with
``G0 = 4 pi S0`` [N^2/Hz].

Cross-spectral matrices ``G_u(f)`` (shape (F, n, n), Hermitian) follow the same
convention; for outputs ``y = H u`` with frequency-response matrix ``H(f)`` (F, n_y, n_u)::

    G_y(f) = H(f) G_u(f) H(f)^H

Wheelbase filtering
-------------------
A vehicle at speed v meets the same track irregularity at each wheelset k later by
``tau_k = (x_lead - x_k) / v`` (x_k the wheelset's longitudinal position, forward
positive), so the input at wheelset k is ``u_k(t) = r(t - tau_k)``, with Fourier factor
``exp(-i w tau_k)``.  Inputs at several wheelsets are thus fully coherent:
``G_u[k, l] = G_r exp(-i w (tau_k - tau_l))``.  The in-phase (bounce) part of two
wheelsets a wheelbase ``b`` apart, ``(1 + exp(-i w b / v)) / 2``, has modulus
``|cos(pi b / lambda)|`` at the wavelength ``lambda = v / f``: it vanishes at
``lambda = 2 b / (2 k + 1)``, k = 0, 1, ... (2b, 2b/3, 2b/5, ...); the anti-phase
(pitch) part ``(1 - exp(-i w b / v)) / 2`` has modulus ``|sin(pi b / lambda)|`` and
vanishes at ``lambda = b / k``, k = 1, 2, ... (and at infinite wavelength).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from express.base.diagnostics import InputError

__all__ = [
    "ModalForm",
    "check_frequencies",
    "check_psd",
    "coordinate_response",
    "delay_factors",
    "harmonic_realisation",
    "modal_form",
    "output_autospectra",
    "output_spectra",
    "resolvent_solve",
    "spatial_to_temporal",
    "spectral_rms",
    "spectral_variance",
    "state_space_response",
    "track_input_spectrum",
    "two_point_filter",
    "two_point_filter_zeros",
    "wheelbase_filter",
    "wheelset_delays",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


def _raise(problems: list[str], where: str) -> None:
    if problems:
        raise InputError("\n".join(f"{where}: {p}" for p in problems))


def check_frequencies(frequencies: ArrayLike, where: str, positive: bool = False) -> FloatArray:
    """A 1-D array of finite, strictly increasing frequencies >= 0 (> 0 if ``positive``).

    Raises
    ------
    InputError
        Listing every problem (shape, non-finite, negative, not increasing).
    """
    try:
        f = np.asarray(frequencies, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{where}: frequencies must be numbers") from None
    problems = []
    if f.ndim != 1 or f.size == 0:
        problems.append(f"frequencies must be a non-empty 1-D sequence, got shape {f.shape}")
    else:
        if not np.all(np.isfinite(f)):
            problems.append("frequencies must be finite")
        elif positive and np.any(f <= 0):
            problems.append(f"frequencies must be > 0 Hz (first bad: {f[f <= 0][0]!r})")
        elif np.any(f < 0):
            problems.append(f"frequencies must be >= 0 Hz (first bad: {f[f < 0][0]!r})")
        if f.size > 1 and np.any(np.diff(f) <= 0):
            i = int(np.argmax(np.diff(f) <= 0))
            problems.append(f"frequencies must increase strictly (item {i + 1}: {f[i]!r} then {f[i + 1]!r})")
    _raise(problems, where)
    return f


def check_psd(psd: ArrayLike, n_f: int, where: str) -> FloatArray:
    """``psd`` as a float array of ``n_f`` finite values >= 0 along axis 0.

    Raises
    ------
    InputError
        Naming the problem and ``where``.
    """
    g = np.asarray(psd, dtype=float)
    problems = []
    if g.ndim == 0 or g.shape[0] != n_f:
        problems.append(f"PSD must have {n_f} values along its first axis (one per frequency), got shape {g.shape}")
    elif not np.all(np.isfinite(g)):
        problems.append("PSD has non-finite values")
    elif np.any(g < 0):
        i = int(np.argmax(g.reshape(n_f, -1).min(axis=1) < 0))
        problems.append(f"PSD must be >= 0 (negative at item {i + 1})")
    _raise(problems, where)
    return g


# --- Frequency response and output spectra -----------------------------------------------


def state_space_response(
    A: ArrayLike, B: ArrayLike, C: ArrayLike, D: ArrayLike | None, frequencies: ArrayLike
) -> ComplexArray:
    """``H(f) = C (i w I - A)^-1 B + D`` of a state-space model, ``w = 2 pi f``.

    Parameters
    ----------
    A, B, C, D : array_like
        Shapes (n, n), (n, m), (p, n), (p, m); ``D`` may be None (zero).
    frequencies : array_like, shape (F,)
        [Hz], >= 0.

    Returns
    -------
    numpy.ndarray, complex, shape (F, p, m)

    Raises
    ------
    numpy.linalg.LinAlgError
        If ``i w I - A`` is singular at one of the frequencies (an undamped mode).
    """
    f = check_frequencies(frequencies, "state_space_response")
    a, b, c = (np.asarray(x, dtype=float) for x in (A, B, C))
    n = a.shape[0]
    if a.shape != (n, n) or b.shape[0] != n or c.shape[1] != n:
        raise InputError(f"state_space_response: inconsistent shapes A {a.shape}, B {b.shape}, C {c.shape}")
    iw = 2j * math.pi * f
    resolvent = iw[:, None, None] * np.eye(n) - a
    x = np.linalg.solve(resolvent, np.broadcast_to(b.astype(complex), (f.size, *b.shape)))
    h = c @ x
    if D is not None:
        h = h + np.asarray(D, dtype=float)
    return h


@dataclass(frozen=True)
class ModalForm:
    """The eigendecomposition ``A = V diag(lambda) V^-1`` of a state matrix, for
    frequency responses by modal superposition.

    With it, ``(i w I - A)^-1 R = V diag(1 / (i w - lambda)) V^-1 R``: once ``V^-1`` has
    met the input matrix and the output matrix has met ``V``, each frequency costs
    O(N) per input and output instead of the O(N^2) of a triangular solve
    (:func:`resolvent_solve`), and the cost grows with the states as N, not N^2.

    Attributes
    ----------
    eigenvalues : numpy.ndarray, complex, shape (N,)
        ``lambda`` [1/s].
    right : numpy.ndarray, complex, shape (N, N)
        ``V``, the right eigenvectors as columns.
    left : numpy.ndarray, complex, shape (N, N)
        ``V^-1``.
    condition : float
        The 2-norm condition number of ``V``: the factor by which rounding in the
        eigenvectors can grow in a response.
    """

    eigenvalues: ComplexArray
    right: ComplexArray
    left: ComplexArray
    condition: float


#: Largest condition number of the eigenvectors :func:`modal_form` accepts: a response
#: through them then carries at most about 1e-16 x 1e6 = 1e-10 relative rounding.
MAX_MODAL_CONDITION = 1.0e6


def modal_form(A: ArrayLike, max_condition: float = MAX_MODAL_CONDITION) -> ModalForm | None:
    """The eigendecomposition of ``A`` if its eigenvectors are well conditioned.

    Parameters
    ----------
    A : array_like, shape (N, N)
        Real state matrix.
    max_condition : float
        Refuse eigenvectors whose condition number exceeds this (a nearly defective
        ``A``, e.g. two modes coalescing): the caller then solves by the Schur form,
        which is backward stable whatever the eigenvectors (:func:`resolvent_solve`).

    Returns
    -------
    ModalForm or None
        None when ``A`` is empty, not finite or its eigenvectors are ill conditioned.
    """
    a = np.asarray(A, dtype=float)
    if a.size == 0 or not np.all(np.isfinite(a)):
        return None
    values, vectors = np.linalg.eig(a)
    condition = float(np.linalg.cond(vectors))
    if not math.isfinite(condition) or condition > max_condition:
        return None
    return ModalForm(values.astype(complex), vectors.astype(complex), np.linalg.inv(vectors).astype(complex), condition)


def resolvent_solve(A: ArrayLike, frequencies: ArrayLike, rhs: ArrayLike) -> ComplexArray:
    """``X(f) = (i w I - A)^-1 R(f)`` at many frequencies, through one Schur form.

    ``A = Z T Z^H`` with ``T`` upper triangular (the complex Schur form,
    :func:`scipy.linalg.schur`, computed once, backward stable); then every frequency
    is a back substitution ``(i w I - T) Y = Z^H R``, O(N^2) per right-hand side
    instead of the O(N^3) of a general solve, and ``X = Z Y``.  This is Laub's
    reduction of frequency-response computations (*Efficient multivariable frequency
    response computations*, IEEE Trans. Automatic Control 26 (1981) 407-408, there with
    the Hessenberg form), the substitution running over all frequencies at once.

    Parameters
    ----------
    A : array_like, shape (N, N)
        Real state matrix.
    frequencies : array_like, shape (F,)
        [Hz], >= 0; ``w = 2 pi f``.
    rhs : array_like, complex, shape (F, N, J)
        Right-hand sides ``R(f)``.

    Returns
    -------
    numpy.ndarray, complex, shape (F, N, J)

    Raises
    ------
    numpy.linalg.LinAlgError
        If ``i w I - A`` is singular at one of the frequencies (an undamped mode there).
    """
    from scipy.linalg import schur

    f = check_frequencies(frequencies, "resolvent_solve")
    a = np.asarray(A, dtype=float)
    r = np.asarray(rhs, dtype=complex)
    n = a.shape[0]
    if a.shape != (n, n) or r.ndim != 3 or r.shape[:2] != (f.size, n):
        raise InputError(f"resolvent_solve: need A (N, N) and rhs (F, N, J), got {a.shape} and {r.shape}")
    t, z = schur(a, output="complex")
    shifts = 2j * math.pi * f
    n_j = r.shape[2]
    # frequency-and-column pairs side by side: row k of Y is one contiguous (F*J) vector
    y = np.conj(z.T) @ np.ascontiguousarray(r.transpose(1, 0, 2)).reshape(n, f.size * n_j)
    pivots = np.repeat(shifts, n_j)
    with np.errstate(divide="ignore", invalid="ignore"):
        for k in range(n - 1, -1, -1):
            if k < n - 1:
                y[k] += t[k, k + 1:] @ y[k + 1:]
            y[k] /= pivots - t[k, k]
    if not np.all(np.isfinite(y)):
        raise np.linalg.LinAlgError("i w I - A is singular at some frequency (an undamped mode)")
    return (z @ y).reshape(n, f.size, n_j).transpose(1, 0, 2)


def coordinate_response(
    a: FloatArray, b: FloatArray, bd: FloatArray, d: tuple[FloatArray, FloatArray, FloatArray],
    u: ComplexArray, s: ComplexArray, f: FloatArray, n: int,
) -> ComplexArray:
    """``(d0 + s d1 + s^2 d2) q`` with ``x = [q; q_D']`` solving ``(s I - A) x = (B + s Bd) u``.

    ``u`` (K, F*J) and ``s = i w`` (F*J,) hold every (frequency, component) column side
    by side; ``d`` the output matrices (P, n) of ``q``, the first ``n`` states.  By modal
    superposition (:func:`modal_form`: O(N) per column and output) where the eigenvectors
    of ``A`` are well conditioned, else by the Schur form (:func:`resolvent_solve`, O(N^2)
    per column).  Returns (P, F*J).

    Raises
    ------
    numpy.linalg.LinAlgError
        If ``i w I - A`` is singular at one of the frequencies (an undamped mode).
    """
    modal = modal_form(a)
    if modal is not None:
        poles = s[None, :] - modal.eigenvalues[:, None]
        if np.any(poles == 0):
            raise np.linalg.LinAlgError("i w I - A is singular at some frequency (an undamped mode)")
        xi = ((modal.left @ b) @ u + ((modal.left @ bd) @ u) * s) / poles
        shapes = modal.right[:n]
        return (d[0] @ shapes) @ xi + ((d[1] @ shapes) @ xi) * s + ((d[2] @ shapes) @ xi) * s**2
    n_f = f.size
    drive = b @ u + (bd @ u) * s
    x = resolvent_solve(a, f, drive.reshape(-1, n_f, s.size // n_f).transpose(1, 0, 2))[:, :n]
    q = x.transpose(1, 0, 2).reshape(n, s.size)
    return d[0] @ q + (d[1] @ q) * s + (d[2] @ q) * s**2


def output_spectra(H: ArrayLike, input_spectra: ArrayLike) -> ComplexArray:
    """Cross-spectral matrix of the outputs, ``G_y = H G_u H^H`` at each frequency.

    Parameters
    ----------
    H : array_like, complex, shape (F, p, m)
        Frequency-response matrix.
    input_spectra : array_like, shape (F, m, m) or (F, m)
        One-sided cross-spectral matrix of the inputs (Hermitian), or the auto-spectra
        of mutually uncorrelated inputs.

    Returns
    -------
    numpy.ndarray, complex, shape (F, p, p)
    """
    h = np.asarray(H, dtype=complex)
    g = np.asarray(input_spectra)
    if g.ndim == 2:
        return (h * g[:, None, :]) @ np.conj(np.swapaxes(h, 1, 2))
    return h @ g @ np.conj(np.swapaxes(h, 1, 2))


def output_autospectra(H: ArrayLike, input_spectra: ArrayLike) -> FloatArray:
    """Auto-spectra (diagonal of :func:`output_spectra`), shape (F, p), real >= 0."""
    h = np.asarray(H, dtype=complex)
    g = np.asarray(input_spectra)
    if g.ndim == 2:
        return np.einsum("fpm,fm,fpm->fp", h, g, np.conj(h)).real
    return np.einsum("fpm,fmn,fpn->fp", h, g, np.conj(h)).real


def spectral_variance(
    frequencies: ArrayLike, psd: ArrayLike, band: tuple[float, float] | None = None
) -> FloatArray | float:
    """``integral G df`` by the trapezoidal rule, optionally over ``band = (f_lo, f_hi)``.

    Parameters
    ----------
    frequencies : array_like, shape (F,)
        [Hz], strictly increasing.
    psd : array_like, shape (F,) or (F, ...)
        One-sided PSD; integrated along axis 0.  At a band edge between grid points the
        PSD is interpolated linearly.
    band : (float, float), optional
        [Hz]; the part of the grid outside it is left out.

    Returns
    -------
    float or numpy.ndarray of shape ``psd.shape[1:]``
    """
    f = check_frequencies(frequencies, "spectral_variance")
    g = check_psd(psd, f.size, "spectral_variance")
    if band is not None:
        lo, hi = (float(x) for x in band)
        if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo < hi):
            raise InputError(f"spectral_variance: band must be 0 <= f_lo < f_hi, got {band!r}")
        lo, hi = max(lo, f[0]), min(hi, f[-1])
        if lo >= hi:
            return 0.0 if g.ndim == 1 else np.zeros(g.shape[1:])
        inside = (f > lo) & (f < hi)
        flat = g.reshape(f.size, -1)
        edges = np.array([[np.interp(x, f, col) for col in flat.T] for x in (lo, hi)])
        f = np.concatenate([[lo], f[inside], [hi]])
        g = np.concatenate([edges[:1], flat[inside], edges[1:]]).reshape(f.size, *g.shape[1:])
    from scipy.integrate import trapezoid  # imported here: the solvers above need no SciPy

    out = trapezoid(g, f, axis=0)
    return float(out) if np.ndim(out) == 0 else out


def spectral_rms(frequencies: ArrayLike, psd: ArrayLike, band: tuple[float, float] | None = None) -> FloatArray | float:
    """``sqrt`` of :func:`spectral_variance` (the RMS of a zero-mean signal)."""
    out = np.sqrt(spectral_variance(frequencies, psd, band))
    return float(out) if np.ndim(out) == 0 else out


def spatial_to_temporal(
    spatial_psd: Callable[[FloatArray], ArrayLike], frequencies: ArrayLike, speed: float
) -> FloatArray:
    """Temporal PSD [x^2/Hz] of a track irregularity met at ``speed``.

    ``G(f) = (2 pi / v) S(Omega = 2 pi f / v)`` for ``S`` one-sided in the wavenumber
    Omega [rad/m] (the convention of :mod:`express.rail.track` spectra), so that
    ``int G df = int S dOmega`` over matching bands.

    Parameters
    ----------
    spatial_psd : callable
        ``S(Omega)`` [x^2/(rad/m)] at an array of wavenumbers [rad/m].
    frequencies : array_like, shape (F,)
        [Hz], > 0.
    speed : float
        [m/s], > 0.
    """
    f = check_frequencies(frequencies, "spatial_to_temporal", positive=True)
    if not (isinstance(speed, (int, float)) and math.isfinite(speed) and speed > 0):
        raise InputError(f"spatial_to_temporal: speed must be > 0 m/s, got {speed!r}")
    omega = 2.0 * math.pi * f / speed
    return np.asarray(spatial_psd(omega), dtype=float) * (2.0 * math.pi / speed)


# --- Wheelbase filtering -----------------------------------------------------------------


def wheelset_delays(positions: ArrayLike, speed: float) -> FloatArray:
    """``tau_k = (max(x) - x_k) / v`` [s]: when each wheelset meets what the leading one met.

    Parameters
    ----------
    positions : array_like, shape (K,)
        Longitudinal positions of the wheelsets [m], forward positive.
    speed : float
        [m/s], > 0.
    """
    x = np.asarray(positions, dtype=float)
    problems = []
    if x.ndim != 1 or x.size == 0 or not np.all(np.isfinite(x)):
        problems.append(f"positions must be a non-empty 1-D sequence of finite values [m], got {positions!r}")
    if not (isinstance(speed, (int, float)) and math.isfinite(speed) and speed > 0):
        problems.append(f"speed must be > 0 m/s, got {speed!r}")
    _raise(problems, "wheelset_delays")
    return (x.max() - x) / float(speed)


def delay_factors(frequencies: ArrayLike, delays: ArrayLike) -> ComplexArray:
    """``exp(-i 2 pi f tau_k)``, shape (F, K)."""
    f = np.asarray(frequencies, dtype=float)
    tau = np.asarray(delays, dtype=float)
    return np.exp(-2j * math.pi * np.outer(f, tau))


def wheelbase_filter(frequencies: ArrayLike, delays: ArrayLike, weights: ArrayLike | None = None) -> ComplexArray:
    """``sum_k w_k exp(-i 2 pi f tau_k)``, shape (F,); default weights ``1/K`` (the mean)."""
    e = delay_factors(frequencies, delays)
    w = np.full(e.shape[1], 1.0 / e.shape[1]) if weights is None else np.asarray(weights, dtype=float)
    return e @ w


def two_point_filter(wavelengths: ArrayLike, wheelbase: float, kind: str = "bounce") -> FloatArray:
    """Modulus of the two-point filter at spatial ``wavelengths`` [m].

    ``|1 + s exp(-i 2 pi b / lambda)| / 2`` with ``s = +1`` (``kind="bounce"``) or
    ``-1`` (``"pitch"``): ``|cos(pi b / lambda)|`` or ``|sin(pi b / lambda)|``.
    """
    lam = np.asarray(wavelengths, dtype=float)
    sign = {"bounce": 1.0, "pitch": -1.0}[kind]
    return np.abs(1.0 + sign * np.exp(-2j * math.pi * wheelbase / lam)) / 2.0


def two_point_filter_zeros(wheelbase: float, kind: str = "bounce", count: int = 5) -> FloatArray:
    """The first ``count`` wavelengths [m] (longest first) where the two-point filter vanishes.

    ``2 b / (2 k + 1)`` for ``"bounce"``, ``b / (k + 1)`` for ``"pitch"``, k = 0, 1, ...
    """
    if not (isinstance(wheelbase, (int, float)) and math.isfinite(wheelbase) and wheelbase > 0):
        raise InputError(f"two_point_filter_zeros: wheelbase must be > 0 m, got {wheelbase!r}")
    k = np.arange(count, dtype=float)
    if kind == "bounce":
        return 2.0 * wheelbase / (2.0 * k + 1.0)
    if kind == "pitch":
        return wheelbase / (k + 1.0)
    raise InputError(f"two_point_filter_zeros: kind must be 'bounce' or 'pitch', got {kind!r}")


def track_input_spectrum(
    frequencies: ArrayLike,
    psds: Sequence[ArrayLike],
    delays: ArrayLike,
    mixing: ArrayLike | None = None,
) -> ComplexArray:
    """Cross-spectral matrix of delayed track inputs at K wheelsets.

    J mutually uncorrelated track quantities ``r_j`` (e.g. alignment, vertical profile,
    cross level) with one-sided PSDs ``G_j(f)`` drive, at wheelset k, the inputs
    ``u_(k, i)(t) = sum_j T[i, j] r_j(t - tau_k)``.  Hence::

        G_u[(k, i), (l, i')] = sum_j T[i, j] T[i', j] G_j(f) exp(-i w (tau_k - tau_l))

    Parameters
    ----------
    frequencies : array_like, shape (F,)
        [Hz].
    psds : sequence of J arrays of shape (F,)
        One-sided PSDs of the track quantities (>= 0).
    delays : array_like, shape (K,)
        ``tau_k`` [s] (:func:`wheelset_delays`).
    mixing : array_like, shape (I, J), optional
        ``T``; default the identity (input i is quantity i).

    Returns
    -------
    numpy.ndarray, complex, shape (F, K*I, K*I)
        Inputs ordered wheelset-major: index ``k * I + i``.
    """
    f = check_frequencies(frequencies, "track_input_spectrum")
    g = np.stack([check_psd(p, f.size, f"track_input_spectrum (PSD {j + 1})") for j, p in enumerate(psds)], axis=1)
    t = np.eye(g.shape[1]) if mixing is None else np.asarray(mixing, dtype=float)
    if t.ndim != 2 or t.shape[1] != g.shape[1]:
        raise InputError(f"track_input_spectrum: mixing must have shape (I, {g.shape[1]}), got {t.shape}")
    e = delay_factors(f, delays)  # (F, K)
    # per-wheelset-pair coherence times the per-quantity mixing: (F,K,K) x (F,I,I)
    coh = e[:, :, None] * np.conj(e[:, None, :])
    mix = np.einsum("ij,fj,kj->fik", t, g, t)
    n_k, n_i = e.shape[1], t.shape[0]
    out = coh[:, :, None, :, None] * mix[:, None, :, None, :]
    return out.reshape(f.size, n_k * n_i, n_k * n_i)


# --- Random realisations -----------------------------------------------------------------


def harmonic_realisation(
    frequencies: ArrayLike, psd: ArrayLike, duration: float, sampling_rate: float, seed: int = 0
) -> tuple[FloatArray, FloatArray]:
    """A seeded random time history with a given one-sided PSD: cosines with random phases.

    ``x(t) = sum_k A_k cos(2 pi f_k t + phi_k)`` with ``f_k = k / T`` (T = ``duration``,
    k = 1 .. N/2 - 1 for N = T * ``sampling_rate`` samples), ``A_k = sqrt(2 G(f_k) / T)``
    (``G`` interpolated linearly in the table, zero outside it) and ``phi_k`` uniform in
    ``[0, 2 pi)`` from ``numpy.random.default_rng(seed)``.  The history repeats every T;
    its mean square over T is exactly ``sum_k G(f_k) / T``, the rectangle-rule integral
    of G, and as the number of cosines grows it tends to a Gaussian process (central
    limit theorem).  Same seed, same history.

    Parameters
    ----------
    frequencies, psd : array_like, shape (F,)
        Table of the PSD [Hz] and [x^2/Hz].
    duration : float
        T [s] > 0.
    sampling_rate : float
        [Hz] > 0; ``N = round(T * sampling_rate)`` must be >= 4.
    seed : int
        >= 0.

    Returns
    -------
    times : numpy.ndarray, shape (N,)
        ``n / sampling_rate`` [s].
    values : numpy.ndarray, shape (N,)
    """
    f = check_frequencies(frequencies, "harmonic_realisation")
    g = check_psd(psd, f.size, "harmonic_realisation")
    problems = []
    if not (isinstance(duration, (int, float)) and math.isfinite(duration) and duration > 0):
        problems.append(f"duration must be > 0 s, got {duration!r}")
    if not (isinstance(sampling_rate, (int, float)) and math.isfinite(sampling_rate) and sampling_rate > 0):
        problems.append(f"sampling_rate must be > 0 Hz, got {sampling_rate!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        problems.append(f"seed must be an integer >= 0, got {seed!r}")
    _raise(problems, "harmonic_realisation")
    n = round(duration * sampling_rate)
    if n < 4:
        raise InputError(f"harmonic_realisation: duration * sampling_rate must give >= 4 samples, got {n}")
    period = n / sampling_rate
    k = np.arange(1, n // 2)
    fk = k / period
    amplitude = np.sqrt(2.0 * np.interp(fk, f, g, left=0.0, right=0.0) / period)
    phases = np.random.default_rng(int(seed)).uniform(0.0, 2.0 * math.pi, size=k.size)
    spectrum = np.zeros(n // 2 + 1, dtype=complex)
    spectrum[k] = 0.5 * n * amplitude * np.exp(1j * phases)
    return np.arange(n) / sampling_rate, np.fft.irfft(spectrum, n=n)
