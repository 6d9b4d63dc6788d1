"""A function node of the parameter graph (:class:`Derivation`): parameters computed by a
named function without a closed form; read by :mod:`express.model.records` into a
:class:`~express.model.records.Model`."""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from express.base.units import Dimension

__all__ = ["Derivation"]


@dataclass(frozen=True)
class Derivation:
    """A function node of the parameter graph: parameters computed by a named
    function of other parameters that has no closed form (a table look-up).

    ``[rail.creep]`` is ``Derivation("kalker", "rail.creep", inputs=(("wheel_load",
    P0, "force"), ...), outputs=(("f11", "f1", "force"), ("f22", "f2", "force")))``.
    The function itself is registered by the layer that knows it
    (:func:`express.model.parameters.register_derivation`).

    Attributes
    ----------
    kind : str
        Name of the registered function (``"kalker"``).
    item : str
        Where it is defined, for messages (``"rail.creep"``).
    inputs : tuple of (argument, sympy.Expr, dimension name)
        The function's arguments as expressions of parameters.
    outputs : tuple of (result key, parameter name, dimension name)
        Which parameter receives which result (a dimension without a name, such as a
        mode shape's 1/sqrt(kg), as a :class:`~express.base.units.Dimension`; None for
        a value of no dimension in the graph, a mode's angular frequency in rad/s).
    line : int or None
    settings : tuple of (str, str)
        Text arguments that are not quantities (the ``"profiles"`` node's profile names
        or files), passed to the function as keywords besides the inputs.
    """

    kind: str
    item: str
    inputs: tuple[tuple[str, sp.Expr, str | Dimension], ...]
    outputs: tuple[tuple[str, str, str | Dimension | None], ...]
    line: int | None = None
    settings: tuple[tuple[str, str], ...] = ()

    def input(self, argument: str) -> sp.Expr:
        """The expression given for ``argument`` (KeyError if none)."""
        for name, expression, _ in self.inputs:
            if name == argument:
                return expression
        raise KeyError(argument)

    def output(self, result: str) -> str:
        """The parameter that receives ``result`` (KeyError if none)."""
        for key, name, _ in self.outputs:
            if key == result:
                return name
        raise KeyError(result)
