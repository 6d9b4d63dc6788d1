"""``express eigen`` (``express.cli.eigen``): eigenvalues and labelled modes at one speed."""

from __future__ import annotations

import numpy as np
import pytest

from cli_support import CONVENTIONAL, LEVER, STEERED, assert_input_error, run, run_json, valued_lever


def test_eigen_json(capsys):
    data = run_json(capsys, "eigen", CONVENTIONAL)
    assert data["speed_kmh"] == pytest.approx(120.0)
    assert data["speed"] == pytest.approx(120 / 3.6)
    eigenvalues = np.array(data["eigenvalues"])
    assert eigenvalues.shape == (40, 2)  # 20 DOFs -> 40 eigenvalues, [re, im]
    assert data["stable"] is True and eigenvalues[:, 0].max() < 0
    assert all({"eigenvalue", "frequency_hz", "damping_ratio", "dominant", "label"} <= set(m) for m in data["modes"])


@pytest.mark.parametrize("speed", ["200", "200 km/h", "55.5555555556 m/s"])
def test_eigen_speed_with_or_without_unit(capsys, speed):
    base = np.array(run_json(capsys, "eigen", CONVENTIONAL)["eigenvalues"])
    faster = run_json(capsys, "eigen", CONVENTIONAL, "--speed", speed)
    assert faster["speed_kmh"] == pytest.approx(200.0)
    assert not np.allclose(np.array(faster["eigenvalues"]), base)


def test_eigen_set_changes_the_eigenvalues(capsys):
    base = np.array(run_json(capsys, "eigen", CONVENTIONAL)["eigenvalues"])
    changed = np.array(run_json(capsys, "eigen", CONVENTIONAL, "--set", "Gamma=0.05")["eigenvalues"])
    assert not np.allclose(changed, base)


@pytest.mark.parametrize("value", ["100", "100 km/h", "27.7777777778 m/s"])
def test_set_v_means_the_same_as_speed(capsys, value):
    """A bare ``--set v=100`` is km/h like ``--speed 100`` (the quantity rule)."""
    by_set = run_json(capsys, "eigen", CONVENTIONAL, "--set", f"v={value}")
    by_speed = run_json(capsys, "eigen", CONVENTIONAL, "--speed", "100")
    assert by_set["speed_kmh"] == pytest.approx(100.0)
    np.testing.assert_allclose(by_set["eigenvalues"], by_speed["eigenvalues"], rtol=1e-9, atol=1e-9)


def test_eigen_table(capsys):
    status, out, err = run(capsys, "eigen", STEERED, "--speed", "120 km/h")
    assert status == 0, err
    assert "f [Hz]" in out and "zeta" in out and "dominant" in out
    assert "hunting" in out and "steering lever" in out and "car body" in out


@pytest.mark.parametrize(
    "argv, mentions",
    [
        (["eigen", CONVENTIONAL, "--speed", "0"], "0 < --speed"),
        (["eigen", CONVENTIONAL, "--speed", "3 kg"], "--speed"),
        (["eigen", CONVENTIONAL, "--set", "ky1=4 s"], "ky1"),
        (["eigen", CONVENTIONAL, "--set", "gamma=0.05"], "Gamma"),
        (["eigen", LEVER], "undefined name"),  # no values: nothing to evaluate
    ],
)
def test_eigen_bad_input_exits_2(capsys, argv, mentions):
    assert_input_error(capsys, *argv, mentions=mentions)


def test_eigen_without_rail_data(capsys, tmp_path):
    """A model with values but no rail data (issue 11): its modes, no speed."""
    status, out, _ = run(capsys, "eigen", str(valued_lever(tmp_path)))
    assert status == 0 and "no rail data: independent of speed" in out


def test_eigen_solves_the_eigenproblem_once(capsys, monkeypatch):
    """The eigenvalue list and the modes come from one ``eig`` (issue 24): every mode's
    eigenvalue is in the list exactly, with its conjugate."""
    calls = []
    for name in ("eig", "eigvals"):
        original = getattr(np.linalg, name)
        monkeypatch.setattr(np.linalg, name, lambda *a, _f=original, _n=name, **k: calls.append(_n) or _f(*a, **k))
    data = run_json(capsys, "eigen", STEERED)
    assert calls == ["eig"]
    listed = {complex(re, im) for re, im in data["eigenvalues"]}
    assert len(data["eigenvalues"]) == 48
    for mode in data["modes"]:
        value = complex(*mode["eigenvalue"])
        assert value in listed and value.conjugate() in listed
