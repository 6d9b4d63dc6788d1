"""The public entry point: ``import express`` gives the names a user needs, lazily (nothing
numerical is imported until a name is used), and every public function documents every
argument in its numpydoc ``Parameters`` section (as python-control's docstring test does)."""

from __future__ import annotations

import dataclasses
import inspect
import re
import subprocess
import sys

import pytest

import express

FUNCTIONS = [name for name in express.__all__ if name != "__version__" and inspect.isfunction(getattr(express, name))]
CLASSES = [name for name in express.__all__ if inspect.isclass(getattr(express, name))]


def test_import_express_loads_nothing_numerical():
    """``import express`` alone imports neither NumPy, SymPy nor any stage package."""
    code = ("import sys, express; heavy = [m for m in ('numpy', 'sympy', 'scipy', 'express.analysis', 'express.io') "
            "if m in sys.modules]; print(heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_every_public_name_resolves_to_its_stage():
    for name in express.__all__:
        value = getattr(express, name)
        module = getattr(value, "__module__", "express")
        assert module.startswith("express"), (name, module)
    assert set(express.__all__) <= set(dir(express))
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        express.nothing  # noqa: B018


def documented(docstring: str, section: str) -> set[str]:
    """The names a numpydoc ``section`` (``Parameters``, ``Attributes``) documents."""
    lines = inspect.cleandoc(docstring or "").splitlines()
    names: set[str] = set()
    previous = ""
    for start, line in enumerate(lines[:-1]):
        if line.strip() == section and set(lines[start + 1].strip()) == {"-"}:
            for entry in lines[start + 2:]:
                if entry and not entry.startswith(" "):
                    if re.fullmatch(r"-{3,}", entry.strip()):
                        names.discard(previous)
                        break
                    previous = re.split(r"\s*:(?:\s|$)", entry, maxsplit=1)[0].strip()
                    names.update(part.strip().lstrip("*") for part in previous.split(","))
    return names


def test_documented_reads_numpydoc():
    doc = """Summary.

    Parameters
    ----------
    a, b : float
        Two.
    **options
        More.

    Returns
    -------
    int
    """
    assert documented(doc, "Parameters") == {"a", "b", "options"}


@pytest.mark.parametrize("name", FUNCTIONS)
def test_public_function_documents_every_argument(name):
    function = getattr(express, name)
    arguments = [p for p in inspect.signature(function).parameters if p not in ("self", "cls")]
    missing = [a for a in arguments if a not in documented(function.__doc__, "Parameters")]
    assert not missing, f"{function.__module__}.{function.__qualname__}: Parameters does not document {missing}"


@pytest.mark.parametrize("name", [n for n in CLASSES if dataclasses.is_dataclass(getattr(express, n))])
def test_public_record_documents_every_field(name):
    record = getattr(express, name)
    fields = [f.name for f in dataclasses.fields(record) if not f.name.startswith("_")]
    missing = [f for f in fields if f not in documented(record.__doc__, "Attributes")]
    assert not missing, f"{record.__module__}.{record.__qualname__}: Attributes does not document {missing}"


#: The result records reachable from ``express.`` (issue 35 item 2): each is data.
RESULT_RECORDS = ["CriticalSpeed", "EigenResult", "FrequencyResponse", "NonlinearCriticalSpeed", "RideResponse",
                  "SimulationResult", "SteadyCurving", "SteadyCurvingSensitivity", "TimeRunSensitivity"]


@pytest.mark.parametrize("name", RESULT_RECORDS)
def test_result_records_are_public_and_are_data(name):
    record = getattr(express, name)
    assert name in express.__all__ and inspect.isclass(record)
    for method in ("to_xarray", "to_pandas", "_repr_html_", "__repr__"):
        assert callable(getattr(record, method, None)), (name, method)
    assert record.__repr__ is not object.__repr__
