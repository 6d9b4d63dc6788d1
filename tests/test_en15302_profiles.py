"""EN 15302 (UIC 519) reference profiles through the contact geometry to the equivalent
conicity, against the standard's Annex E results (express.rail.contact_geometry,
express.rail.conicity).

Profiles (``tests/data/en15302_profiles/``, transcribed from the public repository
criogenox/A_WRCC-Wheel-Rail-Contact-Characterization, MIT licence): the wheels A, B, H, I
and rail A of the standard's Annex D.  Reference: Annex E's tan(gamma_e) of the cases
E1-E4 (each a pair of equal wheels on rail A; ``express/data/en15302/
reference_conicity.csv``).

Placement (ours; the Annex's own placement was not available): rail A is the standard
60E1 at 1:20 (the transcribed rail A is 60E1 turned by 1:20 within 0.030 mm rms, 0.12 mm
at most, checked below; the shipped 60E1 is used because the transcription's points give a rougher
curvature), gauge 1435 mm at 14 mm below the rail top, flange backs 1360 mm apart, taping
lines 70 mm outside them, wheel radius 460 mm, roll included, 0.01 mm steps of y.

Up to 6 mm amplitude every value lies within the standard's tolerance
+-min(0.05, 0.5 tan gamma_e) but two (E3 at 2.5 and 2.6 mm, next to a contact jump that
comes 0.05-0.1 mm earlier here); the largest deviation of each case is held at about 1.3
times what it is now.  Above about 6.2 mm the flange is reached 0.2-0.4 mm earlier than
in the Annex (tan gamma_e 0.52 against 0.35 at 6.5 mm for E1): the Annex's flangeway
clearance is larger than this placement's, so those amplitudes are not compared.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from express.rail.conicity import equivalent_conicity
from express.rail.contact_geometry import ContactSetup, contact_geometry
from express.rail.profile_formats import read_profile
from express.rail.profiles import standard_profile

DATA = Path(__file__).parent / "data" / "en15302_profiles"
SETUP = ContactSetup(gauge=1.435, flange_back=1.360, inclination=1 / 20, wheel_radius=0.46)


def annex_e() -> tuple[np.ndarray, np.ndarray]:
    """Amplitudes [m] and the reference tan(gamma_e) table (columns E1..E9)."""
    folder = resources.files("express").joinpath("data").joinpath("en15302")
    table = np.loadtxt(folder.joinpath("reference_conicity.csv").read_text().splitlines(), delimiter=",",
                       comments="#", skiprows=5)
    return table[:, 0] * 1e-3, table[:, 1:]


# case, wheel, largest deviation achieved at 1-6 mm (outside the exceptions), its bound,
# amplitudes [mm] outside the standard's tolerance
CASES = [
    ("E1", "A", 0.0250, 0.033, ()),
    ("E2", "B", 0.0086, 0.011, ()),
    ("E3", "H", 0.0363, 0.047, (2.5, 2.6)),  # the contact jump 0.05-0.1 mm earlier here
    ("E4", "I", 0.0342, 0.045, ()),  # dead band to 1.7 mm: 0, as the Annex
]


@pytest.mark.parametrize("case, wheel, achieved, bound, outside", CASES, ids=[c[0] for c in CASES])
def test_conicity_from_annex_d_profiles(case, wheel, achieved, bound, outside):
    amplitudes, table = annex_e()
    compared = amplitudes <= 6.0e-3 + 1e-12
    amplitudes, reference = amplitudes[compared], table[compared, int(case[1:]) - 1]
    y = np.arange(-1000, 1001) * 1e-5
    geometry = contact_geometry(read_profile(DATA / f"RUIC519{wheel}.csv", "wheel"), standard_profile("60E1"), y,
                                SETUP)
    ours = equivalent_conicity(y, geometry.delta_r, amplitudes)
    deviation = np.abs(ours - reference)
    tolerance = np.minimum(0.05, 0.5 * reference) + 5e-4  # the references have 3 decimals
    assert [round(a * 1e3, 1) for a in amplitudes[deviation > tolerance]] == list(outside)
    inside = deviation <= tolerance
    assert deviation[inside].max() <= bound, (case, deviation[inside].max(), achieved)


def _gauge_aligned(y: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A rail in the track frame shifted so that its top is at z = 0 and its gauge point
    (14 mm below the top, gauge side) at y = 0."""
    top = int(np.argmax(z))
    z = z - z[top]
    gauge = np.flatnonzero((y < y[top]) & (z >= -0.014))[0]
    return y - np.interp(-0.014, [z[gauge - 1], z[gauge]], [y[gauge - 1], y[gauge]]), z


@pytest.mark.parametrize("inclination, achieved, bound", [(1 / 20, 0.030e-3, 0.04e-3), (1 / 40, 0.41e-3, None)])
def test_rail_a_is_60e1_at_1_in_20(inclination, achieved, bound):
    """The transcribed rail A against 60E1 turned by the inclination, both aligned at the
    top and the gauge point: rms height difference over the common width."""
    rail_a = read_profile(DATA / "SUIC519A.csv", "rail")
    ya, za = _gauge_aligned(np.asarray(rail_a.y), np.asarray(rail_a.z))
    base = standard_profile("60E1")
    angle = np.arctan(inclination)
    y0, z0 = np.asarray(base.y), np.asarray(base.z)
    yr = y0 * np.cos(angle) - z0 * np.sin(angle)
    zr = y0 * np.sin(angle) + z0 * np.cos(angle)
    yr, zr = _gauge_aligned(yr, zr)
    common = (yr > ya[0]) & (yr < ya[-1]) & (zr > -0.014)
    rms = float(np.sqrt(np.mean((np.interp(yr[common], ya, za) - zr[common]) ** 2)))
    if bound is None:
        assert rms > 10 * 0.030e-3, (rms, achieved)  # 1:40 is clearly not it
    else:
        assert rms <= bound, (rms, achieved)
