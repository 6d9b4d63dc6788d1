"""The readable generation of a model file, through the derivation cache.

``express generate`` and the exporters need the factored, readable matrices
(:func:`express.assembly.generator.generate`); :func:`load_generation` derives them once
per set of input files and options and reads them back afterwards
(:mod:`express.io.cache`, ``docs/cache.md``); a fresh derivation is read back from its
entry too, so that every path prints the same form.  ``--set`` overrides are applied after
the cache: they change the values, units and derivation steps, never the matrices.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path

from express.assembly.generator import GenerationResult

__all__ = ["load_generation"]


def load_generation(
    path: str | Path, overrides: Mapping[str, float | str] | None = None, *, keep_virtual: bool = False,
    with_rail: bool = True,
) -> GenerationResult:
    """The readable equations of a model file, with ``overrides`` applied.

    Parameters
    ----------
    path : str or Path
        Model file (classic ``.exp`` or modern ``.toml``).
    overrides : mapping of str to float or str, optional
        Parameter values as for :func:`express.numeric.statespace.load_vehicle`.
    keep_virtual : bool
        Keep the virtual DOFs (the paper's eq. 6).
    with_rail : bool
        Include the wheel/rail and curve terms when the model has rail data.

    Raises
    ------
    ModelError
        For a bad file or override, an invalid model (every problem at once).

    Examples
    --------
    >>> load_generation("examples/lever.exp").equations.K[0, 0]
    b**2*(kLL + kLU)
    """
    from express.base.reads import recorded_reads
    from express.io import load_model
    from express.io.cache import entry_damaged, entry_key, read_entry
    from express.model.parameters import with_values
    from express.numeric.derived import read_generation_entry
    from express.numeric.program import ProgramError
    from express.rail.build import generate_vehicle

    with recorded_reads() as reads:
        model = load_model(Path(path))
    key = entry_key("generation", reads, {"keep_virtual": keep_virtual, "with_rail": with_rail})
    result = None
    payload = read_entry(key)
    if payload is not None:
        try:
            result = read_generation_entry(payload, model)
        except ProgramError:
            entry_damaged(key)
    if result is None:
        result = _through_entry(generate_vehicle(model, keep_virtual=keep_virtual, with_rail=with_rail), model, key)
    if not overrides:
        return result
    return _with_overrides(result, with_values(model, overrides))


def _through_entry(derived: GenerationResult, model, key: str) -> GenerationResult:
    """A fresh derivation stored under ``key`` and read back from its entry, so that a
    cold cache and ``--no-cache`` give the matrices in the warm cache's form.

    The entry's program (:func:`sympy.cse`) keeps the values but not always the form:
    it takes the minus sign out of a sum, ``2*c*(-h + k)`` comes back as
    ``-2*c*(h - k)`` where ``h - k`` also occurs elsewhere.  Reading every path's result
    from the entry makes the exports byte-identical; an entry with a function (it
    cannot be stored) is derived every time and used as derived.
    """
    from express.io.cache import write_entry
    from express.numeric.derived import generation_entry, read_generation_entry
    from express.numeric.program import UnsupportedExpressionError

    try:
        entry = generation_entry(derived)
    except UnsupportedExpressionError:
        return derived
    write_entry(key, entry)
    return read_generation_entry(entry, model)


def _with_overrides(result: GenerationResult, model) -> GenerationResult:
    """``result`` with the values, units and derivation steps of ``model``."""
    from express.assembly.equations import derivation_steps
    from express.assembly.generator import equation_values

    values, units = equation_values(model, result.equations.parameters)
    equations = replace(result.equations, values=values, units=units, derivation=derivation_steps(model))
    return replace(result, equations=equations)
