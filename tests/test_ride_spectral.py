"""Spectral response tools (express.analysis.ride.spectral) against closed forms.

PSD conventions (``docs/ride.md``): the library's PSDs G are one-sided in Hz; the
classic closed forms below are written with S0, the two-sided PSD in rad/s of a white
noise (``E[w(t) w(t + tau)] = 2 pi S0 delta(tau)``), and ``G0 = 4 pi S0``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import linalg, signal

from express.analysis.ride import (
    delay_factors,
    state_space_response,
    harmonic_realisation,
    output_autospectra,
    output_spectra,
    spatial_to_temporal,
    spectral_rms,
    spectral_variance,
    track_input_spectrum,
    two_point_filter,
    two_point_filter_zeros,
    wheelbase_filter,
    wheelset_delays,
)
from express.base.diagnostics import InputError

S0 = 2.5  # two-sided white-noise level [unit^2/(rad/s)]
G0 = 4 * math.pi * S0  # the same, one-sided in Hz
# a fine log grid: the tails of |H|^2 beyond it are below 1e-6 of the variances
FREQS = np.concatenate([[0.0], np.logspace(-5, 5, 40001)])

M, C, K = 1200.0, 3000.0, 4.0e5  # single DOF [kg, N s/m, N/m]
QC = {"ms": 400.0, "mu": 45.0, "ks": 2.2e4, "cs": 1.6e3, "kt": 2.0e5}  # quarter car [kg, N/m, N s/m]


def sdof(input_kind: str) -> tuple[np.ndarray, ...]:
    """State space of m x'' + c (x' - y') + k (x - y) = F, states (x, x') or (z = x - y, x')."""
    if input_kind == "force":  # u = F; outputs x, x'
        A = np.array([[0, 1], [-K / M, -C / M]])
        return A, np.array([[0], [1 / M]]), np.eye(2), None
    # u = y' (base velocity); states z = x - y, x'; outputs z, x'
    A = np.array([[0, 1], [-K / M, -C / M]])
    return A, np.array([[-1], [C / M]]), np.eye(2), None


def test_sdof_white_force_closed_form() -> None:
    A, B, Cm, D = sdof("force")
    H = state_space_response(A, B, Cm, D, FREQS)
    g = output_autospectra(H, np.full((FREQS.size, 1), G0))
    variance = spectral_variance(FREQS, g)
    assert variance[0] == pytest.approx(math.pi * S0 / (K * C), rel=1e-5)  # sigma_x^2 = pi S0 / (k c)
    assert variance[0] == pytest.approx(G0 / (4 * K * C), rel=1e-5)
    assert variance[1] == pytest.approx(math.pi * S0 / (M * C), rel=1e-5)  # sigma_v^2 = pi S0 / (m c)
    # against the direct formula |1 / (k - m w^2 + i c w)|^2
    w = 2 * np.pi * FREQS
    np.testing.assert_allclose(H[:, 0, 0], 1 / (K - M * w**2 + 1j * C * w), rtol=1e-9)


def test_sdof_white_base_velocity_closed_form() -> None:
    """Integral table: int |(b0 + i w b1) / (a0 + i w a1 - w^2 a2)|^2 dw = pi (a0 b1^2 + a2 b0^2) / (a0 a1 a2)."""
    A, B, Cm, D = sdof("base")
    H = state_space_response(A, B, Cm, D, FREQS)
    variance = spectral_variance(FREQS, output_autospectra(H, np.full((FREQS.size, 1), G0)))
    assert variance[0] == pytest.approx(math.pi * S0 * M / C, rel=1e-5)  # relative displacement
    assert variance[1] == pytest.approx(math.pi * S0 * (C / M + K / C), rel=1e-4)  # absolute velocity


def quarter_car() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Two-mass quarter car on a tyre spring, input the road's vertical velocity.

    States (zs - zu, zu - r, zs', zu'); outputs body acceleration, suspension and tyre
    deflections.
    """
    ms, mu, ks, cs, kt = QC["ms"], QC["mu"], QC["ks"], QC["cs"], QC["kt"]
    A = np.array([
        [0, 0, 1, -1],
        [0, 0, 0, 1],
        [-ks / ms, 0, -cs / ms, cs / ms],
        [ks / mu, -kt / mu, cs / mu, -cs / mu],
    ])  # fmt: skip
    B = np.array([[0.0], [-1.0], [0.0], [0.0]])
    Cm = np.vstack([A[2], [1, 0, 0, 0], [0, 1, 0, 0]])
    return A, B, Cm


