"""Running studies (express.analysis.study.run / runner / results): the CSV against
individual ``express critical-speed`` runs, the formats, failing points, checkpoint and
resume (in process and after SIGKILL), a worker that dies, and a real Dask cluster."""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from express.analysis.study import runner
from express.analysis.study.results import checkpoint_path, read_table
from express.analysis.study.run import run_study
from express.analysis.study.spec import read_study
from express.cli import main

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "forced-steering.toml"


def _study(folder: Path, body: str, name: str = "study.toml") -> Path:
    path = folder / name
    path.write_text(f'[study]\nmodel = "{MODEL}"\n' + body)
    return path


GRID = """kind = "grid"
outputs = ["critical_speed", "critical_frequency"]
[study.parameters]
Gamma = { values = [0.03, 0.1, 0.3] }
kx1 = { from = "1 MN/m", to = "4 MN/m", count = 2 }
[study.set]
cyaw = "200 kN*s/m"
"""


def _cli_json(arguments: list[str]) -> dict:
    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        assert main(arguments) == 0
    return json.loads(buffer.getvalue())


def test_grid_csv_equals_individual_critical_speed_runs(tmp_path: Path) -> None:
    study = _study(tmp_path, GRID)
    output = tmp_path / "grid.csv"
    summary = _cli_json(["study", str(study), "-o", str(output), "--workers", "2", "--json"])
    assert summary["points"] == 6 and summary["computed"] == 6 and summary["failed"] == 0
    assert not checkpoint_path(output).exists()
    lines = output.read_text().splitlines()
    assert lines[0] == "Gamma,kx1_N_m,critical_speed_m_s,critical_frequency_hz,error"
    rows = [line.split(",") for line in lines[1:]]
    assert [(float(r[0]), float(r[1])) for r in rows] == [(g, k) for g in (0.03, 0.1, 0.3) for k in (1e6, 4e6)]
    for row in rows:
        single = _cli_json(["critical-speed", str(MODEL), "--set", f"Gamma={row[0]}", "--set", f"kx1={row[1]}",
                            "--set", "cyaw=200 kN*s/m", "--json"])
        assert float(row[2]) == pytest.approx(single["critical_speed"], rel=1e-9, abs=0)
        assert float(row[3]) == pytest.approx(single["frequency_hz"], rel=1e-3)  # bisection midpoint vs crossing
        assert row[4] == ("already unstable at the lowest speed 1 m/s" if single["unstable_at_min"] else "")
    assert rows[0][4] and not rows[1][4]  # Gamma = 0.03 with the soft kx1 hunts at any speed


def test_formats_hold_the_same_numbers(tmp_path: Path) -> None:
    spec = read_study(_study(tmp_path, GRID))
    tables = {}
    for suffix in (".csv", ".parquet", ".nc"):
        run_study(spec, tmp_path / f"r{suffix}", workers=1)
        tables[suffix] = read_table(tmp_path / f"r{suffix}")
    for suffix in (".parquet", ".nc"):
        for name in ("critical_speed", "critical_frequency"):
            assert np.array_equal(tables[suffix][name], tables[".csv"][name])
    import pyarrow.parquet as pq
    import xarray as xr

    metadata = pq.read_schema(tmp_path / "r.parquet").metadata
    assert metadata[b"express.study"].decode() == spec.text
    assert json.loads(metadata[b"express.units"])["kx1"] == "N/m"
    with xr.open_dataset(tmp_path / "r.nc", engine="scipy") as data:
        assert data["critical_speed"].dims == ("Gamma", "kx1")
        assert data["critical_speed"].attrs["units"] == "m/s" and data["kx1"].attrs["units"] == "N/m"
        assert data.attrs["study"] == spec.text
        assert float(data["critical_speed"].sel(Gamma=0.1, kx1=4e6)) == tables[".csv"]["critical_speed"][3]
    # deterministic bytes: the same study written again
    for suffix in (".csv", ".parquet", ".nc"):
        run_study(spec, tmp_path / f"again{suffix}", workers=1)
        assert (tmp_path / f"again{suffix}").read_bytes() == (tmp_path / f"r{suffix}").read_bytes()


