"""Write the bundled vehicle models from one description.

    python examples/make_vehicles.py            # rewrites the example files
    python examples/make_vehicles.py --cars 10 -o train.toml   # a train, for benchmarks

The single cars (``car_toml``) are written as one screen of car (car body, its seats,
two instances of a bogie substructure, rail data) plus the bogie substructure; with
``yaw_bush=True`` the yaw dampers are series elements with their bush stiffness
(``*-yaw-bush.toml``).  ``vehicle_toml`` writes the same car with every item spelled out
(trains; the reference of ``tests/test_substructures.py``).

The paper's forced-steering car (Figs. 7 and 8): car body CB (x, y, roll, yaw), bogie
frames T1, T2 (x, y, roll, yaw), wheelsets W1..W4 (y, yaw) and steering levers
L1..L4 (pitch-axis rotation ry, plus the virtual longitudinal DOF x at the pin):
11 bodies, 28 DOFs, 4 pins, 50 elements + 4 virtual ones (the
issue's example list of 42 plus the 8 primary vertical springs, without which the
bogie roll is unrestrained: K would have a zero-stiffness roll/sway mode).  The conventional twin
drops the levers and links (20 DOFs) and uses the ordinary axle-box stiffness.

Lever kinematics (docs/vehicle.md): each lever is pinned to its bogie frame at
lateral offset +-bL; its upper arm lLU is linked to the car-body steering beam
above the bogie centre (kLU); the link to the axle box at the car end is at lLL
below the pin and the link to the inner axle box at lLL above it (kLL), so that
one rotation moves the two axle boxes of a side in opposite directions, as the
paper describes (the rear bogie is the front one turned end for end).
Both ends of every element are placed at the same station, so the curve module
sees the track geometry correctly.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

HERE = Path(__file__).resolve().parent
SIDES = (("L", "bL", "b1", "b2"), ("R", "-bL", "-b1", "-b2"))


def _q(text: str) -> str:
    return '"' + text + '"'


def _vec(*values) -> str:
    return "[" + ", ".join(v if isinstance(v, str) and v.startswith('"') else _q(str(v)) if isinstance(v, str) else str(v) for v in values) + "]"


def _shift(expression: str, offset: str) -> str:
    """Station expression moved back by ``offset`` (for cars of a train)."""
    if not offset:
        return expression
    return f"{expression} - {offset}" if expression != "0" else f"-{offset}"


class _Writer:
    def __init__(self):
        self.bodies: list[str] = []
        self.points: list[str] = []
        self.elements: list[str] = []
        self.pins: list[str] = []
        self.classic_bodies: list[tuple] = []
        self.counts = {"C": 0}

    def body(self, name, label, mass, inertia, dofs, position):
        self.bodies.append(
            f"[bodies.{name}]\nlabel = {_q(label)}\nmass = {_q(mass)}\n"
            f"inertia = {_vec(*inertia)}\ndofs = [{', '.join(_q(d) for d in dofs)}]\n"
            f"position = {_vec(*position)}\n"
        )

    def point(self, name, body, offset):
        self.points.append(f"[points.{name}]\nbody = {_q(body)}\noffset = {_vec(*offset)}\n")

    def element(self, name, label, s_end, t_end, direction, stiffness, damping="0"):
        self.elements.append(
            f"[elements.{name}]\nlabel = {_q(label)}\nfrom = {_q(s_end)}\nto = {_q(t_end)}\n"
            f"direction = {_q(direction)}\nstiffness = {_q(stiffness)}\ndamping = {_q(damping)}\n"
        )

    def link(self, name, label, s_body, s_offset, t_body, t_offset, direction, stiffness, damping="0"):
        """An element with its two CPs (named after the element)."""
        self.point(f"{name}_S", s_body, s_offset)
        self.point(f"{name}_T", t_body, t_offset)
        self.element(name, label, f"{name}_S", f"{name}_T", direction, stiffness, damping)


def build_car(w: _Writer, steered: bool, prefix: str = "", station: str = "") -> list[str]:
    """Add one car's bodies, CPs, elements and pins; return its wheelset ids."""
    p = prefix
    cb = f"{p}CB"
    w.body(cb, "car body", "mc", ("Icx", "Icy", "Icz"), ("x", "y", "rx", "rz"), (_shift("0", station), 0, "hc"))
    wheelsets = []
    for t_index, (t_sign, w_numbers) in enumerate((("", (1, 2)), ("-", (3, 4))), start=1):
        bogie = f"{p}T{t_index}"
        s_t = f"{t_sign}lT" if t_sign else "lT"
        w.body(bogie, f"bogie frame {t_index}", "mt", ("Itx", "Ity", "Itz"), ("x", "y", "rx", "rz"), (_shift(s_t, station), 0, "ht"))
        for w_index, a_sign in zip(w_numbers, ("", "-")):
            ws = f"{p}W{w_index}"
            wheelsets.append(ws)
            s_w = f"{s_t} + a" if a_sign == "" else f"{s_t} - a"
            w.body(ws, f"wheelset {w_index}", "mw", ("Iwx", "0", "Iwz"), ("y", "rz"), (_shift(s_w, station), 0, "r0"))
            ax = "a" if a_sign == "" else "-a"
            for side, _bl, b1, _b2 in SIDES:
                w.link(f"{ws}_px{side}", f"primary longitudinal, wheelset {w_index} {side}",
                       bogie, (ax, b1, "h1 - ht"), ws, (0, b1, "h1 - r0"), "x", "kx1")
                w.link(f"{ws}_py{side}", f"primary lateral, wheelset {w_index} {side}",
                       bogie, (ax, b1, "h1 - ht"), ws, (0, b1, "h1 - r0"), "y", "ky1", "cy1")
                w.link(f"{ws}_pz{side}", f"primary vertical, wheelset {w_index} {side}",
                       bogie, (ax, b1, "h1 - ht"), ws, (0, b1, "h1 - r0"), "z", "kz1", "cz1")
        s_cb = "lT" if not t_sign else "-lT"
        for side, _bl, _b1, b2 in SIDES:
            w.link(f"{bogie}_sx{side}", f"secondary longitudinal (air spring and yaw damper), bogie {t_index} {side}",
                   cb, (s_cb, b2, "h2 - hc"), bogie, (0, b2, "h2 - ht"), "x", "kx2", "cyaw")
            w.link(f"{bogie}_sy{side}", f"secondary lateral, bogie {t_index} {side}",
                   cb, (s_cb, b2, "h2 - hc"), bogie, (0, b2, "h2 - ht"), "y", "ky2")
            w.link(f"{bogie}_sz{side}", f"secondary vertical, bogie {t_index} {side}",
                   cb, (s_cb, b2, "h2 - hc"), bogie, (0, b2, "h2 - ht"), "z", "kz2", "cz2")
        w.link(f"{bogie}_dy", f"secondary lateral damper, bogie {t_index}",
               cb, (s_cb, 0, "h2 - hc"), bogie, (0, 0, "h2 - ht"), "y", "0", "cy2")
        if not steered:
            continue
        front, rear = (f"{p}W{w_numbers[0]}", f"{p}W{w_numbers[1]}")
        for lever_index, (side, bl, _b1, _b2) in zip((2 * t_index - 1, 2 * t_index), SIDES):
            lever = f"{p}L{lever_index}"
            w.body(lever, f"steering lever {lever_index} ({'left' if side == 'L' else 'right'}, bogie {t_index})",
                   "mL", ("0", "ILy", "0"), ("x", "ry"), (_shift(s_t, station), 0, "ht"))
            w.link(f"{lever}_upper", f"lever {lever_index} upper link to the car-body steering beam",
                   lever, (0, bl, "lLU"), cb, (s_cb, bl, "ht + lLU - hc"), "x", "kLU")
            # the rear bogie is the front one turned end for end: its lower arm drives
            # the axle at the car end (the rear one), its upper arm the inner one
            front_arm, rear_arm = ("-lLL", "lLL") if t_index == 1 else ("lLL", "-lLL")
            w.link(f"{lever}_front", f"lever {lever_index} link to the front axle box",
                   lever, ("a", bl, front_arm), front, (0, bl, "h1 - r0"), "x", "kLL")
            w.link(f"{lever}_rear", f"lever {lever_index} link to the rear axle box",
                   lever, ("-a", bl, rear_arm), rear, (0, bl, "h1 - r0"), "x", "kLL")
            w.link(f"{lever}_pin", f"lever {lever_index} pin to the bogie frame (virtual)",
                   lever, (0, bl, 0), bogie, (0, bl, 0), "x", "kinf")
            w.pins.append(f"[pins.{lever}_pin]\nvirtual = {_q(lever + '_pin_S')}\nnon_virtual = {_q(lever + '_pin_T')}\n")
    return wheelsets