def test_quarter_car_white_base_velocity_against_lyapunov() -> None:
    A, B, Cm = quarter_car()
    H = state_space_response(A, B, Cm, None, FREQS)
    variance = spectral_variance(FREQS, output_autospectra(H, np.full((FREQS.size, 1), G0)))
    # independent: stationary covariance P of x' = A x + B w, A P + P A^T + 2 pi S0 B B^T = 0
    P = linalg.solve_continuous_lyapunov(A, -2 * math.pi * S0 * B @ B.T)
    np.testing.assert_allclose(variance, np.diag(Cm @ P @ Cm.T), rtol=2e-4)


def newland_i4(a: tuple[float, ...], b: tuple[float, ...]) -> float:
    """``int_-inf^inf |H|^2 dw`` for ``H = sum_k b_k (i w)^k / sum_k a_k (i w)^k`` (a: 5, b: 4
    coefficients, stable denominator), the closed form of the integral table (James,
    Nichols & Phillips, 1947; Newland, *Random Vibrations*, appendix 1)."""
    a0, a1, a2, a3, a4 = a
    b0, b1, b2, b3 = b
    top = (b0**2 / a0 * (a2 * a3 - a1 * a4) + a3 * (b1**2 - 2 * b0 * b2) + a1 * (b2**2 - 2 * b1 * b3)
           + b3**2 / a4 * (a1 * a2 - a0 * a3))
    return math.pi * top / (a1 * (a2 * a3 - a1 * a4) - a0 * a3**2)


def quarter_car_denominator() -> tuple[float, ...]:
    """``(ms s^2 + cs s + ks)(mu s^2 + cs s + ks + kt) - (cs s + ks)^2`` by powers of s."""
    ms, mu, ks, cs, kt = QC["ms"], QC["mu"], QC["ks"], QC["cs"], QC["kt"]
    return (ks * kt, cs * kt, ms * (ks + kt) + mu * ks, cs * (ms + mu), ms * mu)


def test_quarter_car_white_force_closed_form() -> None:
    """White force S0 on the body of the quarter car: body displacement and velocity
    variances ``S0 I4`` with ``z_s / F = (mu s^2 + cs s + ks + kt) / D(s)``."""
    A, _, _ = quarter_car()
    B = np.array([[0.0], [0.0], [1 / QC["ms"]], [0.0]])  # force on the body; the road stays at 0
    Cm = np.array([[1.0, 1.0, 0, 0], [0, 0, 1.0, 0]])  # z_s = (z_s - z_u) + (z_u - r); z_s'
    H = state_space_response(A, B, Cm, None, FREQS)
    variance = spectral_variance(FREQS, output_autospectra(H, np.full((FREQS.size, 1), G0)))
    den, (mu, cs, kk) = quarter_car_denominator(), (QC["mu"], QC["cs"], QC["ks"] + QC["kt"])
    assert variance[0] == pytest.approx(S0 * newland_i4(den, (kk, cs, mu, 0.0)), rel=1e-5)
    assert variance[1] == pytest.approx(S0 * newland_i4(den, (0.0, kk, cs, mu)), rel=1e-5)
    # the closed form is not circular: it agrees with the stationary covariance too
    P = linalg.solve_continuous_lyapunov(A, -2 * math.pi * S0 * B @ B.T)
    np.testing.assert_allclose(variance, np.diag(Cm @ P @ Cm.T), rtol=1e-5)


