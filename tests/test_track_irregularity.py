"""Tests of express.rail.track.irregularity: sinusoid, profile, spectrum realisation, limits."""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy.integrate import quad

from express.rail.track import (
    ERRI_LOW,
    MAX_HARMONICS,
    MAX_LATERAL_IRREGULARITY,
    MAX_SAMPLES,
    SPECTRA,
    Harmonics,
    NoIrregularity,
    ProfileIrregularity,
    SinusoidIrregularity,
    SpectrumIrregularity,
    irregularity,
    paper_curve,
)


@pytest.mark.parametrize("name", sorted(SPECTRA))
def test_random_profile_variance_matches_psd(name):
    period = 2000.0
    irr = SpectrumIrregularity(name, seed=7, period=period)
    target = quad(SPECTRA[name].psd, 2 * np.pi / 120, 2 * np.pi / 3, limit=200)[0]
    n = 8192  # > 2 * highest harmonic (period / 3 m = 667)
    s = np.arange(n) * (period / n)
    y = irr(s)
    assert np.mean(y**2) == pytest.approx(target, rel=0.02)  # exact over one period
    assert np.mean(y**2) == pytest.approx(irr.band_variance, rel=1e-9)
    # the spectral shape: one-sided periodogram over the period vs the PSD
    spec = np.abs(np.fft.rfft(y)) ** 2 / n**2 * 2 / (2 * np.pi / period)
    k = np.rint(irr.wavenumbers / (2 * np.pi / period)).astype(int)
    inner = slice(1, -1)  # the outer bins also hold the band's fractional ends
    np.testing.assert_allclose(spec[k][inner], SPECTRA[name].psd(irr.wavenumbers)[inner], rtol=0.01)
    # a window shorter than the period still has about the right variance
    assert np.var(irr(np.arange(0, 1000, 0.5))) == pytest.approx(target, rel=0.5)


def test_random_profile_is_reproducible_and_periodic():
    s = np.linspace(0, 300, 601)
    a = SpectrumIrregularity("fra6", seed=3)
    b = SpectrumIrregularity("fra6", seed=3)
    c = SpectrumIrregularity("fra6", seed=4)
    np.testing.assert_array_equal(a(s), b(s))
    assert np.max(np.abs(a(s) - c(s))) > 1e-4
    np.testing.assert_allclose(a(s + a.period), a(s), atol=1e-12)
    h = 1e-4
    np.testing.assert_allclose(a.rate(s), (a(s + h) - a(s - h)) / (2 * h), atol=1e-8)
    tab = a.tabulate(0, 300, 0.05)
    assert np.max(np.abs(tab(s[1:-1] + 0.013) - a(s[1:-1] + 0.013))) < 2e-5


def test_spectrum_irregularity_validation():
    with pytest.raises(ValueError, match="wavelength_min"):
        SpectrumIrregularity("erri_low", wavelength_min=50, wavelength_max=20)
    with pytest.raises(ValueError, match="unknown spectrum"):
        SpectrumIrregularity("fra9")


def test_sinusoid_and_none():
    irr = SinusoidIrregularity(0.002, 25.0, phase=0.3)
    s = np.linspace(0, 60, 7)
    np.testing.assert_allclose(irr(s), 0.002 * np.sin(2 * np.pi * s / 25 + 0.3))
    np.testing.assert_allclose(irr.rate(s), 0.002 * 2 * np.pi / 25 * np.cos(2 * np.pi * s / 25 + 0.3))
    t = paper_curve(irregularity=irr)
    assert t.lateral_irregularity(10.0) == pytest.approx(irr(10.0))
    assert t.with_irregularity(NoIrregularity()).lateral_irregularity(10.0) == 0.0
    with pytest.raises(ValueError, match="wavelength"):
        SinusoidIrregularity(0.001, 0.0)


# --- limits --------------------------------------------------------------------------------


def test_harmonics_limit_refused_up_front(monkeypatch):
    # issue 17: period 1e6 m with 0.1 m waves would need 1e7 cosines; refused before any is drawn
    def no_drawing(*args, **kwargs):
        raise AssertionError("harmonics drawn before the limit was checked")

    monkeypatch.setattr(Harmonics, "draw", no_drawing)
    monkeypatch.setattr(irregularity, "_harmonic_numbers", no_drawing)
    with pytest.raises(ValueError) as info:
        SpectrumIrregularity("fra5", wavelength_min=0.1, period=1e6)
    message = str(info.value)
    assert "'period' (1e+06 m) with 'wavelength_min' (0.1 m)" in message
    assert f"needs 9.99e+06 harmonics, more than the limit {MAX_HARMONICS}" in message


def test_harmonics_limit_is_the_documented_count():
    # period * (1/wavelength_min - 1/wavelength_max) = MAX_HARMONICS exactly is accepted
    lmin, lmax = 2.0, 4.0
    period = MAX_HARMONICS / (1 / lmin - 1 / lmax)
    irr = SpectrumIrregularity(ERRI_LOW, wavelength_min=lmin, wavelength_max=lmax, period=period)
    assert irr.wavenumbers.size == MAX_HARMONICS + 1  # both band edges are harmonics here
    with pytest.raises(ValueError, match="more than the limit"):
        SpectrumIrregularity(ERRI_LOW, wavelength_min=lmin, wavelength_max=lmax, period=period * 1.01)


