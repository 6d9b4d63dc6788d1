"""The compiled side of the force elements: one entry point, :func:`force_law`, that each
kind's parameter NamedTuple selects (``numba.extending.overload``), and the stacked set's
forces, :func:`stacked_forces`, which the compiled marches call.

A kind registers its law in its own module::

    @overload(force_law)
    def _my_law(x, k, law, z, record, commit):
        if isinstance(law, types.BaseNamedTuple) and law.instance_class is MyLaw:
            return lambda x, k, law, z, record, commit: my_forces(x, k, law, z, record)
        return None

where ``my_forces`` (a :func:`express.base.kernels.kernel`: it allocates nothing) writes
the element's forces at state ``x`` and step ``k`` into ``z[law.first : law.first +
width]`` (``first``: the element's place in the stack, a field of every law) and what it
records into ``record``.  ``commit`` is True where ``x`` is a state the march keeps (the
start and each step's end) and False at the predictor's trial state: an element with
internal states (a friction slider, kept in an array of its law) updates them only when
committing.
"""

from __future__ import annotations

from typing import NamedTuple

from numba import literal_unroll, types
from numba.extending import overload

from express.base.kernels import kernel

__all__ = ["NoForces", "force_law", "stacked_forces"]


def force_law(x, k, law, z, record, commit):
    """The forces of one element at state ``x`` and step ``k`` into ``z`` from its place
    ``law.first`` on, what it records into ``record``; its internal states updated when
    ``commit`` (module docstring).

    Compiled only: each law NamedTuple type registers its implementation with
    ``numba.extending.overload`` (module docstring)."""
    raise NotImplementedError("force_law runs inside compiled code only")


class NoForces(NamedTuple):
    """The law of an empty set (a stack is never empty for the compiled loop)."""

    first: int


@overload(force_law)
def _no_forces(x, k, law, z, record, commit):
    if isinstance(law, types.BaseNamedTuple) and law.instance_class is NoForces:
        return lambda x, k, law, z, record, commit: None
    return None


@kernel
def stacked_forces(x, k, laws, z, record, commit):
    """Every element's forces into ``z``, in the order of the stack (a tuple of laws);
    internal states updated when ``commit``."""
    for law in literal_unroll(laws):
        force_law(x, k, law, z, record, commit)
