"""The time runs' output names before issue 35, and the table of outputs that refuses them
with the new name.

One meaning per name across the contact models: ``Q`` is always a vertical wheel load
(the contact tables' ``Q1L``), ``Y`` a lateral force.  The dead-band model's lateral
force of the flanging wheel was ``Q{n}`` (the paper's notation), its total ``Qtot{n}`` and
its derailment quotient ``QP{n}``; they are ``Y{n}``, ``Ytot{n}`` and ``YQ{n}`` now.
"""

from __future__ import annotations

from typing import Any

from express.base.diagnostics import ArgumentError

__all__ = ["RENAMED", "OutputTable", "RenamedOutputError", "renamed_output"]

#: The dead-band outputs' names before issue 35 (``Q`` meant a lateral force there) ->
#: their names now, by prefix (``Q1`` -> ``Y1``): see :func:`renamed_output`.
RENAMED = {"Qtot": "Ytot", "QP": "YQ", "Q": "Y"}


def renamed_output(name: str) -> str | None:
    """The new name of a dead-band output given by its old name (``"Q1"`` -> ``"Y1"``,
    ``"QP2"`` -> ``"YQ2"``, ``"Qtot1"`` -> ``"Ytot1"``), None for any other name (the
    contact tables' vertical loads ``Q1L`` are not renamed)."""
    for old, new in RENAMED.items():
        if name.startswith(old) and name[len(old):].isdigit():
            return new + name[len(old):]
    return None


class RenamedOutputError(ArgumentError, KeyError):
    """An output asked for by its name before issue 35 (``Q1`` for the lateral force)."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


class OutputTable(dict):
    """The derived outputs of a run by name (a dict); an old dead-band name (``Q1``) that
    is now another (``Y1``) raises :class:`RenamedOutputError` naming the new one."""

    def __missing__(self, name: Any) -> Any:
        new = renamed_output(name) if isinstance(name, str) else None
        if new is not None and new in self:
            raise RenamedOutputError(f"output {name!r} is now called {new!r}: Q is the vertical wheel load, "
                                     "Y the lateral force, in every contact model")
        raise KeyError(name)
