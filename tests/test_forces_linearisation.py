"""How the linear analyses see the nonlinear elements (issue 31, item 6):
:mod:`express.forces.describing` against the production law and closed forms, and
:mod:`express.forces.linearisation` on a vehicle against the symbolic matrices and
Den Hartog's forced response."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from express.base.diagnostics import ArgumentError
from express.forces.describing import jenkin_describing, jenkin_statistical, table_describing, table_statistical
from express.forces.friction import return_mapping
from express.forces.linearisation import Linearisation, LinearisedVehicle, element_linearisations, linearised
from express.io import parse_toml_model
from express.numeric.statespace import vehicle_model
from tests.test_forces_friction import MODEL, _den_hartog

K_SLIP, LIMIT = 2e6, 3000.0  # pre-slip stiffness [N/m], friction limit [N]: slips at 1.5 mm


def _loop(amplitude: float, points: int = 20000) -> tuple[np.ndarray, np.ndarray]:
    """The settled third cycle of ``delta = X cos(t)`` through the march's return mapping:
    ``(delta, F)``."""
    phase = np.arange(3 * points) / points * 2 * math.pi
    delta = amplitude * np.cos(phase)
    slider, force = 0.0, np.empty_like(delta)
    for i, d in enumerate(delta):
        slider = return_mapping(d, slider, K_SLIP, LIMIT)
        force[i] = K_SLIP * (d - slider)
    return delta[-points:], force[-points:]


@pytest.mark.parametrize("amplitude", [1e-3, 1.6e-3, 2e-3, 5e-3, 3e-2])
def test_the_spring_sliders_describing_function_is_the_first_harmonic_of_its_loop(amplitude):
    """a and b against the first harmonic of the loop the march's return mapping draws
    (20 000 points a cycle: achieved 2e-9 relative; asserted 1e-7), and the energy of a
    cycle, pi b X^2, against the loop's area (4 L (X - L/k), and the trapezoidal area of
    the drawn loop to 1e-6, achieved 1.5e-7)."""
    delta, force = _loop(amplitude)
    phase = np.arange(delta.size) / delta.size * 2 * math.pi
    a_drawn = 2 / delta.size * np.sum(force * np.cos(phase)) / amplitude
    b_drawn = -2 / delta.size * np.sum(force * np.sin(phase)) / amplitude  # F1 = a delta + (b/w) delta'
    a, b = jenkin_describing(K_SLIP, LIMIT, amplitude)
    assert abs(a - a_drawn) <= 1e-7 * K_SLIP and abs(b - b_drawn) <= 1e-7 * K_SLIP
    slip = LIMIT / K_SLIP
    expected = 4 * LIMIT * max(0.0, amplitude - slip)
    assert math.pi * b * amplitude**2 == pytest.approx(expected, rel=1e-12, abs=1e-9)
    closed = np.append(delta, delta[0]), np.append(force, force[0])
    area = abs(float(np.sum(0.5 * (closed[1][1:] + closed[1][:-1]) * np.diff(closed[0]))))
    assert area == pytest.approx(expected, rel=1e-6, abs=1e-6)


def test_the_spring_slider_sticks_below_its_slip_and_fades_to_coulomb_far_above():
    """Below ``L/k`` the element is its spring; far above, Coulomb's equivalent damping
    ``b = 4 L / (pi X)`` and ``a -> 0`` as ``(16/(3 pi)) k (d/X)^(3/2)`` (``p ~ 2 sqrt(d/X)``)."""
    assert jenkin_describing(K_SLIP, LIMIT, 1e-3) == (K_SLIP, 0.0)
    x = 1.0
    a, b = jenkin_describing(K_SLIP, LIMIT, x)
    assert b == pytest.approx(4 * LIMIT / (math.pi * x), rel=2e-3)
    assert a == pytest.approx(16 / (3 * math.pi) * K_SLIP * (LIMIT / K_SLIP / x) ** 1.5, rel=2e-3)


@pytest.mark.parametrize("rms", [5e-4, 2e-3, 1e-2])
def test_the_statistical_linearisation_is_the_describing_function_over_rayleigh_amplitudes(rms):
    """Caughey's average against an independent quadrature in the Rayleigh distribution's
    probability (``X = s sqrt(-2 ln(1 - P))``, Gauss–Legendre in P, 4000 points: agreement
    achieved 1e-7, asserted 1e-5 of k)."""
    a, b = jenkin_statistical(K_SLIP, LIMIT, rms)
    p, w = np.polynomial.legendre.leggauss(4000)
    p = 0.5 * (p + 1)
    amplitudes = rms * np.sqrt(-2 * np.log1p(-p))
    values = np.array([jenkin_describing(K_SLIP, LIMIT, x) for x in amplitudes])
    expected = 0.5 * (w[:, None] * values).sum(axis=0)
    assert abs(a - expected[0]) < 1e-5 * K_SLIP and abs(b - expected[1]) < 1e-5 * K_SLIP


# a bilinear spring, knee 10 mm in compression and 20 mm in extension, softer beyond
XS, FS = np.array([-1.0, -0.01, 0.02, 1.0]), np.array([-1e4 - 1e5 * 0.99, -1e4, 2e4, 2e4 + 3e5 * 0.98])


@pytest.mark.parametrize("amplitude", [0.005, 0.015, 0.05, 2.0])
def test_a_tables_describing_function_is_its_first_harmonic(amplitude):
    """Exact against the first harmonic by quadrature (scipy quad over the breakpoints:
    achieved 1e-14 relative, asserted 1e-10)."""
    knees = [t for t in (math.asin(x / amplitude) for x in XS[1:-1] if abs(x) < amplitude)]
    harmonic = quad(lambda t: np.interp(amplitude * math.sin(t), XS, FS, left=None) * math.sin(t), -math.pi / 2,
                    math.pi / 2, points=knees or None, epsabs=0, epsrel=1e-13, limit=200)[0] * 2 / (math.pi * amplitude)
    if amplitude > 1:  # beyond the table's ends the end slopes continue
        slopes = np.diff(FS) / np.diff(XS)

        def extended(x):
            return FS[0] + slopes[0] * (x - XS[0]) if x < XS[0] else (FS[-1] + slopes[-1] * (x - XS[-1]) if x > XS[-1]
                                                                      else np.interp(x, XS, FS))
        harmonic = quad(lambda t: extended(amplitude * math.sin(t)) * math.sin(t), -math.pi / 2, math.pi / 2,
                        points=[math.asin(x / amplitude) for x in XS], epsabs=0, epsrel=1e-13, limit=200)[0]
        harmonic *= 2 / (math.pi * amplitude)
    assert table_describing(XS, FS, amplitude) == pytest.approx(harmonic, rel=1e-10)


def test_a_blow_off_dampers_describing_function_is_the_saturations():
    """A damper ``c`` up to ``v0``, then constant force: the classical saturation
    describing function ``(2c/pi) (asin(r) + r sqrt(1 - r^2))``, ``r = v0 / V``, to 1e-12."""
    c, v0 = 6e5, 0.02
    xs = np.array([-v0 - 1, -v0, v0, v0 + 1])
    fs = np.array([-c * v0, -c * v0, c * v0, c * v0])
    for velocity in (0.01, 0.03, 0.1, 1.0):
        r = min(1.0, v0 / velocity)
        expected = 2 * c / math.pi * (math.asin(r) + r * math.sqrt(1 - r * r))
        assert table_describing(xs, fs, velocity) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("rms", [0.005, 0.02, 0.1])
def test_a_tables_gaussian_linearisation_is_booton_s(rms):
    """``E[F']`` against ``E[r F(r)] / s^2`` by quadrature (Stein's identity; achieved
    1e-12, asserted 1e-9)."""
    slopes = np.diff(FS) / np.diff(XS)

    def force(x):
        return FS[0] + slopes[0] * (x - XS[0]) if x < XS[0] else (FS[-1] + slopes[-1] * (x - XS[-1]) if x > XS[-1]
                                                                  else float(np.interp(x, XS, FS)))
    density = lambda x: math.exp(-0.5 * (x / rms) ** 2) / (rms * math.sqrt(2 * math.pi))  # noqa: E731
    expected = quad(lambda x: x * force(x) * density(x), -40 * rms, 40 * rms, points=list(XS[1:-1]), epsabs=0,
                    epsrel=1e-13, limit=400)[0] / rms**2
    assert table_statistical(XS, FS, rms) == pytest.approx(expected, rel=1e-9)


# ------------------------------------------------------------------ on a vehicle


def _slider(ks: str = "40 MN/m"):
    return vehicle_model(parse_toml_model(MODEL.format(ks=ks), "slider.toml"))


def test_the_equivalent_element_acts_where_the_symbolic_matrices_put_its_spring():
    """K and C of the linearised vehicle against the symbolic model's own: the pre-slip
    stiffness ``ks`` set to ``k_eq`` by ``with_values`` gives the same K to 1e-14, and the
    added C is ``c_eq`` times K's change per unit of ``ks``."""
    vehicle = _slider()
    spec = Linearisation("equivalent", amplitude="0.1 mm", frequency="3 Hz")
    seen = linearised(vehicle, spec)
    assert isinstance(seen, LinearisedVehicle)
    (element,) = seen.elements
    a, b = jenkin_describing(40e6, 200.0, 1e-4)
    assert (element.stiffness, element.damping) == (a, b / (2 * math.pi * 3.0))
    np.testing.assert_allclose(seen.stiffness, vehicle.with_values({"ks": a}).stiffness, rtol=1e-14)
    unit = vehicle.with_values({"ks": 1.0}).stiffness - vehicle.with_values({"ks": 0.0}).stiffness
    np.testing.assert_allclose(seen.damping(1.0) - vehicle.damping(1.0), element.damping * unit, rtol=1e-14)
    assert linearised(vehicle, Linearisation("equivalent", amplitude=1e-9)).stiffness.tolist() == vehicle.stiffness.tolist()
    assert linearised(vehicle, Linearisation()) is vehicle


