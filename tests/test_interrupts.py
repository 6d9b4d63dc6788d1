"""Interrupts (express.base.interrupts, issue 26 item 1): the first Ctrl-C, SIGTERM or
SIGHUP stops a command cleanly, a second one ends it within seconds wherever it is;
no process and no temporary file is left, and an interrupted study resumes to the
identical file.

The end-to-end cases run ``python -m express`` in its own process group and signal the
group, as a terminal does; they are few and marked slow (each costs a few seconds)."""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import subprocess
import sys
import time
import types
from pathlib import Path

import pytest

from express.analysis.study.results import checkpoint_path
from express.analysis.study.run import run_study
from express.analysis.study.spec import read_study
from express.base import interrupts
from express.cli import main

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "forced-steering.toml"
#: Seconds a command may take to end after the second signal ("within a few seconds",
#: with room for a loaded CI machine).
END_WITHIN = 10.0

STUDY = f"""[study]
model = "{MODEL}"
kind = "grid"
outputs = ["critical_speed"]
[study.parameters]
Gamma = {{ from = 0.05, to = 0.4, count = 12 }}
kx1 = {{ from = "0.5 MN/m", to = "8 MN/m", count = 12, scale = "log" }}
"""


# ------------------------------------------------------------------ in this process


def test_temporary_file_is_registered_before_it_exists(tmp_path: Path) -> None:
    handle, path = interrupts.temporary_file(tmp_path, ".out.csv.", ".tmp")
    os.close(handle)
    assert path.exists() and path.name.startswith(".out.csv.") and oct(path.stat().st_mode & 0o777) == "0o600"
    interrupts.remove_temporaries()
    assert not path.exists()
    handle, path = interrupts.temporary_file(tmp_path, ".kept.", ".tmp")
    os.close(handle)
    interrupts.release(path)  # renamed over its target: no longer ours to remove
    interrupts.remove_temporaries()
    assert path.exists()


def test_an_interrupt_while_an_output_is_written_leaves_no_temporary(tmp_path: Path, monkeypatch, capsys) -> None:
    """The window the issue found (``demo`` left ``.summary.json.XXXX.tmp``): an interrupt
    right after the temporary file is created."""
    from express.io import output

    def created_then_interrupted(*args, **kwargs):
        handle, _path = interrupts.temporary_file(*args, **kwargs)
        os.close(handle)
        raise interrupts.Interrupted(signal.SIGINT)

    monkeypatch.setattr(output, "temporary_file", created_then_interrupted)
    status = main(["convert", str(ROOT / "examples" / "lever.exp"), "-o", str(tmp_path / "lever.toml")])
    assert status == 130
    assert "error: interrupted" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == []


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
def test_first_signal_raises_interrupted_with_its_status(signum) -> None:
    before = signal.getsignal(signum)
    with pytest.raises(interrupts.Interrupted) as caught, interrupts.handling_signals():
        os.kill(os.getpid(), signum)
        time.sleep(1)
    assert caught.value.status == 128 + signum
    assert signal.getsignal(signum) is before  # restored for the caller (the tests)


def _callback_of(module: str):
    """A function of ``module`` called as compiled code calls a Python callback: an
    exception it raises is lost (ctypes prints it as "Exception ignored")."""
    def body() -> None:
        os.kill(os.getpid(), signal.SIGINT)
        deadline = time.monotonic() + 0.5
        while time.monotonic() < deadline:  # the handler runs between these bytecodes
            pass

    callback = types.FunctionType(body.__code__, {"__name__": module, "os": os, "signal": signal, "time": time})
    lost: list[BaseException] = []

    def call() -> list[BaseException]:
        try:
            callback()
        except BaseException as error:  # what ctypes does with it
            lost.append(error)
        return lost

    return call


