"""Tests of express.analysis.stability.stability: eigenvalues, root locus, critical speed.

Independent checks (``docs/rail-conventions.md``):

* Klingel's kinematic wavelength of a free wheelset and of a rigid two-axle bogie;
* the critical speed of a wheelset restrained to a fixed frame against the Routh-Hurwitz
  condition of its characteristic quartic;
* the growth / decay rate of a small disturbance in a linear time simulation against
  the largest real part of the eigenvalues;
* the bisection of ``critical_speed`` against a dense scan, and the shape of the
  critical speed against conicity (paper Fig. 11) for the two bundled vehicles.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from express.analysis.stability.stability import (
    CriticalSpeed,
    EigenResult,
    Mode,
    critical_speed,
    critical_speed_vs_conicity,
    eigen_analysis,
    max_real_part,
    root_locus,
)
from express.io import load_model, parse_toml_model
from express.numeric.statespace import vehicle_model

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

# wheel/rail values of the bundled vehicles (examples/*.toml)
MW, IWZ = 1400.0, 600.0
F1, F2 = 8.7e6, 7.8e6
GAMMA, R0, B = 0.1, 0.43, 0.56

_RAIL = """
[rail]
speed = "v"
cant_base = "G"
gravity = "g"
wheelsets = {wheelsets}

