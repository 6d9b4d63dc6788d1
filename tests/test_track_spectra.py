"""Tests of express.rail.track.spectra: published constants, PSD values, exact band integrals, registry."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest
from scipy.integrate import quad

from express.rail.track import (
    ERRI_HIGH,
    ERRI_LOW,
    FRA_CLASS_5,
    FRA_CLASS_6,
    SPECTRA,
    SPECTRA_BY_COMPONENT,
    SpectrumIrregularity,
    TrackSpectrum,
    get_spectrum,
    register_spectrum,
)


def test_spectrum_constants():
    assert FRA_CLASS_5.A_a == pytest.approx(0.0762e-4)
    assert FRA_CLASS_6.A_a == pytest.approx(0.0339e-4)
    assert FRA_CLASS_5.omega_c == FRA_CLASS_6.omega_c == 0.8245
    assert FRA_CLASS_5.k == 0.25
    assert (ERRI_LOW.A, ERRI_HIGH.A) == (2.119e-7, 6.125e-7)
    assert (ERRI_LOW.omega_c, ERRI_LOW.omega_r) == (0.8246, 0.0206)
    assert get_spectrum("ERRI-High") is ERRI_HIGH
    with pytest.raises(KeyError, match="fra5"):
        get_spectrum("fra7")


@pytest.mark.parametrize("f, tabulated", [(0.02, 2.3194e-4), (0.1, 6.1608e-6), (0.2, 7.3333e-7)])
def test_erri_high_against_gensys_table(f, tabulated):
    # GENSYS TRC_IPSD manual, "ORE B176 high level" PSD_LAT in m^2/(1/m) = 2 pi S(Omega)
    # the table has 5 digits (rounding up to 2e-5 relative); achieved <= 7.5e-6
    assert 2 * np.pi * ERRI_HIGH.psd(2 * np.pi * f) == pytest.approx(tabulated, rel=2.5e-5)


@pytest.mark.parametrize("name", sorted(SPECTRA))
def test_closed_form_band_variance(name):
    sp = SPECTRA[name]
    lo, hi = 2 * np.pi / 120, 2 * np.pi / 3
    assert sp.variance(lo, hi) == pytest.approx(quad(sp.psd, lo, hi, limit=200)[0], rel=1e-9)


@pytest.mark.parametrize("name", sorted(SPECTRA))
def test_primitive_is_an_antiderivative(name):
    sp = SPECTRA[name]
    w = np.linspace(0.05, 3.0, 40)
    h = 1e-5
    np.testing.assert_allclose((sp.primitive(w + h) - sp.primitive(w - h)) / (2 * h), sp.psd(w), rtol=1e-6)


def test_every_alignment_spectrum_is_registered_once():
    assert set(SPECTRA) == {"erri_low", "erri_high", *(f"fra{c}" for c in range(1, 7)), *(f"aar{c}" for c in range(1, 7))}
    assert len({id(spectrum) for spectrum in SPECTRA.values()}) == len(SPECTRA)  # each name its own spectrum
    assert SPECTRA is SPECTRA_BY_COMPONENT["alignment"]
    assert all(sp.component == "alignment" for sp in SPECTRA.values())
    assert get_spectrum("FRA6") is FRA_CLASS_6 and get_spectrum(" Erri_Low ") is ERRI_LOW


@dataclass(frozen=True)
class _WhiteVertical(TrackSpectrum):
    """A flat vertical spectrum, S = level: the shape another component would take."""

    component: ClassVar[str] = "vertical"
    name: str
    level: float

    def psd(self, omega):
        return np.full_like(np.asarray(omega, dtype=float), self.level)

    def primitive(self, omega):
        return self.level * np.asarray(omega, dtype=float)


def test_registry_takes_another_component(monkeypatch):
    monkeypatch.setitem(SPECTRA_BY_COMPONENT, "vertical", {})
    flat = _WhiteVertical("flat", 2e-8)
    register_spectrum("Flat-Test", flat)
    assert get_spectrum("flat_test", component="vertical") is flat
    assert flat.variance(1.0, 3.0) == pytest.approx(4e-8)
    with pytest.raises(KeyError, match="unknown spectrum 'flat_test' \\(known alignment spectra: fra5"):
        get_spectrum("flat_test")  # not an alignment spectrum
    register_spectrum("flat_test", flat)  # the same again is harmless
    with pytest.raises(ValueError, match="already registered"):
        register_spectrum("flat_test", _WhiteVertical("other", 1e-8))
    # a realisation of any registered spectrum has the band variance it integrates to
    irr = SpectrumIrregularity(flat, seed=1, wavelength_min=5.0, wavelength_max=50.0, period=500.0)
    s = np.arange(4096) * (500.0 / 4096)
    assert np.mean(np.asarray(irr(s)) ** 2) == pytest.approx(flat.variance(2 * np.pi / 50, 2 * np.pi / 5), rel=1e-9)


def test_register_refuses_unknown_component():
    @dataclass(frozen=True)
    class Odd(_WhiteVertical):
        component: ClassVar[str] = "twist"

    with pytest.raises(ValueError, match="unknown component 'twist'"):
        register_spectrum("odd", Odd("odd", 1.0))