def test_a_signal_inside_a_callback_of_compiled_code_raises_once_it_returns() -> None:
    """Numba's first compilation calls llvmlite's Python callbacks from C: the first
    signal waits until the callback returns, then raises (a CI run lost it there and the
    second signal printed the lost exception's traceback)."""
    call = _callback_of("llvmlite.binding.executionengine")
    alarm = signal.getsignal(signal.SIGALRM)
    with pytest.raises(interrupts.Interrupted) as caught, interrupts.handling_signals():
        lost = call()
        assert lost == []  # nothing raised inside the callback
        time.sleep(1)
    assert caught.value.status == 130
    assert signal.getsignal(signal.SIGALRM) is alarm  # the timer's handler restored


def test_outside_a_callback_the_first_signal_raises_where_it_lands() -> None:
    call = _callback_of("express.some_module")
    with pytest.raises(interrupts.Interrupted), interrupts.handling_signals():
        lost = call()
        assert len(lost) == 1 and isinstance(lost[0], interrupts.Interrupted)  # raised inside
        raise lost[0]


# ------------------------------------------------------------------ whole commands


def _express(arguments: list[str], cwd: Path) -> subprocess.Popen:
    environment = dict(os.environ, PYTHONPATH=str(ROOT / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.Popen([sys.executable, "-m", "express", *arguments], env=environment, cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)


def _handlers_installed(pid: int) -> bool:
    """Whether the command catches SIGHUP yet (its handlers are in place: /proc's SigCgt)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    caught = int(next(line.split()[1] for line in status.splitlines() if line.startswith("SigCgt:")), 16)
    return bool(caught & (1 << (signal.SIGHUP - 1)))


def _wait(condition, process: subprocess.Popen, timeout: float = 300) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, "the command did not get going"
        time.sleep(0.02)


def _group_processes(group: int) -> list[str]:
    found = subprocess.run(["pgrep", "-g", str(group), "-a"], capture_output=True, text=True)
    return found.stdout.splitlines()


def _interrupt_twice(process: subprocess.Popen, signum: int, gap: float) -> tuple[int, str, float]:
    """Signal the group twice, ``gap`` seconds apart; (status, stderr, seconds to end after
    the second signal)."""
    assert process.poll() is None, "the command ended before it was interrupted"
    os.killpg(process.pid, signum)
    time.sleep(gap)
    with contextlib.suppress(ProcessLookupError):  # it may have ended after the first one
        os.killpg(process.pid, signum)
    sent = time.monotonic()
    try:
        _out, err = process.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate()
        pytest.fail("the command hung after two signals")
    ended = time.monotonic() - sent
    time.sleep(0.2)
    assert _group_processes(process.pid) == [], "a process was left behind"
    return process.returncode, err, ended


def _assert_ended(status: int, err: str, ended: float, signum: int, folder: Path) -> None:
    assert status in (128 + signum, -signum), (status, err)  # -signum: killed by it while exiting
    assert "Traceback" not in err, err
    assert "error: interrupted" in err, err
    assert ended < END_WITHIN, f"ended {ended:.1f} s after the second signal"
    left = [str(p.relative_to(folder)) for p in folder.rglob("*") if p.name.endswith(".tmp")]
    assert left == [], f"temporary files left: {left}"


@pytest.fixture(scope="module")
def study_reference(tmp_path_factory) -> tuple[Path, bytes]:
    folder = tmp_path_factory.mktemp("interrupt-reference")
    study = folder / "study.toml"
    study.write_text(STUDY)
    run_study(read_study(study), folder / "reference.csv", workers=2)
    return study, (folder / "reference.csv").read_bytes()


@pytest.mark.slow
@pytest.mark.parametrize(("workers", "signum", "gap"), [
    (1, signal.SIGINT, 0.0),
    (2, signal.SIGTERM, 0.3),
    (4, signal.SIGHUP, 1.0),
], ids=["1-worker-SIGINT-0s", "2-workers-SIGTERM-0.3s", "4-workers-SIGHUP-1s"])
def test_study_interrupted_twice_ends_and_resumes_to_the_identical_file(
    tmp_path: Path, study_reference, workers: int, signum: int, gap: float,
) -> None:
    study, reference = study_reference
    output = tmp_path / "map.csv"
    arguments = ["study", str(study), "-o", str(output), "--workers", str(workers)]
    process = _express(arguments, tmp_path)
    checkpoint = checkpoint_path(output)
    _wait(lambda: checkpoint.exists() and checkpoint.read_text().count("\n") >= 6, process)
    status, err, ended = _interrupt_twice(process, signum, gap)
    _assert_ended(status, err, ended, signum, tmp_path)
    assert not output.exists()
    resumed = _express([*arguments, "--resume"], tmp_path)
    _out, err = resumed.communicate(timeout=600)
    assert resumed.returncode == 0, err
    assert output.read_bytes() == reference
    assert not checkpoint.exists()


@pytest.mark.slow
@pytest.mark.parametrize(("arguments", "signum", "gap"), [
    (["critical-speed", str(MODEL), "--nonlinear", "-o", "nonlinear.csv"], signal.SIGINT, 0.2),
    (["ride", str(MODEL), "--track", "ERRI-low", "--points", "20000", "-o", "ride.csv"], signal.SIGTERM, 0.0),
    (["demo", "out"], signal.SIGHUP, 1.0),
    (["simulate", str(MODEL), "-o", "run.mat"], signal.SIGINT, 0.5),
], ids=["nonlinear-critical-speed", "ride", "demo", "simulate"])
def test_command_interrupted_twice_ends_at_once_and_leaves_nothing(
    tmp_path: Path, arguments: list[str], signum: int, gap: float,
) -> None:
    process = _express(arguments, tmp_path)
    _wait(lambda: _handlers_installed(process.pid), process)
    time.sleep(1.0)  # into the work
    status, err, ended = _interrupt_twice(process, signum, gap)
    _assert_ended(status, err, ended, signum, tmp_path)
    assert not any(p.is_file() for p in tmp_path.rglob("*")), sorted(map(str, tmp_path.rglob("*")))


@contextlib.contextmanager
def _local_dask_cluster(folder: Path):
    """A ``dask scheduler`` and a ``dask worker`` of 2 processes on localhost (the cluster
    of docs/studies.md); yields the scheduler's address."""
    from distributed import Client

    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    environment = dict(os.environ, PYTHONPATH=str(ROOT / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""))
    quiet = {"env": environment, "stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    cluster = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                                 "--port", str(port), "--dashboard-address", ":0"], **quiet)]
    try:
        cluster.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address,
                                         "--nworkers", "2", "--nthreads", "1", "--dashboard-address", ":0",
                                         "--local-directory", str(folder)], **quiet))
        with Client(address, timeout="60s") as client:
            client.wait_for_workers(2, timeout=120)
        yield address
    finally:
        for process in reversed(cluster):
            process.terminate()
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                process.kill()


