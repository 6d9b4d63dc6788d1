"""The output layer (``express.io.output``): whole-file writes, special files, standard
output, transactions of several outputs, concurrency, CSV with units, deterministic
NPZ/MAT bytes, JSON-safe values."""

from __future__ import annotations

import io
import json
import multiprocessing
import os
import re
import stat
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from express.base.diagnostics import AnalysisError, InputError, OutputError
from express.io import archives, output
from express.io.output import (
    check_destination,
    mat_bytes,
    npz_bytes,
    output_transaction,
    write_bytes,
    write_csv,
    write_text,
)
from express.io.text_formats import column_name, csv_text, json_safe


def listing(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


# --------------------------------------------------------------------------- JSON


def test_json_safe_converts_numpy_values_and_keeps_none_as_null():
    data = {"a": np.float64(1.5), "b": np.array([1.0, 2.0]), 3: (np.int64(2), np.bool_(True), None)}
    safe = json_safe(data)
    assert safe == {"a": 1.5, "b": [1.0, 2.0], "3": [2, True, None]}
    json.dumps(safe, allow_nan=False)


@pytest.mark.parametrize(("data", "message"), [
    ({"b": np.array([1.0, np.nan])}, "result.b: not a finite number (nan) at index 1: the analysis gave no valid result"),
    ({"s": [{"v": 1.0}, {"v": float("inf")}]}, "result.s[1].v: not a finite number (inf): the analysis gave no"),
    ({"x": np.float32("-inf")}, "result.x: not a finite number (-inf)"),
])
def test_json_safe_refuses_nan_and_inf_naming_the_place(data, message):
    with pytest.raises(AnalysisError, match=re.escape(message)):
        json_safe(data)


@pytest.mark.parametrize(("columns", "message"), [
    ({"t": [0.0, 0.5, 1.0], "Q1": [1.0, np.nan, np.inf]},
     "Q1_N: not a finite number (nan) at row 2 (t_s = 0.5) (2 of 3 values): the analysis gave no valid result there; "
     "nothing written"),
    ({"t": [np.inf, 0.5], "Q1": [1.0, 2.0]}, "t_s: not a finite number (inf) at row 1: the analysis"),
])
def test_csv_text_refuses_nan_and_inf_naming_column_and_row(columns, message):
    with pytest.raises(AnalysisError, match=re.escape(message)):
        csv_text(columns, {"t": "s", "Q1": "N"})


def test_csv_text_writes_a_documented_marker_as_an_empty_cell():
    text = csv_text({"g": [0.1, 0.2], "v": [30.0, np.nan], "name": ["a", None]}, {"v": "m/s"}, markers=["v"])
    assert text == "g,v_m_s,name\n0.1,30,a\n0.2,,\n"


@pytest.mark.parametrize("writer", [npz_bytes, mat_bytes])
def test_npz_and_mat_refuse_nan_and_inf(writer):
    with pytest.raises(AnalysisError, match=re.escape("K: not a finite number (nan) at index [1, 0]")):
        writer({"dofs": np.array(["a", "b"]), "K": np.array([[1.0, 2.0], [np.nan, 1.0]])})


# --------------------------------------------------------------------------- one file


def test_write_text_creates_the_file_whole_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "sub" / "dir" / "out.txt"
    write_text(target, "line 1\nline 2\n")
    assert target.read_bytes() == b"line 1\nline 2\n"
    assert listing(target.parent) == ["out.txt"]


def test_new_file_mode_follows_the_umask_and_an_existing_mode_is_kept(tmp_path):
    previous = os.umask(0o027)
    try:
        fresh = tmp_path / "fresh.txt"
        write_text(fresh, "x")
        assert stat.S_IMODE(fresh.stat().st_mode) == 0o640
        kept = tmp_path / "kept.txt"
        kept.write_text("old")
        kept.chmod(0o664)
        write_text(kept, "new")
        assert stat.S_IMODE(kept.stat().st_mode) == 0o664 and kept.read_text() == "new"
    finally:
        os.umask(previous)


@pytest.mark.parametrize("failing", ["fsync", "replace", "chmod"])
def test_a_failure_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch, failing):
    """Whichever step fails (flush to disk, rename, permissions), the previous file is
    intact, the error is an OutputError naming the path, and no temporary is left."""
    target = tmp_path / "out.csv"
    target.write_text("old contents\n")

    def broken(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, failing, broken)
    with pytest.raises(OutputError, match=r"out\.csv.*No space left"):
        write_text(target, "new contents\n" * 1000)
    monkeypatch.undo()
    assert target.read_text() == "old contents\n"
    assert listing(tmp_path) == ["out.csv"]


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda d: (d / "out").mkdir() or d / "out", "is a directory"),
        (lambda d: (d / "plain").write_text("x") and d / "plain" / "out.csv", "plain"),
        (lambda d: str(d / "out") + os.sep, "not a file name"),
        (lambda d: "", "not a file name"),
    ],
)
def test_destinations_that_cannot_be_files_are_refused_before_writing(tmp_path, make, message):
    target = make(tmp_path)
    with pytest.raises(OutputError, match=message):
        check_destination(target)
    before = listing(tmp_path)
    with pytest.raises(OutputError):
        write_text(target, "data")
    assert listing(tmp_path) == before


