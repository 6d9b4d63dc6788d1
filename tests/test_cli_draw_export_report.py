"""``express draw``, ``express export``, ``express report`` and ``eigen --mode``:
figures, numerical files and the report from the command line."""

from __future__ import annotations

import re
import zipfile

import numpy as np
import pytest
import scipy.io

from cli_support import CONVENTIONAL, LEVER, STEERED, run, valued_lever


@pytest.mark.parametrize("suffix", [".svg", ".png", ".pdf"])
def test_draw_writes_every_figure_format(tmp_path, capsys, suffix):
    target = tmp_path / f"car{suffix}"
    status, _, err = run(capsys, "draw", STEERED, "-o", target)
    assert status == 0 and target.stat().st_size > 1000 and f"wrote {target}" in err


def test_draw_is_deterministic(tmp_path, capsys):
    first, second = tmp_path / "a.svg", tmp_path / "b.svg"
    assert run(capsys, "draw", CONVENTIONAL, "-o", first)[0] == 0
    assert run(capsys, "draw", CONVENTIONAL, "-o", second)[0] == 0
    assert first.read_bytes() == second.read_bytes()


def test_draw_the_lever_needs_its_lengths(tmp_path, capsys):
    target = tmp_path / "lever.png"
    status, _, err = run(capsys, "draw", LEVER, "-o", target)
    assert status == 2 and not target.exists()
    assert err.count("cannot be drawn") == 4 and "no value for lLU (give it with --set)" in err
    status, _, _ = run(capsys, "draw", LEVER, "-o", target, "--set", "lLU=0.3", "--set", "lLL=0.06", "--set", "b=0.5")
    assert status == 0 and target.read_bytes()[:4] == b"\x89PNG"


def test_draw_refuses_an_unknown_figure_format(tmp_path, capsys):
    status, _, err = run(capsys, "draw", STEERED, "-o", tmp_path / "car.bmp")
    assert status == 2 and "unknown figure format" in err


@pytest.mark.parametrize("speed", ["100", "27.7778 m/s"])
def test_export_mat_has_the_matrices_at_the_speed(tmp_path, capsys, speed):
    target = tmp_path / "car.mat"
    status, _, _ = run(capsys, "export", CONVENTIONAL, "--speed", speed, "-o", target)
    assert status == 0
    data = scipy.io.loadmat(target)
    assert data["speed"].item() == pytest.approx(100 / 3.6, rel=1e-5)
    n = data["M"].shape[0]
    assert data["A"].shape == (2 * n, 2 * n) and data["B"].shape[0] == 2 * n
    np.testing.assert_allclose(data["A"][n:, :n], -np.linalg.solve(data["M"], data["K"]), rtol=1e-9, atol=1e-9)
    assert [d.strip() for d in data["dofs"]][:2] == ["CB.x", "CB.y"]


def test_export_npz_is_deterministic_and_format_follows_the_suffix(tmp_path, capsys):
    first, second = tmp_path / "a.npz", tmp_path / "b.npz"
    assert run(capsys, "export", STEERED, "-o", first)[0] == 0
    assert run(capsys, "export", STEERED, "-o", second)[0] == 0
    assert first.read_bytes() == second.read_bytes()
    with np.load(first) as data:
        assert data["M"].shape == (24, 24) and len(data["inputs"]) == 22
    status, _, err = run(capsys, "export", STEERED, "-o", tmp_path / "car.xyz")
    assert status == 2 and "unknown format" in err


@pytest.mark.slow
def test_export_fmu_is_an_fmi2_archive(tmp_path, capsys):
    target = tmp_path / "car.fmu"
    status, _, _ = run(capsys, "export", CONVENTIONAL, "-o", target)
    assert status == 0
    with zipfile.ZipFile(target) as archive:
        description = archive.read("modelDescription.xml").decode()
    assert 'fmiVersion="2.0"' in description and 'name="W1.yR"' in description and 'name="CB.y"' in description


def test_export_needs_rail_data(tmp_path, capsys):
    status, _, err = run(capsys, "export", valued_lever(tmp_path), "-o", tmp_path / "lever.mat")
    assert status == 2 and "no rail data" in err


@pytest.mark.slow
def test_report_writes_one_self_contained_page(tmp_path, capsys):
    target = tmp_path / "report.html"
    status, _, err = run(capsys, "report", CONVENTIONAL, "-o", target)
    text = target.read_text(encoding="utf-8")
    assert status == 0 and text.startswith("<!DOCTYPE html>") and "<h2>Stability</h2>" in text
    assert not re.search(r"(src|href)=\"https?:", text)


def test_report_of_a_model_without_rail_data(tmp_path, capsys):
    target = tmp_path / "lever.html"
    status, _, err = run(capsys, "report", valued_lever(tmp_path), "-o", target)
    text = target.read_text(encoding="utf-8")
    assert status == 0, err
    assert "<h2>Modes</h2>" in text and "<h2>Stability</h2>" not in text and "<math" in text


def test_eigen_draws_a_mode(tmp_path, capsys):
    plot, animation = tmp_path / "mode.png", tmp_path / "mode.html"
    status, out, _ = run(capsys, "eigen", CONVENTIONAL, "--mode", "3", "--plot", plot, "--animate", animation)
    assert status == 0 and "modes at" in out
    assert plot.read_bytes()[:4] == b"\x89PNG" and animation.read_text().startswith("<!DOCTYPE html>")


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--plot", "{tmp}/m.png"], "give --mode N"),
        (["--mode", "2"], "give one"),
        (["--mode", "2", "--animate", "{tmp}/m.mp4"], "use .gif or .html"),
        (["--mode", "999", "--plot", "{tmp}/m.png"], "the model has modes 1 to"),
    ],
)
def test_eigen_mode_mistakes(tmp_path, capsys, arguments, message):
    status, _, err = run(capsys, "eigen", CONVENTIONAL, *[a.format(tmp=tmp_path) for a in arguments])
    assert status == 2 and message in err
    assert not list(tmp_path.iterdir())


def test_frf_plot_draws_the_dofs_asked_for(tmp_path, capsys, monkeypatch):
    """``frf --plot`` honours ``--dof``: its curve is in the figure beside the floor
    points, each unit on its own axis (issue 25: no m/s^2 and m on one axis)."""
    from express.analysis import plots

    drawn = {}
    original = plots.figure_frequency_responses

    def spy(frequencies, panels, **kwargs):
        drawn.update({unit: [curve["label"] for curve in curves] for unit, curves in panels.items()})
        return original(frequencies, panels, **kwargs)

    monkeypatch.setattr(plots, "figure_frequency_responses", spy)
    status, _, _ = run(capsys, "frf", STEERED, "--dof", "W1.y", "--points", "20", "--plot", tmp_path / "frf.png")
    assert status == 0 and (tmp_path / "frf.png").exists()
    assert drawn["m"] == ["W1.y"] and len(drawn["m/s^2"]) >= 2
