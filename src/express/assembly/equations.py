"""The result of generation: symbolic equations of motion and their inputs.

``M q'' + C q' + K q = P u + Pd u'`` with ``q`` the generalized coordinates named in
``dofs`` and ``u`` the named inputs (ground displacements such as ``G1.x``, and the
rail inputs ``yR1``, ``dy1``, ``rho_B1``, ``S_B1`` ... when the rail modules are used).

A series (Maxwell) element adds its damper stroke ``<element>.stroke`` to ``q``: a
coordinate without mass (its row of ``M`` is zero) but with damping, a first-order
state (``docs/model-format.md``).  Clearance elements (bump stops) are not in the
matrices; :attr:`EquationsOfMotion.clearances` describes them for the nonlinear
simulation.

:attr:`EquationsOfMotion.derivation` keeps how the derived parameters follow from the
given ones (the model's parameter graph in evaluation order): closed forms
(:class:`DerivedParameter`) and function nodes such as Kalker's creep coefficients
(:class:`DerivationCall`), so that an export can compute them instead of freezing them.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Generic, TypeVar

from express.base.diagnostics import Problem

if TYPE_CHECKING:  # SymPy is imported where it is used: a warm numerical command never needs it
    import sympy as sp

    from express.model.records import Model

#: Order in which matrices are exported when present.
MATRIX_ORDER = ("M", "C", "K", "P", "Pd")

#: Suffix of the internal coordinate of a series element: ``<element>.stroke``.
STROKE = "stroke"

_T = TypeVar("_T")


def _sympy() -> Any:
    import sympy

    return sympy


@dataclass(frozen=True)
class Matrices(Mapping[str, _T], Generic[_T]):
    """The matrices of ``M q'' + C q' + K q = P u + Pd u'``, symbolic or numerical.

    A record with a field per matrix, read by name (``matrices.K``) or, as a mapping in
    the order of :data:`MATRIX_ORDER`, by key (``matrices["K"]``, ``matrices.items()``).

    Attributes
    ----------
    M, C, K : matrix, shape (n, n)
        Mass [kg, kg m^2], damping [N s/m ...] and stiffness [N/m ...] matrices.
    P, Pd : matrix, shape (n, m), or None
        Input and input-rate matrices; None when the model has no inputs.
    further : tuple of (str, matrix)
        Further named matrices after these (kept in their order).
    """

    M: _T
    C: _T
    K: _T
    P: _T | None = None
    Pd: _T | None = None
    further: tuple[tuple[str, _T], ...] = ()

    @classmethod
    def of(cls, matrices: Mapping[str, _T]) -> Matrices[_T]:
        """The record of a mapping by name (``"M"``, ``"C"``, ``"K"`` required)."""
        if isinstance(matrices, Matrices):
            return matrices
        further = tuple((key, value) for key, value in matrices.items() if key not in MATRIX_ORDER)
        return cls(matrices["M"], matrices["C"], matrices["K"], matrices.get("P"), matrices.get("Pd"), further)

    def __getitem__(self, key: str) -> _T:
        value = getattr(self, key, None) if key in MATRIX_ORDER else dict(self.further).get(key)
        if value is None:
            raise KeyError(key)
        return value

    def __iter__(self) -> Iterator[str]:
        yield from (key for key in MATRIX_ORDER if getattr(self, key) is not None)
        yield from (key for key, _ in self.further)

    def __len__(self) -> int:
        return sum(1 for _ in self)


@dataclass(frozen=True)
class ElementTerm:
    """A nonlinear element's record for the force elements of the time domain
    (:mod:`express.forces`): its deflection ``delta = gradient . q + inputs . u`` and its
    values by name.  What the values mean is the kind's (a friction element:
    ``stiffness`` the pre-slip spring, ``friction`` the limit ``mu N``); the linear
    matrices hold its linearisation, the kind's module says which.

    Attributes
    ----------
    element : str
        The element's id.
    kind : str
        The :class:`~express.model.records.ElementKind` value (``"friction"``).
    gradient : dict of str to sympy.Expr
        d(delta)/dq by reduced DOF.
    inputs : dict of str to sympy.Expr
        d(delta)/du by input.
    values : dict of str to sympy.Expr
        The element's values by name.
    """

    element: str
    kind: str
    gradient: dict[str, sp.Expr]
    inputs: dict[str, sp.Expr]
    values: dict[str, sp.Expr]


@dataclass(frozen=True)
class ClearanceTerm:
    """A clearance element (bump stop), left out of the linear matrices.

    Its deflection is ``delta = sum gradient[dof] q[dof] + sum inputs[name] u[name]``;
    beyond the gap it pushes back with ``F = stiffness e + progressive e**3``,
    ``e = delta - gap`` (``delta > gap``) or ``delta + gap`` (``delta < -gap``), a
    generalized force ``-F * gradient`` on the DOFs.

    Attributes
    ----------
    element : str
        Element id.
    gradient : dict of str to sympy.Expr
        Coefficient of each DOF (after pin elimination).
    inputs : dict of str to sympy.Expr
        Coefficient of each input.
    gap : sympy.Expr
        [m or rad], >= 0.
    stiffness, progressive : sympy.Expr
        [N/m] and [N/m^3] (rotational: [N m/rad] and [N m/rad^3]).
    """

    element: str
    gradient: dict[str, sp.Expr]
    inputs: dict[str, sp.Expr]
    gap: sp.Expr
    stiffness: sp.Expr
    progressive: sp.Expr = field(default_factory=lambda: _sympy().S.Zero)


@dataclass(frozen=True)
class DerivedParameter:
    """A derivation step ``name = expression``: a closed form of other parameters.

    Attributes
    ----------
    name : str
        The derived parameter (``"P0"``).
    expression : sympy.Expr
        Its definition in SI (``g*(mc + 2*mt + 4*mw)/8``).
    """

    name: str
    expression: sp.Expr


@dataclass(frozen=True)
class DerivationCall:
    """A derivation step computed by a named function without a closed form.

    ``[rail.creep]`` is ``DerivationCall("kalker", "rail.creep", (("wheel_load", P0),
    ...), (("f11", "f1"), ("f22", "f2")))``: f1, f2 from the Hertz ellipse and
    Kalker's table (:func:`express.rail.contact.creep_coefficients`).

    Attributes
    ----------
    kind : str
        Name of the function (``"kalker"``).
    item : str
        Where the model defines it (``"rail.creep"``).
    inputs : tuple of (str, sympy.Expr)
        The function's arguments (SI) as expressions of parameters, in order.
    outputs : tuple of (str, str)
        ``(result key, parameter name)`` of every result that sets a parameter.
    """

    kind: str
    item: str
    inputs: tuple[tuple[str, sp.Expr], ...]
    outputs: tuple[tuple[str, str], ...]


#: One step of :attr:`EquationsOfMotion.derivation`.
DerivationStep = DerivedParameter | DerivationCall


def derivation_steps(model: Model) -> tuple[DerivationStep, ...]:
    """The derived parameters of ``model`` as steps, each after everything it uses.

    Parameters
    ----------
    model : express.model.records.Model
        A resolved model.

    Returns
    -------
    tuple of DerivedParameter or DerivationCall
        From :func:`express.model.parameters.evaluation_order`; a parameter given a value
        explicitly (``--set P0=...``) is no longer derived and has no step, and a
        function step keeps only the outputs it still sets.

    Raises
    ------
    ModelError
        For a cycle or an undefined name in the graph.
    """
    from express.model.parameters import evaluation_order
    from express.model.records import Derivation

    sp = _sympy()
    steps: list[DerivationStep] = []
    for node in evaluation_order(model):
        if isinstance(node, Derivation):
            outputs = tuple(
                (key, name) for key, name, _ in node.outputs
                if name in model.parameters and model.parameters[name].derived_by == node.item
            )
            inputs = tuple((argument, sp.sympify(expression)) for argument, expression, _ in node.inputs)
            steps.append(DerivationCall(node.kind, node.item, inputs, outputs))
        else:
            steps.append(DerivedParameter(node.name, sp.sympify(node.expression)))
    return tuple(steps)


def _names(names: tuple[str, ...], shown: int = 6) -> str:
    return ", ".join(names[:shown]) + (f", ... ({len(names)})" if len(names) > shown else "")


@dataclass(frozen=True, repr=False)
class EquationsOfMotion:
    """Symbolic linear equations of motion of a model.

    Attributes
    ----------
    name : str
        Model name, a valid identifier (used for the MATLAB function name).
    dofs : tuple of str
        Generalized coordinates ``<body>.<dof>`` in matrix order, length n.
    eliminated : tuple of str
        Virtual DOFs removed by the pinned joints (empty with ``keep_virtual``).
    inputs : tuple of str
        Names of the inputs ``u``, length m (may be empty).
    matrices : Matrices of sympy immutable matrices
        ``M``, ``C``, ``K`` (n x n) and, when inputs exist, ``P`` and ``Pd`` (n x m),
        in the order of :data:`MATRIX_ORDER`; further keys may follow (a mapping given
        here becomes a :class:`Matrices`).  The generator
        gives ``sympy.ImmutableSparseMatrix`` when the matrix is mostly zeros (a train's:
        only the non-zeros are stored; ``todok()`` walks them), ``ImmutableMatrix``
        otherwise (:func:`express.assembly.generator.symbolic_matrix`).
    parameters : tuple of str
        Sorted names of every parameter symbol appearing in the matrices.
    values : dict of str to float
        Numerical values (SI units) known for parameters, by name.
    units : dict of str to str
        Unit the value was given in, by name (informative).
    clearances : tuple of ClearanceTerm
        Clearance elements (bump stops) for the nonlinear simulation; not in the matrices.
    element_terms : tuple of ElementTerm
        The other nonlinear elements (friction) for the time domain; their linearisation
        is in the matrices.
    derivation : tuple of DerivedParameter or DerivationCall
        How the derived parameters follow from the given ones, in evaluation order
        (:func:`derivation_steps`); empty when every parameter is given. ``values``
        holds the derived values too, computed from the given ones.
    """

    name: str
    dofs: tuple[str, ...]
    eliminated: tuple[str, ...]
    inputs: tuple[str, ...]
    matrices: Matrices[Any]
    parameters: tuple[str, ...]
    values: dict[str, float] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)
    clearances: tuple[ClearanceTerm, ...] = ()
    element_terms: tuple[ElementTerm, ...] = ()
    derivation: tuple[DerivationStep, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "matrices", Matrices.of(self.matrices))

    @property
    def M(self) -> sp.ImmutableMatrix:
        return self.matrices.M

    @property
    def C(self) -> sp.ImmutableMatrix:
        return self.matrices.C

    @property
    def K(self) -> sp.ImmutableMatrix:
        return self.matrices.K

    #: Largest number of DOFs whose matrices a notebook shows in full.
    LATEX_DOFS = 8

    def __repr__(self) -> str:
        """A few lines: the name, DOFs, inputs, parameters and matrices (not their entries:
        ``print(eq.M)`` or the notebook's LaTeX show those)."""
        return "\n".join([
            f"<EquationsOfMotion {self.name!r}: M q'' + C q' + K q = P u + Pd u'>",
            f"  {len(self.dofs)} DOFs: {_names(self.dofs)}",
            f"  {len(self.inputs)} inputs: {_names(self.inputs) or 'none'}",
            f"  {len(self.parameters)} parameters: {_names(self.parameters)}",
            f"  matrices: {', '.join(self.matrices)}; {len(self.clearances)} clearances, "
            f"{len(self.element_terms)} nonlinear elements, {len(self.eliminated)} DOFs eliminated",
        ])

    def _repr_latex_(self) -> str:
        """The equations in a notebook: ``M q'' + C q' + K q = P u + Pd u'`` with the
        DOFs and, up to :attr:`LATEX_DOFS` of them, M, C and K in full."""
        sp = _sympy()
        q = sp.Matrix([sp.Symbol(dof.replace("_", r"\_")) for dof in self.dofs])
        text = (r"\begin{gathered}M \ddot{q} + C \dot{q} + K q = P u + P_d \dot{u},\quad q = "
                + sp.latex(q.T) + r"^{T}")
        if len(self.dofs) <= self.LATEX_DOFS:
            for name in ("M", "C", "K"):
                text += rf"\\ {name} = " + sp.latex(sp.Matrix(self.matrices[name]))
        else:
            text += rf"\\ \text{{{len(self.dofs)} DOFs: the matrices are shown up to {self.LATEX_DOFS}}}"
        return f"$${text}\\end{{gathered}}$$".replace("\\end", "\\end")


@dataclass(frozen=True, repr=False)
class GenerationResult:
    """Equations of motion plus what the generator noticed.

    Attributes
    ----------
    equations : EquationsOfMotion
        The matrices.
    warnings : tuple of Problem
        Suspicious features (a DOF with zero mass or inertia).
    transformation : sympy immutable matrix
        ``T`` with ``q = T q_r`` (full DOFs x reduced DOFs); sparse for big models
        (:func:`symbolic_matrix`).
    full_dofs : tuple of str
        Generalized coordinates before elimination (rows of ``T``).
    omitted : tuple of str
        What the model describes but the equations leave out, said in words (empty when
        nothing is): the bare :func:`express.assembly.generator.generate` of a model with
        rail data leaves out the wheel/rail and curve terms, which
        :func:`express.rail.build.generate_vehicle` (and ``express generate``) add.
    """

    equations: EquationsOfMotion
    warnings: tuple[Problem, ...]
    transformation: sp.MatrixBase
    full_dofs: tuple[str, ...]
    omitted: tuple[str, ...] = ()

    def __repr__(self) -> str:
        """The equations' short repr, the warnings' count and what is left out."""
        left_out = f"; without {', '.join(self.omitted)}" if self.omitted else ""
        return (f"<GenerationResult: {len(self.warnings)} warnings, {len(self.full_dofs)} DOFs before elimination"
                f"{left_out}>\n  " + repr(self.equations).replace("\n", "\n  "))