def test_output_errors_are_input_errors():
    """A destination the user gave that cannot be written exits 2 like other bad input."""
    assert issubclass(OutputError, InputError) and issubclass(OutputError, ValueError)


def test_inputs_are_never_overwritten_even_through_links(tmp_path):
    model = tmp_path / "model.toml"
    model.write_text("original")
    hard = tmp_path / "hard.toml"
    os.link(model, hard)
    soft = tmp_path / "soft.toml"
    soft.symlink_to(model)
    for target in (model, hard, soft):
        with pytest.raises(OutputError, match="refusing to overwrite the input"):
            write_text(target, "clobbered", inputs=[model])
    assert model.read_text() == "original"
    assert soft.is_symlink()


def test_a_symbolic_link_is_written_through(tmp_path):
    real = tmp_path / "real.csv"
    real.write_text("old")
    link = tmp_path / "link.csv"
    link.symlink_to(real)
    write_text(link, "new")
    assert link.is_symlink() and real.read_text() == "new"


# --------------------------------------------------------------------------- special files


def test_dev_null_is_written_into_not_replaced():
    before = os.stat("/dev/null")
    write_text("/dev/null", "discarded\n" * 100)
    after = os.stat("/dev/null")
    assert stat.S_ISCHR(after.st_mode) and after.st_ino == before.st_ino and after.st_rdev == before.st_rdev


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full on this system")
def test_a_full_device_is_an_output_error_and_stays_a_device():
    with pytest.raises(OutputError, match="/dev/full"):
        write_text("/dev/full", "x" * 10000)
    assert stat.S_ISCHR(os.stat("/dev/full").st_mode)


def test_a_fifo_that_no_process_reads_is_an_error_within_the_wait_not_a_hang(tmp_path, monkeypatch):
    """Issue 36: the open of a FIFO without a reader blocked for ever."""
    monkeypatch.setattr(output, "FIFO_WAIT", 0.3)
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    started = time.monotonic()
    with pytest.raises(OutputError, match=r"pipe: a FIFO that no process opened for reading within 0\.3 s; nothing was written"):
        write_text(fifo, "nobody listens\n")
    assert time.monotonic() - started < 5
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)


