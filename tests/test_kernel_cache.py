"""Numba's compiled kernels go to a writable folder (express.base.kernel_cache, docs/cache.md)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from express.base.kernel_cache import compilation_note, configure_kernel_cache


def test_a_read_only_package_sends_the_kernels_to_the_express_cache(tmp_path):
    environ = {"EXPRESS_CACHE_DIR": str(tmp_path / "cache")}
    read_only = tmp_path / "not writable"  # a folder that cannot be written (absent: os.access is False, even for root)
    assert configure_kernel_cache(read_only, environ) == str(tmp_path / "cache" / "numba")
    assert environ["NUMBA_CACHE_DIR"] == str(tmp_path / "cache" / "numba")


def test_a_given_numba_cache_dir_is_kept(tmp_path):
    environ = {"EXPRESS_CACHE_DIR": str(tmp_path / "cache"), "NUMBA_CACHE_DIR": "/somewhere"}
    assert configure_kernel_cache(tmp_path / "not writable", environ) is None
    assert environ["NUMBA_CACHE_DIR"] == "/somewhere"


def test_a_writable_package_keeps_numbas_own_pycache(tmp_path):
    package = tmp_path / "express"
    (package / "__pycache__").mkdir(parents=True)
    environ: dict[str, str] = {}
    assert configure_kernel_cache(package, environ) is None
    assert "NUMBA_CACHE_DIR" not in environ


def test_the_installed_package_is_checked_by_default():
    """Run from a checkout, the package folder is writable: nothing changes."""
    environ: dict[str, str] = {}
    package = Path(__file__).resolve().parents[1] / "src" / "express"
    assert configure_kernel_cache(package, environ) is None


@pytest.mark.slow
def test_the_first_run_says_what_it_compiled_and_the_second_says_nothing(tmp_path):
    """An empty Numba cache (a fresh install): the first ``conicity`` compiles its kernels
    and says so once; the second loads them and prints no note."""
    env = {k: v for k, v in os.environ.items() if k != "EXPRESS_COMPILE_NOTE"}
    env.update(NUMBA_CACHE_DIR=str(tmp_path / "numba"), EXPRESS_CACHE_DIR=str(tmp_path / "cache"),
               PYTHONPATH=str(Path(__file__).resolve().parents[1] / "src"))
    command = [sys.executable, "-m", "express", "conicity", "S1002", "60E1"]
    first, second = (subprocess.run(command, capture_output=True, text=True, env=env, timeout=900) for _ in range(2))
    assert first.returncode == second.returncode == 0, first.stderr
    (note,) = [line for line in first.stderr.splitlines() if line.startswith("note: compiled")]
    assert re.search(r"compiled \d+ Numba kernels in this run \(\d+ s for the whole command\), once per "
                     r"installation: they are kept in .*numba", note)
    assert "compiled" not in second.stderr
    assert first.stdout == second.stdout


def test_the_note_can_be_switched_off():
    assert compilation_note(12.0, {"EXPRESS_COMPILE_NOTE": "0"}) is None
