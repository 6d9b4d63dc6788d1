"""Contact geometry of a rigid wheelset (express.rail.contact_geometry).

Closed forms: conical and circular wheels on circular rails are solved independently
here (the tangency of a line or a circle to a circle, both wheels at once, with
scipy's fsolve) and compared point by point; the classical linear relations
(delta_r = 2 lambda y for cones; Wickens' lambda R_w / (R_w - R_r) for circular arcs)
hold to the roll correction.  S1002 on 60E1 checks symmetry, tangency and where the
flange contact starts.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq, fsolve

from express.rail.contact_geometry import ContactSetup, contact_geometry, rail_surface
from express.rail.profiles import Profile, standard_profile, uic60_height

R0 = 0.46


def circle_rail(radius: float) -> Profile:
    """An upright rail whose head is one circular arc (down to 85 % of its radius)."""
    y = np.linspace(-0.85 * radius, 0.85 * radius, 2001)
    return Profile("circle", "rail", y, -radius + np.sqrt(radius**2 - y**2))


def cone_wheel(conicity: float) -> Profile:
    s = np.linspace(-0.04, 0.05, 901)
    return Profile("cone", "wheel", s, conicity * s)


def arc_wheel(radius: float, delta0: float) -> Profile:
    """A hollow (concave) circular tread of ``radius``, centre below the tread (on the rail's
    side), slope tan(delta0) at the taping line."""
    s = np.linspace(-0.04, 0.05, 901)
    s0 = radius * math.sin(delta0)
    cz = -math.sqrt(radius**2 - s0**2)
    return Profile("arc", "wheel", s, cz + np.sqrt(radius**2 - (s - s0) ** 2))


def rot(phi: float, v):
    c, s = math.cos(phi), math.sin(phi)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def rail_centre(setup: ContactSetup, radius: float) -> np.ndarray:
    """Centre of a circular rail head in the track side frame (u outward, z), placed as
    the module places rails: inclined about the crown, top at z = 0, gauge point 14 mm
    below the top at u = gauge / 2 (computed here from the circle, independently)."""
    alpha = math.atan(setup.inclination)
    centre = rot(alpha, (0.0, -radius))  # the crown (origin) stays, the centre turns
    top = centre[1] + radius
    depth = setup.gauge_depth
    gauge_u = centre[0] - math.sqrt(radius**2 - (radius - depth) ** 2)
    return np.array([centre[0] - gauge_u + 0.5 * setup.gauge, centre[1] - top])


def exact_cone(y, conicity, radius, setup):
    """Roll, height and rolling radii of a cone on circular rails by tangency."""
    half = setup.tapeline_half_distance
    c = rail_centre(setup, radius)
    norm = math.hypot(1.0, conicity)

    def wheel_point(sigma, phi, zc, s):
        return np.array([y, zc]) + rot(phi, (sigma * (half + s), -R0 + conicity * s))

    def equations(x):
        phi, zc = x
        out = []
        for sigma in (1.0, -1.0):
            normal = rot(phi, (-sigma * conicity, 1.0)) / norm
            centre = np.array([sigma * c[0], c[1]])
            out.append(normal @ (wheel_point(sigma, phi, zc, 0.0) - centre) - radius)
        return out

    phi, zc = fsolve(equations, [0.0, R0], xtol=1e-12)
    radii = []
    for sigma in (1.0, -1.0):
        normal = rot(phi, (-sigma * conicity, 1.0)) / norm
        contact = np.array([sigma * c[0], c[1]]) + radius * normal
        local = rot(-phi, contact - np.array([y, zc]))
        s = sigma * local[0] - half
        radii.append(R0 - conicity * s)
    return phi, zc, radii


def uic60_crown_centre(setup: ContactSetup) -> np.ndarray:
    """Centre of 60E1's R300 crown in the track side frame, upright rail: the gauge point
    14 mm down lies on its R13 arc, found from the analytic head shape."""
    assert setup.inclination == 0.0
    gauge_y = brentq(lambda v: uic60_height(np.array([v]))[0] + 1e3 * setup.gauge_depth, -36.0, -20.0) * 1e-3
    return np.array([0.5 * setup.gauge - gauge_y, -0.3])


def exact_arc(y, wheel_radius, delta0, rail_radius, setup, c):
    """The same for a circular wheel arc on circular rails (centre ``c`` in the track side
    frame): the rail's circle touches the hollow wheel's from inside, R_w - R_r apart."""
    half = setup.tapeline_half_distance
    s0 = wheel_radius * math.sin(delta0)
    cz = -math.sqrt(wheel_radius**2 - s0**2)

    def wheel_centre(sigma, phi, zc):
        return np.array([y, zc]) + rot(phi, (sigma * (half + s0), -R0 + cz))

    def equations(x):
        phi, zc = x
        return [np.linalg.norm(wheel_centre(sigma, phi, zc) - np.array([sigma * c[0], c[1]])) - (wheel_radius - rail_radius)
                for sigma in (1.0, -1.0)]

    phi, zc = fsolve(equations, [0.0, R0], xtol=1e-12)
    radii, angles = [], []
    for sigma in (1.0, -1.0):
        w = wheel_centre(sigma, phi, zc)
        rail = np.array([sigma * c[0], c[1]])
        outward = (rail - w) / np.linalg.norm(rail - w)  # from the wheel's centre through the rail's
        contact = w + wheel_radius * outward
        local = rot(-phi, contact - np.array([y, zc]))
        s = sigma * local[0] - half
        radii.append(R0 - (cz + math.sqrt(wheel_radius**2 - (s - s0) ** 2)))
        angles.append(-math.atan2(sigma * outward[0], outward[1]))  # tangent's slope angle, side frame
    return phi, zc, radii, angles


Y = np.linspace(-6e-3, 6e-3, 25)


@pytest.mark.parametrize("conicity, radius, inclination", [(0.05, 0.04, 0.0), (0.1, 0.03, 0.0), (0.05, 0.04, 1 / 40)])
def test_cone_on_circular_rail_matches_tangency_solution(conicity, radius, inclination):
    setup = ContactSetup(inclination=inclination)
    table = contact_geometry(cone_wheel(conicity), circle_rail(radius), Y, setup)
    for k, y in enumerate(Y):
        phi, zc, (r_left, r_right) = exact_cone(y, conicity, radius, setup)
        assert table.roll[k] == pytest.approx(phi, abs=1e-9)
        assert table.height[k] == pytest.approx(zc - R0, abs=1e-8)
        assert table.radius[0, k] == pytest.approx(r_left, abs=1e-8)
        assert table.radius[1, k] == pytest.approx(r_right, abs=1e-8)
    # the textbook delta_r = 2 lambda y ignores the roll, which turns the contact on the
    # wheel by (r0 - rho) phi (knife edge: r0 phi): with it, to second order
    rolled = 2 * conicity * (Y + (R0 - radius) * table.roll)
    assert np.allclose(table.delta_r, rolled, rtol=0.01, atol=1e-12)
    plain = 2 * conicity * Y
    assert np.allclose(table.delta_r, plain, rtol=1.5 * conicity * R0 / 0.75, atol=1e-12)
    assert not np.allclose(table.delta_r, plain, rtol=0.3 * conicity * R0 / 0.75, atol=0)
    # contact angle: the cone's own angle plus the roll on each side
    assert np.allclose(table.contact_angle[0], math.atan(conicity) + table.roll, atol=1e-9)
    assert np.allclose(table.contact_angle[1], math.atan(conicity) - table.roll, atol=1e-9)
    assert np.allclose(table.rail_curvature_lateral, 1 / radius, rtol=1e-3)
    assert np.allclose(table.wheel_curvature_lateral, 0.0, atol=1e-6)
    assert not table.jumps


def test_circular_arcs_match_centre_distance_and_wickens():
    setup = ContactSetup(inclination=0.0)
    wheel_radius, delta0, rail_radius = 0.5, math.atan(0.01), 0.3
    wheel = arc_wheel(wheel_radius, delta0)
    rail = standard_profile("60E1")  # its crown is the R300 arc within +-10.2 mm
    y = np.linspace(-2e-3, 2e-3, 17)
    table = contact_geometry(wheel, rail, y, setup)
    assert np.abs(table.rail_position).max() < 10.2e-3  # stays on the R300 crown
    centre = uic60_crown_centre(setup)
    # nearly conformal (gap curvature 1/750 m): the contact point moves 750 m per unit of
    # slope error, so the 1 nm rounding of the tabulated 60E1 and its 0.3 um gauge point
    # show as a few um on the wheel; the radii agree to 0.1 um, the roll to 1e-8
    for k, yk in enumerate(y):
        phi, zc, (r_left, r_right), angles = exact_arc(yk, wheel_radius, delta0, rail_radius, setup, centre)
        assert table.roll[k] == pytest.approx(phi, abs=1e-8)
        assert table.height[k] == pytest.approx(zc - R0, abs=1e-8)
        assert table.radius[0, k] == pytest.approx(r_left, abs=1e-7)
        assert table.radius[1, k] == pytest.approx(r_right, abs=1e-7)
        assert table.contact_angle[:, k] == pytest.approx(angles, abs=2e-5)
    # Wickens: effective conicity tan(delta) R_w / (R_w - R_r), delta the centred contact
    # angle, without roll; the roll changes it by a few per cent here
    delta = exact_arc(0.0, wheel_radius, delta0, rail_radius, setup, centre)[3][0]
    slope = np.polyfit(y, table.delta_r, 1)[0] / 2
    wickens = math.tan(delta) * wheel_radius / (wheel_radius - rail_radius)
    assert slope == pytest.approx(wickens, rel=0.05)
    assert np.allclose(table.wheel_curvature_lateral, -1 / wheel_radius, rtol=1e-3)
    assert np.allclose(table.rail_curvature_lateral, 1 / rail_radius, rtol=1e-3)
    assert np.allclose(table.wheel_curvature_rolling, np.cos(table.contact_angle - [[1], [-1]] * table.roll) / table.radius)


@pytest.fixture(scope="module")
def s1002_table():
    y = np.arange(-1000, 1001) * 1e-5  # +-10 mm every 0.01 mm
    return contact_geometry(standard_profile("S1002"), standard_profile("60E1"), y, ContactSetup())


def test_s1002_60e1_symmetric(s1002_table):
    t = s1002_table
    assert np.allclose(t.delta_r, -t.delta_r[::-1], atol=1e-12)
    assert np.allclose(t.roll, -t.roll[::-1], atol=1e-12)
    assert np.allclose(t.contact_angle[0], t.contact_angle[1, ::-1], atol=1e-10)
    assert np.allclose(t.radius[0], t.radius[1, ::-1], atol=1e-12)
    assert t.delta_r[1000] == pytest.approx(0.0, abs=1e-12)
    left = {round(j.y_after, 6) for j in t.jumps if j.side == "left"}
    right = {round(-j.y_before, 6) for j in t.jumps if j.side == "right"}
    assert left == right


def test_s1002_60e1_flange_contact_and_angles(s1002_table):
    t = s1002_table
    # Manchester benchmark (S1002 / UIC60 1:40): flange contact starts between 6.0 and 6.5 mm
    flange = [j for j in t.jumps if j.side == "left" and j.position_after < -0.035]
    assert len(flange) == 1 and 6.0e-3 < flange[0].y_after < 6.5e-3
    # S1002's steepest flange face is 70.0 degrees (slope 2.7475) to the axle; the track
    # frame adds the roll
    to_axle = t.contact_angle - np.array([[1.0], [-1.0]]) * t.roll
    assert 69.9 < np.degrees(to_axle.max()) < 70.01
    assert np.degrees(t.contact_angle[0, -1]) > 40
    # delta_r rises with y and is larger in flange contact
    assert np.all(np.diff(t.delta_r) > -1e-9)
    assert t.delta_r[-1] > 0.015
    # the contact point on the rail moves toward the gauge face in flange contact
    assert t.rail_position[0, -1] < -0.03 < t.rail_position[0, 1000]


def test_tangency_at_the_contact(s1002_table):
    """The wheel's tangent (output) equals the rail's, looked up independently."""
    t = s1002_table
    rail = rail_surface(standard_profile("60E1"), t.setup)
    for row in (0, 1):
        u = t.track_position[row]
        grid = rail.start + rail.step * np.arange(len(rail.z))
        rail_angle = np.arctan(np.interp(u, grid, rail.dz))
        assert np.abs(rail_angle - t.contact_angle[row]).max() < 2e-3


def test_two_point_contact_at_the_flange_jump():
    y = np.arange(6.0, 6.5, 0.001) * 1e-3
    t = contact_geometry(standard_profile("S1002"), standard_profile("60E1"), y, ContactSetup())
    (jump,) = [j for j in t.jumps if j.side == "left"]
    k = int(np.flatnonzero(t.y == jump.y_before)[0])
    # just before the jump the flange is less than 1 um from the rail, and flagged
    assert t.secondary_gap[0, k] < 1e-6 and t.two_point[0, k]
    assert t.secondary_position[0, k] < -0.03  # on the flange
    assert not t.two_point[0, 0]


def test_table_interpolates(s1002_table):
    t = s1002_table
    values = t.at(np.array([0.0, 2.005e-3]))
    assert values["delta_r"][0] == pytest.approx(0.0, abs=1e-12)
    assert values["delta_r"][1] == pytest.approx(0.5 * (t.delta_r[1200] + t.delta_r[1201]))
    assert values["contact_angle"].shape == (2, 2)
    with pytest.raises(ValueError, match="outside"):
        t.at(0.011)


@pytest.mark.parametrize("kwargs, message", [
    ({"y": np.array([0.0, 0.0])}, "strictly increasing"),
    ({"y": np.array([np.nan])}, "finite"),
    ({"setup": ContactSetup(gauge=1.75)}, "no contact"),
])
def test_bad_arguments(kwargs, message):
    args = {"y": np.array([0.0]), "setup": ContactSetup()} | kwargs
    with pytest.raises(ValueError, match=message):
        contact_geometry(standard_profile("S1002"), standard_profile("60E1"), args["y"], args["setup"])


def test_bad_setup_and_kinds():
    with pytest.raises(ValueError, match="flange_back"):
        ContactSetup(gauge=1.3, flange_back=1.36)
    with pytest.raises(ValueError, match="inclination"):
        ContactSetup(inclination=-0.1)
    with pytest.raises(ValueError, match="wheel profile and a rail"):
        contact_geometry(standard_profile("60E1"), standard_profile("S1002"), np.zeros(1))


# --- express contact-geometry -----------------------------------------------------------


def test_cli_contact_geometry(tmp_path, capsys):
    from express.cli import main

    out, fig = tmp_path / "t.csv", tmp_path / "t.png"
    args = ["contact-geometry", "S1002", "UIC60", "--y-range=-1:1:0.5", "--inclination", "1:40", "--gauge", "1435 mm"]
    assert main([*args, "-o", str(out), "--plot", str(fig), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["points"] == 5 and summary["gauge_m"] == pytest.approx(1.435)
    assert [j["side"] for j in summary["jumps"]] == ["right", "left"]
    lines = out.read_text().splitlines()
    assert lines[0].startswith("y_m,roll_rad,height_m,delta_r_m,r_left_m,r_right_m,contact_angle_left_rad")
    assert len(lines) == 6 and fig.stat().st_size > 10_000


@pytest.mark.parametrize("y_range", [["--y-range", "-1:1:0.5"], ["--y-range", "-1:1:0.5 mm"], ["--y-range=-1:1:0.5"],
                                     ["--y-range", "-.001:0.001:0.0005 m"]])
def test_cli_y_range_may_start_with_a_minus(tmp_path, y_range):
    """A range that starts with a minus is the option's value, with or without ``=``."""
    from express.cli import main

    out = tmp_path / "t.csv"
    assert main(["contact-geometry", "S1002", "60E1", *y_range, "-o", str(out)]) == 0
    assert [line.split(",")[0] for line in out.read_text().splitlines()[1:]] == ["-0.001", "-0.0005", "0", "0.0005", "0.001"]


