"""Reading and writing: the model readers (classic, paper Fig. 5, and TOML with substructures),
the TOML writer, and :mod:`.output`, the one writer of every output (whole or not at all).

The readers (and SymPy with them) are imported on first use: a command that only
writes, or reads a model from the derivation cache, does not load them.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import TYPE_CHECKING, Any

from express.base.diagnostics import ModelError, Problem
from express.base.limits import input_kind_problem

if TYPE_CHECKING:
    from express.io.classic import parse_classic, read_classic
    from express.io.toml_model import parse_toml_model, read_toml_model
    from express.io.toml_writer import model_to_toml
    from express.model.records import Model

__all__ = ["load_model", "model_to_toml", "parse_classic", "parse_toml_model", "read_classic", "read_toml_model"]

#: Name -> the module it is read from on first use (PEP 562).
_LAZY = {
    "parse_classic": "express.io.classic",
    "read_classic": "express.io.classic",
    "parse_toml_model": "express.io.toml_model",
    "read_toml_model": "express.io.toml_model",
    "model_to_toml": "express.io.toml_writer",
}


def __getattr__(name: str) -> Any:
    """A reader or the writer, imported on first use."""
    if name not in _LAZY:
        raise AttributeError(f"module 'express.io' has no attribute {name!r}")
    value = getattr(importlib.import_module(_LAZY[name]), name)
    globals()[name] = value
    return value


def load_model(path: str | Path) -> Model:
    """Read a model file: ``.toml`` is the modern format, anything else the classic one.

    Parameters
    ----------
    path : str or Path
        The model file.

    Returns
    -------
    Model

    Raises
    ------
    ModelError
        For a missing, unreadable or malformed file (every problem at once).
    """
    path = Path(path)
    kind = "file does not exist" if not path.exists() else input_kind_problem(path)
    if kind is not None:
        raise ModelError([Problem(str(path), None, "", kind)])
    if path.suffix.lower() == ".toml":
        from express.io.toml_model import read_toml_model

        return read_toml_model(path)
    from express.io.classic import read_classic

    return read_classic(path)