[rail.wheel_rail]
f1 = "f1"
f2 = "f2"
conicity = "Gamma"
r0 = "r0"
b = "b"
flange_clearance = "delta"
rail_stiffness = "kR"
friction = "mu"
wheel_load = "P0"
"""

_COMMON = f"""
mw = {MW}
Iwz = {IWZ}
f1 = {F1}
f2 = {F2}
Gamma = {GAMMA}
r0 = {R0}
b = {B}
delta = 0.006
kR = 2.0e7
mu = 0.3
P0 = 5.0e4
G = 1.067
g = 9.81
v = 1.0
"""

_WHEELSET_BODY = """
[bodies.W1]
mass = "mw"
inertia = [0, 0, "Iwz"]
dofs = ["y", "rz"]
position = [0, 0, "r0"]
"""


def _points_and_elements(points, elements) -> str:
    text = ""
    for pid, host, offset in points:
        text += f'\n[points.{pid}]\nbody = "{host}"\noffset = {offset}\n'
    for eid, start, end, direction, stiffness in elements:
        text += (f'\n[elements.{eid}]\nfrom = "{start}"\nto = "{end}"\n'
                 f'direction = "{direction}"\nstiffness = "{stiffness}"\n')
    return text


def free_wheelset_toml() -> str:
    """One wheelset (y, rz) on the rails and nothing else."""
    return ('[model]\nname = "free_wheelset"\n[parameters]\n' + _COMMON + _WHEELSET_BODY
            + _RAIL.format(wheelsets='["W1"]'))


def restrained_wheelset_toml(*, ky: float, kx: float, d: float, oscillator: bool = False) -> str:
    """A wheelset tied to a fixed frame (ground ``GR``) by a lateral spring ``ky`` at its
    centre and two longitudinal springs ``kx`` at ``y = +-d`` (yaw stiffness
    ``kpsi = 2 kx d^2``). With ``oscillator``, an extra undamped mass-spring body ``B``
    on the ground, whose eigenvalues have zero real part."""
    text = ('[model]\nname = "restrained_wheelset"\n[parameters]\n' + _COMMON
            + f"ky = {ky}\nkx = {kx}\nd = {d}\nmB = 1000.0\nkB = 4.0e5\n"
            + '\n[grounds.GR]\nlabel = "track-fixed frame"\n' + _WHEELSET_BODY)
    points = [("gy", "GR", "[0, 0, 0]"), ("wy", "W1", "[0, 0, 0]"),
              ("gxL", "GR", '[0, "d", 0]'), ("wxL", "W1", '[0, "d", 0]'),
              ("gxR", "GR", '[0, "-d", 0]'), ("wxR", "W1", '[0, "-d", 0]')]
    elements = [("lat", "gy", "wy", "y", "ky"), ("lonL", "gxL", "wxL", "x", "kx"),
                ("lonR", "gxR", "wxR", "x", "kx")]
    if oscillator:
        text += '\n[bodies.B]\nmass = "mB"\ndofs = ["y"]\nposition = [0, 0, 1]\n'
        points += [("gB", "GR", "[0, 0, 1]"), ("pB", "B", "[0, 0, 0]")]
        elements += [("kB", "gB", "pB", "y", "kB")]
    return text + _points_and_elements(points, elements) + _RAIL.format(wheelsets='["W1"]')


def rigid_bogie_toml(*, a: float, kp: float) -> str:
    """A bogie frame ``T`` (y, rz) carrying two wheelsets at ``x = +-a`` through
    longitudinal and lateral springs of stiffness ``kp`` at ``y = +-1 m``: with ``kp``
    very large, a rigid two-axle bogie."""
    text = ('[model]\nname = "rigid_bogie"\n[parameters]\n' + _COMMON
            + f'mt = 2600.0\nItz = 2600.0\na = {a}\nb1 = 1.0\nkp = {kp}\n'
            + '\n[bodies.T]\nmass = "mt"\ninertia = [0, 0, "Itz"]\ndofs = ["y", "rz"]\nposition = [0, 0, 0.55]\n')
    points, elements = [], []
    for w, x in (("W1", "a"), ("W2", "-a")):
        text += f'\n[bodies.{w}]\nmass = "mw"\ninertia = [0, 0, "Iwz"]\ndofs = ["y", "rz"]\nposition = ["{x}", 0, "r0"]\n'
        for side, y in (("L", "b1"), ("R", "-b1")):
            for direction in ("x", "y"):
                name = f"{w}_{direction}{side}"
                points += [(f"{name}_T", "T", f'["{x}", "{y}", 0]'), (f"{name}_W", w, f'[0, "{y}", 0]')]
                elements.append((name, f"{name}_T", f"{name}_W", direction, "kp"))
    return text + _points_and_elements(points, elements) + _RAIL.format(wheelsets='["W1", "W2"]')


@pytest.fixture(scope="module")
def steered():
    return vehicle_model(load_model(EXAMPLES / "forced-steering.toml"))


@pytest.fixture(scope="module")
def conventional():
    return vehicle_model(load_model(EXAMPLES / "conventional.toml"))


def _kinematic_mode(result: EigenResult, expected_hz: float) -> Mode:
    return min(result.modes, key=lambda mode: abs(mode.frequency_hz - expected_hz))


# --- (a) Klingel: free wheelset ----------------------------------------------------------


def test_klingel_free_wheelset():
    """A free wheelset at low speed oscillates at ``v / L``, ``L = 2 pi sqrt(r0 b / Gamma)``.

    Klingel's formula is the quasi-static (inertia-free) limit: ``y' = v psi`` (no
    lateral creep) and ``psi' = -v Gamma y / (r0 b)`` (no longitudinal creep). Inertia
    enters relative to the creep terms as ``m w v / (2 f2)`` and ``I w v / (2 b^2 f1)``;
    with ``w`` proportional to ``v`` that ratio grows as ``v^2``: at 1 m/s
    (``w = 0.64 rad/s``) it is ``6e-5``, so the frequency must agree far better than
    the 1 % asked (measured: 1e-8).
    """
    wheelset = vehicle_model(parse_toml_model(free_wheelset_toml()))
    assert wheelset.dofs == ("W1.y", "W1.rz")
    speed = 1.0
    expected = speed / (2 * np.pi * np.sqrt(R0 * B / GAMMA))
    mode = _kinematic_mode(eigen_analysis(wheelset, speed), expected)
    assert mode.frequency_hz == pytest.approx(expected, rel=1e-2)
    assert mode.frequency_hz == pytest.approx(expected, rel=1e-5)  # what the model gives
    assert mode.imag == pytest.approx(2 * np.pi * expected, rel=1e-5)
    # the frequency scales with the speed (kinematic): same wavelength at 2 m/s
    twice = _kinematic_mode(eigen_analysis(wheelset, 2 * speed), 2 * expected)
    assert twice.frequency_hz / mode.frequency_hz == pytest.approx(2.0, rel=1e-5)
    # a free wheelset is (slightly) unstable at every speed: reported as such
    result = critical_speed(wheelset)
    assert result is not None and result.unstable_at_min and result.speed == 1.0
    assert "unstable at the lowest speed" in result.describe()


# --- (b) rigid two-axle bogie --------------------------------------------------------------


def test_kinematic_wavelength_rigid_bogie():
    """Rigid bogie of semi-wheelbase ``a``: ``L = 2 pi sqrt(r0 b (1 + (f2/f1)(a/b)^2) / Gamma)``.

    The bogie is a frame with primary springs of 1e10 N/m: the formula assumes a rigid
    bogie and no inertia. The flexibility enters relative to the creep stiffness as
    ``2 f2 / kp`` ~ 2e-3 at most, inertia as at the free wheelset (~1e-4 at 1 m/s),
    so 1 % is a safe bound for what is a 1e-3-level approximation (measured 1e-7).
    """
    a = 1.15
    bogie = vehicle_model(parse_toml_model(rigid_bogie_toml(a=a, kp=1e10)))
    wavelength = 2 * np.pi * np.sqrt(R0 * B * (1 + (F2 / F1) * (a / B) ** 2) / GAMMA)
    speed = 1.0
    mode = _kinematic_mode(eigen_analysis(bogie, speed), speed / wavelength)
    assert speed / mode.frequency_hz == pytest.approx(wavelength, rel=1e-2)
    # far longer than the free wheelset's 3.08 m
    assert wavelength / (2 * np.pi * np.sqrt(R0 * B / GAMMA)) == pytest.approx(2.19, abs=0.01)
    assert mode.describe().startswith("hunting")


# --- (c) wheelset restrained to a fixed frame: Routh-Hurwitz -------------------------------


KY, KX, D = 1.0e6, 1.0e6, 1.0


def _hurwitz_critical_speed(m, inertia, f1, f2, gamma, r0, b, ky, kpsi) -> float:
    """Critical speed of the restrained wheelset from the Routh-Hurwitz conditions.

    Equations (``w = 1/v``)::

        m y''   + 2 f2 w y'       + ky y   - 2 f2 psi          = 0
        I psi'' + 2 b^2 f1 w psi' + kpsi psi + (2 b f1 Gamma / r0) y = 0

    Characteristic polynomial ``det(s^2 M + s C + K)``:
    ``a4 s^4 + a3 s^3 + a2 s^2 + a1 s + a0`` with ``cy = 2 f2``, ``cp = 2 b^2 f1``,
    ``kc = 2 b f1 Gamma / r0``::

        a4 = m I                  a3 = w (m cp + I cy) = w A3
        a2 = m kpsi + I ky + w^2 cy cp = B2 + w^2 cy cp
        a1 = w (cy kpsi + cp ky) = w A1
        a0 = ky kpsi + 2 f2 kc

    All coefficients are positive; the quartic is Hurwitz iff moreover
    ``Delta_3 = a3 a2 a1 - a4 a1^2 - a3^2 a0 > 0``. A pair of roots crosses the
    imaginary axis where ``Delta_3 = 0``:
    ``Delta_3 = w^2 (A3 A1 (B2 + w^2 cy cp) - a4 A1^2 - A3^2 a0)``, so::

        1 / v_cr^2 = (a4 A1^2 + A3^2 a0 - A3 A1 B2) / (A3 A1 cy cp)

    (stable at every speed when the numerator is negative). The closed form is checked
    here against sympy's Hurwitz determinant of the same polynomial.
    """
    cy, cp, kc = 2 * f2, 2 * b**2 * f1, 2 * b * f1 * gamma / r0
    a4, a3_, b2, a1_ = m * inertia, m * cp + inertia * cy, m * kpsi + inertia * ky, cy * kpsi + cp * ky
    a0 = ky * kpsi + 2 * f2 * kc
    closed = (a3_ * a1_ * cy * cp / (a4 * a1_**2 + a3_**2 * a0 - a3_ * a1_ * b2)) ** 0.5
    # the same with sympy: build the determinant, take Delta_3, solve for w
    s, w = sp.symbols("s w", positive=True)
    matrix = sp.Matrix([[m * s**2 + cy * w * s + ky, -2 * f2],
                        [kc, inertia * s**2 + cp * w * s + kpsi]])
    poly = sp.Poly(sp.expand(matrix.det()), s)
    c4, c3, c2, c1, c0 = (poly.coeff_monomial(s**k) for k in (4, 3, 2, 1, 0))
    delta3 = sp.expand(c3 * c2 * c1 - c4 * c1**2 - c3**2 * c0)
    roots = [r for r in sp.solve(sp.cancel(delta3 / w**2), w) if r.is_real and r > 0]
    assert len(roots) == 1
    symbolic = 1.0 / float(roots[0])
    assert symbolic == pytest.approx(closed, rel=1e-9)
    return closed


def test_restrained_wheelset_critical_speed_routh_hurwitz():
    model = parse_toml_model(restrained_wheelset_toml(ky=KY, kx=KX, d=D))
    wheelset = vehicle_model(model)
    kpsi = 2 * KX * D**2
    # nothing in the model that the quartic leaves out
    np.testing.assert_allclose(wheelset.mass, np.diag([MW, IWZ]))
    np.testing.assert_allclose(wheelset.stiffness, [[KY, -2 * F2], [2 * B * F1 * GAMMA / R0, kpsi]])
    np.testing.assert_allclose(wheelset.damping(10.0), np.diag([2 * F2 / 10.0, 2 * B**2 * F1 / 10.0]))
    expected = _hurwitz_critical_speed(MW, IWZ, F1, F2, GAMMA, R0, B, KY, kpsi)
    result = critical_speed(wheelset, v_max=500.0)
    assert isinstance(result, CriticalSpeed) and not result.unstable_at_min
    assert result.speed == pytest.approx(expected, rel=5e-3)
    assert abs(result.speed - expected) * 3.6 <= 0.05 + 1e-9  # midpoint of a 0.1 km/h bracket
    assert result.speed == pytest.approx(73.55, abs=0.05)
    assert abs(result.mode.real) < 1e-2 and result.mode.describe().startswith("hunting")
    lo, hi = result.bracket
    assert lo < expected < hi and (hi - lo) * 3.6 <= 0.1


def test_threshold_ignores_modes_with_zero_real_part():
    """An undamped oscillator (eigenvalues +-i w, real part zero up to round-off) added
    to the restrained wheelset does not change the critical speed."""
    plain = vehicle_model(parse_toml_model(restrained_wheelset_toml(ky=KY, kx=KX, d=D)))
    with_oscillator = vehicle_model(parse_toml_model(restrained_wheelset_toml(ky=KY, kx=KX, d=D, oscillator=True)))
    undamped = [m for m in eigen_analysis(with_oscillator, 10.0).modes if m.dominant[0][0] == "B.y"]
    assert len(undamped) == 1 and abs(undamped[0].real) < 1e-6
    assert undamped[0].imag == pytest.approx(np.sqrt(4.0e5 / 1000.0), rel=1e-9)
    first = critical_speed(plain, v_max=500.0)
    second = critical_speed(with_oscillator, v_max=500.0)
    assert second is not None and not second.unstable_at_min
    assert second.speed == pytest.approx(first.speed, abs=0.1 / 3.6)


# --- modes and eigen_analysis ----------------------------------------------------------------


def test_eigen_analysis_modes(steered):
    speed = 120 / 3.6
    result = eigen_analysis(steered, speed)
    everything = steered.eigenvalues(speed)
    # one of each conjugate pair, every real eigenvalue: rebuilding gives all 2n
    rebuilt = np.concatenate([[m.eigenvalue, m.eigenvalue.conjugate()] if m.imag > 0 else [m.eigenvalue]
                              for m in result.modes])
    assert rebuilt.size == 2 * steered.n
    for value in everything:
        assert np.min(np.abs(rebuilt - value)) < 1e-8 * max(1.0, abs(value))
    reals = [m.real for m in result.modes]
    assert reals == sorted(reals, reverse=True)
    assert result.stable and result.max_real == reals[0]
    for mode in result.modes:
        assert mode.imag >= 0
        assert mode.frequency_hz == pytest.approx(mode.imag / (2 * np.pi))
        assert mode.damping_ratio == pytest.approx(-mode.real / abs(mode.eigenvalue))
        shares = [share for _, share in mode.dominant]
        assert 1 <= len(shares) <= 4 and shares == sorted(shares, reverse=True)
        assert 0 < sum(shares) <= 1 + 1e-12
        assert sum(share for _, share in mode.body_shares) == pytest.approx(1.0)
    rows = result.rows()
    assert len(rows) == len(result.modes) and rows[0]["real"] == reals[0]
    assert set(rows[0]) == {"real", "imag", "frequency_hz", "damping_ratio", "description"}
    assert "km/h" in result.table().splitlines()[0]
    # the car body's lateral mode near 0.57 Hz is labelled as such
    body = _kinematic_mode(result, 0.567)
    assert body.describe().startswith("car body lower sway") and body.dominant[0][0] in ("CB.y", "CB.rx")


def test_mode_describe():
    mode = Mode(complex(-0.5, 20.0), 20 / (2 * np.pi), 0.025,
                (("W1.y", 0.4), ("W2.y", 0.3), ("T1.rz", 0.2), ("CB.y", 0.05)), "hunting, front bogie")
    assert mode.describe() == "hunting, front bogie (W1.y, W2.y, T1.rz)"
    assert mode.stable and mode.real == -0.5 and mode.imag == 20.0


def test_speed_must_be_positive(steered):
    with pytest.raises(ValueError, match="positive"):
        eigen_analysis(steered, 0.0)
    with pytest.raises(ValueError, match="positive"):
        root_locus(steered, [10.0, -1.0])
    with pytest.raises(ValueError, match="v_min"):
        critical_speed(steered, v_min=50.0, v_max=10.0)


# --- (d) root locus ------------------------------------------------------------------------


def test_root_locus_matches_eigenvalues(steered):
    speeds = np.array([5.0, 33.3, 80.0, 140.0])
    locus = root_locus(steered, speeds)
    assert locus.shape == (4, 2 * steered.n) and locus.dtype == complex
    for row, speed in zip(locus, speeds):
        reference = np.linalg.eigvals(steered.state_matrix(speed))
        scale = 1e-8 * np.abs(reference).max()
        for value in reference:
            assert np.min(np.abs(row - value)) < scale
        for value in row:
            assert np.min(np.abs(reference - value)) < scale
        assert np.all(np.diff(row.real) <= 1e-9 * np.abs(row).max())  # descending real part
    np.testing.assert_allclose(max_real_part(steered, speeds), locus[:, 0].real, rtol=1e-9, atol=1e-9)
    assert root_locus(steered, 30.0).shape == (1, 2 * steered.n)


# --- (e) critical speed -----------------------------------------------------------------------


def _first_crossing(vehicle, lo: float, hi: float, step: float, threshold: float = 1e-6) -> float:
    """First speed of a uniform scan where the largest real part exceeds threshold,
    linearly interpolated with the point before."""
    speeds = np.arange(lo, hi + step, step)
    sigma = max_real_part(vehicle, speeds) - threshold
    index = int(np.argmax(sigma > 0))
    assert sigma[index] > 0 and index > 0
    s0, s1 = sigma[index - 1], sigma[index]
    return float(speeds[index - 1] + step * (-s0) / (s1 - s0))


@pytest.mark.parametrize("name", ["steered", "conventional"])
def test_critical_speed_against_dense_scan(name, request):
    vehicle = request.getfixturevalue(name)
    result = critical_speed(vehicle)
    assert result is not None and not result.unstable_at_min
    # a coarse uniform scan over the whole range finds no earlier crossing ...
    coarse = _first_crossing(vehicle, 1.0, 150.0, 0.5)
    assert abs(coarse - result.speed) < 0.5
    # ... and a dense one around it agrees within the tolerance
    dense = _first_crossing(vehicle, result.speed - 0.3, result.speed + 0.3, 0.002)
    assert abs(dense - result.speed) * 3.6 <= 0.1
    assert result.mode.describe().startswith("hunting")
    assert abs(result.mode.real) < 0.01  # the crossing mode at the crossing
    assert result.speed_kmh == pytest.approx(3.6 * result.speed)


def test_critical_speed_is_a_record_when_stable_over_the_range(conventional):
    stable = critical_speed(conventional, v_max=40.0)
    assert not stable.found and stable.reason == "stable up to v_max" and stable.speed != stable.speed
    assert stable.as_dict()["critical_speed"] is None and stable.mode.real < 0


CONICITIES = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4]


@pytest.fixture(scope="module")
def conventional_sweep(conventional):
    return critical_speed_vs_conicity(conventional, CONICITIES)


def test_critical_speed_falls_with_conicity_conventional(conventional, conventional_sweep):
    """Conventional bogies: the critical speed falls as the conicity grows (Fig. 11)."""
    results = conventional_sweep
    speeds = [r.speed_kmh for r in results]
    assert all(not r.unstable_at_min for r in results)
    assert all(np.diff(speeds) < 0)
    assert speeds[1] == pytest.approx(3.6 * critical_speed(conventional).speed, abs=1e-9)


@pytest.mark.regression
def test_conventional_sweep_regression_guard(conventional_sweep):
    """Regression guard, not validation: this code's own speeds (km/h), 462 at 0.05,
    421 at 0.1, 389 at 0.15, 361 at 0.2, 315 at 0.3, 277 at 0.4 (the paper's Fig. 11 is
    for the paper's unpublished parameters, docs/parameters.md)."""
    speeds = [r.speed_kmh for r in conventional_sweep]
    assert speeds[0] == pytest.approx(462, abs=1) and speeds[-1] == pytest.approx(277, abs=1)


def test_critical_speed_vs_conicity_steered(steered):
    """Forced steering: interior maximum near Gamma = 0.12 and a sharp drop towards
    Gamma -> 0, where the front bogie's kinematic mode goes unstable at every speed
    (the paper's Fig. 11 shape).

    Measured (km/h): unstable already at 3.6 km/h for Gamma <= 0.03; 51 at 0.04,
    78 at 0.06, 351 at 0.08, 365 at 0.1, 368 at 0.12, 365 at 0.15, 350 at 0.2,
    312 at 0.3, 277 at 0.4.
    """
    conicities = [0.02, 0.04, 0.06, 0.08, 0.1, 0.12, 0.15, 0.2, 0.3, 0.4]
    results = critical_speed_vs_conicity(steered, conicities)
    assert results[0].unstable_at_min and results[0].speed == 1.0
    assert all(not r.unstable_at_min for r in results[1:])
    speeds = np.array([r.speed_kmh for r in results[1:]])
    best = int(np.argmax(speeds)) + 1
    assert 0.08 < conicities[best] < 0.2  # interior maximum
    assert speeds.max() == pytest.approx(368, abs=3)
    assert results[-1].speed_kmh < speeds.max() - 50
    assert results[2].speed_kmh < 0.3 * speeds.max()  # sharp drop below 0.07
    assert results[1].speed_kmh < results[2].speed_kmh < results[3].speed_kmh
    assert all(r.mode.describe().startswith("hunting, front bogie") for r in results)


def test_conicity_parameter_must_exist(steered):
    with pytest.raises(ValueError, match="no parameter"):
        critical_speed_vs_conicity(steered, [0.1], parameter="conicity")


# --- (f) growth rate in a linear time simulation ------------------------------------------


def _envelope_rate(time: np.ndarray, signal: np.ndarray, after: float) -> float:
    """Slope of log |peaks| of ``signal`` for ``time > after`` (least squares)."""
    magnitude = np.abs(signal)
    peaks = np.flatnonzero((magnitude[1:-1] > magnitude[:-2]) & (magnitude[1:-1] >= magnitude[2:])) + 1
    peaks = peaks[time[peaks] > after]
    assert peaks.size > 10
    return float(np.polyfit(time[peaks], np.log(magnitude[peaks]), 1)[0])


@pytest.mark.parametrize("factor", [1.05, 0.95])
def test_growth_rate_matches_eigenvalue(steered, factor):
    """A 1 mm lateral displacement of W1 in the linear simulation (no flange, no
    saturation, straight track) grows above the critical speed, decays below it, at
    the rate of the largest real part (within 2 %; measured 2e-4 and 3e-6).

    The forced-steering car is used: at 1.05 v_cr only its front-bogie hunting mode is
    unstable (+0.29 1/s) and the next is far below (-0.30 1/s), so after 4 s the log
    envelope is a straight line. (The conventional car's two bogies have nearly equal
    hunting modes, 0.35 and 0.03 1/s at 1.05 v_cr, whose beating spoils a short fit.)
    """
    from express.analysis.time.simulate import simulate
    from express.rail.track import Straight, Track

    speed = factor * critical_speed(steered).speed
    rate = eigen_analysis(steered, speed).modes[0].real
    assert (rate > 0) == (factor > 1)
    duration = 12.0
    initial = np.zeros(2 * steered.n)
    initial[steered.dof_index("W1.y")] = 1e-3
    result = simulate(steered, Track([Straight(speed * duration + 1.0)]), speed=speed, dt=0.005,
                      end=speed * duration, flange=False, saturation=False, initial_state=initial)
    y = result.q[:, steered.dof_index("W1.y")]
    measured = _envelope_rate(result.time, y, after=4.0)
    assert measured == pytest.approx(rate, rel=0.02)
    late = np.abs(y[result.time > duration - 1.0]).max()
    assert (late > 1e-3) if factor > 1 else (late < 1e-3)
