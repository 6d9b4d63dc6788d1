"""Limits on the work an input file may ask for, checked before the work starts.

A model file is data, and it may come from someone else: a few lines of text must
not be able to make EXPRESS run for minutes or exhaust memory.  Every limit below is
far beyond the bundled vehicles (a 20-car train has 220 bodies and 1 118 elements,
its file 0.4 MB) and is checked before the corresponding work, with a message that
names the item, the limit and, when there is one, the way to raise it
(``docs/reliability.md``).

=========================  =======================  ============================  ==========================
limit                      default                  override                      checked by
=========================  =======================  ============================  ==========================
model file size            16 MB                    ``EXPRESS_MAX_FILE_MB``       the model readers
bodies in a model          1 000                    ``EXPRESS_MAX_BODIES``        the model readers
elements in a model        10 000                   ``EXPRESS_MAX_ELEMENTS``      the model readers
connection points          20 000                   ``EXPRESS_MAX_POINTS``        the model readers
parameters                 10 000                   ``EXPRESS_MAX_PARAMETERS``    the model readers
expression length          1 000 characters         ``EXPRESS_MAX_EXPRESSION``    :mod:`express.expressions`
nesting depth              100 levels               none                          :mod:`express.expressions`
exponent                   integer, ``|n| <= 64``   none                          :mod:`express.expressions`
exact constants            within a double's range  none                          :mod:`express.expressions`
=========================  =======================  ============================  ==========================

The overrides are environment variables, read when a limit is checked, so that they
stay in the hands of the person who runs the command: a file cannot raise its own
limits.  A value must be a positive whole number (``EXPRESS_MAX_BODIES=5000``);
anything else is refused with a message naming the variable.

Examples
--------
>>> limit("bodies")
1000
>>> LIMITS["bodies"].variable
'EXPRESS_MAX_BODIES'
"""

from __future__ import annotations

import os
from dataclasses import dataclass

from .diagnostics import UsageError

__all__ = ["LIMITS", "MAX_EXPONENT", "MAX_NESTING", "Limit", "exceeded", "limit"]

#: Deepest nesting of parentheses, signs and powers in one expression (no override:
#: no formula needs more, and Python's own recursion limit is not far beyond).
MAX_NESTING = 100
#: Largest integer exponent ``|n|`` of ``x^n`` in an expression (no override).
MAX_EXPONENT = 64


@dataclass(frozen=True)
class Limit:
    """One limit: its default, the environment variable that raises it, and the unit
    of its value in messages (``"bodies"``, ``"MB"``)."""

    name: str
    default: int
    variable: str
    unit: str
    why: str

    def value(self) -> int:
        """The limit in force (the variable's value when set).

        Raises
        ------
        UsageError
            When the variable is set to something else than a positive whole number.
        """
        text = os.environ.get(self.variable, "").strip()
        if not text:
            return self.default
        try:
            value = int(text)
        except ValueError:
            value = 0
        if value <= 0:
            raise UsageError(f"environment variable {self.variable}={text!r}: expected a positive whole number")
        return value


LIMITS = {
    limit.name: limit
    for limit in (
        Limit("file_mb", 16, "EXPRESS_MAX_FILE_MB", "MB", "model file size"),
        Limit("bodies", 1000, "EXPRESS_MAX_BODIES", "bodies", "bodies in a model"),
        Limit("elements", 10000, "EXPRESS_MAX_ELEMENTS", "elements", "elements in a model"),
        Limit("points", 20000, "EXPRESS_MAX_POINTS", "connection points", "connection points in a model"),
        Limit("parameters", 10000, "EXPRESS_MAX_PARAMETERS", "parameters", "parameters in a model"),
        Limit("expression", 1000, "EXPRESS_MAX_EXPRESSION", "characters", "length of one expression"),
    )
}


def limit(name: str) -> int:
    """The value in force of the limit ``name`` (a key of :data:`LIMITS`)."""
    return LIMITS[name].value()


def exceeded(name: str, found: int) -> str | None:
    """``None`` when ``found`` is within the limit ``name``, else the message to give.

    Examples
    --------
    >>> exceeded("bodies", 12) is None
    True
    >>> exceeded("bodies", 5000)
    '5000 bodies, more than the limit of 1000 bodies (raise it with the environment variable EXPRESS_MAX_BODIES)'
    """
    spec = LIMITS[name]
    allowed = spec.value()
    if found <= allowed:
        return None
    return (
        f"{found} {spec.unit}, more than the limit of {allowed} {spec.unit} "
        f"(raise it with the environment variable {spec.variable})"
    )
