"""The contact of a wheelset from a tabulated contact geometry read from a file (another
program's export, :mod:`express.io.contact_table_file`), and Kalker's coefficients given
directly: the ``conicity = { from = "table", file = ..., f23 = ... }`` node.

The node is a ``"profiles"`` derivation (same results, :data:`express.io.toml_contact.PROFILE_OUTPUTS`)
whose settings name a ``table`` file instead of profiles, so that the linear model (the
equivalent conicity and Wickens' contact terms) and the simulation (the contact tables)
take it exactly as they take profiles.  The file is resampled on the uniform grid of
:class:`~express.rail.contact_tables.ContactTables` (0.01 mm, linear interpolation, 0 a
node).  The Hertz ellipse of each contact uses the rolling relative curvature
``cos(theta) / (2 r)`` and the lateral one ``kappa / 2`` (``kappa`` of the file, at least
0.04 1/m as for profiles; without it, a circular contact).

Kalker's coefficients given (``f11``, ``f22`` [N], ``f23`` [N m], ``f33`` [N m^2]) replace the
centred contact's values: the linear terms use the given ``f23``; the simulation's tables
have their C11, C22, C23 scaled by one factor each so that the centred contact under the
wheel load gives the given values (their change with ``y`` stays Hertz's).  ``f33`` is
recorded, not used: neither the linearised wheelset nor the creep law has a spin moment.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from express.base.diagnostics import ArgumentError, ModelError
from express.io.contact_table_file import ContactTableData, read_contact_table, write_contact_table
from express.rail.conicity import equivalent_conicity
from express.rail.contact import hertz_contact
from express.rail.contact_geometry import ContactSetup, prepare_surfaces, solve_contact
from express.rail.contact_tables import (
    ANGLE,
    ARM,
    AXLE_ANGLE,
    C11,
    C22,
    C23,
    COS_ANGLE,
    FIELDS,
    LEAD_RATE,
    RADIUS,
    ROLL,
    ROLL_SLOPE,
    SECANT_CBRT,
    SEMI_A,
    SEMI_B,
    SIN_ANGLE,
    SIN_AXLE,
    ContactTables,
    LinearContact,
    linear_contact_parameters,
)
from express.rail.kalker import kalker_coefficients
from express.rail.profiles import Profile

__all__ = ["COEFFICIENTS", "STEP", "export_profile_table", "file_tables", "given_coefficients", "table_derivation",
           "table_path"]

#: The grid step of the resampled tables [m].
STEP = 1e-5
#: Kalker's coefficients a node may give: (key, dimension).
COEFFICIENTS = (("f11", "force"), ("f22", "force"), ("f23", "rotational_stiffness"), ("f33", "spin_coefficient"))
_MIN_LATERAL = 0.02  # smallest B = kappa / 2 [1/m], as for profiles
_CACHE: dict[tuple, ContactTables] = {}


def table_path(table: str, base: str) -> Path:
    """The table file, relative to ``base`` (the model's folder)."""
    path = Path(table)
    return path if path.is_absolute() else Path(base or ".") / path


def file_tables(path: str | Path, youngs_modulus: float = 206e9, poisson: float = 0.3) -> ContactTables:
    """:class:`ContactTables` of a contact table file, resampled every :data:`STEP`.

    Raises
    ------
    ArgumentError
        For a file that cannot be read (its problems with their lines).
    """
    path = Path(path)
    try:
        stamp = path.stat().st_mtime_ns
    except OSError:
        stamp = 0
    key = (str(path.resolve()), stamp, float(youngs_modulus), float(poisson))
    if key not in _CACHE:
        try:
            data = read_contact_table(path)
        except ModelError as error:
            raise ArgumentError("; ".join(str(problem) for problem in error.problems)) from None
        _CACHE[key] = _resampled(data, youngs_modulus, poisson)
    return _CACHE[key]


def _resampled(data: ContactTableData, youngs_modulus: float, poisson: float) -> ContactTables:
    given = data.columns
    first, last = math.ceil(given["y"][0] / STEP - 1e-9), math.floor(given["y"][-1] / STEP + 1e-9)
    y = STEP * np.arange(first, last + 1)
    column = {name: np.interp(y, given["y"], values) for name, values in given.items()}
    table = np.zeros((len(FIELDS), 2, len(y)))
    sign = np.array([[1.0], [-1.0]])
    table[RADIUS] = [column["r_L"], column["r_R"]]
    table[ANGLE] = [column["delta_L"], column["delta_R"]]
    table[ROLL] = column["roll"]
    table[ROLL_SLOPE] = np.gradient(column["roll"], y)
    table[AXLE_ANGLE] = table[ANGLE] - sign * table[ROLL]
    table[ARM] = np.array([column["y_cL"], column["y_cR"]]) - sign * y
    table[COS_ANGLE], table[SIN_ANGLE] = np.cos(table[ANGLE]), np.sin(table[ANGLE])
    table[SIN_AXLE] = np.sin(table[AXLE_ANGLE])
    table[LEAD_RATE] = sign * (table[RADIUS] * np.tan(table[AXLE_ANGLE]) - table[ARM])
    table[SECANT_CBRT] = np.cos(table[ANGLE]) ** (-1.0 / 3.0)
    rolling = 0.5 * np.cos(table[AXLE_ANGLE]) / table[RADIUS]
    if "kappa_L" in column:
        lateral = np.maximum(0.5 * np.array([column["kappa_L"], column["kappa_R"]]), _MIN_LATERAL)
    else:
        lateral = rolling
    cache: dict[tuple[float, float], tuple[float, ...]] = {}
    for side in (0, 1):
        for k in range(len(y)):
            key = (round(float(rolling[side, k]), 9), round(float(lateral[side, k]), 6))
            if key not in cache:
                ellipse = hertz_contact(1.0, 0.5 / key[0], 0.5 / key[1], youngs_modulus, poisson)
                cache[key] = (ellipse.a, ellipse.b, *kalker_coefficients(ellipse.a, ellipse.b, poisson)[:3])
            table[SEMI_A:C23 + 1, side, k] = cache[key]
    centre = int(np.argmin(np.abs(y)))
    setup = ContactSetup(wheel_radius=float(np.mean(table[RADIUS, :, centre])))
    return ContactTables(float(y[0]), STEP, table, setup, float(youngs_modulus), float(poisson),
                         Path(data.source).name)


def _centred(tables: ContactTables, wheel_load: float, delta0: float) -> tuple[float, float, float]:
    """f11, f22 [N], f23 [N m] of the centred contact under ``wheel_load / cos(delta0)``."""
    centre = int(np.argmin(np.abs(tables.y)))
    scale = (wheel_load / math.cos(delta0)) ** (1.0 / 3.0)
    ab = float(np.mean(tables.data[SEMI_A, :, centre] * tables.data[SEMI_B, :, centre])) * scale * scale
    shear = tables.shear_modulus
    return (shear * ab * float(np.mean(tables.data[C11, :, centre])),
            shear * ab * float(np.mean(tables.data[C22, :, centre])),
            shear * ab**1.5 * float(np.mean(tables.data[C23, :, centre])))


def given_coefficients(tables: ContactTables, wheel_load: float, given: dict[str, float]) -> ContactTables:
    """``tables`` with C11, C22, C23 scaled so that the centred contact has the ``given``
    f11, f22, f23 (NaN or absent: unchanged)."""
    wanted = [given.get(key, math.nan) for key in ("f11", "f22", "f23")]
    if all(math.isnan(value) for value in wanted):
        return tables
    delta0 = float(np.mean(tables.data[ANGLE, :, int(np.argmin(np.abs(tables.y)))]))
    own = _centred(tables, wheel_load, delta0)
    data = tables.data.copy()
    for field, value, current in zip((C11, C22, C23), wanted, own, strict=True):
        if not math.isnan(value):
            data[field] *= value / current
    return ContactTables(tables.start, tables.step, data, tables.setup, tables.youngs_modulus, tables.poisson,
                         tables.names)


def table_derivation(*, table: str, base: str = "", amplitude: float, wheel_load: float, youngs_modulus: float,
                     poisson: float, **given: float) -> tuple[dict[str, float], LinearContact]:
    """The results of a ``from = "table"`` node but the linear wheelset terms (those of
    :func:`express.rail.profile_contact.profile_derivation`, SI, which adds them from the
    returned :class:`LinearContact`); ``given``: Kalker's coefficients of
    :data:`COEFFICIENTS` the model gives (NaN: from the table's Hertz)."""
    if not amplitude > 0:
        raise ArgumentError(f"amplitude must be positive, got {amplitude:g} m")
    if not wheel_load > 0:
        raise ArgumentError(f"wheel_load must be positive, got {wheel_load:g} N")
    tables = file_tables(table_path(table, base), youngs_modulus, poisson)
    try:
        linear = linear_contact_parameters(tables, amplitude)
        conicity = float(equivalent_conicity(tables.y, tables.data[RADIUS, 0] - tables.data[RADIUS, 1], amplitude))
    except ModelError as error:
        raise ArgumentError("; ".join(p.message for p in error.problems)) from None
    f11, f22, f23 = (value if math.isnan(given.get(key, math.nan)) else given[key]
                     for key, value in zip(("f11", "f22", "f23"), _centred(tables, wheel_load, linear.delta0),
                                           strict=True))
    return {"conicity": conicity, "epsilon": linear.epsilon, "sigma": linear.sigma, "delta0": linear.delta0,
            "half_distance": linear.half_distance, "radius": linear.radius, "f11": f11, "f22": f22,
            "f23": f23}, linear


def export_profile_table(wheel: Profile, rail: Profile, setup: ContactSetup, path: str | Path, *,
                         reach: float = 15e-3, step: float = STEP) -> None:
    """Write the contact geometry of a wheel/rail pair (:func:`express.rail.contact_geometry.solve_contact`)
    as a contact table file for ``|y| <= reach`` every ``step`` [m], with the curvatures."""
    count = math.ceil(reach / step - 1e-9)
    y = step * np.arange(-count, count + 1)
    geometry = solve_contact(prepare_surfaces(wheel, rail, setup), y, setup)
    kappa = geometry.wheel_curvature_lateral + geometry.rail_curvature_lateral
    columns = {"y": y, "r_L": geometry.radius[0], "r_R": geometry.radius[1], "delta_L": geometry.contact_angle[0],
               "delta_R": geometry.contact_angle[1], "y_cL": geometry.track_position[0],
               "y_cR": geometry.track_position[1], "roll": geometry.roll, "kappa_L": kappa[0], "kappa_R": kappa[1]}
    write_contact_table(path, columns, f"{wheel.name} on {rail.name}: {setup}")
