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
from typing import Any

import sympy as sp
from sympy import QQ
from sympy.polys.fields import field
from sympy.polys.rings import ring

__all__ = ["ExactDomain", "inverted_symbols", "needs_fractions"]


def needs_fractions(expressions: Iterable[sp.Expr]) -> bool:
    """Whether any expression divides by a parameter (needs the fraction field)."""
    return inverted_symbols(expressions) != set()


def inverted_symbols(expressions: Iterable[sp.Expr]) -> set[sp.Symbol] | None:
    """The parameters that expressions divide by, when each divisor is a single
    parameter (``f/v``, ``g/G``); ``None`` when some divisor is a sum or product
    (``1/(a + b)``), which needs the fraction field."""
    inverted: set[sp.Symbol] = set()
    for expression in expressions:
        for power in sp.sympify(expression).atoms(sp.Pow):
            if power.exp.is_negative and power.base.free_symbols:
                if not power.base.is_Symbol:
                    return None
                inverted.add(power.base)
    return inverted


class ExactDomain:
    """The exact domain of a model's parameter expressions.

    Parameters
    ----------
    symbols : iterable of sympy.Symbol
        Every parameter symbol that may appear (sorted by name for determinism).
    fractions : bool
        Use the fraction field ``QQ(parameters)`` instead of the ring.
    inverses : iterable of sympy.Symbol
        Parameters that are divided by (``v`` in ``f/v``): in the ring their inverses
        are further generators (Laurent polynomials), which keeps ring speed for the
        common case of single-parameter divisors.
    separate : iterable of sympy.Symbol
        Parameters whose part of an entry :meth:`readable` splits off before factoring
        when the entry is a product of a polynomial in them and one in the others (a
        flexible body's mode shapes: ``phi_1 phi_2 (2 kz2 + ...)``): the other part,
        the same for every mode, is factored once.
    """

    def __init__(self, symbols: Iterable[sp.Symbol], fractions: bool = False, inverses: Iterable[sp.Symbol] = (),
                 separate: Iterable[sp.Symbol] = ()):
        self.symbols = tuple(sorted(set(symbols), key=lambda s: s.name))
        self.fractions = fractions
        inverses = () if fractions else tuple(sorted(set(inverses), key=lambda s: s.name))
        # parameter names start with a letter, so these cannot clash with one
        self._inverse = {symbol: sp.Symbol(f"_inverse_{symbol.name}") for symbol in inverses}
        self._restore = {inverse: 1 / symbol for symbol, inverse in self._inverse.items()}
        gens = (self.symbols + tuple(self._inverse.values())) or (sp.Symbol("_unused"),)
        if fractions:
            self.domain, *_ = field(gens, QQ)
        else:
            self.domain, *_ = ring(gens, QQ)
        self.zero = self.domain.zero
        self.one = self.domain.one
        self._from_cache: dict[sp.Expr, object] = {}
        self._readable_cache: dict[object, sp.Expr] = {}
        apart = set(separate)
        self._separate = tuple(i for i, g in enumerate(gens) if g in apart) if not fractions else ()

    def from_expr(self, expression: sp.Expr):
        """Convert a SymPy expression of the parameters into the domain."""
        cached = self._from_cache.get(expression)
        if cached is None:
            value = sp.sympify(expression)
            if self._inverse:
                value = value.replace(
                    lambda e: e.is_Pow and e.exp.is_negative and e.base in self._inverse,
                    lambda e: self._inverse[e.base] ** (-e.exp),
                )
            cached = self.domain.from_expr(value) if value != 0 else self.zero
            self._from_cache[expression] = cached
        return cached

    def to_expr(self, element) -> sp.Expr:
        """Plain SymPy expression of a domain element (no factoring)."""
        return element.as_expr().xreplace(self._restore)

    def readable(self, element) -> sp.Expr:
        """A factored SymPy expression of a domain element, for people to read."""
        if not element:
            return sp.S.Zero
        key = element
        cached = self._readable_cache.get(key)
        if cached is not None:
            return cached
        split = _split(element, self._separate) if self._separate else None
        if split is not None:
            result = self.readable(split[0]) * self.readable(split[1])
        elif self.fractions:
            numerator = _readable_polynomial(element.numer)
            denominator = _readable_polynomial(element.denom)
            result = numerator / denominator
        else:
            result = _readable_polynomial(element).xreplace(self._restore)
        self._readable_cache[key] = result
        return result


def _split(polynomial, separate: tuple[int, ...]):
    """``(a, b)`` with ``polynomial == a * b``, ``a`` in the generators ``separate`` only
    and ``b`` in the others, both not constant; None when the polynomial is not such a
    product (exact: every group of terms with the same ``separate`` exponents must be the
    same polynomial of the others up to a rational factor)."""
    groups: dict[tuple, dict[tuple, Any]] = {}
    for monomial, coefficient in polynomial.terms():
        key = tuple(monomial[i] for i in separate)
        rest = tuple(0 if i in separate else e for i, e in enumerate(monomial))
        groups.setdefault(key, {})[rest] = coefficient
    if len(groups) == 1 and next(iter(groups)) == (0,) * len(separate):
        return None  # no separate generator in it
    first = next(iter(groups.values()))
    anchor, value = next(iter(first.items()))
    ratios = {}
    for key, group in groups.items():
        if group.keys() != first.keys():
            return None
        ratio = group[anchor] / value
        if any(group[m] != ratio * c for m, c in first.items()):
            return None
        ratios[key] = ratio
    ring_ = polynomial.ring
    width = ring_.ngens
    shape = {tuple(key[separate.index(i)] if i in separate else 0 for i in range(width)): r for key, r in ratios.items()}
    a, b = ring_.from_dict(shape), ring_.from_dict(first)
    if len(a.terms()) == 1 and len(b.terms()) == 1:
        return None  # a monomial: nothing to gain
    if a.is_ground or b.is_ground:
        return None
    return a, b


#: Polynomials with more terms are not fully factored (only their rational content and
#: common monomial are pulled out): full factorization grows steeply with size.
_FACTOR_TERMS = 40


def _readable_polynomial(polynomial) -> sp.Expr:
    if len(polynomial.terms()) == 1:
        return polynomial.as_expr()
    if len(polynomial.terms()) > _FACTOR_TERMS:
        terms = polynomial.terms()
        monomial = tuple(min(exponents) for exponents in zip(*(m for m, _ in terms), strict=True))
        ring = polynomial.ring
        rest = ring.from_dict({tuple(e - g for e, g in zip(m, monomial, strict=True)): c for m, c in terms})
        content, primitive = rest.primitive()
        common = ring.from_dict({monomial: ring.domain.one})
        return sp.Mul(ring.domain.to_sympy(content), common.as_expr(), primitive.as_expr())
    polynomial = _compact(polynomial)
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


_COMPACT_RINGS: dict[tuple, object] = {}


def _compact(polynomial):
    """The same polynomial in a ring of only the generators it uses.

    Factorization works on a dense recursive representation whose cost grows with the
    number of generators: a model has dozens of parameters, an entry uses a few.
    """
    terms = polynomial.terms()
    used = tuple(i for i in range(polynomial.ring.ngens) if any(m[i] for m, _ in terms))
    if len(used) == polynomial.ring.ngens:
        return polynomial
    symbols = tuple(polynomial.ring.symbols[i] for i in used)
    small = _COMPACT_RINGS.get(symbols)
    if small is None:
        small, *_ = ring(symbols, polynomial.ring.domain)
        _COMPACT_RINGS[symbols] = small
    return small.from_dict({tuple(m[i] for i in used): c for m, c in terms})
