"""Issue 32 item 3's check on the stiffest bundled vehicle: the Y25 freight wagon (friction,
nested coils, contact from the profiles) on the R 600 m track, ``express simulate
--assess`` at its defaults (the step check: 10, 5, 2.5 ms, converged at 2.5 ms within 1 %
of every limit) against one run at 0.25 ms."""

from __future__ import annotations

import pytest

from cli_support import EXAMPLES, run_json

WAGON = EXAMPLES / "y25-wagon.toml"


@pytest.mark.slow
def test_the_wagons_default_run_is_within_its_stated_tolerance_of_a_quarter_millisecond_run(capsys):
    """Every EN 14363 criterion of the default run within 1 % of its limit (the step
    check's stated tolerance) of the 0.25 ms run's; measured 2026-12-03: largest 0.44 %
    (SY4_rms), (SY)2m within 0.10 % (SY4: 11 977 against 12 004 N), (Y/Q)2m 0.05 %,
    dQ/Q0 0.08 %. The 0.25 ms run itself is just above the friction elements' resolved
    step (0.208 ms, it warns): the reference the issue names."""
    default = run_json(capsys, "simulate", WAGON, "--track", "R600", "--assess")
    fine = run_json(capsys, "simulate", WAGON, "--track", "R600", "--assess", "--dt", "0.25ms", "--no-step-check")
    assert default["step_check"]["converged"] and default["dt"] == 0.0025 and fine["dt"] == 0.00025
    coarse = {c["name"]: c for c in default["assessment"]["criteria"]}
    errors = {c["name"]: abs(coarse[c["name"]]["value"] - c["value"]) / c["limit"]
              for c in fine["assessment"]["criteria"]}
    assert max(errors.values()) < 0.01, errors
    assert max(errors[f"SY{k}"] for k in range(1, 5)) < 0.002
