"""Comfort indices (express.analysis.ride.comfort): Sperling's Wz and EN 12299 N_MV."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from express.analysis.ride import (
    SPERLING_CONSTANT,
    WB,
    WD,
    harmonic_realisation,
    mean_comfort,
    mean_comfort_spectral,
    p95_from_spectrum,
    spectral_variance,
    sperling_index,
    sperling_index_harmonics,
    sperling_index_time,
    sperling_weighting,
    window_rms,
)
from express.base.diagnostics import InputError

FS = 200.0


def test_sperling_constant() -> None:
    assert pytest.approx((100 * math.sqrt(2)) ** 0.3) == SPERLING_CONSTANT
    assert pytest.approx(4.417, abs=5e-4) == SPERLING_CONSTANT


@pytest.mark.parametrize("direction", ["vertical", "lateral"])
@pytest.mark.parametrize("f0", [1.0, 4.0, 12.0])
def test_sperling_single_harmonic_three_ways(direction: str, f0: float) -> None:
    """Sperling's definition for one harmonic (peak a in cm/s^2): Wz = (a B)^0.3; the
    spectral (energy) form and the time-history form give the same."""
    peak = 0.4  # m/s^2
    expected = (100 * peak * float(sperling_weighting(f0, direction))) ** 0.3
    assert sperling_index_harmonics([f0], [peak], direction) == pytest.approx(expected, rel=1e-12)
    # a whole number of periods: the periodogram puts all the power on one line
    t = np.arange(int(20 * FS)) / FS
    assert sperling_index_time(peak * np.sin(2 * np.pi * f0 * t + 0.3), FS, direction) == pytest.approx(
        expected, rel=1e-9
    )
    # a narrow band of the same mean square peak^2/2 (triangle of area peak^2/2)
    df = 1e-4
    f = np.array([f0 - df, f0, f0 + df])
    g = np.array([0.0, peak**2 / 2 / df, 0.0])
    assert sperling_index(f, g, direction) == pytest.approx(expected, rel=1e-6)


def test_sperling_harmonics_combine_by_tenth_powers() -> None:
    f, a = [1.0, 3.0, 8.0], [0.2, 0.1, 0.3]
    single = [sperling_index_harmonics([fi], [ai]) for fi, ai in zip(f, a, strict=True)]
    assert sperling_index_harmonics(f, a) == pytest.approx(sum(w**10 for w in single) ** 0.1, rel=1e-12)


def test_sperling_lateral_over_vertical_and_scaling() -> None:
    f = np.linspace(0.1, 40.0, 400)
    g = 0.02 / (1 + ((f - 1.5) / 0.5) ** 2)
    wz_v, wz_l = sperling_index(f, g, "vertical"), sperling_index(f, g, "lateral")
    assert wz_l / wz_v == pytest.approx(1.25**0.3, rel=1e-12)
    # Wz scales as the acceleration to the power 0.3
    assert sperling_index(f, 4 * g) / wz_v == pytest.approx(2**0.3, rel=1e-12)
    # and only the band 0.5-30 Hz counts
    outside = np.where((f < 0.5) | (f > 30.0), 1.0, 0.0)
    assert sperling_index(f, g + outside) == pytest.approx(wz_v, rel=1e-3)


def test_sperling_time_history_against_spectrum() -> None:
    f = np.linspace(0.0, 40.0, 801)
    g = 0.01 * np.exp(-(((f - 1.2) / 0.4) ** 2)) + 0.002 * np.exp(-(((f - 9.0) / 1.5) ** 2))
    _, a = harmonic_realisation(f, g, duration=300.0, sampling_rate=FS, seed=11)
    assert sperling_index_time(a, FS) == pytest.approx(sperling_index(f, g), rel=0.005)


# --- EN 12299 ----------------------------------------------------------------------------


def test_window_rms() -> None:
    x = np.r_[np.full(10, 2.0), np.full(10, -3.0), np.full(7, 9.0)]  # the last part is too short
    np.testing.assert_allclose(window_rms(x, sampling_rate=2.0, window=5.0), [2.0, 3.0])
    with pytest.raises(InputError, match="window"):
        window_rms(np.ones(5), sampling_rate=2.0, window=5.0)


def test_mean_comfort_of_sinusoids() -> None:
    """Steady sinusoids: every 5-s RMS is |W(f)| A / sqrt 2, so N_MV follows in closed form."""
    t = np.arange(int(300 * FS)) / FS
    ramp = np.clip(t / 10.0, 0.0, 1.0)  # a gentle start: no filter transient above the steady level
    cases = {"x": (0.3, 0.8, WD), "y": (0.5, 1.6, WD), "z": (0.6, 6.0, WB)}
    signals = {k: ramp * a * np.sin(2 * np.pi * f * t) for k, (a, f, _) in cases.items()}
    result = mean_comfort(signals["x"], signals["y"], signals["z"], FS)
    expected = {k: float(w.magnitude(f)) * a / math.sqrt(2) for k, (a, f, w) in cases.items()}
    assert result.a_xp95 == pytest.approx(expected["x"], rel=2e-3)
    assert result.a_yp95 == pytest.approx(expected["y"], rel=2e-3)
    assert result.a_zp95 == pytest.approx(expected["z"], rel=2e-3)
    assert result.n_mv == pytest.approx(6 * math.sqrt(sum(v**2 for v in expected.values())), rel=2e-3)
    assert result.method == "time"


def car_body_spectra() -> tuple[np.ndarray, ...]:
    """Plausible floor acceleration PSDs [(m/s^2)^2/Hz]: body modes near 1 Hz, a bending
    mode near 9 Hz vertically."""
    f = np.linspace(0.0, 60.0, 3001)

    def mode(f0: float, zeta: float, level: float) -> np.ndarray:
        r = f / f0
        return level / ((1 - r**2) ** 2 + (2 * zeta * r) ** 2)

    gx = mode(2.5, 0.2, 2e-4)
    gy = mode(1.0, 0.15, 4e-3) + mode(6.0, 0.1, 2e-4)
    gz = mode(1.2, 0.2, 3e-3) + mode(9.0, 0.05, 4e-4)
    return f, gx, gy, gz


def test_mean_comfort_spectral_rms_method_is_the_weighted_rms() -> None:
    f, gx, gy, gz = car_body_spectra()
    result = mean_comfort_spectral(f, gx, gy, gz, method="rms")
    sig = [math.sqrt(spectral_variance(f, w.magnitude(f) ** 2 * g)) for w, g in ((WD, gx), (WD, gy), (WB, gz))]
    assert (result.a_xp95, result.a_yp95, result.a_zp95) == pytest.approx(sig, rel=1e-12)
    assert result.n_mv == pytest.approx(6 * math.sqrt(sum(s**2 for s in sig)), rel=1e-12)


def test_p95_of_band_limited_white_noise_follows_bendat_piersol() -> None:
    """Ideal band-limited white noise of bandwidth B: the T-s mean square is chi-square
    with 2 B T degrees of freedom (Bendat & Piersol)."""
    bandwidth, window = 4.0, 5.0
    f = np.linspace(0.0, 40.0, 40001)
    g = np.where((f >= 10.0) & (f <= 10.0 + bandwidth), 0.5, 0.0)
    sigma = math.sqrt(0.5 * bandwidth)
    nu = 2 * bandwidth * window
    expected = sigma * math.sqrt(stats.chi2.ppf(0.95, nu) / nu)
    assert p95_from_spectrum(f, g, window) == pytest.approx(expected, rel=0.005)  # achieved 0.21 %
    assert p95_from_spectrum(f, g, window, method="rms") == pytest.approx(sigma, rel=3e-4)  # achieved 1.25e-4


@pytest.mark.slow
def test_mean_comfort_spectral_against_long_time_histories() -> None:
    """A seeded 6000 s realisation (1200 windows of 5 s, so that the sample percentile
    itself scatters by about 1 %): the Gaussian spectral estimate of each a_P95 and of
    N_MV within 3 % of the time-history values."""
    f, gx, gy, gz = car_body_spectra()
    histories = [
        harmonic_realisation(f, g, duration=6000.0, sampling_rate=FS, seed=s)[1] for g, s in ((gx, 1), (gy, 2), (gz, 3))
    ]
    timed = mean_comfort(*histories, FS)
    spectral = mean_comfort_spectral(f, gx, gy, gz)
    plain = mean_comfort_spectral(f, gx, gy, gz, method="rms")
    for name in ("a_xp95", "a_yp95", "a_zp95", "n_mv"):
        assert getattr(spectral, name) == pytest.approx(getattr(timed, name), rel=0.03), name
    # the window-to-window scatter matters: the plain RMS underestimates the percentile
    assert plain.n_mv < 0.95 * timed.n_mv


def test_comfort_bad_input() -> None:
    f = np.array([0.0, 1.0, 2.0])
    with pytest.raises(InputError, match="psd_y"):
        mean_comfort_spectral(f, np.ones(3), -np.ones(3), np.ones(3))
    with pytest.raises(InputError, match="method"):
        p95_from_spectrum(f, np.ones(3), method="crest")
    with pytest.raises(InputError):
        sperling_index_harmonics([0.0], [1.0])
    with pytest.raises(InputError) as err:
        sperling_index_time([1.0, 2.0], -1.0)
    assert len(str(err.value).splitlines()) == 2