def test_quarter_car_white_base_velocity_closed_form() -> None:
    """White road velocity S0: body velocity ``kt (cs s + ks) / D`` and acceleration
    ``s kt (cs s + ks) / D`` per unit road velocity, variances ``S0 I4``."""
    A, B, _ = quarter_car()
    Cm = np.array([[0, 0, 1.0, 0], A[2]])  # z_s', z_s''
    H = state_space_response(A, B, Cm, None, FREQS)
    variance = spectral_variance(FREQS, output_autospectra(H, np.full((FREQS.size, 1), G0)))
    den, kt, ks, cs = quarter_car_denominator(), QC["kt"], QC["ks"], QC["cs"]
    assert variance[0] == pytest.approx(S0 * newland_i4(den, (kt * ks, kt * cs, 0.0, 0.0)), rel=1e-5)
    assert variance[1] == pytest.approx(S0 * newland_i4(den, (0.0, kt * ks, kt * cs, 0.0)), rel=1e-4)


def test_time_domain_realisation_rms_within_3_percent_of_spectral() -> None:
    """A seeded 400 s road-velocity realisation through the quarter car (scipy lsim)."""
    A, B, Cm = quarter_car()
    f_table = np.array([0.0, 0.2, 20.0, 20.5])
    g_table = np.array([0.0, 1e-4, 1e-4, 0.0])  # band-limited white road velocity [(m/s)^2/Hz]
    fs = 250.0
    t, u = harmonic_realisation(f_table, g_table, duration=400.0, sampling_rate=fs, seed=7)
    _, y, _ = signal.lsim((A, B, Cm, np.zeros((3, 1))), u, t)
    settled = t > 20.0
    rms_time = np.sqrt(np.mean(y[settled] ** 2, axis=0))
    f = np.linspace(0.0, 25.0, 5001)
    g_u = np.interp(f, f_table, g_table)
    rms_spectral = spectral_rms(f, output_autospectra(state_space_response(A, B, Cm, None, f), g_u[:, None]))
    np.testing.assert_allclose(rms_time, rms_spectral, rtol=0.03)


def test_output_spectra_full_matrix() -> None:
    rng = np.random.default_rng(1)
    H = rng.normal(size=(5, 3, 2)) + 1j * rng.normal(size=(5, 3, 2))
    L = rng.normal(size=(5, 2, 2)) + 1j * rng.normal(size=(5, 2, 2))
    Gu = L @ np.conj(np.swapaxes(L, 1, 2))  # Hermitian, positive semi-definite
    Gy = output_spectra(H, Gu)
    for i in range(5):
        np.testing.assert_allclose(Gy[i], H[i] @ Gu[i] @ H[i].conj().T, rtol=1e-12)
    np.testing.assert_allclose(output_autospectra(H, Gu), np.einsum("fii->fi", Gy).real, rtol=1e-12)
    diag = np.abs(rng.normal(size=(5, 2)))
    np.testing.assert_allclose(output_spectra(H, diag), output_spectra(H, diag[:, :, None] * np.eye(2)), rtol=1e-12)


def test_spectral_variance_band_edges_between_grid_points() -> None:
    f = np.linspace(0.0, 10.0, 11)
    g = 2.0 * f  # exact for the trapezoidal rule
    assert spectral_variance(f, g) == pytest.approx(100.0)
    assert spectral_variance(f, g, band=(2.5, 7.25)) == pytest.approx(7.25**2 - 2.5**2)
    assert spectral_variance(f, np.c_[g, 3 * g], band=(2.5, 7.25))[1] == pytest.approx(3 * (7.25**2 - 2.5**2))
    assert spectral_variance(f, g, band=(20.0, 30.0)) == 0.0
    assert spectral_rms(f, g) == pytest.approx(10.0)


def test_spatial_to_temporal_preserves_band_variance() -> None:
    a, wc = 3e-7, 0.8  # S(Omega) = a / (Omega^2 + wc^2) [m^2/(rad/m)], integral a/wc atan(Omega/wc)
    v = 160 / 3.6
    f = np.linspace(0.5, 30.0, 20001)
    g = spatial_to_temporal(lambda om: a / (om**2 + wc**2), f, v)
    om1, om2 = 2 * np.pi * f[[0, -1]] / v
    assert spectral_variance(f, g) == pytest.approx(a / wc * (math.atan(om2 / wc) - math.atan(om1 / wc)), rel=1e-7)


