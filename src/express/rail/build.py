"""Rail vehicle assembly: the wheel/rail and curve terms added to the core generator.

Also registers the ``"kalker"`` derivation of the parameter graph (``[rail.creep]``:
creep coefficients from the contact) and the ``"profiles"`` one (conicity and contact
terms from wheel and rail profiles, :mod:`express.rail.profile_contact`), see
:mod:`express.model.parameters`.

Inputs are named and ordered as the paper's eq. (13): the irregularity at every
wheelset (``W1.yR``, ...), the flange penetrations (``W1.dy``, ...), the curvature
at every station (``B1.rho``, ...) and the cant at every station (``B1.S``, ...);
ground inputs of the core model, if any, come first.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from express.assembly.equations import ElementTerm
from express.assembly.generator import AddedTerms, GenerationResult, element_deflections, generate
from express.base.diagnostics import ArgumentError
from express.base.reads import recording
from express.model.parameters import register_derivation
from express.model.records import Derivation, Model
from express.rail.curve import cant_deficiency_forces, curvature_point_inputs, station_of, stations
from express.rail.layout import RailLayout
from express.rail.wheelrail import flange_input, irregularity_input, wheelset_terms

__all__ = ["RailLayout", "generate_vehicle", "rail_layout", "rail_terms", "vehicle_deflections"]

#: Kind of the profiles derivation (:data:`express.rail.profile_contact.KIND`, spelled
#: here so that a model without profiles never imports that module: it brings Numba and
#: the contact tables, some 0.2 s of start-up, issue 16).
PROFILES = "profiles"


def rail_layout(model: Model) -> RailLayout:
    """The rail inputs of ``model`` (which must have rail data)."""
    if model.rail is None:
        raise ArgumentError(f"{model.source}: the model has no [rail] data")
    wheelsets = model.rail.wheelsets
    all_stations = stations(model)
    return RailLayout(
        wheelsets=tuple(w.body for w in wheelsets),
        stations=tuple(all_stations),
        irregularity=tuple(irregularity_input(w) for w in wheelsets),
        flange=tuple(flange_input(w) for w in wheelsets),
        curvature=tuple(s.curvature_input for s in all_stations),
        cant=tuple(s.cant_input for s in all_stations),
    )


def rail_terms(model: Model) -> AddedTerms:
    """Every wheel/rail and curve term of ``model`` as :class:`AddedTerms`."""
    rail = model.rail
    if rail is None:
        return AddedTerms()
    layout = rail_layout(model)
    by_body = station_of(model)
    nodes = _profile_nodes(model)
    stiffness, damping, forces = [], [], []
    for wheelset in rail.wheelsets:
        node = nodes.get(wheelset.body)
        contact = _contact_terms(node) if node is not None else None
        k, c, p = wheelset_terms(wheelset, rail.speed, by_body[wheelset.body].curvature_input, contact)
        stiffness += k
        damping += c
        forces += p
    forces += cant_deficiency_forces(model, rail.speed, rail.gravity, rail.cant_base)
    return AddedTerms(
        inputs=layout.inputs,
        point_inputs=curvature_point_inputs(model),
        stiffness=stiffness,
        damping=damping,
        forces=forces,
    )


def generate_vehicle(
    model: Model, *, keep_virtual: bool = False, with_rail: bool = True, readable: bool = True
) -> GenerationResult:
    """Generate the equations of a model, with its rail terms when it has rail data
    (:func:`express.assembly.generator.generate` with the terms of :func:`rail_terms`).

    Parameters
    ----------
    model : Model
        The model (validated again).
    keep_virtual : bool
        Keep the virtual DOFs and elements of the pinned joints (the paper's eq. 6).
    with_rail : bool
        Add the wheel/rail and curve terms when the model has rail data.
    readable : bool
        Factor the entries for reading (``False``: expanded, quicker for numbers only).

    Returns
    -------
    GenerationResult

    Examples
    --------
    >>> from express.io import load_model
    >>> vehicle = load_model("examples/forced-steering.toml")
    >>> eom = generate_vehicle(vehicle).equations
    >>> len(eom.dofs), len(eom.eliminated)
    (24, 4)
    """
    added = rail_terms(model) if with_rail and model.rail is not None else None
    return generate(model, keep_virtual=keep_virtual, added=added, readable=readable)


def vehicle_deflections(model: Model, *, with_rail: bool = True) -> tuple[ElementTerm, ...]:
    """Every element's deflection in the coordinates of :func:`generate_vehicle`
    (:func:`express.assembly.generator.element_deflections`): with rail data, the ends'
    curvature terms move them as in the equations.

    Parameters
    ----------
    model : Model
        A model :func:`generate_vehicle` accepts.
    with_rail : bool
        As in :func:`generate_vehicle`.
    """
    if not (with_rail and model.rail is not None):
        return element_deflections(model)
    layout = rail_layout(model)
    return element_deflections(model, AddedTerms(inputs=layout.inputs, point_inputs=curvature_point_inputs(model)))


def _profile_nodes(model: Model) -> dict[str, Derivation]:
    """:func:`express.rail.profile_contact.profile_nodes`, imported only for a model
    that has a profiles derivation."""
    if not any(derivation.kind == PROFILES for derivation in model.derivations):
        return {}
    from express.rail.profile_contact import profile_nodes

    return profile_nodes(model)


def _contact_terms(node: Derivation) -> dict:
    from express.rail.profile_contact import contact_terms

    return contact_terms(node)


def _kalker(wheel_load: float, wheel_radius: float, rail_head_radius: float, youngs_modulus: float, poisson: float) -> dict[str, float]:
    """The ``"kalker"`` derivation of ``[rail.creep]``: f11, f22 [N] per wheel from the
    Hertz ellipse and Kalker's Table E.3 (:func:`express.rail.contact.creep_coefficients`).

    While a model file is read for the derivation cache (:func:`express.base.reads.recording`)
    the result is kept there too, by the exact arguments: a warm command then needs
    neither SciPy's root finder nor its import (``docs/cache.md``)."""
    arguments = (wheel_load, wheel_radius, rail_head_radius, youngs_modulus, poisson)
    if recording():
        from express.io.cache import memoized_values

        return memoized_values("kalker", arguments, lambda: _kalker_now(*arguments), _kalker_valid)
    return _kalker_now(*arguments)


def _kalker_valid(values: Mapping[str, float]) -> bool:
    """What :func:`_kalker_now` gives: exactly f11 and f22, positive (cache entries are
    checked against it before use)."""
    return set(values) == {"f11", "f22"} and all(value > 0 for value in values.values())


def _kalker_now(*arguments: float) -> dict[str, float]:
    from express.rail.contact import creep_coefficients  # SciPy's special functions and root finder: on first use

    coefficients = creep_coefficients(*arguments)
    return {"f11": coefficients.f11, "f22": coefficients.f22}


def _profiles(**arguments: Any) -> Mapping[str, float]:
    """The ``"profiles"`` derivation (:func:`express.rail.profile_contact.profile_derivation`),
    its module imported on first use."""
    from express.rail.profile_contact import profile_derivation

    return profile_derivation(**arguments)


register_derivation("kalker", _kalker)
register_derivation(PROFILES, _profiles)
