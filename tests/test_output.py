"""Shared output helpers: JSON-safe conversion."""

import json

import numpy as np

from express.io.output import json_safe


def test_json_safe_converts_numpy_and_non_finite_values():
    data = {"a": np.float64(1.5), "b": np.array([1.0, np.nan]), 3: (np.int64(2), np.bool_(True), float("inf"))}
    safe = json_safe(data)
    assert safe == {"a": 1.5, "b": [1.0, None], "3": [2, True, None]}
    json.dumps(safe, allow_nan=False)
