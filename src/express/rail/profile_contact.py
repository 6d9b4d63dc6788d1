"""The contact of a model's wheelsets from wheel and rail profiles: the ``"profiles"``
derivation of the parameter graph, and what the linear model and the simulation take
from it.

A model says ``conicity = { from = "profiles", wheel = "S1002", rail = "60E1", ... }`` in
``[rail.wheel_rail]`` (or for one wheelset); the reader makes a
:class:`~express.model.records.Derivation` of kind ``"profiles"`` whose outputs are parameters
(``docs/model-format.md``): the EN 15302 equivalent conicity at the amplitude and the
contact quantities of the linearised wheelset, see :data:`OUTPUTS`.  Its function,
:func:`profile_derivation`, is registered by :mod:`express.rail.build`; it is evaluated
with every other parameter, so ``--set`` of an input (an amplitude given as a parameter,
the wheel load through the masses) re-evaluates it.  Contact tables are cached, so a
re-evaluation with the same profiles and placement costs milliseconds.

:func:`profile_nodes` finds the node of each wheelset; :func:`contact_terms` gives the
symbols of its outputs for the linear terms (:func:`express.rail.wheelrail.wheelset_terms`);
:func:`wheelset_contacts` builds the tables the simulation looks up.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from functools import lru_cache
from pathlib import Path

import numpy as np
import sympy as sp

from express.base.diagnostics import ArgumentError, ModelError
from express.io.toml_contact import PROFILE_INPUTS, PROFILE_OUTPUTS
from express.model.parameters import expression_value
from express.model.records import Derivation, Model
from express.rail.conicity import equivalent_conicity
from express.rail.contact_forces import WheelsetContact, wheelset_contact
from express.rail.contact_geometry import ContactSetup
from express.rail.contact_tables import (
    C11,
    C22,
    C23,
    SEMI_A,
    SEMI_B,
    ContactTables,
    LinearContact,
    contact_tables,
    linear_contact_parameters,
)
from express.rail.options import ProfileKind
from express.rail.profile_formats import read_profile
from express.rail.profiles import STANDARD_PROFILES, Profile, standard_profile

__all__ = [
    "DEFAULTS",
    "INPUTS",
    "KIND",
    "OUTPUTS",
    "contact_terms",
    "linear_wheelset_terms",
    "profile_derivation",
    "profile_nodes",
    "profile_tables",
    "wheelset_contacts",
]

#: Kind of the derivation node.
KIND = "profiles"
#: Arguments of the node: (key, dimension, default); ``None``: the wheelset's own value
#: (``wheel_radius`` is its r0, ``wheel_load`` its wheel load).  Results: (key, suffix
#: of the parameter name, dimension); the conicity takes the node's name itself, the
#: others ``<name>_<suffix>``.  Defined once, by the reader of the model file (a lower
#: layer), which makes the node.
INPUTS = PROFILE_INPUTS
OUTPUTS = PROFILE_OUTPUTS
#: The placement and material defaults of :data:`INPUTS` (SI), read from the one definition.
DEFAULTS: dict[str, float] = {key: default for key, _, default in INPUTS if default is not None}


@lru_cache(maxsize=8)
def _standard(name: str) -> Profile:
    return standard_profile(name)


def _profile(text: str, kind: ProfileKind, base: str, units: str) -> Profile:
    """A standard profile by name, else a file relative to ``base``."""
    if text.strip().upper().replace(" ", "") in {*STANDARD_PROFILES, "UIC60"}:
        return _standard(text.strip().upper().replace(" ", ""))
    path = Path(text)
    if not path.is_absolute():
        path = Path(base or ".") / path
    try:
        return read_profile(path, kind, units=units or None)
    except ModelError as error:
        where = "; ".join(f"{p.file}" + (f":{p.line}" if p.line else "") + f": {p.message}" for p in error.problems)
        raise ArgumentError(f"{kind} profile {text!r}: {where}") from None


def profile_tables(wheel: str, rail: str, *, base: str = "", units: str = "", gauge: float = DEFAULTS["gauge"],
                   flange_back: float = DEFAULTS["flange_back"], inclination: float = DEFAULTS["inclination"],
                   wheel_radius: float = 0.46, youngs_modulus: float = DEFAULTS["youngs_modulus"],
                   poisson: float = DEFAULTS["poisson"]) -> ContactTables:
    """Contact tables (:func:`express.rail.contact_tables.contact_tables`) of the named
    profiles or files (relative to ``base``) placed as given (SI)."""
    try:
        setup = ContactSetup(gauge=gauge, flange_back=flange_back, inclination=inclination, wheel_radius=wheel_radius)
    except ValueError as error:
        raise ArgumentError(f"contact setup: {error}") from None
    return contact_tables(_profile(wheel, "wheel", base, units), _profile(rail, "rail", base, units), setup,
                          youngs_modulus=youngs_modulus, poisson=poisson)


def profile_derivation(*, wheel: str = "", rail: str = "", base: str = "", units: str = "",
                       gauge: float = DEFAULTS["gauge"], flange_back: float = DEFAULTS["flange_back"],
                       inclination: float = DEFAULTS["inclination"], wheel_radius: float = 0.46, amplitude: float,
                       wheel_load: float, youngs_modulus: float, poisson: float, table: str = "",
                       **given: float) -> dict[str, float]:
    """The ``"profiles"`` node: the results of :data:`OUTPUTS` (SI).

    ``conicity`` is EN 15302's equivalent conicity at ``amplitude``
    (:func:`express.rail.conicity.equivalent_conicity` of the tables' delta r);
    ``epsilon``, ``sigma``, ``delta0``, ``half_distance`` (l0), ``radius`` are
    :func:`express.rail.contact_tables.linear_contact_parameters` at the amplitude;
    ``f23`` is Kalker's spin coefficient ``G (ab)^1.5 C23`` of the centred contact under
    the normal force ``wheel_load / cos(delta0)``; Kalker's coefficients ``given`` (``f11``,
    ``f22`` [N], ``f23`` [N m], ``f33`` [N m^2], :data:`express.io.toml_contact.COEFFICIENT_INPUTS`)
    replace them (``f33`` is not used, ``docs/contact.md``).  With ``table`` (a contact table file,
    ``from = "table"``) the profiles are not used:
    :func:`express.rail.table_contact.table_derivation`, Kalker's coefficients ``given``.

    Raises
    ------
    ArgumentError
        Naming what is wrong (a profile file's problems with their lines, a placement
        where the wheels miss the rails, an amplitude beyond the tables).
    """
    if table:
        from express.rail.table_contact import table_derivation

        results, linear = table_derivation(table=table, base=base, amplitude=amplitude, wheel_load=wheel_load,
                                           youngs_modulus=youngs_modulus, poisson=poisson, **given)
        return {**results, **linear_wheelset_terms(linear, wheel_load, results["f23"])}
    if not 0.0 <= inclination <= 0.2:
        raise ArgumentError(f"inclination {inclination:g}: the tangent must lie in 0..0.2 (1:inf .. 1:5)")
    if not amplitude > 0:
        raise ArgumentError(f"amplitude must be positive, got {amplitude:g} m")
    if not wheel_load > 0:
        raise ArgumentError(f"wheel_load must be positive, got {wheel_load:g} N")
    tables = profile_tables(wheel, rail, base=base, units=units, gauge=gauge, flange_back=flange_back,
                            inclination=inclination, wheel_radius=wheel_radius, youngs_modulus=youngs_modulus,
                            poisson=poisson)
    try:
        linear = linear_contact_parameters(tables, amplitude)
        delta_r = tables.data[0, 0] - tables.data[0, 1]
        conicity = float(equivalent_conicity(tables.y, delta_r, amplitude))
    except ModelError as error:
        raise ArgumentError("; ".join(p.message for p in error.problems)) from None
    centre = int(np.argmin(np.abs(tables.y)))
    normal = wheel_load / math.cos(linear.delta0)
    scale = normal ** (1.0 / 3.0)
    ab = float(np.mean(tables.data[SEMI_A, :, centre] * tables.data[SEMI_B, :, centre])) * scale * scale
    shear = tables.shear_modulus
    f11, f22, f23 = (shear * ab * float(np.mean(tables.data[C11, :, centre])),
                     shear * ab * float(np.mean(tables.data[C22, :, centre])),
                     shear * ab**1.5 * float(np.mean(tables.data[C23, :, centre])))
    f11, f22, f23 = (given.get(key, value) for key, value in (("f11", f11), ("f22", f22), ("f23", f23)))
    return {"conicity": conicity, "epsilon": linear.epsilon, "sigma": linear.sigma, "delta0": linear.delta0,
            "half_distance": linear.half_distance, "radius": linear.radius, "f11": f11, "f22": f22, "f23": f23,
            **linear_wheelset_terms(linear, wheel_load, f23)}


def linear_wheelset_terms(linear: LinearContact, wheel_load: float, f23: float) -> dict[str, float]:
    """Coefficients of the linearised wheelset's contact terms (``docs/contact.md``):

    * ``lateral_stiffness`` ``2 Q eps / (l0 c^2) - 2 f23 (eps / c^2 - sigma) / (l0 r0)``
      (gravitational stiffness, less the spin creep of the changing contact angles);
    * ``yaw_stiffness`` ``-2 tan(d0) (l0 - r0 tan(d0)) (Q - f23 / r0)`` (the lateral forces
      of the normal forces and of the centred spin at the contacts' lead: negative);
    * ``angle_factor`` ``1 / c^2`` and ``lateral_factor`` ``(1 + r0 sigma / l0) / c^2`` of the
      lateral creep terms ``2 f22 (factor y' / v - angle_factor psi)``,

    with ``c = cos(delta0)``, ``Q`` the wheel load, ``l0``, ``r0`` the centred contact's
    distance from the wheelset centre and rolling radius.
    """
    q, l0, r0, eps, sigma = wheel_load, linear.half_distance, linear.radius, linear.epsilon, linear.sigma
    c2 = math.cos(linear.delta0) ** 2
    tangent = math.tan(linear.delta0)
    return {
        "lateral_stiffness": 2.0 * q * eps / (l0 * c2) - 2.0 * f23 * (eps / c2 - sigma) / (l0 * r0),
        "yaw_stiffness": -2.0 * tangent * (l0 - r0 * tangent) * (q - f23 / r0),
        "angle_factor": 1.0 / c2,
        "lateral_factor": (1.0 + r0 * sigma / l0) / c2,
    }


# ------------------------------------------------------------------ the model's side


def profile_nodes(model: Model) -> dict[str, Derivation]:
    """The ``"profiles"`` node of every wheelset whose conicity is its output, by body."""
    if model.rail is None:
        return {}
    by_output = {d.output("conicity"): d for d in model.derivations if d.kind == KIND}
    found = {}
    for wheelset in model.rail.wheelsets:
        expression = sp.sympify(wheelset.conicity)
        if expression.is_Symbol and expression.name in by_output:
            found[wheelset.body] = by_output[expression.name]
    return found


def contact_terms(node: Derivation) -> dict[str, sp.Symbol]:
    """The parameters of the node's results as symbols, by result key."""
    return {key: sp.Symbol(name) for key, name, _ in node.outputs}


def _node_tables(node: Derivation, values: Mapping[str, float], wheel_load: float) -> ContactTables:
    arguments = {argument: expression_value(expression, values) for argument, expression, _ in node.inputs}
    settings = dict(node.settings)
    from express.rail.table_contact import file_tables, given_coefficients, table_path

    if settings.get("table"):
        tables = file_tables(table_path(settings["table"], settings.get("base", "")), arguments["youngs_modulus"],
                             arguments["poisson"])
        return given_coefficients(tables, wheel_load, arguments)
    placement = ("gauge", "flange_back", "inclination", "wheel_radius", "youngs_modulus", "poisson")
    tables = profile_tables(settings["wheel"], settings["rail"], base=settings.get("base", ""),
                            units=settings.get("units", ""), **{key: arguments[key] for key in placement})
    return given_coefficients(tables, wheel_load, arguments)


def wheelset_contacts(model: Model, values: Mapping[str, float], wheelsets) -> list[WheelsetContact | None]:
    """The contact of each wheelset (``None`` where the conicity is not from profiles),
    with its wheel load, friction and rail stiffness (``wheelsets``: the numerical
    :class:`~express.numeric.statespace.WheelsetData`, in the model's order)."""
    nodes = profile_nodes(model)
    contacts: list[WheelsetContact | None] = []
    for data in wheelsets:
        node = nodes.get(data.name)
        if node is None:
            contacts.append(None)
            continue
        tables = _node_tables(node, values, data.wheel_load)
        contacts.append(wheelset_contact(tables, data.wheel_load, data.friction, data.rail_stiffness))
    return contacts