def _parameters(conventional: bool) -> str:
    data = tomllib.loads((HERE / "vehicle_parameters.toml").read_text(encoding="utf-8"))
    values = dict(data["parameters"])
    if conventional:
        values.update(data.get("parameters_conventional", {}))
    lines = []
    source_lines = (HERE / "vehicle_parameters.toml").read_text(encoding="utf-8").splitlines()
    comments = {}
    for line in source_lines:
        name = line.split("=", 1)[0].strip()
        if "#" in line and ("{" in line or '"' in line.split("#", 1)[0]):
            comments.setdefault(name, line.split("#", 1)[1].strip())
    for name, spec in values.items():
        if name == "v":
            lines.append('v = "120 km/h"  # paper: running speed')
            continue
        if conventional and name in ("mL", "ILy", "lLU", "lLL", "bL", "kLU", "kLL", "kx1c"):
            continue
        if name in ("f1", "f2"):
            continue  # computed from the contact: [rail.creep]
        comment = comments.get(name, "")
        if conventional and name in data.get("parameters_conventional", {}):
            comment = "conventional bogie: " + comment
        if isinstance(spec, str):  # a derived parameter: an expression of others
            lines.append(f'{name} = "{spec}"' + (f"  # {comment}" if comment else ""))
            continue
        lines.append(f'{name} = {{ value = {spec["value"]!r}, unit = "{spec["unit"]}" }}' + (f"  # {comment}" if comment else ""))
    lines.append('hf = { value = 1.2, unit = "m" }  # floor height above rail (est.: JR EMU floor 1.1-1.2 m)')
    lines.append('Rrail = { value = 0.3, unit = "m" }  # rail-head transverse radius (JIS 50N crown, 300 mm)')
    lines.append('Emod = { value = 206, unit = "GPa" }  # Young\'s modulus of wheel and rail steel')
    lines.append('nu = { value = 0.3, unit = "1" }  # Poisson\'s ratio')
    if not conventional:
        lines.append('kinf = { value = 1.0e9, unit = "N/m" }  # virtual pin stiffness: eliminated, never used')
    return "\n".join(lines) + "\n"


