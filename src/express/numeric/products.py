"""What a command makes from a model's files alone, kept in the derivation cache.

Some products of a model depend only on its files and a few options — an export's text,
the drawing's geometry — yet making them again means reading the model file into its
SymPy records (a 100-car train: 6 s) before the work itself.  :func:`cached_product`
stores such a product as data, found by the model file's bytes, the product's kind and
its options, and used only while every file the first run read still has its recorded
SHA-256 (as the warm vehicle entry, :mod:`express.numeric.warm`).  The warnings the
first run gave are kept and given again, the model file named as the later run names it.

The product is data (JSON) read back by the kind's own checked decoder, never run.
Callers use it only without ``--set`` overrides (``docs/cache.md``).
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

from express.io.cache import cache_enabled, entry_damaged, entry_key, read_entry, write_entry
from express.numeric.program import ProgramError, checked_list, checked_strings
from express.numeric.warm import file_digest, read_warning_items, repeat_warnings, unchanged, warning_items

__all__ = ["cached_product"]

T = TypeVar("T")


def cached_product(path: str | Path, kind: str, options: dict[str, Any], make: Callable[[], T],
                   encode: Callable[[T], tuple[str, Any]], decode: Callable[[Any], T]) -> T:
    """The product ``kind`` of the model file ``path``: from the cache, or ``make()`` stored.

    Parameters
    ----------
    path : str or Path
        The model file, as the command was given it (warnings name it so).
    kind : str
        What the product is (``"export text"``, ``"drawing geometry"``): part of the key.
    options : dict
        Everything besides the files that shapes the product (JSON-able).
    make : callable
        Makes the product (reads the model); the warnings it gives are recorded and given
        again by every later use.
    encode : callable
        ``product -> (name, data)``: the name ``express cache info`` lists the entry under,
        and the product as JSON-able data; raises ProgramError for a product that cannot
        be stored (it is then made by every run).
    decode : callable
        ``data -> product``; raises :class:`~express.numeric.program.ProgramError` for data
        that does not check (the entry is then ignored with one warning and made anew).

    Returns
    -------
    The product, the same whether made now or read back.
    """
    key = _key(path, kind, options) if cache_enabled() else None
    if key is None:
        return make()
    found = _read(key, kind, str(path), decode)
    if found is not None:
        return found[0]
    from express.base.reads import recorded_reads

    with recorded_reads() as reads, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        product = make()
    for warning in caught:
        warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno, source=warning.source)
    items = warning_items(caught)
    if items is not None and reads:
        try:
            name, data = encode(product)
        except ProgramError:  # a product that cannot be stored as data: made every time
            return product
        write_entry(key, {"name": name, "kind": kind, "reads": [list(read) for read in reads], "source": str(path),
                          "warnings": items, "data": data})
    return product


def _key(path: str | Path, kind: str, options: dict[str, Any]) -> str | None:
    digest = file_digest(os.fspath(path))
    if digest is None:  # a pipe or an unreadable file: read once, by the model reader
        return None
    return entry_key(kind, [(os.path.abspath(path), digest)], options)


def _read(key: str, kind: str, source: str, decode: Callable[[Any], T]) -> tuple[T] | None:
    """``(product,)`` of the entry with its warnings given again; None when there is none,
    a file it lists changed (made anew), or it is damaged (one warning, made anew)."""
    payload = read_entry(key)
    if payload is None:
        return None
    try:
        if not isinstance(payload, dict) or payload.get("kind") != kind:
            raise ProgramError(f"not a {kind} entry")
        listed = checked_list(payload.get("reads"))
        reads = [(r[0], r[1]) for r in listed if len(checked_strings(r)) == 2]
        if not reads or len(reads) != len(listed):
            raise ProgramError("bad reads")
        messages = read_warning_items(payload.get("warnings"))
        recorded = payload.get("source")
        if not isinstance(recorded, str):
            raise ProgramError("bad source")
        product = decode(payload.get("data"))
    except ProgramError:
        entry_damaged(key)
        return None
    if not unchanged(reads):
        return None
    repeat_warnings(messages, recorded, source)
    return (product,)