def test_cli_contact_geometry_bad_profile(tmp_path, capsys):
    from express.cli import main

    wheel = tmp_path / "w.csv"
    wheel.write_text("y_mm,z_mm\n" + "".join(f"{y},{0.05 * y}\n" for y in range(-40, 41, 2)).replace("\n0,0.0\n", "\n0,x\n"))
    out = tmp_path / "t.csv"
    assert main(["contact-geometry", str(wheel), "60E1", "-o", str(out)]) == 2
    assert capsys.readouterr().err.splitlines() == [f"error: {wheel}:22: vertical coordinate: 'x' is not a number"]
    assert not out.exists()
    assert main(["contact-geometry", "60E1", "S1002"]) == 2
    assert "60E1 is a rail profile, given as the wheel" in capsys.readouterr().err
    assert main(["contact-geometry", "S1002", "60E1", "--gauge", "1435"]) == 2  # bare numbers are SI
    assert "outside the valid range" in capsys.readouterr().err


GOOD_WHEEL = "y_mm,z_mm\n" + "".join(f"{y},{0.05 * y}\n" for y in range(-40, 41, 2))
#: A malformed profile file of each kind the issue names -> the first problem line
#: (the file's data start on line 2).
BAD_PROFILES = {
    "empty": ("", "w.csv: no profile points"),
    "nan": (GOOD_WHEEL.replace("\n0,0.0\n", "\n0,nan\n"), "w.csv:22: vertical coordinate: 'nan' is not a finite number"),
    "non-monotonic": (GOOD_WHEEL.replace("\n-36,", "\n-39,"), "w.csv:4: lateral coordinate: y = -39 does not increase"),
    "wrong-columns": (GOOD_WHEEL.replace("\n0,0.0\n", "\n0,0.0,1\n"), "w.csv:22: expected 2 columns (lateral, vertical), found 3"),
    "wrong-header": (GOOD_WHEEL.replace("y_mm,z_mm", "lateral,height"), "w.csv:1: header: 'lateral, height': expected the columns"),
    "wrong-units": (GOOD_WHEEL.replace("y_mm,z_mm", "y_m,z_m"), "w.csv: units: the profile spans 80 m x 4 m, too large"),
}


@pytest.mark.parametrize("command", ["contact-geometry", "conicity"])
@pytest.mark.parametrize("kind", list(BAD_PROFILES))
def test_cli_malformed_profile_exit_2_nothing_written(tmp_path, capsys, kind, command):
    from express.cli import main

    text, first = BAD_PROFILES[kind]
    bad = tmp_path / "w.csv"
    bad.write_text(text)
    out, fig = tmp_path / "t.csv", tmp_path / "t.png"
    assert main([command, str(bad), "60E1", "-o", str(out), "--plot", str(fig)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err and all(line.startswith(f"error: {tmp_path}/w.csv") for line in err), err
    assert err[0].startswith(f"error: {tmp_path}/{first}"), err
    assert list(tmp_path.iterdir()) == [bad]