def _rail_section(wheelsets: list[str], prefix: str = "") -> str:
    """The [rail] tables: wheel/rail data, Kalker creep, floor output points."""
    wheelset_list = ", ".join(_q(x) for x in wheelsets)
    return (
        "[rail]\nspeed = \"v\"\ncant_base = \"G\"\ngravity = \"g\"\n"
        f"wheelsets = [{wheelset_list}]\n\n"
        "[rail.wheel_rail]\nf1 = \"f1\"\nf2 = \"f2\"\nconicity = \"Gamma\"\nr0 = \"r0\"\nb = \"b\"\n"
        "flange_clearance = \"delta\"\nrail_stiffness = \"kR\"\nfriction = \"mu\"\nwheel_load = \"P0\"\n\n"
        "# f1, f2 (per wheel) from the Hertz ellipse and Kalker's coefficients (docs/contact.md)\n"
        "[rail.creep]\nfrom = \"kalker\"\nlongitudinal = \"f1\"\nlateral = \"f2\"\nwheel_load = \"P0\"\n"
        "wheel_radius = \"r0\"\nrail_head_radius = \"Rrail\"\nyoungs_modulus = \"Emod\"\npoisson = \"nu\"\n\n"
        f"[rail.outputs.floor_front]\nbody = \"{prefix}CB\"\noffset = [\"lT\", 0, \"hf - hc\"]\n\n"
        f"[rail.outputs.floor_rear]\nbody = \"{prefix}CB\"\noffset = [\"-lT\", 0, \"hf - hc\"]\n"
    )


