"""Contact geometry from a table file (``conicity = { from = "table", ... }``,
:mod:`express.io.contact_table_file`, :mod:`express.rail.table_contact`) and Kalker's
coefficients given directly (issue 33, item 4)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cli_support import assert_input_error
from express.analysis.time.simulate import simulate
from express.base.diagnostics import ModelError
from express.io.contact_table_file import write_contact_table
from express.io.toml_model import parse_toml_model
from express.numeric.statespace import vehicle_model
from express.rail.contact_geometry import ContactSetup
from express.rail.contact_tables import C11, FIELDS, LEAD_RATE, contact_tables
from express.rail.profile_contact import wheelset_contacts
from express.rail.profiles import standard_profile
from express.rail.table_contact import export_profile_table, file_tables
from express.rail.track import Straight, Track
from test_profile_contact import WHEELSET

PROFILES = 'conicity = { from = "profiles", wheel = "S1002", rail = "60E1", inclination = "1:40", gauge = "1435 mm", flange_back = "1360 mm", amplitude = "A" }'
TRACK = Track((Straight(5000.0),))


def table_model(tmp_path, node: str, text: str = WHEELSET):
    assert PROFILES in text
    path = tmp_path / "wheelset.toml"
    path.write_text(text.replace(PROFILES, f"conicity = {node}"))
    return parse_toml_model(path.read_text(), str(path))


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """Our S1002/60E1 geometry written as a table file (every 0.01 mm, with curvatures)."""
    folder = tmp_path_factory.mktemp("table")
    export_profile_table(standard_profile("S1002"), standard_profile("60E1"), ContactSetup(), folder / "contact.csv")
    return folder


def test_table_file_reproduces_the_profile_tables(exported):
    """Read back, the table file gives our tables: every field to 1e-8 relative (the
    file's 12 digits; achieved 2e-10 for C23), but the contact's lead per yaw, which the
    file route takes from the angles (``r tan(theta) - arm``): within 0.01 m/rad (achieved
    0.0072 m/rad, in the two-point flange zone only)."""
    read = file_tables(exported / "contact.csv")
    ours = contact_tables(standard_profile("S1002"), standard_profile("60E1"), ContactSetup())
    assert read.data.shape == ours.data.shape and read.start == pytest.approx(ours.start, abs=1e-12)
    for field, name in enumerate(FIELDS):
        scale = np.abs(ours.data[field]).max()
        tolerance = 0.01 if field == LEAD_RATE else 1e-8 * scale
        assert np.abs(read.data[field] - ours.data[field]).max() <= tolerance, name


def test_linear_and_time_run_match_the_profile_route(exported):
    """The table route's linear model equals the profile route's (results to 1e-9, achieved
    3e-11; eigenvalues at 30 m/s to 1e-10 of the largest, achieved 6e-13) and a 1 s
    contact run (FASTSIM tables, flange, saturation) from a 2 mm offset agrees to 1e-9 m
    (achieved 1.6e-11 m)."""
    profiles = vehicle_model(parse_toml_model(WHEELSET, "wheelset.toml"))
    table = vehicle_model(table_model(exported, '{ from = "table", file = "contact.csv", amplitude = "A" }'))
    for key in ("Gamma_e", "Gamma_e_ky", "Gamma_e_kpsi", "Gamma_e_f23", "Gamma_e_epsilon", "Gamma_e_sigma"):
        assert table.values[key] == pytest.approx(profiles.values[key], rel=1e-9), key
    ours, theirs = (np.sort_complex(vehicle.eigenvalues(30.0)) for vehicle in (profiles, table))
    assert np.abs(ours - theirs).max() <= 1e-10 * np.abs(ours).max()
    state = np.zeros(profiles.form.size)
    state[0] = 2e-3
    runs = [simulate(vehicle, TRACK, speed=30.0, dt=0.002, end=30.0, initial_state=state, progress=False)
            for vehicle in (profiles, table)]
    assert np.abs(runs[0].q[:, 0] - 2e-3).max() > 1e-4  # it moved
    assert np.abs(runs[0].q - runs[1].q).max() < 1e-9


def cone(folder, slope: float = 0.05, r0: float = 0.46, l0: float = 0.75):
    """A conical wheel on a knife-edge rail: ``r = r0 +- slope y``, contact angles
    ``slope``, contacts at ``l0`` from the wheelset centre, no roll."""
    y = np.linspace(-10e-3, 10e-3, 21)
    ones = np.ones_like(y)
    write_contact_table(folder / "cone.csv", {
        "y": y, "r_L": r0 + slope * y, "r_R": r0 - slope * y, "delta_L": slope * ones, "delta_R": slope * ones,
        "y_cL": l0 + y, "y_cR": l0 - y, "roll": 0 * y}, "conical wheel, closed form")


def test_conical_wheel_gives_the_closed_form(tmp_path):
    """Cone of slope 0.05: equivalent conicity 0.05 (EN 15302 of a linear delta r is its
    slope: to 1e-9), epsilon = sigma = 0, no gravitational lateral stiffness, and the
    kinematic (Klingel) hunting of a nearly free wheelset at 5 m/s: ``omega = v
    sqrt(lambda / (r0 b))`` = 1.9035 rad/s (to 1e-4; achieved 2.2e-6, the share of the
    inertia, the 1 N/m springs and the gravitational yaw stiffness)."""
    cone(tmp_path)
    text = WHEELSET.replace('ky = { value = 1.0, unit = "MN/m" }', 'ky = { value = 1, unit = "N/m" }').replace(
        'kx = { value = 5.0, unit = "MN/m" }', 'kx = { value = 1, unit = "N/m" }')
    vehicle = vehicle_model(table_model(tmp_path, '{ from = "table", file = "cone.csv", amplitude = "A" }', text))
    values = vehicle.values
    assert values["Gamma_e"] == pytest.approx(0.05, abs=1e-9)
    assert values["Gamma_e_epsilon"] == pytest.approx(0, abs=1e-12)
    assert values["Gamma_e_sigma"] == pytest.approx(0, abs=1e-12)
    assert values["Gamma_e_ky"] == pytest.approx(0, abs=1e-6)
    assert values["Gamma_e_l0"] == pytest.approx(0.75, abs=1e-12)
    klingel = 5.0 * math.sqrt(0.05 / (0.46 * 0.75))
    eigenvalues = vehicle.eigenvalues(5.0)
    nearest = eigenvalues[np.argmin(np.abs(np.abs(eigenvalues.imag) - klingel))]
    assert abs(nearest.imag) == pytest.approx(klingel, rel=1e-4)


def test_given_coefficients_enter_exactly(tmp_path):
    """Given f23 [N m] enters the lateral-yaw creep terms exactly (``C[y, psi] = 2 f23 / v``,
    ``P[y, rho] = -2 f23``, and the spin part of the gravitational stiffness, docs/contact.md);
    given f11, f22 scale the simulation's tables so that the centred contact has them."""
    cone(tmp_path)
    node = ('{ from = "table", file = "cone.csv", amplitude = "A", f11 = "9 MN", f22 = "8 MN", f23 = "2 kN*m", '
            'f33 = "15 N*m^2" }')
    model = table_model(tmp_path, node)
    vehicle = vehicle_model(model)
    values = vehicle.values
    assert values["Gamma_e_f23"] == 2000.0 and values["Gamma_e_f11"] == 9e6 and values["Gamma_e_f22"] == 8e6
    y, psi = vehicle.dof_index("W1.y"), vehicle.dof_index("W1.rz")
    assert vehicle.damping_creep[y, psi] == pytest.approx(2 * 2000.0, rel=1e-12)
    assert vehicle.forcing_base[y, list(vehicle.inputs).index("W1.rho")] == pytest.approx(-2 * 2000.0, rel=1e-12)
    tangent = math.tan(0.05)
    expected = -2 * tangent * (0.75 - 0.46 * tangent) * (50e3 - 2000.0 / 0.46)  # yaw stiffness, closed form
    assert values["Gamma_e_kpsi"] == pytest.approx(expected, rel=1e-12)
    tables = wheelset_contacts(model, values, vehicle.wheelsets)[0].tables
    plain = file_tables(tmp_path / "cone.csv")
    ratio = tables.data[C11] / plain.data[C11]
    assert np.ptp(ratio) < 1e-12 and ratio[0, 0] != pytest.approx(1.0)


BAD = [
    ("y, r_L, r_R, delta_L, delta_R, y_cL, roll\nmm, mm, mm, rad, rad, mm, rad\n0, 460, 460, 0.05, 0.05, 750, 0\n"
     "1, 460, 460, 0.05, 0.05, 750, 0\n", 'contact.csv:1: missing column "y_cR"'),
    ("y, r_L, r_R, delta_L, delta_R, y_cL, y_cR, roll\nmm, mm, mm, rad, rad, mm, mm, rad\n"
     "-1, 460, 460, 0.05, 0.05, 750, 750, 0\n1, 460, 460, 0.05, 0.05, 750, 750, 0\n"
     "0, 460, 460, 0.05, 0.05, 750, 750, 0\n", "contact.csv:5: y must increase strictly"),
    ("y, r_L, r_R, delta_L, delta_R, y_cL, y_cR, roll\nmm, mm, kg, rad, rad, mm, mm, rad\n"
     "-1, 460, 460, 0.05, 0.05, 750, 750, 0\n1, 460, 460, 0.05, 0.05, 750, 750, 0\n",
     "contact.csv:2: column r_R: unit 'kg'"),
    ("# a comment\ny, r_L, r_R, delta_L, delta_R, y_cL, y_cR, roll\nmm, mm, mm, rad, rad, mm, mm, rad\n"
     "-1, 460, 460, 0.05, 0.05, 750, 750, 0\n1, 460, nan, 0.05, 0.05, 750, 750, 0\n",
     "contact.csv:5: r_R: 'nan' is not a finite number"),
]


@pytest.mark.parametrize(("table", "mention"), BAD)
def test_bad_tables_name_file_and_line(tmp_path, table, mention):
    (tmp_path / "contact.csv").write_text(table)
    with pytest.raises(ModelError) as error:
        table_model(tmp_path, '{ from = "table", file = "contact.csv" }')
    assert mention in str(error.value)


@pytest.mark.parametrize(("table", "mention"), BAD[:2])
def test_bad_tables_exit_2_and_write_nothing(capsys, tmp_path, table, mention):
    (tmp_path / "contact.csv").write_text(table)
    path = tmp_path / "wheelset.toml"
    path.write_text(WHEELSET.replace(PROFILES, 'conicity = { from = "table", file = "contact.csv" }'))
    out = tmp_path / "out.npz"
    assert_input_error(capsys, "export", str(path), "-o", str(out), mentions=mention)
    assert not out.exists()


def test_bad_node_keys(tmp_path):
    cone(tmp_path)
    with pytest.raises(ModelError) as error:
        table_model(tmp_path, '{ from = "table", file = "cone.csv", f23 = "3 N", wheel = "S1002" }')
    text = str(error.value)
    assert "f23" in text and "wheel" in text


def test_written_model_keeps_the_table_node(tmp_path):
    """The TOML writer writes the node back; read again it gives the same results."""
    from express.io.toml_writer import model_to_toml

    cone(tmp_path)
    model = table_model(tmp_path, '{ from = "table", file = "cone.csv", amplitude = "A", f23 = "2 kN*m" }')
    text = model_to_toml(model, tmp_path)
    assert 'from = "table"' in text and 'file = "cone.csv"' in text
    again = parse_toml_model(text, str(tmp_path / "again.toml"))
    assert again.values()["Gamma_e_f23"] == 2000.0
    assert again.values()["Gamma_e"] == pytest.approx(model.values()["Gamma_e"], rel=1e-15)


def test_profiles_node_takes_given_coefficients_too():
    """``from = "profiles"`` with ``f23`` given: the linear terms use it (``ky``'s spin part,
    closed form of docs/contact.md), the other results stay the profiles'."""
    plain = parse_toml_model(WHEELSET, "wheelset.toml").values()
    given = parse_toml_model(WHEELSET.replace('amplitude = "A" }', 'amplitude = "A", f23 = "5 kN*m" }'),
                             "wheelset.toml").values()
    assert given["Gamma_e_f23"] == 5000.0 and given["Gamma_e"] == plain["Gamma_e"]
    eps, sigma, l0, r0 = (plain[f"Gamma_e_{key}"] for key in ("epsilon", "sigma", "l0", "r0"))
    c2 = math.cos(plain["Gamma_e_delta0"]) ** 2
    change = -2 * (5000.0 - plain["Gamma_e_f23"]) * (eps / c2 - sigma) / (l0 * r0)
    assert given["Gamma_e_ky"] - plain["Gamma_e_ky"] == pytest.approx(change, rel=1e-9)


def test_bundled_example_table():
    """``examples/contact/cone-0.05.csv`` is the cone of :func:`cone` (docs/model-format.md)."""
    from pathlib import Path

    from express.io.contact_table_file import read_contact_table

    path = Path(__file__).resolve().parents[1] / "examples" / "contact" / "cone-0.05.csv"
    columns = read_contact_table(path).columns
    assert np.allclose(columns["r_L"] - columns["r_R"], 2 * 0.05 * columns["y"], atol=1e-15)
    assert np.allclose(columns["y_cL"] - columns["y"], 0.75, atol=1e-15)


def test_every_problem_of_a_table_at_once(tmp_path):
    """The table of docs/model-format.md's error example: four problems, in line order."""
    (tmp_path / "contact.csv").write_text("y, r_L, r_R, delta_L, delta_R, y_cL, roll\nmm, mm, kg, rad, rad, mm, rad\n"
                                          "0, 460, 460, 0.05, 0.05, 750, 0\n-1, 460, nan, 0.05, 0.05, 750, 0\n")
    with pytest.raises(ModelError) as error:
        table_model(tmp_path, '{ from = "table", file = "contact.csv" }')
    lines = [problem.message.replace(f"{tmp_path}/", "") for problem in error.value.problems]
    assert lines == ['contact.csv:1: missing column "y_cR"',
                     "contact.csv:2: column r_R: unit 'kg': 'kg' is not a length (m)",
                     "contact.csv:4: r_R: 'nan' is not a finite number",
                     "contact.csv:4: y must increase strictly: -1 mm after 0 mm"]


def test_a_wear_prediction_refuses_a_table(tmp_path):
    """A table file has no wheel profile to wear: a clear error, not a crash."""
    from express.analysis.wear.cases import profile_nodes_of
    from express.base.diagnostics import ArgumentError

    cone(tmp_path)
    vehicle = vehicle_model(table_model(tmp_path, '{ from = "table", file = "cone.csv" }'))
    with pytest.raises(ArgumentError, match="does not come from profiles"):
        profile_nodes_of(vehicle)