def test_failing_point_is_recorded_and_the_study_goes_on(tmp_path: Path) -> None:
    body = ('outputs = ["critical_speed", "least_damping_ratio"]\n[study.parameters]\n'
            'Rrail = { values = [0.3, -0.3, 0.2] }\n')
    output = tmp_path / "f.csv"
    summary = run_study(read_study(_study(tmp_path, body)), output, workers=1)
    table = read_table(output)
    assert summary.points == 3 and summary.failed == 1
    assert math.isnan(table["critical_speed"][1]) and math.isnan(table["least_damping_ratio"][1])
    assert (table["error"][1] and "Rrail" in table["error"][1]) or "radius" in table["error"][1]
    assert table["error"][0] == table["error"][2] == ""
    assert np.isfinite(table["critical_speed"][[0, 2]]).all()


@pytest.mark.parametrize("check", ["grid", "local"])
def test_resume_after_a_crash_computes_only_the_missing_points(tmp_path: Path, monkeypatch, check: str) -> None:
    spec = read_study(_study(tmp_path, GRID.replace("count = 2", "count = 4") + f'[study.options]\ncheck = "{check}"\n'))
    reference = tmp_path / "reference.csv"
    monkeypatch.setattr(runner, "BLOCK", 3)  # blocks of the local check: 3 points
    run_study(spec, reference, workers=1)
    output = tmp_path / "crashed.csv"
    original = runner.Engine.run

    def crash_after_two_chunks(self, indices, vectors):
        for number, records in enumerate(original(self, indices, vectors)):
            if number == 2:
                raise KeyboardInterrupt
            yield records

    monkeypatch.setattr(runner, "chunk_size", lambda points, workers: 2)
    monkeypatch.setattr(runner.Engine, "run", crash_after_two_chunks)
    with pytest.raises(KeyboardInterrupt):
        run_study(spec, output, workers=1)
    checkpoint = checkpoint_path(output)
    done = 4 if check == "grid" else 6  # chunks of 2 points, or blocks of 3
    assert not output.exists() and len(checkpoint.read_text().splitlines()) == 1 + done
    with open(checkpoint, "a") as stream:
        stream.write('{"point": 7, "values": [0.1, 2')  # a line cut short by the crash
    if check == "local":  # a block of which only some points were written is run again whole
        lines = checkpoint.read_text().splitlines(keepends=True)
        checkpoint.write_text("".join(lines[:-2]))
        done = 3
    monkeypatch.setattr(runner.Engine, "run", original)
    assert main(["study", str(spec.path), "-o", str(output)]) == 2  # a checkpoint exists: --resume or delete it
    summary = run_study(spec, output, workers=1, resume=True)
    assert summary.computed == 12 - done
    assert output.read_bytes() == reference.read_bytes()
    assert not checkpoint.exists()


def test_checkpoint_of_another_study_is_refused(tmp_path: Path) -> None:
    spec = read_study(_study(tmp_path, GRID))
    output = tmp_path / "x.csv"
    checkpoint_path(output).write_text('{"format": "express-study-checkpoint", "key": "other"}\n')
    with pytest.raises(Exception, match="another study"):
        run_study(spec, output, workers=1, resume=True)
    assert not output.exists()


# ------------------------------------------------------------------ processes, kills, Dask

SLOW_GRID = """kind = "grid"
outputs = ["critical_speed"]
[study.parameters]
Gamma = { from = 0.05, to = 0.4, count = 12 }
kx1 = { from = "0.5 MN/m", to = "8 MN/m", count = 12, scale = "log" }
"""