def vehicle_toml(steered: bool = True, cars: int = 1, car_length: str = "20.0") -> str:
    """TOML text of the forced-steering (``steered``) or conventional vehicle, or a train."""
    w = _Writer()
    wheelsets: list[str] = []
    for car in range(cars):
        prefix = f"C{car + 1}" if cars > 1 else ""
        station = "" if car == 0 else f"{car}*Lc"
        wheelsets += build_car(w, steered, prefix, station)
        if car > 0:
            previous = f"C{car}CB"
            here = f"{prefix}CB"
            for direction, stiffness, damping in (("x", "kcx", "ccx"), ("y", "kcy", "ccy")):
                w.link(f"{prefix}_coupler_{direction}", f"coupler {car}-{car + 1} ({direction})",
                       previous, ("-Lc/2", 0, 0), here, ("Lc/2", 0, 0), direction, stiffness, damping)
    name = "forced_steering" if steered else "conventional"
    title = ("Forced-steering narrow-gauge limited-express car (Tanifuji & Suzuki 2001, Figs. 7-8)"
             if steered else "The same car with conventional bogies (no steering levers or links)")
    if cars > 1:
        name += f"_train{cars}"
        title = f"{cars}-car train of: {title}"
    out = [
        "# EXPRESS model file (modern format, docs/model-format.md).",
        "# Written by examples/make_vehicles.py; parameter sources in docs/parameters.md.",
        "",
        "[model]",
        f'name = "{name}"',
        f'title = "{title}"',
        "",
        "[parameters]",
        _parameters(conventional=not steered),
    ]
    if cars > 1:
        out.append(f'Lc = {{ value = {car_length}, unit = "m" }}  # car length (coupler to coupler)\n'
                   'kcx = { value = 1.0e7, unit = "N/m" }\nccx = { value = 1.0e5, unit = "N*s/m" }\n'
                   'kcy = { value = 1.0e5, unit = "N/m" }\nccy = { value = 1.0e4, unit = "N*s/m" }\n')
    out += w.bodies + w.points + w.elements + w.pins
    out.append(_rail_section(wheelsets, "C1" if cars > 1 else ""))
    return "\n".join(out)

def _inline(**fields) -> str:
    """A TOML inline table from keyword values (strings quoted, tuples as lists)."""
    parts = []
    for key, value in fields.items():
        if isinstance(value, tuple):
            value = _vec(*value)
        elif isinstance(value, bool):
            value = "true" if value else "false"
        elif isinstance(value, str):
            value = _q(value)
        parts.append(f"{'from' if key == 'from_' else key} = {value}")
    return "{ " + ", ".join(parts) + " }"


