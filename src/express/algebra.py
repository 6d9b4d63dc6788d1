"""Exact sparse arithmetic on parameter expressions, and readable simplification.

Assembly works in SymPy's polynomial ring ``QQ[parameters]`` (or its fraction field
when a model divides by a parameter): sums and products there are dictionary
operations, orders of magnitude faster than on general ``sympy.Expr`` trees, and the
result is canonical, so a virtual stiffness that cancels vanishes exactly.

:func:`readable` turns an entry back into a SymPy expression a person can read:
the rational content and common monomial are pulled out and the rest factored,
``b**2*kLL + b**2*kLU`` -> ``b**2*(kLL + kLU)``.
"""

from __future__ import annotations

from collections.abc import Iterable

import sympy as sp
from sympy import QQ
from sympy.polys.fields import field
from sympy.polys.rings import ring

__all__ = ["ExactDomain", "SparseVector", "needs_fractions"]

SparseVector = dict  # index -> domain element, zero entries omitted


def needs_fractions(expressions: Iterable[sp.Expr]) -> bool:
    """Whether any expression divides by a parameter (needs the fraction field)."""
    for expression in expressions:
        for power in sp.sympify(expression).atoms(sp.Pow):
            if power.exp.is_negative and power.base.free_symbols:
                return True
    return False


class ExactDomain:
    """The exact domain of a model's parameter expressions.

    Parameters
    ----------
    symbols : iterable of sympy.Symbol
        Every parameter symbol that may appear (sorted by name for determinism).
    fractions : bool
        Use the fraction field ``QQ(parameters)`` instead of the ring.
    """

    def __init__(self, symbols: Iterable[sp.Symbol], fractions: bool = False):
        self.symbols = tuple(sorted(set(symbols), key=lambda s: s.name))
        self.fractions = fractions
        gens = self.symbols or (sp.Symbol("_unused"),)
        if fractions:
            self.domain, *_ = field(gens, QQ)
        else:
            self.domain, *_ = ring(gens, QQ)
        self.zero = self.domain.zero
        self.one = self.domain.one
        self._from_cache: dict[sp.Expr, object] = {}
        self._readable_cache: dict[object, sp.Expr] = {}

    def from_expr(self, expression: sp.Expr):
        """Convert a SymPy expression of the parameters into the domain."""
        cached = self._from_cache.get(expression)
        if cached is None:
            cached = self.domain.from_expr(sp.sympify(expression)) if expression != 0 else self.zero
            self._from_cache[expression] = cached
        return cached

    def to_expr(self, element) -> sp.Expr:
        """Plain SymPy expression of a domain element (no factoring)."""
        return element.as_expr()

    def readable(self, element) -> sp.Expr:
        """A factored SymPy expression of a domain element, for people to read."""
        if not element:
            return sp.S.Zero
        key = element
        cached = self._readable_cache.get(key)
        if cached is not None:
            return cached
        if self.fractions:
            numerator = _readable_polynomial(element.numer)
            denominator = _readable_polynomial(element.denom)
            result = numerator / denominator
        else:
            result = _readable_polynomial(element)
        self._readable_cache[key] = result
        return result


#: Polynomials with more terms are not fully factored (only their rational content and
#: common monomial are pulled out): full factorization grows steeply with size.
_FACTOR_TERMS = 40


def _readable_polynomial(polynomial) -> sp.Expr:
    if len(polynomial.terms()) == 1:
        return polynomial.as_expr()
    if len(polynomial.terms()) > _FACTOR_TERMS:
        terms = polynomial.terms()
        monomial = tuple(min(exponents) for exponents in zip(*(m for m, _ in terms)))
        ring = polynomial.ring
        rest = ring.from_dict({tuple(e - g for e, g in zip(m, monomial)): c for m, c in terms})
        content, primitive = rest.primitive()
        common = ring.from_dict({monomial: ring.domain.one})
        return sp.Mul(ring.domain.to_sympy(content), common.as_expr(), primitive.as_expr())
    coefficient, factors = polynomial.factor_list()
    coefficient = polynomial.ring.domain.to_sympy(coefficient)
    if coefficient < 0:
        # prefer b*(kLU*lLU - kLL*lLL) over -b*(kLL*lLL - kLU*lLU): move the sign
        # into a factor of odd power whose terms have mixed signs
        for index, (factor, power) in enumerate(factors):
            signs = {c > 0 for c in factor.coeffs()}
            if power % 2 == 1 and len(signs) == 2:
                factors[index] = (-factor, power)
                coefficient = -coefficient
                break
    return sp.Mul(coefficient, *[factor.as_expr() ** power for factor, power in factors])
