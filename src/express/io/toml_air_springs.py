"""Air springs of a TOML model (issue 31, item 4): ``air_spring = {...}`` on an element,
read into the elements the linear analyses already see exactly.

The standard linear model of an air spring with a reservoir (Nishimura's model, the
simplified form of Berg's): a spring ``k_bag`` in parallel with a series (Maxwell)
branch, the reservoir spring ``k_res`` in series with the orifice damping ``c``.  Its
dynamic stiffness is

    K(w) = k_bag + k_res i w c / (k_res + i w c)

so ``K(0) = k_bag`` (the orifice open: bag and reservoir one volume) and ``K(inf) =
k_bag + k_res`` (the orifice shut: the bag alone).  The element ``<id>`` is the
parallel spring (with the element's own ``damping``, if any), ``<id>_reservoir`` the
series element (its stroke, ``<id>_reservoir.stroke``, a first-order coordinate), and an
optional ``lateral`` / ``longitudinal`` shear stiffness and damping the plain elements
``<id>_lateral`` (y) and ``<id>_longitudinal`` (x) between the same points.

Given directly: ``bag``, ``reservoir`` [N/m], ``orifice`` [N s/m].  Or derived from
the gas: pressure ``p`` (``gauge_pressure`` or ``absolute_pressure``; with a gauge
pressure the ``ambient`` pressure, default 101.325 kPa, is added), effective area ``A``,
bag and reservoir volumes ``Vb``, ``Vr``, polytropic exponent ``n`` (default 1.4,
adiabatic; 1 isothermal) and the effective area's change with the deflection
``area_gradient`` ``dA/dz`` [m^2/m, default 0].  The gas's stiffness of a volume ``V``
is ``n p_abs A^2 / V`` and the area term ``p_gauge dA/dz``; with ``k_b = n p_abs A^2/Vb``
and ``k_r = n p_abs A^2/Vr`` the pneumatic circuit (bag, orifice, reservoir) is ``k_b`` in
series with (``k_r`` parallel to the orifice), whose three-parameter equivalent is

    k_bag = k_b k_r / (k_b + k_r) + p_gauge dA/dz = n p_abs A^2 / (Vb + Vr) + p_gauge dA/dz
    k_res = k_b^2 / (k_b + k_r)                   = n p_abs A^2 Vr / (Vb (Vb + Vr))
    c     = R A^2 (Vr / (Vb + Vr))^2              (an ``orifice_resistance`` R [Pa s/m^3])

or ``orifice`` given as ``c`` itself.  Without a reservoir volume the air spring is the bag
alone, ``n p_abs A^2 / Vb + p_gauge dA/dz``.  Sources: Berg, "A three-dimensional
airspring model with friction and orifice damping", *Vehicle System Dynamics* 33 (suppl.,
1999) 528-539 (its vertical model without the friction part); Bruni, Vinolas, Berg, Polach
& Stichel, "Modelling of suspension components in a rail vehicle dynamics context",
*Vehicle System Dynamics* 49 (2011) 1021-1072 (the air spring models, Nishimura's among
them); the volumes' stiffness ``n p A^2 / V`` from the polytropic law ``p V^n`` constant,
the three-parameter equivalent of the circuit derived and tested in
``tests/test_forces_air_spring.py``.
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from express.base.units import DIMENSIONS
from express.model.records import Axis, Element, ElementKind, Motion

__all__ = ["AIR_SPRING_KEYS", "AMBIENT", "read_air_spring"]

AIR_SPRING_KEYS = ("bag", "reservoir", "orifice", "gauge_pressure", "absolute_pressure", "ambient", "area",
                   "bag_volume", "reservoir_volume", "polytropic", "area_gradient", "orifice_resistance",
                   "lateral", "longitudinal")
SHEAR_KEYS = ("stiffness", "damping")
#: The standard atmosphere [Pa], added to a gauge pressure.
AMBIENT = sp.Integer(101325)
_GAS = ("gauge_pressure", "absolute_pressure", "area", "bag_volume", "reservoir_volume", "polytropic",
        "area_gradient", "orifice_resistance", "ambient")
_AREA = DIMENSIONS["length"] ** 2
_VOLUME = DIMENSIONS["length"] ** 3
#: Dimension of each gas input, and whether it must be positive (else >= 0).
_INPUTS = {
    "gauge_pressure": (DIMENSIONS["pressure"], False), "absolute_pressure": (DIMENSIONS["pressure"], True),
    "ambient": (DIMENSIONS["pressure"], True), "area": (_AREA, True), "bag_volume": (_VOLUME, True),
    "reservoir_volume": (_VOLUME, True), "polytropic": (DIMENSIONS["dimensionless"], True),
    "area_gradient": (DIMENSIONS["length"], False), "orifice_resistance": (DIMENSIONS["pressure"] / _VOLUME * DIMENSIONS["time"], True),
}


def read_air_spring(reader: Any, element_id: str, path: tuple[str, ...], item: str, spec: dict,
                    base: Element) -> list[Element]:
    """The elements of the air spring ``spec["air_spring"]`` on the element ``base`` (its
    ends, direction and own damping as read): the bag, the reservoir branch and the shear
    elements (module docstring); problems go to ``reader`` with the line."""
    where = path + ("air_spring",)
    table = reader.table(spec["air_spring"], where, item)
    reader.unknown_keys(table, AIR_SPRING_KEYS, where, item)
    if base.rotational or base.direction is not Axis.Z or base.vector is not None:
        reader.problem(path + ("direction",), item, 'an air spring acts along z (direction = "z"); its shear '
                       "stiffness goes in lateral = {...} / longitudinal = {...}")
    for clash in ("stiffness", "series", "gap", "friction", "characteristic"):
        if clash in spec:
            reader.problem(path + (clash,), item, f'an air spring has no "{clash}": its stiffness is the bag\'s '
                           "(air_spring = {bag = ...} or the gas's pressure, area and volumes)")

    def value(key: str) -> sp.Expr:
        return reader.expression(table[key], where + (key,), item, f"air_spring {key}")

    given = [key for key in ("bag", "reservoir") if key in table]
    gas = [key for key in _GAS if key in table]
    checked: list[tuple[str, sp.Expr, Any, bool]] = []
    orifice = value("orifice") if "orifice" in table else None
    if given and gas:
        reader.problem(where, item, f"an air spring is given either directly (bag, reservoir, orifice) or by its gas "
                       f"(pressure, area, volumes), not both: got {', '.join(given + gas)}")
        return [base]
    if given:
        if "bag" not in table:
            reader.problem(where, item, "an air spring given directly needs its bag stiffness (bag = ...)")
            return [base]
        bag = value("bag")
        reservoir = value("reservoir") if "reservoir" in table else None
    else:
        found = _from_gas(reader, where, item, table, gas, value, orifice, checked)
        if found is None:
            return [base]
        bag, reservoir, orifice = found
    if reservoir is not None and orifice is None:
        reader.problem(where, item, "an air spring with a reservoir needs its orifice damping (orifice = ...) "
                       "or the orifice_resistance")
    if reservoir is None and orifice is not None:
        reader.problem(where, item, "an orifice needs a reservoir (reservoir = ... or reservoir_volume = ...)")
    label = base.label or f"air spring {element_id}"
    line = reader.line(*where)  # messages on the derived elements point at the air spring's own line
    derived: tuple = ()
    if checked:  # from the gas: the inputs' dimensions are checked, not the formulas' (bare numbers are SI)
        damping = DIMENSIONS["damping"]
        checked.append(("damping", base.damping, damping, False))
        if "orifice" in table:
            checked.append(("air_spring orifice", orifice, damping, True))
        derived = ((f"derived from air spring {element_id}", sp.S.Zero, DIMENSIONS["dimensionless"], False),)
    elements = [Element(element_id, bag, base.damping, base.s_end, base.t_end, base.direction, f"{label}: bag",
                        line, checked=tuple(checked))]
    if reservoir is not None and orifice is not None:
        elements.append(Element(f"{element_id}_reservoir", reservoir, orifice, base.s_end, base.t_end, base.direction,
                                f"{label}: reservoir and orifice", line, kind=ElementKind.SERIES, checked=derived))
    for key, axis in (("lateral", Axis.Y), ("longitudinal", Axis.X)):
        if key in table:
            shear = reader.table(table[key], where + (key,), item)
            reader.unknown_keys(shear, SHEAR_KEYS, where + (key,), item)
            elements.append(Element(
                f"{element_id}_{key}",
                reader.expression(shear.get("stiffness", 0), where + (key, "stiffness"), item, f"{key} stiffness"),
                reader.expression(shear.get("damping", 0), where + (key, "damping"), item, f"{key} damping"),
                base.s_end, base.t_end, axis, f"{label}: {key} shear", line, motion=Motion.TRANSLATION))
    return elements


def _from_gas(reader: Any, where: tuple[str, ...], item: str, table: dict, gas: list[str], value: Any,
              orifice: sp.Expr | None, checked: list) -> tuple[sp.Expr, sp.Expr | None, sp.Expr | None] | None:
    """``(k_bag, k_res, c)`` from the gas's pressure, area and volumes (module docstring);
    the inputs go to ``checked`` with their dimensions; None when the gas is incomplete."""
    pressures = [key for key in ("gauge_pressure", "absolute_pressure") if key in table]
    missing = [key for key in ("area", "bag_volume") if key not in table]
    if len(pressures) != 1 or missing:
        reader.problem(where, item, "an air spring needs its bag stiffness (bag = ...) or its gas: one of "
                       "gauge_pressure / absolute_pressure, area and bag_volume"
                       + (f" (missing {', '.join(missing)})" if missing else "")
                       + (" (both pressures given)" if len(pressures) > 1 else ""))
        return None
    if "ambient" in table and "absolute_pressure" in table:
        reader.problem(where + ("ambient",), item, "ambient goes with a gauge_pressure only")
    inputs = {key: value(key) for key in gas}
    for key, expression in inputs.items():
        checked.append((key.replace("_", " "), expression, *_INPUTS[key]))
    gauge = inputs.get("gauge_pressure")
    absolute = inputs["absolute_pressure"] if gauge is None else gauge + inputs.get("ambient", AMBIENT)
    n = inputs.get("polytropic", sp.Float(1.4))
    area, bag_volume = inputs["area"], inputs["bag_volume"]
    effective = (gauge if gauge is not None else absolute - AMBIENT) * inputs.get("area_gradient", sp.S.Zero)
    gas_stiffness = n * absolute * area**2
    if "reservoir_volume" in inputs:
        volume = inputs["reservoir_volume"]
        bag = gas_stiffness / (bag_volume + volume) + effective
        reservoir = gas_stiffness * volume / (bag_volume * (bag_volume + volume))
        if "orifice_resistance" in inputs:
            if orifice is not None:
                reader.problem(where, item, "give orifice (its damping) or orifice_resistance, not both")
            orifice = inputs["orifice_resistance"] * area**2 * (volume / (bag_volume + volume)) ** 2
    else:
        bag, reservoir = gas_stiffness / bag_volume + effective, None
        if "orifice_resistance" in inputs:
            reader.problem(where, item, "an orifice needs a reservoir (reservoir_volume = ...)")
    return bag, reservoir, orifice