@pytest.mark.slow
def test_a_study_on_a_dask_cluster_interrupted_twice_cancels_its_tasks(tmp_path: Path, study_reference) -> None:
    """Two SIGINTs 0.3 s apart to a study running on a Dask cluster: the command ends at
    once, the scheduler is left with no task of it, the cluster stays up, and the study
    resumes on it to the identical file."""
    from distributed import Client

    study, reference = study_reference
    output = tmp_path / "map.csv"
    with _local_dask_cluster(tmp_path) as address:
        arguments = ["study", str(study), "-o", str(output), "--scheduler", address]
        process = _express(arguments, tmp_path)
        checkpoint = checkpoint_path(output)
        _wait(lambda: checkpoint.exists() and checkpoint.read_text().count("\n") >= 6, process)
        status, err, ended = _interrupt_twice(process, signal.SIGINT, 0.3)
        _assert_ended(status, err, ended, signal.SIGINT, tmp_path)
        with Client(address, timeout="60s") as client:
            deadline = time.monotonic() + END_WITHIN
            while any(client.processing().values()) and time.monotonic() < deadline:
                time.sleep(0.1)
            assert not any(client.processing().values()), client.processing()
            assert len(client.scheduler_info()["workers"]) == 2  # the cluster is not the command's to stop
        resumed = _express([*arguments, "--resume"], tmp_path)
        _out, err = resumed.communicate(timeout=600)
        assert resumed.returncode == 0, err
    assert output.read_bytes() == reference