# --- Wheelbase filtering -----------------------------------------------------------------


@pytest.mark.parametrize("kind", ["bounce", "pitch"])
def test_two_point_filter_zeros(kind: str) -> None:
    b = 2.5
    zeros = two_point_filter_zeros(b, kind, count=6)
    expected = 2 * b / (2 * np.arange(6) + 1) if kind == "bounce" else b / np.arange(1, 7)
    np.testing.assert_allclose(zeros, expected, rtol=1e-15)
    assert np.all(two_point_filter(zeros, b, kind) < 1e-12)
    # and the maxima (= 1) of one kind sit at the zeros of the other
    other = "pitch" if kind == "bounce" else "bounce"
    np.testing.assert_allclose(two_point_filter(two_point_filter_zeros(b, other, 6), b, kind), 1.0, rtol=1e-12)


def test_delayed_inputs_cancel_at_the_filter_zeros() -> None:
    """The mean of two wheelsets' inputs, through the cross-spectral matrix: zero at
    v f = wavelengths 2b/(2k+1); the difference: zero at b/k."""
    b, v = 2.5, 30.0
    tau = wheelset_delays([b / 2, -b / 2], v)
    np.testing.assert_allclose(tau, [0.0, b / v])
    lam = two_point_filter_zeros(b, "bounce", 4)
    f = np.sort(v / lam)
    gu = track_input_spectrum(f, [np.ones(f.size)], tau)
    mean = output_autospectra(np.broadcast_to([[[0.5, 0.5]]], (f.size, 1, 2)), gu)[:, 0]
    assert np.all(mean < 1e-24)
    f_pitch = np.sort(v / two_point_filter_zeros(b, "pitch", 4))
    diff = output_autospectra(
        np.broadcast_to([[[0.5, -0.5]]], (4, 1, 2)), track_input_spectrum(f_pitch, [np.ones(4)], tau)
    )
    assert np.all(diff[:, 0] < 1e-24)
    np.testing.assert_allclose(np.abs(wheelbase_filter(f, tau)), 0.0, atol=1e-12)
    np.testing.assert_allclose(np.abs(wheelbase_filter(f_pitch, tau, [0.5, -0.5])), 0.0, atol=1e-12)


def test_track_input_spectrum_with_mixing_is_hermitian_and_coherent() -> None:
    f = np.linspace(0.1, 20.0, 50)
    tau = wheelset_delays([9.0, 6.5, -6.5, -9.0], 50.0)
    g1, g2 = 1.0 / (1 + f**2), 0.3 / (1 + f)
    T = np.array([[1.0, 0.0], [0.5, 0.5], [0.5, -0.5]])  # e.g. y, z_left, z_right from (y, z)
    gu = track_input_spectrum(f, [g1, g2], tau, T)
    assert gu.shape == (50, 12, 12)
    np.testing.assert_allclose(gu, np.conj(np.swapaxes(gu, 1, 2)), atol=1e-15)
    assert np.all(np.linalg.eigvalsh(gu) > -1e-12)  # positive semi-definite
    # entry (wheelset 2, input 1) x (wheelset 0, input 2): 0.5*0.5 g2 exp(-i w (tau2 - tau0)) + 0.5*0 ...
    e = delay_factors(f, tau)
    expected = (0.5 * 0.5 * g1 + 0.5 * (-0.5) * g2) * e[:, 2] * np.conj(e[:, 0])
    np.testing.assert_allclose(gu[:, 2 * 3 + 1, 0 * 3 + 2], expected, rtol=1e-12)


# --- Realisations -------------------------------------------------------------------------