def _express(arguments: list[str], **kwargs) -> subprocess.Popen:
    environment = dict(os.environ, PYTHONPATH=str(ROOT / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.Popen([sys.executable, "-m", "express", *arguments], env=environment,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kwargs)


def _lines(path: Path) -> int:
    try:
        return path.read_text().count("\n")
    except FileNotFoundError:
        return 0


def _wait_for_lines(path: Path, count: int, process: subprocess.Popen, timeout: float = 300) -> None:
    deadline = time.monotonic() + timeout
    while _lines(path) < count:
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, "the study made no progress"
        time.sleep(0.05)


@pytest.fixture(scope="module")
def slow_reference(tmp_path_factory) -> tuple[Path, bytes]:
    folder = tmp_path_factory.mktemp("reference")
    study = _study(folder, SLOW_GRID)
    output = folder / "reference.csv"
    run_study(read_study(study), output, workers=2)
    return study, output.read_bytes()


@pytest.mark.slow
def test_killed_study_resumes_to_the_identical_file(tmp_path: Path, slow_reference) -> None:
    study, reference = slow_reference
    output = tmp_path / "killed.csv"
    process = _express(["study", str(study), "-o", str(output), "--workers", "2"], start_new_session=True)
    checkpoint = checkpoint_path(output)
    _wait_for_lines(checkpoint, 1 + 20, process)
    os.killpg(process.pid, signal.SIGKILL)  # the study and its worker processes
    process.communicate()
    done = _lines(checkpoint) - 1
    assert not output.exists() and 20 <= done < 144
    resumed = _express(["study", str(study), "-o", str(output), "--workers", "2", "--resume", "--json"])
    out, err = resumed.communicate(timeout=600)
    assert resumed.returncode == 0, err
    summary = json.loads(out)
    assert summary["points"] == 144 and summary["computed"] <= 144 - done + 1  # + a torn line at most
    assert output.read_bytes() == reference


@pytest.mark.slow
def test_dead_worker_process_has_its_points_run_again(tmp_path: Path, slow_reference) -> None:
    import psutil

    study, reference = slow_reference
    output = tmp_path / "dead-worker.csv"
    process = _express(["study", str(study), "-o", str(output), "--workers", "2"])
    _wait_for_lines(checkpoint_path(output), 1 + 10, process)
    children = psutil.Process(process.pid).children()
    assert children, "no worker processes"
    children[0].send_signal(signal.SIGKILL)
    _out, err = process.communicate(timeout=600)
    assert process.returncode == 0, err
    assert output.read_bytes() == reference


def _dask_worker_processes(pid: int) -> list:
    """The worker processes that ``dask worker --nworkers 2`` (process ``pid``) started."""
    import psutil

    return [child for child in psutil.Process(pid).children()
            if "resource_tracker" not in " ".join(child.cmdline()) and child.is_running()]


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@contextlib.contextmanager
def _dask_cluster(tmp_path: Path, workers: int):
    """A real ``dask scheduler`` and ``dask worker --nworkers N`` on localhost: yields the
    scheduler's address and the worker command's process; both ended afterwards."""
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    environment = dict(os.environ, PYTHONPATH=str(ROOT / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""))
    dask = [sys.executable, "-m", "distributed.cli.dask_scheduler"]
    scheduler = subprocess.Popen([*dask, "--host", "127.0.0.1", "--port", str(port), "--dashboard-address", ":0"],
                                 env=environment, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    worker = None
    try:
        worker = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nworkers",
                                   str(workers), "--nthreads", "1", "--dashboard-address", ":0", "--local-directory",
                                   str(tmp_path)], env=environment, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        from distributed import Client

        with Client(address, timeout="60s") as client:
            client.wait_for_workers(workers, timeout=120)
        yield address, worker
    finally:
        for process in (worker, scheduler):
            if process is not None:
                process.terminate()
                try:
                    process.wait(timeout=30)
                except subprocess.TimeoutExpired:
                    process.kill()


@pytest.mark.slow
def test_dask_scheduler_and_worker_on_localhost_give_the_same_results(tmp_path: Path, slow_reference) -> None:
    """A real ``dask scheduler`` and ``dask worker`` (2 processes) on localhost: the file of
    the local run; then again with one worker process killed mid-study."""
    study, reference = slow_reference
    with _dask_cluster(tmp_path, 2) as (address, worker):
        output = tmp_path / "dask.csv"
        run = _express(["study", str(study), "-o", str(output), "--scheduler", address, "--json"])
        out, err = run.communicate(timeout=600)
        assert run.returncode == 0, err
        assert json.loads(out)["workers"] == 2
        assert output.read_bytes() == reference
        # a Dask worker process that dies mid-study: the scheduler runs its points elsewhere
        output = tmp_path / "dask-killed.csv"
        run = _express(["study", str(study), "-o", str(output), "--scheduler", address, "--json"])
        _wait_for_lines(checkpoint_path(output), 1 + 20, run)
        victims = _dask_worker_processes(worker.pid)
        assert len(victims) == 2, victims
        victims[0].send_signal(signal.SIGKILL)
        assert _lines(checkpoint_path(output)) < 1 + 144  # killed mid-study
        out, err = run.communicate(timeout=600)
        assert run.returncode == 0, err
        assert json.loads(out)["failed"] == 0 and not victims[0].is_running()
        assert output.read_bytes() == reference


@pytest.mark.slow
def test_the_only_dask_worker_killed_loses_nothing(tmp_path: Path, slow_reference) -> None:
    """Issue 36 item 2: with the only worker killed by ``kill -9`` the study exited 0 with
    most rows NaN ("cancelled for reason: already forgotten": the study's task had been
    scattered to that worker alone) and removed its checkpoint.  Now the lost chunks are
    submitted again (the task scattered anew) to the worker the nanny restarts, and the file
    is the undisturbed run's."""
    study, reference = slow_reference
    with _dask_cluster(tmp_path, 1) as (address, worker):
        output = tmp_path / "only-worker-killed.csv"
        run = _express(["study", str(study), "-o", str(output), "--scheduler", address, "--json"])
        _wait_for_lines(checkpoint_path(output), 1 + 20, run)
        (victim,) = _dask_worker_processes(worker.pid)
        victim.send_signal(signal.SIGKILL)
        assert _lines(checkpoint_path(output)) < 1 + 144  # killed mid-study
        out, err = run.communicate(timeout=600)
        assert run.returncode == 0, err
        assert json.loads(out)["failed"] == 0
        assert output.read_bytes() == reference


def test_local_check_gives_the_grid_check_file_across_a_low_speed_window(tmp_path: Path) -> None:
    """The bundled map's corner where a low-speed instability window opens (lLL >= 120 mm
    with soft kx1): the local check, following neighbours, gives the grid check's file."""
    body = """kind = "grid"
outputs = ["critical_speed", "critical_frequency"]
[study.parameters]
lLL = { from = "110 mm", to = "130 mm", count = 5 }
kx1 = { from = "0.5 MN/m", to = "2 MN/m", count = 7, scale = "log" }
[study.options]
v_max = "600 km/h"
"""
    files = {}
    for check in ("grid", "local"):
        study = _study(tmp_path, body + f'check = "{check}"\n', f"{check}.toml")
        files[check] = tmp_path / f"{check}.csv"
        run_study(read_study(study), files[check], workers=2)
    table = read_table(files["grid"])
    assert table["critical_speed"].min() < 25 < 80 < table["critical_speed"].max()  # both regimes present
    assert files["local"].read_bytes() == files["grid"].read_bytes()


def test_track_frf_and_damping_outputs_equal_the_analyses(tmp_path: Path) -> None:
    """The outputs other than the critical speed, against the library calls they stand for."""
    from express.analysis.frequency.frequency import frequency_response
    from express.analysis.time.simulate import simulate
    from express.numeric.statespace import load_vehicle
    from express.rail.track import paper_curve

    body = """outputs = ["max_Y", "max_YQ", "max_lever_angle", "frf_peak_acceleration", "frf_peak_frequency",
           "least_damping_ratio", "least_damping_frequency"]
[study.parameters]
mc = { values = ["30 t", "45 t"] }
[study.options]
speed = "100 km/h"
dt = 0.01
frf_points = 50
"""
    output = tmp_path / "other.csv"
    run_study(read_study(_study(tmp_path, body)), output, workers=1)
    table = read_table(output)
    for row, mass in enumerate((30e3, 45e3)):
        vehicle = load_vehicle(MODEL, {"mc": mass})
        speed = 100 / 3.6
        maxima = simulate(vehicle, paper_curve(), speed=speed, dt=0.01, progress=False).max_abs()
        assert table["max_Y"][row] == max(v for k, v in maxima.items() if k[1:].isdigit() and k[0] == "Y")
        assert table["max_YQ"][row] == max(v for k, v in maxima.items() if k[:2] == "YQ" and k[2:].isdigit())
        assert table["max_lever_angle"][row] == max(v for k, v in maxima.items() if k.startswith("theta_"))
        frequencies = np.geomspace(0.1, 20.0, 50)
        response = frequency_response(vehicle, frequencies, amplitude=1e-3, speed=speed)
        first = vehicle.model.rail.outputs[0].name
        amplitude = np.abs(response.acceleration_of(first))
        assert table["frf_peak_acceleration"][row] == amplitude.max()
        assert table["frf_peak_frequency"][row] == frequencies[np.argmax(amplitude)]
        eigenvalues = np.linalg.eigvals(vehicle.state_matrix(speed))
        ratios = -eigenvalues.real / np.abs(eigenvalues)
        assert table["least_damping_ratio"][row] == ratios.min()
        assert table["least_damping_frequency"][row] == pytest.approx(abs(eigenvalues[np.argmin(ratios)].imag) / (2 * np.pi))
    assert table["error"] == ["", ""]


def test_points_lost_to_the_machinery_end_with_exit_1_and_resume_completes(tmp_path: Path, monkeypatch) -> None:
    """Issue 36 item 2: points a worker could not return (here: marked lost by the engine,
    as after a worker died each time) are not results — the study ends with status 1 and
    the reason, the checkpoint keeps the points done, and ``--resume`` computes the rest to
    the file of an undisturbed run."""
    from express.base.diagnostics import AnalysisError

    spec = read_study(_study(tmp_path, GRID))
    reference = tmp_path / "reference.csv"
    run_study(spec, reference, workers=1)
    original = runner.Engine.run

    def losing(self, indices, vectors):
        for records in original(self, indices, vectors):
            yield [runner._failed([r["point"]], [r["values"]], len(r["outputs"]), "the worker died")[0]
                   if r["point"] in (1, 4) else r for r in records]

    monkeypatch.setattr(runner.Engine, "run", losing)
    output = tmp_path / "lost.csv"
    with pytest.raises(AnalysisError, match="2 of 6 points could not be evaluated .the worker died.*--resume"):
        run_study(spec, output, workers=1)
    assert not output.exists() and checkpoint_path(output).exists()
    monkeypatch.setattr(runner.Engine, "run", original)
    summary = run_study(spec, output, workers=1, resume=True)
    assert summary.computed == 2 and output.read_bytes() == reference.read_bytes()
    assert not checkpoint_path(output).exists()


@pytest.mark.slow
@pytest.mark.parametrize("address, words, seconds", [
    ("silent", "no answer from a Dask scheduler within 30 s", 60),
    ("garbage", "not a Dask scheduler address", 15),
], ids=["a port that accepts and never answers", "not an address"])
def test_a_scheduler_that_cannot_serve_is_a_clear_error_in_bounded_time(tmp_path: Path, address, words, seconds):
    """Issue 36 items 2 and 6: a port that accepts but never answers held ``--scheduler``
    for good (after SIGTERM a further 40 s in ``Client.__del__``, with its traceback);
    ``--scheduler garbage`` printed its error, then that traceback 40-60 s later.  Now:
    exit 2, one error line, within the bound, no traceback."""
    import threading

    study = _study(tmp_path, GRID)
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    accepted: list = []
    threading.Thread(target=lambda: [accepted.append(server.accept()) for _ in range(8)], daemon=True).start()
    target = f"tcp://127.0.0.1:{server.getsockname()[1]}" if address == "silent" else address
    started = time.monotonic()
    run = _express(["study", str(study), "-o", str(tmp_path / "out.csv"), "--scheduler", target])
    try:
        _, err = run.communicate(timeout=seconds + 30)
    finally:
        server.close()
    assert run.returncode == 2 and words in err and "Traceback" not in err, err
    assert time.monotonic() - started < seconds
    assert not (tmp_path / "out.csv").exists()


@pytest.mark.slow
def test_killing_the_study_ends_its_worker_processes(tmp_path: Path, slow_reference) -> None:
    """Issue 36 item 4: after ``kill -9`` of a study's own process (not its group) its
    worker processes ran on (38 s later); now the kernel ends them with it."""
    import psutil

    study, _ = slow_reference
    output = tmp_path / "orphans.csv"
    process = _express(["study", str(study), "-o", str(output), "--workers", "2"], start_new_session=True)
    _wait_for_lines(checkpoint_path(output), 1 + 5, process)
    children = [c for c in psutil.Process(process.pid).children() if "resource_tracker" not in " ".join(c.cmdline())]
    assert children, "no worker processes"
    process.send_signal(signal.SIGKILL)  # the study alone: its workers are not signalled
    process.wait(timeout=60)  # not communicate(): orphans would hold its pipes open
    _gone, alive = psutil.wait_procs(children, timeout=10)
    for orphan in alive:
        orphan.kill()
    assert not alive, [c.pid for c in alive]


@pytest.mark.slow
def test_killing_the_study_ends_its_tasks_on_a_dask_cluster(tmp_path: Path, slow_reference) -> None:
    """Issue 36 item 2: killing the study's process ends its cluster's work too.  The
    scheduler sees the client's connection close, forgets its tasks (the pending ones never
    run) and the worker finishes at most the chunk it holds; nothing is left queued."""
    from distributed import Client

    study, _ = slow_reference
    with _dask_cluster(tmp_path, 1) as (address, _worker):
        output = tmp_path / "cluster-orphans.csv"
        process = _express(["study", str(study), "-o", str(output), "--scheduler", address], start_new_session=True)
        _wait_for_lines(checkpoint_path(output), 1 + 5, process)
        with Client(address, timeout="60s") as client:
            assert client.run_on_scheduler(_task_count) > 0  # the study's work is on the cluster
            process.send_signal(signal.SIGKILL)
            process.wait(timeout=60)
            deadline = time.monotonic() + 30
            while client.run_on_scheduler(_task_count) and time.monotonic() < deadline:
                time.sleep(0.2)
            assert client.run_on_scheduler(_task_count) == 0
            assert client.run_on_scheduler(_client_count) == 1  # this one: the study's client is gone


# lambdas: pickled by value (the scheduler cannot import this test module)
_task_count = lambda dask_scheduler: len(dask_scheduler.tasks)  # noqa: E731
_client_count = lambda dask_scheduler: len([c for c in dask_scheduler.clients if not c.startswith("fire-and-forget")])  # noqa: E731


def test_a_checkpoint_record_nested_beyond_the_json_parser_is_skipped(tmp_path: Path) -> None:
    """Issue 36 item 5: a record of 100 000 nested arrays was an internal error on --resume."""
    from express.analysis.study.results import Checkpoint

    path = tmp_path / "out.csv.checkpoint.jsonl"
    checkpoint = Checkpoint(path, {"study": "s"})
    checkpoint.open(resume=False)
    checkpoint.append([{"point": 0, "values": [1.0]}])
    checkpoint.close()
    with open(path, "a", encoding="utf-8") as stream:
        stream.write("[" * 100_000 + "\n" + json.dumps({"point": 1, "values": [2.0]}) + "\n")
    again = Checkpoint(path, {"study": "s"})
    again.open(resume=True)
    assert [record["point"] for record in again.records()] == [0, 1]
    again.close()
