"""The one way EXPRESS suggests a valid name for a mistyped one.

Every option and key that takes a name (``--set``, ``--parameter``, ``--dof``,
``--output``, ``--track``, study keys, track classes) says ``did you mean X?`` through
:func:`did_you_mean`, so that the same slip gets the same hint everywhere.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterable

__all__ = ["closest_name", "did_you_mean", "is_valid_name"]

#: Similarity (difflib ratio) below which no name is suggested.
CUTOFF = 0.6


def closest_name(name: str, known: Iterable[str]) -> str | None:
    """The valid name closest to ``name``, or None.

    In order: the same name in another case; the one name that ``name`` begins or that
    begins with ``name`` (``Gamma`` -> ``Gamma_e``); the most similar name
    (:func:`difflib.get_close_matches`, cutoff :data:`CUTOFF`), then the same ignoring case.

    Examples
    --------
    >>> closest_name("Gamma", ["Gamma_e", "g", "mc"])
    'Gamma_e'
    >>> closest_name("cyw", ["cyaw", "cy2"])
    'cyaw'
    >>> closest_name("MC", ["mc", "mt"]), closest_name("zzz", ["mc"])
    ('mc', None)
    """
    choices = sorted({str(k) for k in known})
    if not name or not choices:
        return None
    folded = [k for k in choices if k.lower() == name.lower()]
    if folded:
        return folded[0]
    lower = name.lower()
    prefixed = [k for k in choices if k.lower().startswith(lower) or lower.startswith(k.lower())]
    if len(prefixed) == 1 and min(len(prefixed[0]), len(name)) >= 2:
        return prefixed[0]
    close = difflib.get_close_matches(name, choices, n=1, cutoff=CUTOFF)
    if close:
        return close[0]
    by_lower = {k.lower(): k for k in reversed(choices)}
    close = difflib.get_close_matches(lower, list(by_lower), n=1, cutoff=CUTOFF)
    return by_lower[close[0]] if close else None


def did_you_mean(name: str, known: Iterable[str]) -> str:
    """``"; did you mean X?"`` for the closest valid name (:func:`closest_name`), or ``""``.

    Examples
    --------
    >>> "unknown DOF 'CB.yy'" + did_you_mean("CB.yy", ["CB.y", "CB.rz"])
    "unknown DOF 'CB.yy'; did you mean CB.y?"
    """
    close = closest_name(name, known)
    return f"; did you mean {close}?" if close else ""


_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


def is_valid_name(name: str) -> bool:
    """Whether ``name`` can be a parameter name (letter first, then letters, digits, ``_``)."""
    return bool(_NAME.match(name))
