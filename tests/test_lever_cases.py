"""The paper's Table 1 and Fig. 3: which way the lever turns when q1 steps.

The two-DOF example of the paper (Fig. 2, input Fig. 5 = ``examples/lever.exp``):
body B1 turns about z (q1 = B1.rz) and carries, at ``y = -b`` from its centre, the pin
(C6) of the lever B2, which turns about y (q2 = B2.ry) and is held to the wall by
``kLU`` at height ``+lLU`` (C1) and ``kLL`` at ``-lLL`` (C3), both along x.

Sign convention, derived by hand from conventions.md (``u = t + theta x r``):

* the pin C6 at ``r = (0, -b, 0)`` on B1 moves by ``(0, 0, q1) x (0, -b, 0) =
  (b q1, 0, 0)``: a positive q1 pushes the lever's pin forward (+x) by ``b q1``;
* on the lever, ``(0, q2, 0) x (0, 0, l) = (l q2, 0, 0)``: the upper CP moves by
  ``x + lLU q2`` and the lower CP by ``x - lLL q2``;
* with ``x = b q1`` imposed, the moment balance about the pin,
  ``-kLU lLU (x + lLU q2) + kLL lLL (x - lLL q2) = 0``, gives
  ``q2 = b q1 (lLL kLL - lLU kLU) / (lLU^2 kLU + lLL^2 kLL)``.

So with ``b > 0`` and ``q1 > 0``, q2 settles positive when ``lLU kLU < lLL kLL``
(case 1), negative when ``lLU kLU > lLL kLL`` (case 2) and at zero when they are equal
(case 3) -- exactly the paper's statement below Table 1.  The tests below check that
the *generated* equations give the same answer, by simulation as in Fig. 3.

The paper drives q1 by a step.  B1 has no mass of its own (only J1), so q1 is modelled
as prescribed, ``q1(t) = Q H(t - t0)``; the lever then obeys the second row of the
generated equations, ``M22 q2'' + (C22 + c2) q2' + K22 q2 = -K21 q1`` (M and C are
diagonal, so q1 reaches q2 only through K21), with a little damping ``c2`` added on q2
so that it settles.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from express.assembly.generator import generate
from express.io import read_classic

ROOT = Path(__file__).resolve().parents[1]
LEVER = ROOT / "examples" / "lever.exp"

R = sp.Rational
kN = 1000
# Table 1 as printed: (lLU [m], lLL [m], kLU [kN/m], kLL [kN/m])
TABLE_1 = {
    1: (R(30, 100), R(6, 100), 500, 5500),
    2: (R(6, 100), R(30, 100), 5500, 500),
    3: (R(6, 100), R(30, 100), 1000, 5000),
}
# Case 3 used here: lever arms of case 1 with the printed stiffnesses (300 = 300).
CASE_3_BALANCED = (R(30, 100), R(6, 100), 1000, 5000)

# values the paper does not give (they do not affect the sign)
OTHER = {"b": R(1, 2), "J1": 10, "J2": R(1, 2), "m": 20, "c": 1000}
Q = 0.01  # step of q1 [rad]
T0 = 0.01  # time of the step [s]


@pytest.fixture(scope="module")
def lever():
    """The generated (pin eliminated) lever equations."""
    equations = generate(read_classic(LEVER)).equations
    assert equations.dofs == ("B1.rz", "B2.ry")
    return equations


def values_for(lLU, lLL, kLU, kLL):
    symbols = {name: sp.Symbol(name) for name in ("lLU", "lLL", "kLU", "kLL", *OTHER)}
    chosen = {"lLU": lLU, "lLL": lLL, "kLU": kLU * kN, "kLL": kLL * kN, **OTHER}
    return {symbols[name]: value for name, value in chosen.items()}


def numeric(matrix, values):
    exact = matrix.subs(values)
    assert not exact.free_symbols, exact.free_symbols
    return exact


def static_q2(equations, values):
    """The settled lever angle for the step Q: -K21/K22 Q (exact)."""
    K = numeric(equations.K, values)
    return -K[1, 0] / K[1, 1] * sp.Float(Q)


def simulate_step(equations, values, t_end=0.6):
    """Prescribed step on q1, lever q2 from the generated second row; returns (t, q2)
    and the exact static answer -K21/K22 * Q."""
    M, C, K = (numeric(equations.matrices[n], values) for n in ("M", "C", "K"))
    m22, c22, k21, k22 = float(M[1, 1]), float(C[1, 1]), float(K[1, 0]), float(K[1, 1])
    assert float(M[1, 0]) == 0 and float(C[1, 0]) == 0  # only K couples q1 into q2
    damping = c22 + 2 * 0.3 * np.sqrt(k22 * m22)  # add ~30 % of critical damping on q2

    def rhs_with(q1):
        def rhs(t, y):
            q2, v2 = y
            return [v2, (-damping * v2 - k22 * q2 - k21 * q1) / m22]

        return rhs

    # the step: q1 = 0 up to T0, then Q (two integrations, so the jump is exact)
    pieces = []
    state = [0.0, 0.0]
    for q1, (start, stop) in ((0.0, (0.0, T0)), (Q, (T0, t_end))):
        times = np.linspace(start, stop, 1 + int(round((stop - start) / 2e-4)))
        solution = solve_ivp(
            rhs_with(q1), (start, stop), state, t_eval=times, max_step=1e-4, rtol=1e-9, atol=1e-12
        )
        assert solution.success, solution.message
        pieces.append((solution.t[:-1], solution.y[0][:-1]))
        state = solution.y[:, -1]
    t = np.concatenate([p[0] for p in pieces] + [[t_end]])
    q2 = np.concatenate([p[1] for p in pieces] + [[state[0]]])
    return t, q2, static_q2(equations, values)


def test_case_3_as_printed_is_not_balanced():
    """Table 1 prints case 3 (lLU kLU = lLL kLL) as lLU 0.06 m, lLL 0.30 m, kLU 1000,
    kLL 5000 kN/m, but 0.06 x 1000 = 60 is not 0.30 x 5000 = 1500 (kN): the printed row
    does not meet its own condition.  Swapping the lever arms (0.30, 0.06) does:
    300 = 300."""
    lLU, lLL, kLU, kLL = TABLE_1[3]
    assert lLU * kLU == 60 and lLL * kLL == 1500
    assert lLU * kLU != lLL * kLL
    lLU, lLL, kLU, kLL = CASE_3_BALANCED
    assert lLU * kLU == lLL * kLL == 300


@pytest.mark.parametrize("case", [1, 2])
def test_table_1_rows_meet_their_conditions(case):
    """Cases 1 and 2 as printed satisfy lLU kLU < lLL kLL and > respectively."""
    lLU, lLL, kLU, kLL = TABLE_1[case]
    assert (lLU * kLU < lLL * kLL) if case == 1 else (lLU * kLU > lLL * kLL)


def test_generated_static_answer_is_the_hand_derivation(lever):
    """-K21/K22 from the generated K equals the moment balance derived in the module
    docstring: b (lLL kLL - lLU kLU) / (lLU^2 kLU + lLL^2 kLL)."""
    b, kLL, kLU, lLL, lLU = sp.symbols("b kLL kLU lLL lLU")
    generated = -lever.K[1, 0] / lever.K[1, 1]
    by_hand = b * (lLL * kLL - lLU * kLU) / (lLU**2 * kLU + lLL**2 * kLL)
    assert sp.simplify(generated - by_hand) == 0


CASES = [
    pytest.param(TABLE_1[1], +1, id="case1-lLUkLU<lLLkLL-positive"),
    pytest.param(TABLE_1[2], -1, id="case2-lLUkLU>lLLkLL-negative"),
    pytest.param(CASE_3_BALANCED, 0, id="case3-balanced-zero"),
]


@pytest.mark.parametrize("row, sign", CASES)
def test_fig_3_step_response_sign(lever, row, sign):
    """Fig. 3: after a positive step of q1 the lever angle q2 settles positive in case
    1, negative in case 2 and stays at zero in case 3 -- the paper's statement.  The
    simulated response settles on the static answer and never crosses to the other
    side on the way."""
    t, q2, static = simulate_step(lever, values_for(*row))
    final = q2[-1]
    if sign == 0:
        assert static == 0  # exactly: K21 vanishes for the balanced lever
        assert np.max(np.abs(q2)) <= 1e-12
        return
    assert np.sign(final) == sign, f"q2 settles at {final:.3e}, the paper says sign {sign:+d}"
    assert np.sign(float(static)) == sign
    assert final == pytest.approx(float(static), rel=1e-3)
    before = t < T0
    assert np.all(q2[before] == 0)  # nothing happens before the step
    assert np.all(sign * q2[~before] >= -1e-9 * abs(float(static)))


@pytest.mark.parametrize("row, sign", CASES[:2])
def test_settled_angle_scales_with_the_pin_arm(lever, row, sign):
    """The settled q2 is proportional to the pin's lever arm b and flips sign with it
    (the pin on the other side of B1 is pushed backwards by a positive q1)."""
    values = values_for(*row)
    b = sp.Symbol("b")
    static = static_q2(lever, values)
    values[b] = -values[b]
    flipped = static_q2(lever, values)
    assert float(flipped) == pytest.approx(-float(static))
    values[b] = -2 * values[b]
    doubled = static_q2(lever, values)
    assert float(doubled) == pytest.approx(2 * float(static))


def test_printed_case_3_would_turn_the_lever(lever):
    """With the printed (unbalanced) case-3 row, lLU kLU = 60 < lLL kLL = 1500 (kN), so the
    generated equations turn the lever positive, like case 1 -- not the zero of Fig. 3."""
    _, q2, static = simulate_step(lever, values_for(*TABLE_1[3]))
    assert float(static) > 0 and q2[-1] > 0


# ------------------------------------------------------------ analyses without rail data


def _lever_vehicle(damping: float):
    """The lever of Table 1, case 1, as a numerical model (no rail data)."""
    from express.io import load_model
    from express.model.parameters import with_values
    from express.numeric.statespace import vehicle_model

    chosen = {name.name: float(value) for name, value in values_for(*TABLE_1[1]).items()}
    chosen["c"] = damping
    return vehicle_model(with_values(load_model(LEVER), chosen)), chosen


def _closed_form_frequencies(lever, values):
    """Roots of det(K - w^2 M) = 0 for the 2 x 2 lever (M diagonal), in Hz."""
    M, K = (lever.matrices[name].subs({sp.Symbol(k): v for k, v in values.items()}) for name in ("M", "K"))
    m1, m2 = float(M[0, 0]), float(M[1, 1])
    k11, k12, k22 = float(K[0, 0]), float(K[0, 1]), float(K[1, 1])
    s = k11 * m2 + k22 * m1
    root = np.sqrt(s**2 - 4 * m1 * m2 * (k11 * k22 - k12**2))
    return np.sqrt(np.array([(s - root), (s + root)]) / (2 * m1 * m2)) / (2 * np.pi)


def test_lever_natural_frequencies_are_the_closed_form(lever):
    from express.analysis.stability.stability import eigen_analysis, natural_frequencies

    vehicle, values = _lever_vehicle(damping=0.0)
    expected = _closed_form_frequencies(lever, values)
    np.testing.assert_allclose(natural_frequencies(vehicle), expected, rtol=1e-12)
    result = eigen_analysis(vehicle)  # no speed needed: no rail data
    assert np.isnan(result.speed)
    frequencies = sorted(mode.frequency_hz for mode in result.modes)
    np.testing.assert_allclose(frequencies, expected, rtol=1e-9)
    assert all(abs(mode.damping_ratio) < 1e-9 for mode in result.modes)
    assert "independent of the speed" in result.table()


def test_damped_lever_keeps_the_natural_frequencies(lever):
    """With the damper c: |lambda| of each mode is close to the undamped frequency and
    the damping ratios are positive."""
    from express.analysis.stability.stability import eigen_analysis

    vehicle, values = _lever_vehicle(damping=1000.0)
    expected = _closed_form_frequencies(lever, values)
    result = eigen_analysis(vehicle)
    natural = sorted(mode.natural_frequency_hz for mode in result.modes)
    np.testing.assert_allclose(natural, expected, rtol=1e-3)
    assert all(0 < mode.damping_ratio < 0.05 for mode in result.modes)
    assert {mode.kind for mode in result.modes} <= {"B1 yaw, B2 pitch", "B2 pitch, B1 yaw", "B1 yaw", "B2 pitch"}


def test_lever_frf_to_ground_inputs_is_the_direct_solution(lever):
    """H(w) = (K - w^2 M + i w C)^-1 (P + i w Pd) from the symbolic matrices, solved here."""
    from express.analysis.frequency.frequency import ground_response

    vehicle, values = _lever_vehicle(damping=1000.0)
    frequencies = np.array([0.0, 5.0, 48.0, 200.0])
    response = ground_response(vehicle, frequencies)
    assert response.inputs == lever.inputs == ("G1.x", "G2.x", "G3.x")
    substitution = {sp.Symbol(k): v for k, v in values.items()}
    M, C, K, P, Pd = (np.array(lever.matrices[n].subs(substitution), dtype=float) for n in ("M", "C", "K", "P", "Pd"))
    for k, f in enumerate(frequencies):
        w = 2 * np.pi * f
        expected = np.linalg.solve(K - w**2 * M + 1j * w * C, P + 1j * w * Pd)
        np.testing.assert_allclose(response.H[k], expected, rtol=1e-10, atol=1e-14)
    # static: the upper wall G1 moved by 1 m turns the lever by -kLU lLU / K22 ... checked against K
    static = np.linalg.solve(K, P)
    np.testing.assert_allclose(response.of("B2.ry", "G1.x")[0], static[1, 0], rtol=1e-12)


def test_cli_eigen_and_frf_work_without_rail_data(capsys):
    import json

    from express.cli import main

    settings = [f"--set={k}={v}" for k, v in _lever_vehicle(0.0)[1].items()]
    assert main(["eigen", str(LEVER), "--json", *settings]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["speed"] is None and len(data["eigenvalues"]) == 4
    assert all(len(pair) == 2 for pair in data["eigenvalues"])
    assert main(["frf", str(LEVER), "--json", "--points", "3", "--dof", "B2.ry", *settings]) == 0
    data = json.loads(capsys.readouterr().out)
    assert set(data["outputs"]) == {"B2.ry/G1.x", "B2.ry/G2.x", "B2.ry/G3.x"}
    assert data["outputs"]["B2.ry/G1.x"]["unit"] == "rad"