def test_a_reader_that_opens_the_fifo_late_still_gets_everything(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    received = []
    reader = threading.Timer(0.5, lambda: received.append(fifo.read_bytes()))
    reader.start()
    write_text(fifo, "x" * 200_000)  # more than a pipe holds: the writes wait on the reader
    reader.join(timeout=30)
    assert received == [b"x" * 200_000]


def test_a_fifo_is_written_into_not_replaced(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    received = []
    reader = threading.Thread(target=lambda: received.append(fifo.read_bytes()))
    reader.start()
    write_text(fifo, "through the pipe\n")
    reader.join(timeout=30)
    assert received == [b"through the pipe\n"]
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert listing(tmp_path) == ["pipe"]


def test_dash_is_standard_output_for_text_and_refused_for_binary(capsysbinary):
    write_text("-", "a,b\n1,2\n")
    assert capsysbinary.readouterr().out == b"a,b\n1,2\n"
    with pytest.raises(OutputError, match="binary"):
        check_destination("-", binary=True)


# --------------------------------------------------------------------------- transactions


def test_all_or_nothing_when_a_destination_is_bad(tmp_path):
    """``-o a.csv -o blocked/b.csv``: the bad destination is found before any work and
    a.csv keeps its old contents."""
    first = tmp_path / "a.csv"
    first.write_text("old a\n")
    (tmp_path / "blocked").write_text("a file, not a directory")
    worked = []
    with pytest.raises(OutputError, match="blocked"), output_transaction() as outputs:
        outputs.declare(first)
        outputs.declare(tmp_path / "blocked" / "b.csv")
        worked.append(True)
    assert worked == []
    assert first.read_text() == "old a\n"
    assert listing(tmp_path) == ["a.csv", "blocked"]


def test_all_or_nothing_when_the_work_fails(tmp_path):
    """Outputs staged before a failure are discarded: old files intact, no temporary
    files, no directory made for them."""
    first = tmp_path / "a.csv"
    first.write_text("old a\n")
    with pytest.raises(RuntimeError), output_transaction():
        write_text(first, "new a\n")
        write_bytes(tmp_path / "new" / "deeper" / "b.png", b"\x89PNG")
        assert first.read_text() == "old a\n"  # nothing replaced before the end
        raise RuntimeError("the analysis failed")
    assert first.read_text() == "old a\n"
    assert listing(tmp_path) == ["a.csv"]


def test_a_transaction_replaces_every_output_at_the_end(tmp_path):
    with output_transaction(inputs=[]) as outputs:
        outputs.declare(tmp_path / "a.csv")
        write_text(tmp_path / "a.csv", "a\n")
        write_csv(tmp_path / "out" / "b.csv", {"t": [0.0, 1.0]}, {"t": "s"})
        assert not (tmp_path / "a.csv").exists()  # replaced only when the block ends
    assert (tmp_path / "a.csv").read_text() == "a\n"
    assert (tmp_path / "out" / "b.csv").read_text() == "t_s\n0\n1\n"
    assert listing(tmp_path) == ["a.csv", "out"]


def test_the_same_file_twice_is_refused(tmp_path):
    with pytest.raises(OutputError, match="given twice"), output_transaction() as outputs:
        outputs.declare(tmp_path / "a.csv")
        outputs.declare(tmp_path / "." / "a.csv")


def test_a_failed_rename_names_what_was_replaced(tmp_path, monkeypatch):
    """The documented window: renames are one at a time; if the second fails the first
    is already new, and the message says so."""
    first, second = tmp_path / "a.csv", tmp_path / "b.csv"
    first.write_text("old a\n")
    second.write_text("old b\n")
    real_replace = os.replace
    calls = []

    def replace_once(source, target):
        calls.append(target)
        if len(calls) == 2:
            raise OSError(5, "Input/output error")
        real_replace(source, target)

    monkeypatch.setattr(os, "replace", replace_once)
    with pytest.raises(OutputError, match=r"already replaced: .*a\.csv"), output_transaction():
        write_text(first, "new a\n")
        write_text(second, "new b\n")
    assert first.read_text() == "new a\n" and second.read_text() == "old b\n"
    assert listing(tmp_path) == ["a.csv", "b.csv"]


# --------------------------------------------------------------------------- concurrency


def _writer(path: str, label: int, rounds: int) -> None:
    payload = (f"{label:04d}," * 50_000 + "\n").encode()
    for _ in range(rounds):
        write_bytes(path, payload)


def test_concurrent_writers_of_one_path_end_with_one_complete_file(tmp_path):
    """Several processes write one path at the same time (a shell loop with ``&``):
    every read sees one writer's complete file, the end state is complete, and no
    temporary file is left."""
    target = tmp_path / "shared.csv"
    context = multiprocessing.get_context("spawn")
    writers = [context.Process(target=_writer, args=(str(target), label, 15)) for label in range(4)]
    for process in writers:
        process.start()
    seen = set()
    while any(p.is_alive() for p in writers):
        if target.exists():
            data = target.read_bytes()
            labels = set(data.decode().rstrip("\n").split(",")) - {""}
            assert len(labels) == 1 and len(data) == 250_001, "a reader saw a mixed or partial file"
            seen |= labels
    for process in writers:
        process.join(timeout=120)
        assert process.exitcode == 0
    final = target.read_bytes()
    assert len(final) == 250_001 and len(set(final.decode().rstrip("\n").split(",")) - {""}) == 1
    assert listing(tmp_path) == ["shared.csv"]


# --------------------------------------------------------------------------- formats


@pytest.mark.parametrize(
    "name, unit, header",
    [
        ("time", "s", "time_s"),
        ("Q1", "N", "Q1_N"),
        ("frequency", "Hz", "frequency_hz"),
        ("floor_acc_amplitude", "m/s^2", "floor_acc_amplitude_m_s2"),
        ("W1.y_dot", "m/s", "W1.y_dot_m_s"),
        ("rho1", "1/m", "rho1_1_m"),
        ("phase", "deg", "phase_deg"),
        ("k", "N*m/rad", "k_Nm_rad"),
        ("QP1", "", "QP1"),
        ("Gamma", None, "Gamma"),
    ],
)
def test_column_names_carry_the_unit(name, unit, header):
    assert column_name(name, unit) == header


def test_csv_text_is_deterministic_and_round_trips():
    time = np.linspace(0.0, 1.0, 7)
    columns = {"time": time, "Q1": 1e4 * np.sin(time), "label": ["a"] * 7}
    text = csv_text(columns, {"time": "s", "Q1": "N"})
    assert text == csv_text(columns, {"time": "s", "Q1": "N"})
    lines = text.splitlines()
    assert lines[0] == "time_s,Q1_N,label"
    data = np.loadtxt(io.StringIO(text), delimiter=",", skiprows=1, usecols=(0, 1))
    np.testing.assert_allclose(data[:, 1], columns["Q1"], rtol=1e-8)
    with pytest.raises(ValueError, match="different lengths"):
        csv_text({"a": [1, 2], "b": [1]})


@pytest.mark.parametrize("compress", [False, True])
def test_npz_and_mat_bytes_are_deterministic_and_load_back(compress):
    from scipy.io import loadmat

    arrays = {"t": np.linspace(0, 1, 5), "K": np.arange(4.0).reshape(2, 2)}
    first = npz_bytes(arrays, compress=compress)
    assert first == npz_bytes(arrays, compress=compress)
    with np.load(io.BytesIO(first)) as stored:
        np.testing.assert_array_equal(stored["K"], arrays["K"])
    mat = mat_bytes(arrays, compress=compress)
    assert mat == mat_bytes(arrays, compress=compress)
    assert mat.startswith(archives.MAT_HEADER)
    np.testing.assert_array_equal(np.ravel(loadmat(io.BytesIO(mat))["t"]), arrays["t"])


def test_npz_compress_deflates_the_members():
    """``compress=True`` deflates (it stored the members as they were until the members were
    streamed: a ZipInfo given to ``writestr`` keeps its own ZIP_STORED)."""
    import zipfile

    arrays = {"x": np.zeros(10_000), "K": np.ones((50, 50))}
    stored, deflated = npz_bytes(arrays), npz_bytes(arrays, compress=True)
    with zipfile.ZipFile(io.BytesIO(deflated)) as archive:
        assert {info.compress_type for info in archive.infolist()} == {zipfile.ZIP_DEFLATED}
    with zipfile.ZipFile(io.BytesIO(stored)) as archive:
        assert {info.compress_type for info in archive.infolist()} == {zipfile.ZIP_STORED}
    assert len(deflated) < len(stored) / 20
    with np.load(io.BytesIO(deflated)) as back:
        np.testing.assert_array_equal(back["K"], arrays["K"])


def test_inputs_found_during_the_work_are_protected(tmp_path):
    """A file read once the work started (a profile named by a track) may not be one of
    the declared destinations, nor be written afterwards."""
    profile = tmp_path / "profile.csv"
    profile.write_text("0,0\n1,0.001\n")
    with pytest.raises(OutputError, match="refusing"), output_transaction() as outputs:
        outputs.declare(profile)
        outputs.add_inputs([profile])
    with pytest.raises(OutputError, match="refusing"), output_transaction() as outputs:
        outputs.add_inputs([profile])
        write_text(profile, "clobbered")
    assert profile.read_text() == "0,0\n1,0.001\n"