def test_spectrum_field_problems_all_at_once():
    problems = SpectrumIrregularity.field_problems("fra7", seed=1.5, wavelength_min=-1, period=float("inf"))
    keys = [key for key, _ in problems]
    assert keys == ["spectrum", "seed", "wavelength_min", "period"]
    assert SpectrumIrregularity.field_problems("fra5") == []
    (key, message), = SpectrumIrregularity.field_problems("fra5", wavelength_min=100, wavelength_max=100.4,
                                                           period=100.5)
    assert key == "period" and "no wavenumber" in message


def test_harmonics_are_drawn_once_and_read_only():
    irr = SpectrumIrregularity("fra5", seed=2, period=1000.0)
    assert irr.harmonics is irr.harmonics
    assert irr.harmonics.spectrum is SPECTRA["fra5"] and irr.psd_spectrum is SPECTRA["fra5"]
    with pytest.raises(ValueError):
        irr.wavenumbers[0] = 1.0
    assert irr == SpectrumIrregularity("fra5", seed=2, period=1000.0)


@pytest.mark.parametrize(
    "args, text",
    [
        ((0.0, 10.0, 0.0), "'step' must be > 0 m"),
        ((0.0, 10.0, float("nan")), "'step' must be > 0 m"),
        ((10.0, 0.0, 0.25), "need finite start < stop"),
        ((0.0, float("inf"), 0.25), "need finite start < stop"),
        ((0.0, 1e6, 1e-3), f"1e+09 points from 0 m to 1e+06 m every 0.001 m, more than the limit {MAX_SAMPLES}"),
    ],
)
def test_tabulate_limits(args, text):
    irr = SpectrumIrregularity("erri_low")
    with pytest.raises(ValueError, match=re.escape(text)):
        irr.tabulate(*args)


def test_lateral_irregularity_limit():
    assert SinusoidIrregularity(MAX_LATERAL_IRREGULARITY, 20.0).amplitude == MAX_LATERAL_IRREGULARITY
    with pytest.raises(ValueError, match=r"'amplitude' must be at most 0\.1 m in size, got 2\.0 m"):
        SinusoidIrregularity(2.0, 20.0)  # 2 mm written as metres
    with pytest.raises(ValueError, match=r"\|yr\| reaches 3 m"):
        ProfileIrregularity([0.0, 10.0], [0.0, -3.0])


def test_profile_validation():
    with pytest.raises(ValueError, match="differ in length"):
        ProfileIrregularity([0.0, 1.0, 2.0], [0.0, 0.0])
    with pytest.raises(ValueError, match="at least two points"):
        ProfileIrregularity([0.0], [0.0])
    with pytest.raises(ValueError, match="strictly increasing"):
        ProfileIrregularity([0.0, 0.0], [0.0, 0.0])
    with pytest.raises(ValueError, match="finite"):
        ProfileIrregularity([0.0, np.nan], [0.0, 0.0])
    # arrays and lists give the same profile; a scalar in, a float out
    irr = ProfileIrregularity(np.array([0.0, 10.0]), np.array([0.0, 0.01]))
    assert irr(2.5) == pytest.approx(0.0025) and isinstance(irr(2.5), float)
    assert ProfileIrregularity([0, 10], [0, 0.01]).rate(2.5) == pytest.approx(1e-3)
    assert NoIrregularity()(np.ones(3)).shape == (3,)


def _cosine_sum(s, w, a, phi, derivative):
    """The definition, one cosine per term (independent of Harmonics.evaluate)."""
    arg = np.outer(s, w) + phi
    return -np.sin(arg) @ (a * w) if derivative else np.cos(arg) @ a


@pytest.mark.parametrize("derivative", [False, True])
@pytest.mark.parametrize("period, lmin", [(10_000.0, 3.0), (250.0, 3.0), (120.0, 100.0), (2000.0, 1.0)])
def test_harmonic_sum_equals_the_cosine_sum(period, lmin, derivative):
    # block sizes: 3250 harmonics, 81 (one full block and a partial one), 1 (a single cosine), 1984
    irr = SpectrumIrregularity("fra5", seed=5, wavelength_min=lmin, wavelength_max=min(120.0, period), period=period)
    h = irr.harmonics
    s = np.concatenate([np.linspace(-30.0, 1500.0, 3001), [1e5 + 0.3]])
    expected = _cosine_sum(s, h.wavenumbers, h.amplitudes, h.phases, derivative)
    scale = np.max(np.abs(expected))
    np.testing.assert_allclose(h.evaluate(s, derivative), expected, rtol=0, atol=1e-11 * scale)


def test_harmonic_sum_of_arbitrary_wavenumbers():
    rng = np.random.default_rng(0)
    w = np.sort(rng.uniform(0.05, 2.0, 300))
    a, phi = rng.uniform(0, 1e-3, 300), rng.uniform(0, 2 * np.pi, 300)
    h = Harmonics(ERRI_LOW, w, a, phi)
    s = np.linspace(0, 400, 777)
    for derivative in (False, True):
        np.testing.assert_allclose(h.evaluate(s, derivative), _cosine_sum(s, w, a, phi, derivative), atol=1e-15)
