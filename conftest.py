"""Test-session settings for the whole tree (tests/ and the doctests in src/).

The derivation cache (``docs/cache.md``) goes to a fresh temporary folder for the
session, so that the tests never read or fill a real user's cache; tests that compare
outputs make their own folders.
"""

from __future__ import annotations

import os
import shutil
import tempfile

_FOLDER = tempfile.mkdtemp(prefix="express-test-cache-")


def pytest_configure(config):
    os.environ["EXPRESS_CACHE_DIR"] = _FOLDER
    os.environ.pop("EXPRESS_NO_CACHE", None)


def pytest_unconfigure(config):
    shutil.rmtree(_FOLDER, ignore_errors=True)
