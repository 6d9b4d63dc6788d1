"""The compiled kernels without reference counting (express.base.kernels): the same
results bit for bit as Numba's plain ``njit``, and an allocating kernel refused."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from numba import njit

from express.base.kernels import KERNEL_OPTIONS, kernel


def test_kernel_options_turn_the_runtime_off_and_cache():
    assert KERNEL_OPTIONS == {"cache": True, "_nrt": False}


def _rows(table, row, out):
    for i in range(table.shape[1]):
        out[i] = table[row, i] * 2.0 + np.sqrt(abs(table[row, i]))


def test_kernel_matches_njit_bit_for_bit():
    """A kernel's arithmetic is that of njit: identical bits (tolerance 0)."""
    table = np.random.default_rng(3).normal(size=(4, 7))
    plain, fast = np.zeros(7), np.zeros(7)
    njit(_rows)(table, 2, plain)
    kernel(_rows)(table, 2, fast)
    assert plain.tobytes() == fast.tobytes()


def _allocates(n):
    return np.zeros(n)


def test_an_allocating_kernel_is_refused():
    """A kernel must not allocate (module docstring): Numba refuses to compile it."""
    from numba.core.errors import TypingError

    with pytest.raises(TypingError, match="zeros"):
        kernel(_allocates)(3)


def test_the_contact_kernel_matches_njit_bit_for_bit():
    """The wheelset kernel compiled as a kernel and as plain njit (its Python source; the
    helpers it calls are the same kernels in both) give the same forces, bit for bit,
    across the flange (regression of the switch to kernels:
    the ~20 simulate outputs of the Y25 wagon and the Manchester car were identical too,
    checked by hash when the switch was made)."""
    from express.io import parse_toml_model
    from express.numeric.statespace import vehicle_model
    from express.rail.contact_forces import OUTPUTS, WORK_FIELDS, contact_set, profile_wheelset_forces
    from express.rail.profile_contact import wheelset_contacts

    path = Path(__file__).resolve().parents[1] / "examples" / "manchester-s1002.toml"
    vehicle = vehicle_model(parse_toml_model(path.read_text(), str(path)))
    contacts = contact_set(wheelset_contacts(vehicle.model, vehicle.values, vehicle.wheelsets)[:1])
    plain_kernel = njit(profile_wheelset_forces.py_func)
    for y in np.linspace(-9e-3, 9e-3, 13):
        plain, fast = np.zeros(len(OUTPUTS)), np.zeros(len(OUTPUTS))
        for function, out in ((plain_kernel, plain), (profile_wheelset_forces, fast)):
            function(contacts, 0, 60e3, 55e3, float(y), 2e-3, 0.01, 0.002, 1 / 800, 40.0,
                     np.zeros((2, len(WORK_FIELDS))), out)
        assert plain.tobytes() == fast.tobytes(), y