def test_a_linearised_vehicle_re_linearises_with_new_values():
    """A new friction limit moves k_eq and c_eq as the closed form says."""
    seen = linearised(_slider(), Linearisation("equivalent", amplitude="0.1 mm", frequency="3 Hz"))
    changed = seen.with_values({"F": 500.0})
    assert isinstance(changed, LinearisedVehicle)
    a, b = jenkin_describing(40e6, 500.0, 1e-4)
    assert (changed.elements[0].stiffness, changed.elements[0].damping) == (a, b / (2 * math.pi * 3.0))


def _harmonic_balance(vehicle, r: float, ground: float) -> float:
    """The amplitude of the mass forced through its spring by ``ground cos(w t)``, with
    the friction element at its own amplitude: the fixed point of the equivalent
    linearisation (harmonic balance)."""
    omega = r * math.sqrt(40e3 / 100.0)
    amplitude = ground
    for _ in range(200):
        seen = linearised(vehicle, Linearisation("equivalent", amplitude=amplitude, frequency=omega / (2 * math.pi)))
        a, b, bd = seen.state_matrix(1.0), seen.input_matrix(1.0), seen.input_rate_matrix(1.0)
        u = np.array([ground, 0.0])
        x = np.linalg.solve(1j * omega * np.eye(a.shape[0]) - a, (b + 1j * omega * bd) @ u)
        new = abs(x[0])
        if abs(new - amplitude) < 1e-13:
            break
        amplitude = 0.5 * (amplitude + new)
    return new


