"""The force elements of one run: which elements a vehicle and the run's options ask for,
built on the run's track inputs (:mod:`express.forces`), for the time march and the
steady-curving solver alike.

The wheel/rail element comes first — the contact from the profiles' tables when the
model's conicity comes from profiles (its wheel loads from
:func:`express.analysis.curving.measure.march_wheel_loads`), else the paper's dead-band
flange spring and saturation — then the bump stops, the friction elements and the
characteristics.
"""

from __future__ import annotations

from dataclasses import dataclass

from express.analysis.time.track_inputs import TrackInputs
from express.base.diagnostics import ArgumentError
from express.forces.bump_stops import bump_stops_of
from express.forces.characteristic import characteristic_elements_of
from express.forces.contact import ContactElement, linear_coefficients, roll_coordinates
from express.forces.deadband import DeadbandElement
from express.forces.element import ForceElement, ForceSet
from express.forces.friction import friction_elements_of
from express.forces.wheelsets import wheelset_coordinates
from express.numeric.statespace import VehicleModel
from express.rail.contact_forces import ContactSet
from express.rail.options import ContactModel, CreepLaw

__all__ = ["RunForces", "contact_tables_of", "run_forces"]


@dataclass(frozen=True)
class RunForces:
    """The force elements of a run and what the run reports of them.

    Attributes
    ----------
    forces : ForceSet
    wheel_loads : str or None
        Where the contact's wheel loads come from (``"dynamic"``, ``"quasi-static
        estimate"``), None without the contact tables.
    """

    forces: ForceSet
    wheel_loads: str | None = None

    @property
    def contact(self) -> ContactElement | None:
        """The contact element, if the run has one."""
        found = self.forces.of_kind(ContactElement)
        return found[0] if found else None  # type: ignore[return-value]


def contact_tables_of(vehicle: VehicleModel, contact: ContactModel | None, creep_law: CreepLaw) -> ContactSet | None:
    """The stacked contact tables when the contact comes from profiles (``None``: the
    dead-band model)."""
    if contact not in (None, "tables", "deadband"):
        raise ArgumentError(f'contact must be "tables" or "deadband", not {contact!r}')
    if contact == "deadband" or vehicle.model is None:
        return None
    from express.forces.contact import contact_arrays
    from express.rail.profile_contact import wheelset_contacts

    contacts = wheelset_contacts(vehicle.model, vehicle.values, vehicle.wheelsets)
    if any(c is None for c in contacts):
        if contact == "tables":
            missing = [w.name for w, c in zip(vehicle.wheelsets, contacts, strict=True) if c is None]
            raise ArgumentError(f"contact tables need profiles for every wheelset (none for {', '.join(missing)})")
        return None
    return contact_arrays([c for c in contacts if c is not None], creep_law)


def run_forces(vehicle: VehicleModel, inputs: TrackInputs, speed: float, *, tables: ContactSet | None,
               flange: bool, saturation: bool, clearances: bool) -> RunForces:
    """The force elements of a run of ``vehicle`` at ``speed`` [m/s] on ``inputs``.

    Parameters
    ----------
    tables : ContactSet or None
        The contact tables (:func:`contact_tables_of`), or None for the dead-band model.
    flange, saturation : bool
        The dead-band model's flange contact and creep saturation.
    clearances : bool
        Include the suspension's nonlinear elements (bump stops, friction, characteristics);
        without them friction elements are stuck and characteristics are their tangents at
        the static state, as the linear analyses see them.
    """
    if clearances and getattr(vehicle, "tangent_vehicle", None) is not None:
        raise ArgumentError("a vehicle linearised for the linear analyses (express.forces.linearisation) holds its "
                            "nonlinear elements' equivalents in K and C; a run marches the whole elements: give its "
                            ".tangent_vehicle")
    coordinates = wheelset_coordinates(vehicle, inputs.y_rail, inputs.rho_wheelsets, speed)
    elements: list[ForceElement] = []
    kind = None
    if tables is not None:
        from express.analysis.curving.measure import march_wheel_loads

        loads, kind = march_wheel_loads(vehicle, inputs, speed, tables.wheel_load)
        elements.append(ContactElement(vehicle, coordinates, tables, linear_coefficients(vehicle, speed), loads,
                                       roll_coordinates(vehicle)))
    else:
        elements.append(DeadbandElement(vehicle, coordinates, flange=flange, saturation=saturation))
    if clearances:  # the suspension's nonlinear elements
        for element in (bump_stops_of(vehicle, inputs.u), friction_elements_of(vehicle, inputs.u),
                        characteristic_elements_of(vehicle, inputs.u, inputs.u_rate)):
            if element is not None:
                elements.append(element)
    return RunForces(ForceSet(tuple(elements), vehicle.form.size), kind)
