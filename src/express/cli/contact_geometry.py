"""``express contact-geometry``: contact points, rolling radius difference, contact angles,
roll and curvatures of a rigid wheelset against its lateral displacement, from wheel and
rail profiles (:func:`express.rail.contact_geometry.contact_geometry`, ``docs/contact.md``)."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from express.base.diagnostics import InputError, UsageError
from express.cli import common
from express.cli.runner import run_command

__all__ = ["add_parser", "add_profile_arguments", "figure_contact_geometry", "load_profiles", "main", "run", "setup_from"]

GAUGE = common.Quantity("--gauge", "length", "m", 0.5, 2.0)
FLANGE_BACK = common.Quantity("--flange-back", "length", "m", 0.4, 2.0)
WHEEL_RADIUS = common.Quantity("--wheel-radius", "length", "m", 0.1, 1.0)
#: Most displacements one run computes.
MAX_POINTS = 200_001


def span(option: str, default_unit: str = "mm", positive: bool = False):
    """``START:STOP:STEP [mm|m]`` -> the values in metres (the ``type=`` of argparse);
    the stop is included within a tenth of a step."""

    def parse(text: str):
        import numpy as np

        body, _, unit = text.strip().partition(" ")
        unit = unit.strip() or default_unit
        factors = {"mm": 1e-3, "m": 1.0}
        try:
            start, stop, step = (float(part) for part in body.split(":"))
        except ValueError:
            raise argparse.ArgumentTypeError(f'"{text}": expected START:STOP:STEP [mm|m], e.g. -10:10:0.01 mm') from None
        if unit not in factors:
            raise argparse.ArgumentTypeError(f'"{text}": the unit must be mm or m')
        if not (math.isfinite(start) and math.isfinite(stop) and step > 0 and stop > start) or (positive and start <= 0):
            raise argparse.ArgumentTypeError(f'"{text}": need STEP > 0 and STOP > START' + (" > 0" if positive else ""))
        count = math.floor((stop - start) / step + 0.1) + 1
        if count > MAX_POINTS:
            raise argparse.ArgumentTypeError(f'"{text}": {count} points, more than {MAX_POINTS}')
        return (start + step * np.arange(count)) * factors[unit]

    parse.__name__ = option.lstrip("-")
    return parse


def _inclination(text: str) -> float:
    from express.rail.profiles import parse_inclination

    try:
        return parse_inclination(text)
    except InputError as error:  # argparse reports ArgumentTypeError with its message
        raise argparse.ArgumentTypeError(str(error)) from None


def add_profile_arguments(parser: argparse.ArgumentParser, required: bool = True) -> None:
    """WHEEL RAIL and the track and wheelset dimensions (shared with ``conicity``)."""
    nargs = 2 if required else "*"
    parser.add_argument("profiles", nargs=nargs, metavar="PROFILE",
                        help="the wheel profile, then the rail profile: each a file (two columns; or by its suffix SIMPACK .prw/.prr, "
                        "MiniProf .whl/.ban; docs/contact.md) or a standard name (S1002; 60E1 alias UIC60)")
    parser.add_argument("--units", choices=("mm", "m"), help="unit of profile files without a header line")
    parser.add_argument("--gauge", type=GAUGE, default=1.435, help=GAUGE.help("track gauge, 14 mm below the rail top", "1435 mm"))
    parser.add_argument("--flange-back", type=FLANGE_BACK, default=1.360,
                        help=FLANGE_BACK.help("distance between the flange backs", "1360 mm"))
    parser.add_argument("--inclination", type=_inclination, default=0.025, metavar="1:N",
                        help="rail inclination toward the track centre: 1:20, 1:40, 1:inf (upright); default 1:40")
    parser.add_argument("--wheel-radius", type=WHEEL_RADIUS, default=0.46,
                        help=WHEEL_RADIUS.help("nominal rolling radius at the taping line", "460 mm"))


def setup_from(gauge: float, flange_back: float, inclination: float, wheel_radius: float):
    from express.rail.contact_geometry import ContactSetup

    return ContactSetup(gauge=gauge, flange_back=flange_back, inclination=inclination, wheel_radius=wheel_radius)


def _same_file(first: str, second: str) -> bool:
    import os

    try:
        return os.path.samefile(first, second)
    except OSError:
        return False


def load_profiles(names: list[str], units: str | None):
    """The wheel and rail :class:`~express.rail.profiles.Profile` of ``WHEEL RAIL``, each
    checked for its role by its shape (:func:`express.rail.profiles.role_problems`: a
    rail file given as the wheel, a mirrored wheel, the same file twice are refused)."""
    from express.base.diagnostics import ModelError
    from express.rail.options import PROFILE_KINDS
    from express.rail.profile_formats import read_profile
    from express.rail.profiles import STANDARD_PROFILES, role_problems, standard_profile

    standard = {name.upper() for name in STANDARD_PROFILES} | {"UIC60"}
    profiles: list = []
    problems: list = []
    if _same_file(*names):
        raise UsageError(f"{names[0]} and {names[1]}: the same file given as the wheel and as the rail")
    for name, kind in zip(names, PROFILE_KINDS, strict=True):
        try:
            if not Path(name).exists() and name.strip().upper() in standard:
                profile = standard_profile(name)
                if profile.kind != kind:
                    raise UsageError(f"{name} is a {profile.kind} profile, given as the {kind}")
            else:
                profile = read_profile(name, kind, units=units)
        except ModelError as error:
            problems += error.problems
            continue
        problems += role_problems(profile.y * 1e3, profile.z * 1e3, profile.source or name, kind)
        profiles.append(profile)
    if problems:
        raise ModelError(problems)
    return profiles


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "contact-geometry", help="contact points, delta r, contact angles and roll of a wheelset from profiles",
        description="Rigid wheelset on track, no yaw: for each lateral displacement y the roll that keeps both "
        "wheels on their rails, the contact points, rolling radii and their difference, contact angles and "
        "curvatures; contact jumps and two-point contact are reported. See docs/contact.md.",
    )
    add_profile_arguments(parser)
    parser.add_argument("--y-range", type=span("--y-range"), default=None, metavar="START:STOP:STEP",
                        help="lateral displacements [mm unless a unit follows]; default -10:10:0.01 mm")
    parser.add_argument("-o", "--output", metavar="FILE", help="the table as CSV, units in the header (- for standard output)")
    parser.add_argument("--plot", type=common.figure_path, metavar="FILE", help="delta r, contact angles and contact points (.png, .svg or .pdf)")
    common.add_json_option(parser)
    parser.set_defaults(handler=run, numeric=True)


def run(
    profiles: list[str], *, units: str | None = None, gauge: float = 1.435, flange_back: float = 1.360,
    inclination: float = 0.025, wheel_radius: float = 0.46, y_range: Any = None, output: str | None = None,
    plot: Path | None = None, as_json: bool = False,
) -> int:
    """Compute the table and write the outputs together; returns the exit status."""
    import numpy as np

    from express.io.output import output_transaction, write_csv
    from express.rail.contact_geometry import contact_geometry

    if output == "-" and as_json:
        raise UsageError("-o - and --json both write to standard output; choose one")
    y = np.arange(-1000, 1001) * 1e-5 if y_range is None else y_range
    setup = setup_from(gauge, flange_back, inclination, wheel_radius)
    inputs = [p for p in profiles if Path(p).exists()]
    with output_transaction(inputs) as transaction:
        if output is not None:
            transaction.declare(output)
        if plot is not None:
            transaction.declare(plot, binary=True)
        wheel, rail = load_profiles(profiles, units)
        table = contact_geometry(wheel, rail, y, setup)
        require_finite(table, f"{wheel.name} on {rail.name}")
        if output is not None:
            columns, column_units = table_columns(table)
            write_csv(output, columns, column_units, markers=MARKERS)
        if plot is not None:
            from express.analysis.plots import save_figure

            save_figure(figure_contact_geometry(table, f"{wheel.name} on {rail.name}"), plot)
    for path in [p for p in (output, plot) if p is not None and str(p) != "-"]:
        common.note(f"wrote {path}")
    summary = _summary(wheel.name, rail.name, table)
    if as_json:
        common.print_json(summary)
    else:
        _print_summary(summary, sys.stderr if output == "-" else sys.stdout)
    return 0


def require_finite(table, label: str) -> None:
    """No NaN or inf is ever written or printed as a result: a contact table with a
    non-finite roll, height, delta r, radius or contact angle is no result (status 1,
    nothing written), naming the first lateral displacement where it happens."""
    import numpy as np

    from express.base.diagnostics import AnalysisError

    bad = ~np.isfinite(table.roll) | ~np.isfinite(table.height) | ~np.isfinite(table.delta_r)
    bad |= ~np.all(np.isfinite(table.radius), axis=0) | ~np.all(np.isfinite(table.contact_angle), axis=0)
    if bad.any():
        first = int(np.flatnonzero(bad)[0])
        raise AnalysisError(
            f"{label}: no contact solution at {int(bad.sum())} of {bad.size} lateral displacements, the first at "
            f"y = {table.y[first] * 1e3:.4g} mm (the profiles do not meet there: check their roles, sides and "
            "units); nothing written"
        )


def table_columns(table) -> tuple[dict[str, Any], dict[str, str]]:
    """CSV columns (name -> values) and units of a contact table, left before right."""
    import numpy as np

    columns: dict[str, Any] = {"y": table.y, "roll": table.roll, "height": table.height, "delta_r": table.delta_r}
    units = {"y": "m", "roll": "rad", "height": "m", "delta_r": "m"}
    per_side = (("r", "radius", "m"), ("contact_angle", "contact_angle", "rad"),
                ("wheel_position", "wheel_position", "m"), ("rail_position", "rail_position", "m"),
                ("track_position", "track_position", "m"),
                ("wheel_curvature_lateral", "wheel_curvature_lateral", "1/m"),
                ("rail_curvature_lateral", "rail_curvature_lateral", "1/m"),
                ("wheel_curvature_rolling", "wheel_curvature_rolling", "1/m"),
                ("secondary_gap", "secondary_gap", "m"), ("two_point", "two_point", ""))
    for name, field, unit in per_side:
        values = getattr(table, field)
        for row, side in enumerate(("left", "right")):
            column = f"{name}_{side}"
            columns[column] = values[row].astype(int) if field == "two_point" else values[row]
            units[column] = unit
    for side in ("left", "right"):  # no second contact (an infinite gap): an empty cell, docs/contact.md
        gap = columns[f"secondary_gap_{side}"]
        columns[f"secondary_gap_{side}"] = np.where(np.isposinf(gap), np.nan, gap)
    return columns, units


#: Columns whose empty cell is documented: no second contact.
MARKERS = ("secondary_gap_left", "secondary_gap_right")


def _summary(wheel: str, rail: str, table) -> dict[str, Any]:
    setup = table.setup
    return {
        "wheel": wheel, "rail": rail, "gauge_m": setup.gauge, "flange_back_m": setup.flange_back,
        "inclination": setup.inclination, "wheel_radius_m": setup.wheel_radius,
        "y_m": [float(table.y[0]), float(table.y[-1])], "points": len(table.y),
        "delta_r_max_m": float(abs(table.delta_r).max()),
        "contact_angle_max_rad": float(table.contact_angle.max()),
        "jumps": [{"side": j.side, "y_before_m": j.y_before, "y_after_m": j.y_after,
                   "position_before_m": j.position_before, "position_after_m": j.position_after} for j in table.jumps],
        "two_point_contact_y_m": sorted({float(y) for y in table.y[table.two_point.any(axis=0)]}),
    }


def _print_summary(summary: dict[str, Any], stream) -> None:
    print(f"{summary['wheel']} on {summary['rail']}: gauge {summary['gauge_m'] * 1e3:g} mm, flange back "
          f"{summary['flange_back_m'] * 1e3:g} mm, inclination {_ratio(summary['inclination'])}, "
          f"r0 {summary['wheel_radius_m'] * 1e3:g} mm", file=stream)
    y0, y1 = summary["y_m"]
    print(f"  y {y0 * 1e3:g} .. {y1 * 1e3:g} mm ({summary['points']} points); |delta r| up to "
          f"{summary['delta_r_max_m'] * 1e3:.3f} mm; contact angle up to {math.degrees(summary['contact_angle_max_rad']):.1f} deg",
          file=stream)
    for jump in summary["jumps"]:
        print(f"  contact jump, {jump['side']} wheel: y {jump['y_before_m'] * 1e3:.3f} -> {jump['y_after_m'] * 1e3:.3f} mm, "
              f"wheel position {jump['position_before_m'] * 1e3:.2f} -> {jump['position_after_m'] * 1e3:.2f} mm", file=stream)
    if not summary["jumps"]:
        print("  no contact jumps", file=stream)
    if summary["two_point_contact_y_m"]:
        print(f"  two-point contact at {len(summary['two_point_contact_y_m'])} displacements", file=stream)


def _ratio(tangent: float) -> str:
    return "1:inf" if tangent == 0 else f"1:{1 / tangent:g}"


def figure_contact_geometry(table, title: str):
    """Figure: delta r, contact angles and the contact points on the wheel, against y."""
    import matplotlib
    import numpy as np
    from matplotlib.figure import Figure

    from express.analysis.plots import STYLE

    with matplotlib.rc_context(STYLE):
        figure = Figure(figsize=(7.0, 7.6))
        top, middle, bottom = figure.subplots(3, 1, sharex=True)
        y = table.y * 1e3
        top.plot(y, table.delta_r * 1e3, color="#1f77b4")
        top.set_ylabel("Δr = r_left − r_right [mm]")
        for row, (side, colour) in enumerate((("left", "#1f77b4"), ("right", "#d62728"))):
            middle.plot(y, np.degrees(table.contact_angle[row]), color=colour, label=f"{side} wheel")
            bottom.plot(y, table.wheel_position[row] * 1e3, color=colour, label=f"{side} wheel")
        middle.set_ylabel("contact angle [deg]")
        middle.legend(loc="upper center")
        bottom.set_ylabel("contact point on the wheel [mm]\n(from the taping line)")
        bottom.set_xlabel("lateral displacement y [mm] (positive to the left)")
        for jump in table.jumps:
            for axes in (top, middle, bottom):
                axes.axvline(0.5 * (jump.y_before + jump.y_after) * 1e3, color="#555555", linewidth=0.6, linestyle=":")
        setup = table.setup
        top.set_title(f"{title}: gauge {setup.gauge * 1e3:g} mm, flange back {setup.flange_back * 1e3:g} mm, "
                      f"rails {_ratio(setup.inclination)}")
        figure.tight_layout()
    return figure


def main(argv: Sequence[str] | None = None) -> int:
    """``express contact-geometry`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
