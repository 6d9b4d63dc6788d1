"""``express study`` as a user runs it (express.cli.study): the study file of issue 13
as written against single ``express critical-speed --set`` runs, the progress bar (on
a terminal only, never with --json), the vehicle compiled once per worker, and the
bundled study with the figure of ``docs/studies.md``."""

from __future__ import annotations

import contextlib
import fcntl
import io
import json
import os
import pty
import re
import shutil
import struct
import subprocess
import sys
import termios
from pathlib import Path

import numpy as np
import pytest

from express.analysis.study.run import default_workers
from express.cli import main
from test_study_spec import ISSUE_STUDY

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "forced-steering.toml"



@pytest.fixture()
def issue_study(tmp_path: Path) -> Path:
    (tmp_path / "examples").mkdir()
    shutil.copy(MODEL, tmp_path / "examples" / "forced-steering.toml")
    path = tmp_path / "study.toml"
    path.write_text(ISSUE_STUDY)
    return path


def _cli_json(arguments: list[str]) -> dict:
    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        assert main(arguments) == 0
    return json.loads(buffer.getvalue())


def test_issue_study_runs_as_written_and_equals_single_runs(issue_study: Path) -> None:
    """The issue's file through ``express study -o x.csv``: one row per point, the varied
    parameters in SI, critical_speed in m/s, error; each row equal to
    ``express critical-speed --set ...`` to 1e-9 relative."""
    output = issue_study.parent / "x.csv"
    summary = _cli_json(["study", str(issue_study), "-o", str(output), "--json"])
    assert summary["points"] == 6 and summary["failed"] == 0
    assert summary["workers"] == min(default_workers(), 6)  # all local cores by default
    lines = output.read_text().splitlines()
    assert lines[0] == "Gamma,kx1_N_m,critical_speed_m_s,error"
    rows = [line.split(",") for line in lines[1:]]
    assert [(float(r[0]), float(r[1])) for r in rows] == [(g, k) for g in (0.05, 0.1, 0.2) for k in (1e6, 4e6)]
    model = issue_study.parent / "examples" / "forced-steering.toml"
    for gamma, kx1, speed, error in rows:
        single = _cli_json(["critical-speed", str(model), "--set", f"Gamma={gamma}", "--set", f"kx1={kx1}",
                            "--set", "cyaw=200 kN*s/m", "--json"])
        assert float(speed) == pytest.approx(single["critical_speed"], rel=1e-9, abs=0)
        assert error == ""
    speeds = [float(r[2]) for r in rows]
    assert len(set(speeds)) == 6 and 10 < min(speeds) < max(speeds) < 150  # m/s, every point its own value


# ------------------------------------------------------------------ progress bar


def _environment() -> dict[str, str]:
    return dict(os.environ, PYTHONPATH=str(ROOT / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""))


def _run_on_terminal(arguments: list[str]) -> tuple[int, str, str]:
    """Run ``express`` with standard error on a pseudo-terminal: status, stdout, what the
    terminal showed."""
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))  # a new pty is 0 x 0
    process = subprocess.Popen([sys.executable, "-m", "express", *arguments], env=_environment(),
                               stdout=subprocess.PIPE, stderr=slave, stdin=subprocess.DEVNULL)
    os.close(slave)
    shown = bytearray()
    while True:
        try:
            chunk = os.read(master, 4096)
        except OSError:  # the terminal closed: the process ended
            break
        if not chunk:
            break
        shown += chunk
    out = process.stdout.read().decode() if process.stdout is not None else ""
    os.close(master)
    return process.wait(timeout=120), out, shown.decode(errors="replace")


#: tqdm's bar: count, elapsed<remaining (the ETA) and rate.
BAR = re.compile(r"6/6 \[\d\d:\d\d<\d\d:\d\d, +[\d.]+pt/s\]")


