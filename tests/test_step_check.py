"""The step check of an assessed time run (express.analysis.time.step_check): fake runs
whose assessed quantity has a known step error, then one real run through the CLI."""

from __future__ import annotations

import math
from dataclasses import dataclass

import pytest

from express.analysis.time.step_check import TOLERANCE, checked_run


@dataclass(frozen=True)
class _Criterion:
    name: str
    value: float
    limit: float | None


@dataclass(frozen=True)
class _Assessment:
    criteria: tuple


def _first_order(error_per_second: float, limit: float | None = 1.0, diverges_above: float = math.inf):
    """A run whose quantity is ``0.5 + error_per_second dt`` (a first-order step error),
    diverging at steps above ``diverges_above``; it records the steps it was asked for."""
    asked: list[float] = []

    def run(dt: float):
        asked.append(dt)
        if dt > diverges_above:
            return None
        return f"run at {dt}", _Assessment((_Criterion("dQQ0", 0.5 + error_per_second * dt, limit),))

    return run, asked


@pytest.mark.parametrize(("error", "limit", "diverges", "steps", "converged"), [
    (1.0, 1.0, math.inf, [5e-3, 10e-3], True),  # moves 0.5 % of the limit: accepted as it is
    (2.5, 1.0, math.inf, [5e-3, 10e-3, 2.5e-3], True),  # 1.25 %, then 0.625 %: one halving
    (100.0, 1.0, math.inf, [5e-3, 10e-3, 2.5e-3, 1.25e-3, 0.625e-3], False),  # still 6 % after three
    (1.0, None, math.inf, [5e-3, 10e-3], True),  # no limit: against the value (0.5 % of 0.505)
    (1.0, 1.0, 6e-3, [5e-3, 10e-3, 2.5e-3], True),  # the coarse run diverged: halved, then compared
])
def test_the_step_is_halved_until_the_quantities_agree(error, limit, diverges, steps, converged):
    run, asked = _first_order(error, limit, diverges)
    result, assessment, check = checked_run(run, 5e-3)
    assert asked == steps
    finest = steps[-1] if len(steps) > 2 else steps[0]
    assert check.dt == finest and result == f"run at {finest}" and check.compared_dt == 2 * finest
    assert check.converged is converged
    # the estimate is the change between the last two runs: error x dt for this run
    scale = limit if limit else 0.5 + error * finest
    assert check.fractions["dQQ0"] == pytest.approx(error * finest / scale, rel=1e-12)
    assert ("NOT converged" in check.sentence()) is (not converged)
    assert check.steps == tuple([steps[1], steps[0]] + steps[2:])


def test_the_tolerance_is_one_percent_of_the_limit():
    assert TOLERANCE == 0.01


def test_simulate_assess_states_its_step_and_its_error(capsys):
    """``simulate --assess`` checks its step by default and says so in the JSON summary
    and the printed one; ``--no-step-check`` leaves it out (the conventional car along
    R400: converged at the default 5 ms)."""
    from cli_support import CONVENTIONAL, run, run_json

    summary = run_json(capsys, "simulate", str(CONVENTIONAL), "--track", "R400", "--assess", "--json")
    step = summary["step_check"]
    assert step["dt"] == summary["dt"] == 0.005 and step["compared_dt"] == 0.01 and step["converged"]
    assert step["worst_fraction"] <= TOLERANCE and step["worst"] in step["errors"]
    assert {c["name"] for c in summary["assessment"]["criteria"]} >= set(step["errors"])
    status, out, _ = run(capsys, "simulate", str(CONVENTIONAL), "--track", "R400", "--assess")
    assert status == 0 and "checked against 10 ms: converged" in out
    plain = run_json(capsys, "simulate", str(CONVENTIONAL), "--track", "R400", "--assess", "--json", "--no-step-check")
    assert "step_check" not in plain
