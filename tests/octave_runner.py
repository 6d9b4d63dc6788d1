"""Test helpers: run generated MATLAB files in GNU Octave and evaluate matrices with SymPy.

Reusable by any test that checks exported MATLAB code against the symbolic matrices:

* :func:`find_octave` / :func:`require_octave`: locate ``octave-cli`` (or ``octave``);
  ``require_octave`` skips the test when Octave is missing, except when the environment
  variable ``CI`` is set (non-empty), where it fails: CI installs Debian's ``octave``.
* :func:`run_octave`: call the function of a ``.m`` file with a parameter struct and
  read back every output matrix at full double precision.
* :func:`evaluate_matrices`: the reference values, by SymPy substitution.
* :func:`assert_matrices_close`: compare two such dicts.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

OCTAVE_EXECUTABLES = ("octave-cli", "octave")

_FUNCTION = re.compile(
    r"^\s*function\s+(?:\[(?P<outs>[^\]]*)\]|(?P<out>\w+))\s*=\s*(?P<name>\w+)\s*\(", re.M
)


def find_octave() -> str | None:
    """Path of ``octave-cli`` (preferred) or ``octave``, or None when neither is on PATH."""
    for exe in OCTAVE_EXECUTABLES:
        path = shutil.which(exe)
        if path:
            return path
    return None


def require_octave() -> str:
    """Return the Octave executable, or skip the test (fail it when ``CI`` is set).

    Returns
    -------
    str
        Path of the executable.
    """
    path = find_octave()
    if path is None:
        if os.environ.get("CI", ""):
            pytest.fail(
                "GNU Octave is required in CI (CI is set) but neither octave-cli nor "
                "octave is on PATH; install it, e.g. `apt-get install -y octave`"
            )
        pytest.skip("GNU Octave (octave-cli or octave) is not installed")
    return path


def _quote(text: str) -> str:
    return "'" + str(text).replace("'", "''") + "'"


def _number(value: float) -> str:
    value = float(value)
    if value != value:
        return "NaN"
    if value in (float("inf"), float("-inf")):
        return "Inf" if value > 0 else "-Inf"
    return repr(value)


def function_signature(mfile: str | os.PathLike) -> tuple[str, list[str]]:
    """Read the function name and output names of a MATLAB function file.

    Parameters
    ----------
    mfile : path-like
        The ``.m`` file.

    Returns
    -------
    (str, list of str)
        Function name and output names.
    """
    text = Path(mfile).read_text(encoding="utf-8")
    match = _FUNCTION.search(text)
    if match is None:
        raise ValueError(f"{mfile}: no function line found")
    outs = match.group("outs")
    names = [o.strip() for o in re.split(r"[,\s]+", outs) if o.strip()] if outs else [
        match.group("out")
    ]
    return match.group("name"), names


def run_octave(
    mfile: str | os.PathLike,
    values: Mapping[str, float] | None,
    *,
    octave: str | None = None,
    timeout: float = 300.0,
) -> dict[str, np.ndarray]:
    """Call the function of a MATLAB file in Octave and return its output matrices.

    Parameters
    ----------
    mfile : path-like
        Function file; it must be named ``<function name>.m``.
    values : Mapping[str, float] or None
        Fields of the parameter struct ``p`` passed to the function; None calls the
        function without argument (its default values).
    octave : str, optional
        Octave executable; :func:`find_octave` by default.
    timeout : float, optional
        Seconds before giving up.

    Returns
    -------
    dict of str to numpy.ndarray
        Every output of the function, by output name, as float arrays; a struct output
        ``values`` of scalars gives one 1 x 1 array per field, ``"values.<field>"``.

    Raises
    ------
    RuntimeError
        If Octave is missing, fails, or prints something unexpected.
    """
    mfile = Path(mfile).resolve()
    name, outputs = function_signature(mfile)
    if mfile.stem != name:
        raise ValueError(f"{mfile.name} defines {name}; MATLAB needs the file {name}.m")
    exe = octave or find_octave()
    if exe is None:
        raise RuntimeError("GNU Octave is not installed")
    lines = [f"addpath({_quote(mfile.parent)});"]
    if values is None:
        lines.append(f"[{', '.join(outputs)}] = {name}();")
    else:
        lines.append("p__ = struct();")
        lines += [f"p__.({_quote(k)}) = {_number(v)};" for k, v in sorted(values.items())]
        lines.append(f"[{', '.join(outputs)}] = {name}(p__);")
    for out in outputs:
        lines += [
            f"if isstruct({out})",  # a struct of scalars: one 1 x 1 result per field
            f"  for f__ = fieldnames({out})'",
            f"    fprintf('@@ %s.%s 1 1\\n', {_quote(out)}, f__{{1}}); fprintf('%.17g\\n', {out}.(f__{{1}}));",
            "  end",
            "else",
            f"if ~isreal({out}) || ~isnumeric({out}), error('{out} is not real'); end",
            f"fprintf('@@ %s %d %d\\n', {_quote(out)}, size({out}, 1), size({out}, 2));",
            f"fprintf('%.17g\\n', full({out}).');",
            "end",
        ]
    with tempfile.TemporaryDirectory(prefix="express-octave-") as tmp:
        driver = Path(tmp) / "express_driver.m"
        driver.write_text("\n".join(lines) + "\n", encoding="utf-8")
        proc = subprocess.run(
            [exe, "--no-gui", "--norc", "--quiet", "--no-window-system",
             "--eval", f"source({_quote(driver)})"],
            cwd=tmp,
            capture_output=True,
            text=True,
            timeout=timeout,
        )
    if proc.returncode != 0:
        raise RuntimeError(
            f"octave failed (exit {proc.returncode}) on {mfile.name}:\n"
            f"{proc.stdout}\n{proc.stderr}"
        )
    return _parse(proc.stdout, outputs)


def _parse(stdout: str, outputs: list[str]) -> dict[str, np.ndarray]:
    result: dict[str, np.ndarray] = {}
    tokens = stdout.split("\n")
    k = 0
    while k < len(tokens):
        line = tokens[k].strip()
        k += 1
        if not line.startswith("@@ "):
            continue
        _, name, rows, cols = line.split()
        rows, cols = int(rows), int(cols)
        numbers = [float(tokens[k + i]) for i in range(rows * cols)]
        k += rows * cols
        result[name] = np.array(numbers, dtype=float).reshape(rows, cols)
    missing = [o for o in outputs if o not in result and not any(k.startswith(o + ".") for k in result)]
    if missing:
        raise RuntimeError(f"octave printed no value for {missing}:\n{stdout}")
    return result


def evaluate_matrices(eom, values: Mapping[str, float] | None = None) -> dict[str, np.ndarray]:
    """Reference values of the matrices of a record: SymPy substitution at 30 digits.

    Parameters
    ----------
    eom : EquationsOfMotion
        The record.
    values : Mapping[str, float], optional
        Parameter values by name; ``eom.values`` by default.

    Returns
    -------
    dict of str to numpy.ndarray
        Every matrix of ``eom.matrices`` as float arrays.
    """
    values = eom.values if values is None else values
    result = {}
    for key, mat in eom.matrices.items():
        mat = sp.ImmutableMatrix(mat)
        subs = {s: sp.Float(float(values[s.name]), 30) for s in mat.free_symbols}
        num = mat.xreplace(subs).evalf(30)
        result[key] = np.array(
            [[float(num[i, j]) for j in range(mat.cols)] for i in range(mat.rows)], dtype=float
        ).reshape(mat.rows, mat.cols)
    return result


def assert_matrices_close(
    actual: Mapping[str, np.ndarray],
    expected: Mapping[str, np.ndarray],
    rtol: float = 1e-12,
) -> None:
    """Assert both dicts hold the same matrices to relative tolerance ``rtol``.

    The tolerance is relative to each matrix's largest entry (``atol = rtol * max|A|``),
    so entries that cancel to (near) zero do not fail spuriously.
    """
    assert sorted(actual) == sorted(expected), (sorted(actual), sorted(expected))
    for key in expected:
        a, e = np.asarray(actual[key]), np.asarray(expected[key])
        assert a.shape == e.shape, (key, a.shape, e.shape)
        scale = float(np.max(np.abs(e))) if e.size else 0.0
        np.testing.assert_allclose(a, e, rtol=rtol, atol=rtol * scale, err_msg=key)
