"""One way to suggest a valid name (issue 25 item 6): every option and key that takes a
name says ``did you mean X?`` through :mod:`express.base.names`; sensitivities rank the
design parameters and list physical constants and parameters without effect apart."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from express.base.names import closest_name, did_you_mean
from express.cli import main

ROOT = Path(__file__).resolve().parents[1]
MANCHESTER = str(ROOT / "examples" / "manchester.toml")
CONVENTIONAL = str(ROOT / "examples" / "conventional.toml")


@pytest.mark.parametrize(
    "name, known, expected",
    [
        ("Gamma", ["Gamma_e", "g", "mc"], "Gamma_e"),  # the issue's --parameter Gamma
        ("cyw", ["cyaw", "cy2", "kyaw"], "cyaw"),  # the issue's --set cyw
        ("MC", ["mc", "mt"], "mc"),  # case first
        ("fra-7", ["FRA-6", "AAR-6"], "FRA-6"),  # similarity ignores case
        ("R25", ["R250", "R400"], "R250"),
        ("CB.yy", ["CB.y", "CB.rz"], "CB.y"),
        ("zzz", ["mc", "mt"], None),
        ("k", ["kx1", "ky1"], None),  # a prefix of several names names none of them
    ],
)
def test_closest_name(name, known, expected):
    assert closest_name(name, known) == expected
    assert did_you_mean(name, known) == (f"; did you mean {expected}?" if expected else "")


@pytest.mark.parametrize(
    "argv, hint",
    [
        (["eigen", MANCHESTER, "--set", "Gama=0.2"], "did you mean Gamma?"),
        (["sensitivity", MANCHESTER, "--parameter", "Gama"], "--parameter Gama: not a given parameter of the model "
                                                            "(nor the speed); did you mean Gamma?"),
        (["sensitivity", MANCHESTER, "--output", "critical"], "invalid choice: 'critical'; did you mean critical-speed?"),
        (["frf", MANCHESTER, "--dof", "CB.yy"], "--dof CB.yy: unknown DOF; did you mean CB.y?"),
        (["ride", MANCHESTER, "--track", "fra-7"], "unknown track class 'fra-7'; did you mean FRA-6?"),
        (["curving", CONVENTIONAL, "--track", "R25"], "not a bundled track; did you mean R250?"),
        (["eigne", MANCHESTER], "invalid choice: 'eigne'; did you mean eigen?"),
    ],
)
def test_every_option_that_takes_a_name_suggests_the_same_way(capsys, argv, hint):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert hint in err, err
    assert "Traceback" not in err


@pytest.mark.slow
def test_sensitivity_ranks_design_parameters_and_lists_constants_and_idle_ones_apart(capsys):
    assert main(["sensitivity", MANCHESTER, "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert set(summary["constants"]) == {"g", "Emod", "nu"}
    # parameters of the nonlinear contact, the bump stops, cant and an output height
    # enter no matrix of the linear vehicle
    assert set(summary["without_effect"]) == {"G", "delta", "hf", "hs", "kR", "kstop", "kstop3", "mu", "ystop"}
    ranked = summary["sensitivities"]
    assert not set(ranked) & (set(summary["constants"]) | set(summary["without_effect"]))
    assert all(value != 0 for value in ranked.values())
    assert {"a", "Gamma", "mc", "ky1"} <= set(ranked)
    assert main(["sensitivity", MANCHESTER, "--all", "--json"]) == 0
    every = json.loads(capsys.readouterr().out)
    assert set(every["sensitivities"]) == set(ranked) | set(summary["constants"]) | set(summary["without_effect"])
    assert "constants" not in every
