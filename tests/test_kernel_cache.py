"""Numba's compiled kernels go to a writable folder (express.base.kernel_cache, docs/cache.md)."""

from __future__ import annotations

from pathlib import Path

from express.base.kernel_cache import configure_kernel_cache


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