@pytest.mark.parametrize("r, deviation", [(0.8, 0.017), (1.5, 0.018), (2.5, 0.028)])
def test_the_equivalent_linearisation_at_its_own_amplitude_is_den_hartogs_response(r, deviation):
    """The slider forced through its spring, F/P0 = 0.25 (U = 20 mm): harmonic balance
    with the describing function against Den Hartog's exact non-stop amplitude.  The
    describing function keeps the first harmonic only; the measured deviation (-1.50 %,
    +1.66 %, +2.57 % at r = 0.8, 1.5, 2.5 with the pre-slip spring at 1e7 k) is asserted to
    its rounded-up value.  Jacobsen's equivalent-damping closed form (c_eq = 4F/(pi w X),
    X = U sqrt(1 - (4F/(pi k U))^2) / |1 - r^2|) is met to 4.4e-5, 8.1e-5, 1.7e-4 (the
    finite pre-slip spring), asserted to 3e-4."""
    vehicle = _slider("400 GN/m")
    exact = 0.02 * _den_hartog(r, 0.25)
    found = _harmonic_balance(vehicle, r, 0.02)
    assert abs(found / exact - 1) < deviation
    jacobsen = 0.02 * math.sqrt(1 - (4 * 0.25 / math.pi) ** 2) / abs(1 - r * r)
    assert found == pytest.approx(jacobsen, rel=3e-4)


def test_bad_linearisations_are_refused():
    with pytest.raises(ArgumentError, match="one of tangent, equivalent, statistical"):
        Linearisation("describing")
    with pytest.raises(ArgumentError, match="amplitude"):
        Linearisation("equivalent", amplitude=-1e-3)
    with pytest.raises(ArgumentError, match="length"):
        Linearisation("equivalent", amplitude="3 Hz")


def test_the_statistical_choice_keeps_an_element_without_its_level_at_its_tangent():
    (element,) = element_linearisations(_slider(), Linearisation("statistical"))
    assert (element.stiffness, element.damping) == (40e6, 0.0)
    (element,) = element_linearisations(_slider(), Linearisation("statistical", levels={"slider": (1e-4, 2e-3)}))
    a, b = jenkin_statistical(40e6, 200.0, 1e-4)
    assert element.stiffness == a and element.damping == pytest.approx(b / 20.0, rel=1e-14)