@pytest.mark.slow
def test_progress_bar_on_a_terminal_only(issue_study: Path) -> None:
    folder = issue_study.parent
    status, out, shown = _run_on_terminal(["study", str(issue_study), "-o", str(folder / "tty.csv"), "--workers", "1"])
    assert status == 0, shown
    assert BAR.search(shown), shown  # the bar, with its ETA, on the terminal
    assert "wrote" in out and "6 points" in out
    # --json: silent on the terminal, the summary on stdout only
    status, out, shown = _run_on_terminal(["study", str(issue_study), "-o", str(folder / "json.csv"), "--workers", "1",
                                           "--json"])
    assert status == 0 and shown == "" and json.loads(out)["points"] == 6
    # standard error not a terminal: no bar
    done = subprocess.run([sys.executable, "-m", "express", "study", str(issue_study), "-o", str(folder / "pipe.csv"),
                           "--workers", "1"], env=_environment(), capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stderr == ""
    assert (folder / "tty.csv").read_bytes() == (folder / "json.csv").read_bytes() == (folder / "pipe.csv").read_bytes()


def test_progress_follows_the_points(issue_study: Path, monkeypatch, capsys) -> None:
    """On a terminal the bar counts every point (in process: standard error taken for a
    terminal)."""
    from express.cli import common

    monkeypatch.setattr(common, "is_terminal", lambda stream: True)
    assert main(["study", str(issue_study), "-o", str(issue_study.parent / "p.csv"), "--workers", "1"]) == 0
    err = capsys.readouterr().err
    assert "6/6" in err and "pt/s" in err
    assert main(["study", str(issue_study), "-o", str(issue_study.parent / "q.csv"), "--workers", "1", "--json"]) == 0
    assert capsys.readouterr().err == ""


# ------------------------------------------------------------------ compiled once per worker


def test_the_vehicle_is_compiled_once_per_worker(issue_study: Path, monkeypatch, tmp_path: Path) -> None:
    """The symbolic matrices are compiled once (before the pool forks: its workers
    inherit the vehicle) and every point is evaluated from its values; counted across
    processes through a file."""
    from express.analysis.study import runner
    from express.numeric import compiled as numeric

    monkeypatch.setattr(runner, "_WORKERS", {})  # no worker kept from an earlier study in this process
    record = tmp_path / "compiled.txt"
    original = numeric.CompiledMatrices.__init__

    def counted(self, *args, **kwargs):
        with open(record, "a") as stream:
            stream.write(f"{os.getpid()}\n")
        original(self, *args, **kwargs)

    monkeypatch.setattr(numeric.CompiledMatrices, "__init__", counted)
    summary = _cli_json(["study", str(issue_study), "-o", str(tmp_path / "pool.csv"), "--workers", "2", "--json"])
    assert summary["computed"] == 6 and summary["workers"] == 2
    assert record.read_text().splitlines() == [str(os.getpid())]  # once, in this process, none in the workers


# ------------------------------------------------------------------ the bundled study


@pytest.mark.slow
def test_bundled_study_and_its_figure(tmp_path: Path) -> None:
    """``examples/studies/critical_speed_map.toml`` as docs/studies.md runs it: 425 points,
    the map's figure, and what the text says of it."""
    study = ROOT / "examples" / "studies" / "critical_speed_map.toml"
    output, figure = tmp_path / "map.nc", tmp_path / "map.png"
    summary = _cli_json(["study", str(study), "-o", str(output), "--plot", str(figure), "--json"])
    assert summary["points"] == 425 and summary["failed"] == 0
    assert figure.read_bytes().startswith(b"\x89PNG")
    import xarray as xr

    with xr.open_dataset(output, engine="scipy") as data:
        speed = data["critical_speed"].values * 3.6  # km/h, dims (lLL, kx1)
        lever = data["lLL"].values / 0.3
        kx1 = data["kx1"].values
        assert data["critical_speed"].dims == ("lLL", "kx1") and speed.shape == (25, 17)
    # regression guards (this code's own map, as docs/studies.md describes it), not validation
    assert 410 < speed.max() < 430 and lever[np.unravel_index(speed.argmax(), speed.shape)[0]] < 0.2
    high = speed[:, kx1 >= 2e6]
    assert 320 < high[lever > 0.45].min() < 345  # a long arm lowers it towards 330 km/h
    window = speed[np.ix_(lever > 0.4, kx1 < 1.5e6)]
    assert window.min() < 80 and (speed[np.ix_(lever < 0.35, kx1 < 1.5e6)] > 200).all()  # low-speed hunting only there
