"""Reading and writing: the model readers (classic, paper Fig. 5, and TOML with substructures),
the TOML writer, and :mod:`.output`, the one writer of every output (whole or not at all)."""

from __future__ import annotations

from pathlib import Path

from express.base.diagnostics import ModelError, Problem
from express.base.limits import input_kind_problem
from express.io.classic import parse_classic, read_classic
from express.io.toml_model import parse_toml_model, read_toml_model
from express.io.toml_writer import model_to_toml
from express.model.records import Model

__all__ = ["load_model", "model_to_toml", "parse_classic", "parse_toml_model", "read_classic", "read_toml_model"]


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
        return read_toml_model(path)
    return read_classic(path)
