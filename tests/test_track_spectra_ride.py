"""Vertical, cross-level, gauge and tabulated track spectra (express.rail.track.spectra)
against their defining formulas, exact band variances and seeded realisations."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from express.analysis.ride import spatial_to_temporal, spectral_variance
from express.rail.track.irregularity import Harmonics, SpectrumIrregularity
from express.rail.track.spectra import (
    AAR_CLASSES,
    ERRI_LEVELS,
    FRA_CLASSES,
    SPECTRA,
    SPECTRA_BY_COMPONENT,
    ERRICrossLevelSpectrum,
    get_spectrum,
)
from express.rail.track.tabulated_spectra import TabulatedSpectrum, table_problems

WC, WR, WS, B = 0.8246, 0.0206, 0.4380, 0.75  # ERRI / DB constants [rad/m], half rail distance [m]
FRA_WC, K = 0.8245, 0.25

# Published constants, written out again: FRA A_v, A_a [cm^2 rad/m], Omega_s [rad/m] per class 1..6
FRA_AV = [1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339]
FRA_AA = [3.3634, 1.2107, 0.4128, 0.3027, 0.0762, 0.0339]
FRA_WS = [0.6046, 0.9308, 0.8520, 1.1312, 0.8209, 0.4380]
ERRI_A = {"vertical": (4.032e-7, 1.080e-6), "alignment": (2.119e-7, 6.125e-7), "gauge": (5.32e-8, 1.032e-7)}


def erri_profile(w: np.ndarray, a: float) -> np.ndarray:
    return a * WC**2 / ((w**2 + WR**2) * (w**2 + WC**2))


def erri_three_pole(w: np.ndarray, a: float) -> np.ndarray:
    return a * WC**2 * w**2 / ((w**2 + WR**2) * (w**2 + WC**2) * (w**2 + WS**2))


def fra_profile(w: np.ndarray, a_cm2: float) -> np.ndarray:
    return K * a_cm2 * 1e-4 * FRA_WC**2 / (w**2 * (w**2 + FRA_WC**2))


def fra_cross_level(w: np.ndarray, a_cm2: float, ws: float) -> np.ndarray:
    return 4 * K * a_cm2 * 1e-4 * FRA_WC**2 / ((w**2 + FRA_WC**2) * (w**2 + ws**2))


W = np.logspace(-3, 1.5, 200)  # rad/m


def expected_cases() -> list[tuple[str, str, object]]:
    cases: list[tuple[str, str, object]] = []
    for level, i in (("low", 0), ("high", 1)):
        cases.append(("vertical", f"erri_{level}", erri_profile(W, ERRI_A["vertical"][i])))
        cases.append(("alignment", f"erri_{level}", erri_profile(W, ERRI_A["alignment"][i])))
        # the published cross-level angle PSD times (2 b)^2: height difference between rails
        cases.append(("cross_level", f"erri_{level}", (2 * B) ** 2 * erri_three_pole(W, ERRI_A["vertical"][i]) / B**2))
        cases.append(("gauge", f"erri_{level}", erri_three_pole(W, ERRI_A["gauge"][i])))
    for c in range(1, 7):
        cases.append(("vertical", f"fra{c}", fra_profile(W, FRA_AV[c - 1])))
        cases.append(("cross_level", f"fra{c}", fra_cross_level(W, FRA_AV[c - 1], FRA_WS[c - 1])))
        cases.append(("gauge", f"fra{c}", fra_cross_level(W, FRA_AV[c - 1], FRA_WS[c - 1])))
        cases.append(("gauge", f"aar{c}", fra_cross_level(W, FRA_AV[c - 1], FRA_WS[c - 1])))
    return cases


@pytest.mark.parametrize(("component", "name", "expected"), expected_cases(), ids=lambda x: str(x)[:12])
def test_registered_spectra_match_their_defining_formulas(component: str, name: str, expected: np.ndarray) -> None:
    spectrum = get_spectrum(name, component)
    assert spectrum.component == component
    np.testing.assert_allclose(spectrum.psd(W), expected, rtol=1e-12)


@pytest.mark.parametrize("c", range(1, 7))
def test_fra_alignment_classes(c: int) -> None:
    np.testing.assert_allclose(FRA_CLASSES["alignment"][c - 1].psd(W), fra_profile(W, FRA_AA[c - 1]), rtol=1e-12)
    # classes 5 and 6 are the track files' fra5, fra6
    if c >= 5:
        assert FRA_CLASSES["alignment"][c - 1] is SPECTRA[f"fra{c}"]


def test_fra_class_5_vertical_known_value_in_si() -> None:
    """Unit check by hand: A_v = 0.2095 cm^2 rad/m is 0.2095e-4 m^2 rad/m; at Omega = Omega_c
    the PSD is k A_v / (2 Omega_c^2) = 0.25 x 0.2095 / (2 x 0.67980) = 0.038522 cm^2/(rad/m)
    = 3.8522e-6 m^2/(rad/m) (a cm^2 slip would give 1e4 times that, a missing one 1e-4)."""
    vertical = FRA_CLASSES["vertical"][4]
    assert vertical.psd(0.8245) == pytest.approx(3.8522e-6, rel=1e-4)
    # and the alignment of class 6 at 1 rad/m: 0.25 x 0.0339e-4 x 0.67980 / (1 x 1.67980)
    assert FRA_CLASSES["alignment"][5].psd(1.0) == pytest.approx(3.4298e-7, rel=1e-4)


@pytest.mark.parametrize("component", ["vertical", "alignment", "cross_level", "gauge"])
@pytest.mark.parametrize("c", range(1, 7))
def test_aar_classes_are_the_us_class_spectra(component: str, c: int) -> None:
    aar, fra = AAR_CLASSES[component][c - 1], FRA_CLASSES[component][c - 1]
    assert aar.name.startswith(f"AAR class {c}") and aar.component == component
    np.testing.assert_allclose(aar.psd(W), fra.psd(W), rtol=0)  # same published constants
    a_cm2 = FRA_AA[c - 1] if component == "alignment" else FRA_AV[c - 1]
    two_rail = component in ("cross_level", "gauge")  # one form for both (spectra.FRAGaugeSpectrum)
    expected = fra_cross_level(W, a_cm2, FRA_WS[c - 1]) if two_rail else fra_profile(W, a_cm2)
    np.testing.assert_allclose(aar.psd(W), expected, rtol=1e-12)
    if component != "alignment":
        assert get_spectrum(f"aar{c}", component) is aar


def all_new_spectra() -> list[object]:
    out: list[object] = [sp for comp in ("vertical", "cross_level", "gauge") for sp in ERRI_LEVELS[comp].values()]
    out += [sp for comp in ("vertical", "alignment", "cross_level", "gauge") for sp in FRA_CLASSES[comp]]
    out.append(TabulatedSpectrum("table", (0.05, 0.3, 1.0, 4.0), (2e-5, 4e-6, 1e-7, 0.0), "vertical"))
    return out


@pytest.mark.parametrize("spectrum", all_new_spectra(), ids=lambda sp: sp.name)
@pytest.mark.parametrize(("lo", "hi"), [(2 * np.pi / 120, 2 * np.pi / 3), (0.02, 0.1), (0.5, 20.0)])
def test_band_variance_is_the_integral_of_the_psd(spectrum, lo: float, hi: float) -> None:
    integral = quad(spectrum.psd, lo, hi, limit=500, epsabs=0.0, epsrel=1e-11)[0]
    assert spectrum.variance(lo, hi) == pytest.approx(integral, rel=1e-8)


@pytest.mark.parametrize("spectrum", [*ERRI_LEVELS["cross_level"].values(), *ERRI_LEVELS["gauge"].values(),
                                      *FRA_CLASSES["cross_level"], *FRA_CLASSES["gauge"]], ids=lambda sp: sp.name)
def test_finite_at_zero_wavenumber_and_total_variance(spectrum) -> None:
    assert np.isfinite(spectrum.psd(0.0))
    total = quad(spectrum.psd, 0.0, np.inf, limit=500, epsabs=0.0, epsrel=1e-10)[0]
    assert spectrum.variance(0.0, 1e9) == pytest.approx(total, rel=1e-6)


def test_every_component_registers_the_erri_fra_and_aar_classes() -> None:
    assert set(SPECTRA) == set(SPECTRA_BY_COMPONENT["vertical"])
    assert SPECTRA["fra5"] is FRA_CLASSES["alignment"][4] and SPECTRA["aar3"] is AAR_CLASSES["alignment"][2]
    assert set(SPECTRA_BY_COMPONENT["vertical"]) == {"erri_low", "erri_high", *(f"fra{c}" for c in range(1, 7)),
                                                     *(f"aar{c}" for c in range(1, 7))}
    assert set(SPECTRA_BY_COMPONENT["gauge"]) == set(SPECTRA_BY_COMPONENT["vertical"])
    assert get_spectrum("ERRI-High", "cross_level") is ERRI_LEVELS["cross_level"]["high"]
    with pytest.raises(KeyError, match=r"known gauge spectra: erri_low, erri_high, fra1, .*aar6"):
        get_spectrum("fra7", "gauge")


def test_cross_level_height_difference_does_not_depend_on_b() -> None:
    sp = ERRICrossLevelSpectrum("x", A=4.032e-7)
    for b in (0.7175, 0.75, 0.8):  # angle PSD A b^-2 (...) times (2 b)^2
        np.testing.assert_allclose(sp.psd(W), (2 * b) ** 2 * erri_three_pole(W, 4.032e-7) / b**2, rtol=1e-12)


# --- User tables ---------------------------------------------------------------------------


def test_tabulated_spectrum_interpolates_and_integrates_exactly() -> None:
    sp = TabulatedSpectrum("t", (0.1, 0.5, 2.0), (4.0, 2.0, 1.0))
    np.testing.assert_allclose(sp.psd([0.05, 0.1, 0.3, 1.25, 2.0, 3.0]), [0.0, 4.0, 3.0, 1.5, 1.0, 0.0])
    assert sp.variance(0.0, 10.0) == pytest.approx(0.4 * 3.0 + 1.5 * 1.5)  # trapezoids
    assert sp.variance(0.3, 1.25) == pytest.approx(0.2 * (3 + 2) / 2 + 0.75 * (2 + 1.5) / 2)
    assert sp.component == "alignment"


def test_tabulated_spectrum_per_cycle_table_keeps_the_variance() -> None:
    n = np.array([0.01, 0.05, 0.1, 0.3])  # 1/m
    g = np.array([3e-4, 2e-5, 4e-6, 1e-7])  # m^2/(1/m)
    sp = TabulatedSpectrum.from_table("cycles", n, g, unit="1/m", component="vertical")
    np.testing.assert_allclose(sp.wavenumbers, 2 * np.pi * n)
    assert sp.variance(0.0, 10.0) == pytest.approx(np.trapezoid(g, n) if hasattr(np, "trapezoid") else np.trapz(g, n))
    assert sp.component == "vertical"


def test_tabulated_spectrum_approximates_a_published_one() -> None:
    ref = ERRI_LEVELS["vertical"]["low"]
    w = np.geomspace(2 * np.pi / 200, 2 * np.pi / 1, 2000)
    sp = TabulatedSpectrum("erri table", tuple(w), tuple(ref.psd(w)), "vertical")
    lo, hi = 2 * np.pi / 120, 2 * np.pi / 3
    assert sp.variance(lo, hi) == pytest.approx(ref.variance(lo, hi), rel=1e-4)


def test_table_problems_lists_every_problem() -> None:
    problems = table_problems([0.1, 0.3, 0.2], [1.0, -1.0, 2.0], component="twist")
    assert len(problems) == 3
    assert any("increase strictly (row 3" in p for p in problems)
    assert any(">= 0 (row 2" in p for p in problems)
    assert any("unknown component 'twist'" in p for p in problems)
    with pytest.raises(ValueError, match="my table: need two columns"):
        TabulatedSpectrum("my table", (0.1,), (1.0,))
    with pytest.raises(ValueError, match="unit"):
        TabulatedSpectrum.from_table("t", [0.1, 0.2], [1.0, 1.0], unit="Hz")


# --- Realisations --------------------------------------------------------------------------


@pytest.mark.parametrize("spectrum", [ERRI_LEVELS["vertical"]["high"], ERRI_LEVELS["cross_level"]["low"],
                                      ERRI_LEVELS["gauge"]["high"], FRA_CLASSES["cross_level"][3],
                                      FRA_CLASSES["vertical"][5], AAR_CLASSES["alignment"][3]],
                         ids=lambda sp: sp.name)
def test_seeded_realisation_has_the_band_variance(spectrum) -> None:
    """Sum of cosines with random phases (Harmonics.draw): over one period the mean square
    of the sampled profile is the band variance, exactly; the same seed, the same profile."""
    period, lmin, lmax = 2000.0, 3.0, 120.0
    h = Harmonics.draw(spectrum, 5, lmin, lmax, period)
    assert np.array_equal(h.phases, Harmonics.draw(spectrum, 5, lmin, lmax, period).phases)
    assert not np.array_equal(h.phases, Harmonics.draw(spectrum, 6, lmin, lmax, period).phases)
    s = np.arange(0.0, period, 0.5)  # 4000 samples, k up to 667 < 2000: orthogonal on the grid
    profile = np.cos(np.outer(s, h.wavenumbers) + h.phases) @ h.amplitudes
    band = spectrum.variance(2 * np.pi / lmax, 2 * np.pi / lmin)
    assert np.mean(profile**2) == pytest.approx(band, rel=1e-9)
    # and a SpectrumIrregularity built on it gives the same profile
    irr = SpectrumIrregularity(spectrum, seed=5, wavelength_min=lmin, wavelength_max=lmax, period=period)
    np.testing.assert_allclose(irr.value(s[:50]), profile[:50], rtol=1e-9, atol=1e-15)


def test_realisation_spectrum_matches_the_psd() -> None:
    """The periodogram of a realisation, averaged over octave-wide bands, against S (the
    cosines sit on the FFT lines, so this checks the amplitudes, not a statistic)."""
    spectrum = ERRI_LEVELS["vertical"]["low"]
    period, ds = 2048.0, 0.5
    h = Harmonics.draw(spectrum, 2, 2.5, 200.0, period)
    s = np.arange(0.0, period, ds)
    profile = np.cos(np.outer(s, h.wavenumbers) + h.phases) @ h.amplitudes
    spec = np.abs(np.fft.rfft(profile)) ** 2 * 2 * ds / s.size / (2 * np.pi)  # one-sided, per rad/m
    omega = 2 * np.pi * np.fft.rfftfreq(s.size, ds)
    for lo in (0.05, 0.1, 0.2, 0.4, 0.8):
        band = (omega >= lo) & (omega < 2 * lo)
        assert np.mean(spec[band]) / np.mean(spectrum.psd(omega[band])) == pytest.approx(1.0, rel=0.05)


def test_temporal_psd_of_a_track_spectrum_keeps_band_variances() -> None:
    spectrum = get_spectrum("erri_high", "vertical")
    v = 200 / 3.6
    f = np.linspace(v / 120, v / 3, 40001)  # Hz: wavelengths 120 m .. 3 m
    g = spatial_to_temporal(spectrum.psd, f, v)
    assert spectral_variance(f, g) == pytest.approx(spectrum.variance(2 * np.pi / 120, 2 * np.pi / 3), rel=1e-6)
    assert math.isfinite(g[0]) and np.all(g > 0)
