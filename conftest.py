"""Test-session settings for the whole tree (tests/ and the doctests in src/).

The derivation cache (``docs/cache.md``) goes to a fresh temporary folder for the
session, so that the tests never read or fill a real user's cache; tests that compare
outputs make their own folders.  The note on Numba kernels compiled by a first run is
left out (``EXPRESS_COMPILE_NOTE=0``): which test runs first on a fresh machine would
otherwise change what one command prints; ``tests/test_kernel_cache.py`` turns it on.
"""

from __future__ import annotations

import os
import shutil
import tempfile

_FOLDER = tempfile.mkdtemp(prefix="express-test-cache-")


def pytest_configure(config):
    os.environ["EXPRESS_CACHE_DIR"] = _FOLDER
    os.environ["EXPRESS_COMPILE_NOTE"] = "0"  # a fresh machine's first command would print it
    os.environ.pop("EXPRESS_NO_CACHE", None)


def pytest_unconfigure(config):
    shutil.rmtree(_FOLDER, ignore_errors=True)