def _bogie_substructure(steered: bool, yaw_bush: bool) -> str:
    """The two-axle bogie (frame, wheelsets, primary and secondary suspension, and for
    the steered car the steering levers and links), in its own frame (station 0)."""
    lines = ["[substructures.bogie]",
             'label = "two-axle bogie: frame T, wheelsets WF (front) and WR, primary suspension'
             + (', steering levers LL, LR' if steered else '') + '"']
    if steered:
        lines.append('parameters = ["arm"]  # offset of the lever arm driving the front axle box')
    connectors = ["seat_L", "seat_R", "seat_C"] + (["beam_L", "beam_R"] if steered else [])
    lines.append("connectors = [" + ", ".join(_q(c) for c in connectors) + "]  # car-body points")
    lines += ["", "[substructures.bogie.bodies]",
              "T = " + _inline(label="bogie frame", mass="mt", inertia=("Itx", "Ity", "Itz"),
                               dofs=("x", "y", "rx", "rz"), position=(0, 0, "ht")),
              "WF = " + _inline(label="front wheelset", mass="mw", inertia=("Iwx", "0", "Iwz"), dofs=("y", "rz"),
                                position=("a", 0, "r0")),
              "WR = " + _inline(label="rear wheelset", mass="mw", inertia=("Iwx", "0", "Iwz"), dofs=("y", "rz"),
                                position=("-a", 0, "r0"))]
    if steered:
        for lever, side in (("LL", "left"), ("LR", "right")):
            lines.append(f"{lever} = " + _inline(label=f"steering lever ({side})", mass="mL", inertia=("0", "ILy", "0"),
                                                 dofs=("x", "ry"), position=(0, 0, "ht")))
    points = ["", "[substructures.bogie.points]"]
    elements = ["", "[substructures.bogie.elements]"]
    pins = []
    for ws, ax in (("WF", "a"), ("WR", "-a")):
        for side, bl, b1, b2 in SIDES:
            box = f"{ws}_{side}"
            points.append(f"{box}_T = " + _inline(body="T", offset=(ax, b1, "h1 - ht")))
            points.append(f"{box}_W = " + _inline(body=ws, offset=(0, b1, "h1 - r0")))
            for axis, k, c in (("x", "kx1", "0"), ("y", "ky1", "cy1"), ("z", "kz1", "cz1")):
                elements.append(f"{ws}_p{axis}{side} = " + _inline(
                    label=f"primary {axis}, {ws} {side}", from_=f"{box}_T", to=f"{box}_W", direction=axis,
                    stiffness=k, damping=c))
    for side, bl, b1, b2 in SIDES:
        points.append(f"s{side} = " + _inline(body="T", offset=(0, b2, "h2 - ht")))
        damper = "0" if yaw_bush else "cyaw"
        elements.append(f"sx{side} = " + _inline(
            label=f"secondary x (air spring{'' if yaw_bush else ' and yaw damper'}), {side}",
            from_=f"seat_{side}", to=f"s{side}", direction="x", stiffness="kx2", damping=damper))
        elements.append(f"sy{side} = " + _inline(label=f"secondary y, {side}", from_=f"seat_{side}", to=f"s{side}",
                                               direction="y", stiffness="ky2"))
        elements.append(f"sz{side} = " + _inline(label=f"secondary z, {side}", from_=f"seat_{side}", to=f"s{side}",
                                               direction="z", stiffness="kz2", damping="cz2"))
        if yaw_bush:
            elements.append(f"yaw{side} = " + _inline(
                label=f"yaw damper with its bushes in series, {side}", from_=f"seat_{side}", to=f"s{side}",
                direction="x", stiffness="kyaw", damping="cyaw", series=True))
    points.append("sC = " + _inline(body="T", offset=(0, 0, "h2 - ht")))
    elements.append("dy = " + _inline(label="secondary lateral damper", from_="seat_C", to="sC", direction="y",
                                      stiffness="0", damping="cy2"))
    if steered:
        for lever, (side, bl, _b1, _b2) in zip(("LL", "LR"), SIDES):
            points += [f"{lever}_top = " + _inline(body=lever, offset=(0, bl, "lLU")),
                       f"{lever}_front = " + _inline(body=lever, offset=("a", bl, "arm")),
                       f"{lever}_rear = " + _inline(body=lever, offset=("-a", bl, "-arm")),
                       f"{lever}_axle_front = " + _inline(body="WF", offset=(0, bl, "h1 - r0")),
                       f"{lever}_axle_rear = " + _inline(body="WR", offset=(0, bl, "h1 - r0")),
                       f"{lever}_pin = " + _inline(body=lever, offset=(0, bl, 0)),
                       f"{lever}_seat = " + _inline(body="T", offset=(0, bl, 0))]
            elements += [
                f"{lever}_upper = " + _inline(label="lever upper link to the car-body steering beam",
                                              from_=f"{lever}_top", to=f"beam_{side}", direction="x", stiffness="kLU"),
                f"{lever}_front = " + _inline(label="lever link to the front axle box", from_=f"{lever}_front",
                                              to=f"{lever}_axle_front", direction="x", stiffness="kLL"),
                f"{lever}_rear = " + _inline(label="lever link to the rear axle box", from_=f"{lever}_rear",
                                             to=f"{lever}_axle_rear", direction="x", stiffness="kLL"),
                f"{lever}_pin = " + _inline(label="lever pin to the frame (virtual)", from_=f"{lever}_pin",
                                            to=f"{lever}_seat", direction="x", stiffness="kinf"),
            ]
            pins.append(f"{lever}_pin = " + _inline(virtual=f"{lever}_pin", non_virtual=f"{lever}_seat"))
    out = lines + points + elements
    if pins:
        out += ["", "[substructures.bogie.pins]"] + pins
    return "\n".join(out) + "\n"