def test_harmonic_realisation_is_seeded_and_has_the_spectrum_variance() -> None:
    f = np.array([0.0, 1.0, 10.0, 12.0])
    g = np.array([0.0, 2.0, 2.0, 0.0])
    t, x = harmonic_realisation(f, g, duration=200.0, sampling_rate=100.0, seed=3)
    _, x_again = harmonic_realisation(f, g, duration=200.0, sampling_rate=100.0, seed=3)
    _, x_other = harmonic_realisation(f, g, duration=200.0, sampling_rate=100.0, seed=4)
    assert np.array_equal(x, x_again) and not np.allclose(x, x_other)
    assert t.size == 20000 and t[1] == pytest.approx(0.01)
    fk = np.arange(1, 10000) / 200.0
    assert np.mean(x**2) == pytest.approx(np.sum(np.interp(fk, f, g)) / 200.0, rel=1e-10)
    assert np.mean(x**2) == pytest.approx(spectral_variance(f, g), rel=1e-3)
    kurtosis = np.mean(x**4) / np.mean(x**2) ** 2
    assert kurtosis == pytest.approx(3.0, abs=0.1)  # close to Gaussian


def test_bad_input_reports_every_problem() -> None:
    with pytest.raises(InputError) as err:
        spectral_variance([0.0, 2.0, 1.0], [1.0, -1.0, 1.0])
    assert "increase strictly" in str(err.value)
    with pytest.raises(InputError, match=">= 0"):
        spectral_variance([0.0, 1.0, 2.0], [1.0, -1.0, 1.0])
    with pytest.raises(InputError, match="speed must be > 0"):
        spatial_to_temporal(lambda om: om, [1.0], 0.0)
    with pytest.raises(InputError) as err:
        wheelset_delays([0.0, math.nan], 0.0)
    assert len(str(err.value).splitlines()) == 2
    with pytest.raises(InputError) as err:
        harmonic_realisation([0.0, 1.0], [1.0, 1.0], duration=-1.0, sampling_rate=0.0, seed=-2)
    assert len(str(err.value).splitlines()) == 3
    with pytest.raises(InputError, match="kind"):
        two_point_filter_zeros(2.0, "roll")


# --- modal superposition (modal_form) against a dense solve ---------------------------


def _stable_matrix(n, seed):
    """A real matrix with eigenvalues in the left half-plane (a shifted random one)."""
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(n, n))
    return a - (np.max(np.linalg.eigvals(a).real) + 0.5) * np.eye(n)


@pytest.mark.parametrize("n, seed", [(6, 1), (40, 2), (74, 3)])
def test_modal_superposition_equals_a_dense_solve(n, seed):
    """``V diag(1/(i w - lambda)) V^-1 B`` against ``solve(i w I - A, B)`` at 50
    frequencies: achieved about 1e-14 of the largest entry, asserted 1e-11."""
    from express.analysis.ride.spectral import modal_form

    a = _stable_matrix(n, seed)
    b = np.random.default_rng(seed + 10).normal(size=(n, 3))
    modal = modal_form(a)
    assert modal is not None and modal.condition < 1e6
    w = 2 * math.pi * np.geomspace(0.01, 100.0, 50)
    for omega in w:
        dense = np.linalg.solve(1j * omega * np.eye(n) - a, b)
        superposed = modal.right @ ((modal.left @ b) / (1j * omega - modal.eigenvalues)[:, None])
        assert np.max(np.abs(superposed - dense)) <= 1e-11 * np.max(np.abs(dense))


def test_a_defective_matrix_has_no_modal_form():
    """A Jordan block (two coalesced modes) has no basis of eigenvectors: refused, so the
    response is solved by the Schur form instead; a diagonalisable matrix is accepted."""
    from express.analysis.ride.spectral import modal_form

    jordan = np.array([[-1.0, 1.0, 0.0], [0.0, -1.0, 1.0], [0.0, 0.0, -1.0]])
    assert modal_form(jordan) is None
    assert modal_form(np.array([[np.nan]])) is None
    assert modal_form(np.diag([-1.0, -2.0, -3.0])).condition == pytest.approx(1.0)