def car_toml(steered: bool = True, yaw_bush: bool = False) -> str:
    """The single car written with a bogie substructure: the whole car (car body, its
    seats, two bogie instances, rail data) on one screen, then the bogie.

    ``yaw_bush``: the yaw dampers become series elements with the stiffness of their
    bushes (``kyaw``) instead of pure dampers in parallel with the air springs.
    """
    name = "forced_steering" if steered else "conventional"
    title = ("Forced-steering narrow-gauge limited-express car (Tanifuji & Suzuki 2001, Figs. 7-8)"
             if steered else "The same car with conventional bogies (no steering levers or links)")
    if yaw_bush:
        name += "_yaw_bush"
        title += "; yaw dampers with series bush stiffness"
    parameters = _parameters(conventional=not steered)
    if yaw_bush:
        parameters += ('kyaw = { value = 1.0e7, unit = "N/m" }  # series stiffness of a yaw damper (bushes, '
                       "mounting, oil): 10 MN/m as in Hindawi MPE 2019, Table 2 (docs/parameters.md)\n")
    out = [
        "# EXPRESS model file (modern format, docs/model-format.md).",
        "# Written by examples/make_vehicles.py; parameter sources in docs/parameters.md.",
        "# The car: car body CB, its seats of the secondary suspension, two instances of the",
        "# bogie substructure (defined below the rail data).",
        "",
        "[model]", f'name = "{name}"', f'title = "{title}"', "",
        "[parameters]", parameters,
        "[bodies.CB]", 'label = "car body"', 'mass = "mc"', 'inertia = ["Icx", "Icy", "Icz"]',
        'dofs = ["x", "y", "rx", "rz"]', 'position = [0, 0, "hc"]', "",
        "[points]  # the car body's seats of the secondary suspension (and steering beams) above each bogie",
    ]
    instances = []
    for index, (bogie, station, arm, wheelsets, levers) in enumerate(
        (("T1", "lT", "-lLL", ("W1", "W2"), ("L1", "L2")), ("T2", "-lT", "lLL", ("W3", "W4"), ("L3", "L4"))), start=1
    ):
        out.append(f"CB_{bogie}L = " + _inline(body="CB", offset=(station, "b2", "h2 - hc")))
        out.append(f"CB_{bogie}R = " + _inline(body="CB", offset=(station, "-b2", "h2 - hc")))
        out.append(f"CB_{bogie}C = " + _inline(body="CB", offset=(station, 0, "h2 - hc")))
        connect = {"seat_L": f"CB_{bogie}L", "seat_R": f"CB_{bogie}R", "seat_C": f"CB_{bogie}C"}
        rename = {"T": bogie, "WF": wheelsets[0], "WR": wheelsets[1]}
        if steered:
            out.append(f"CB_{bogie}_beamL = " + _inline(body="CB", offset=(station, "bL", "ht + lLU - hc")))
            out.append(f"CB_{bogie}_beamR = " + _inline(body="CB", offset=(station, "-bL", "ht + lLU - hc")))
            connect.update(beam_L=f"CB_{bogie}_beamL", beam_R=f"CB_{bogie}_beamR")
            rename.update(LL=levers[0], LR=levers[1])
        instance = [f"[instances.{'front' if index == 1 else 'rear'}]", 'substructure = "bogie"',
                    f'prefix = "{bogie}_"', f'station = "{station}"']
        if steered:
            comment = "front bogie" if index == 1 else "rear bogie: the front one turned end for end"
            instance.append(f'parameters = {{ arm = "{arm}" }}  # {comment}')
        instance.append("connect = { " + ", ".join(f'{k} = "{v}"' for k, v in connect.items()) + " }")
        instance.append("rename = { " + ", ".join(f'{k} = "{v}"' for k, v in rename.items()) + " }")
        instances += [""] + instance
    out += instances + [""]
    out.append(_rail_section(["W1", "W2", "W3", "W4"]))
    out.append(_bogie_substructure(steered, yaw_bush))
    return "\n".join(out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cars", type=int, default=0, help="write a train of this many steered cars")
    parser.add_argument("-o", "--output", help="output file for --cars")
    args = parser.parse_args(argv)
    if args.cars:
        text = vehicle_toml(True, cars=args.cars)
        Path(args.output or f"train{args.cars}.toml").write_text(text, encoding="utf-8")
        return 0
    (HERE / "forced-steering.toml").write_text(car_toml(True), encoding="utf-8")
    sys.path.insert(0, str(HERE.parent / "src"))
    from express.io import load_model
    from express.io.classic_writer import model_to_classic

    classic, _ = model_to_classic(load_model(HERE / "forced-steering.toml"))
    (HERE / "forced-steering.exp").write_text(classic, encoding="utf-8")
    (HERE / "conventional.toml").write_text(car_toml(False), encoding="utf-8")
    (HERE / "forced-steering-yaw-bush.toml").write_text(car_toml(True, yaw_bush=True), encoding="utf-8")
    (HERE / "conventional-yaw-bush.toml").write_text(car_toml(False, yaw_bush=True), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
