"""``express conicity``: EN 15302 equivalent conicity against the amplitude, from a
delta-r file or from wheel and rail profiles (:mod:`express.rail.conicity`,
``docs/contact.md``)."""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from express.base.diagnostics import UsageError
from express.cli import common
from express.cli.contact_geometry import add_profile_arguments, load_profiles, setup_from, span
from express.cli.runner import run_command

__all__ = ["add_parser", "figure_conicity", "main", "run"]

R0 = common.Quantity("--r0", "length", "m", 0.1, 1.0)
CONTACT_DISTANCE = common.Quantity("--contact-distance", "length", "m", 0.5, 2.5)


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "conicity", help="EN 15302 equivalent conicity from a delta-r file or from profiles",
        description="Equivalent conicity tan(gamma_e) by EN 15302: the wavelength of the wheelset's kinematic "
        "oscillation with the nonlinear rolling radius difference, integrated exactly for the piecewise-linear "
        "delta r, compared with Klingel's. Give --delta-r FILE.csv (header y_m,delta_r_m) or WHEEL RAIL. "
        "See docs/contact.md.",
    )
    add_profile_arguments(parser, required=False)
    parser.add_argument("--delta-r", type=Path, metavar="FILE.csv", help="rolling radius difference: CSV y_m,delta_r_m")
    parser.add_argument("--amplitudes", type=span("--amplitudes", positive=True), default=None, metavar="START:STOP:STEP",
                        help="amplitudes [mm unless a unit follows]; default 1:7.5:0.1 mm")
    parser.add_argument("--r0", type=R0, default=None,
                        help=R0.help("rolling radius for the wavelength (the conicity does not depend on it)", "0.46 m"))
    parser.add_argument("--contact-distance", type=CONTACT_DISTANCE, default=None,
                        help=CONTACT_DISTANCE.help("distance between the contact points, for the wavelength", "1.5 m"))
    parser.add_argument("-o", "--output", metavar="FILE", help="amplitude_m,tan_gamma_e as CSV (- for standard output)")
    parser.add_argument("--plot", type=common.figure_path, metavar="FILE", help="conicity against amplitude (.png, .svg or .pdf)")
    common.add_json_option(parser)
    parser.set_defaults(handler=run, numeric=True)


def run(
    profiles: list[str], *, delta_r: Path | None = None, units: str | None = None, gauge: float = 1.435,
    flange_back: float = 1.360, inclination: float = 0.025, wheel_radius: float = 0.46, amplitudes: Any = None,
    r0: float | None = None, contact_distance: float | None = None, output: str | None = None,
    plot: Path | None = None, as_json: bool = False,
) -> int:
    """Compute tan(gamma_e) at every amplitude and write the outputs together."""
    import numpy as np

    from express.io.output import output_transaction, write_csv
    from express.rail.conicity import conicity_from_profiles, equivalent_conicity, read_delta_r

    if not ((delta_r is not None and not profiles) or (delta_r is None and len(profiles) == 2)):
        raise UsageError("conicity: give either --delta-r FILE.csv or the two profiles WHEEL RAIL")
    if output == "-" and as_json:
        raise UsageError("-o - and --json both write to standard output; choose one")
    amplitude = np.arange(10, 76) * 1e-4 if amplitudes is None else amplitudes
    inputs = [delta_r] if delta_r is not None else [p for p in profiles if Path(p).exists()]
    with output_transaction(inputs) as transaction:
        if output is not None:
            transaction.declare(output)
        if plot is not None:
            transaction.declare(plot, binary=True)
        if delta_r is not None:
            tan_gamma = equivalent_conicity(read_delta_r(delta_r), amplitudes=amplitude)
            label = str(delta_r)
        else:
            wheel, rail = load_profiles(profiles, units)
            setup = setup_from(gauge, flange_back, inclination, wheel_radius)
            tan_gamma, _ = conicity_from_profiles(wheel, rail, amplitude, setup)  # ArgumentError: no contact
            label = f"{wheel.name} on {rail.name}, rails 1:{'inf' if inclination == 0 else f'{1 / inclination:g}'}, " \
                    f"gauge {gauge * 1e3:g} mm"
        if not np.all(np.isfinite(tan_gamma)):
            from express.base.diagnostics import AnalysisError

            first = float(amplitude[np.flatnonzero(~np.isfinite(tan_gamma))[0]])
            raise AnalysisError(f"{label}: no equivalent conicity at {int((~np.isfinite(tan_gamma)).sum())} "
                                f"amplitudes, the first {first * 1e3:.4g} mm (no contact there); nothing written")
        columns = {"amplitude": amplitude, "tan_gamma_e": tan_gamma}
        column_units = {"amplitude": "m", "tan_gamma_e": ""}
        wavelength = None
        if r0 is not None or contact_distance is not None:
            e, r = contact_distance or 1.5, r0 or 0.46
            with np.errstate(divide="ignore"):
                wavelength = 2 * math.pi * np.sqrt(e * r / (2 * tan_gamma))
            columns["wavelength"], column_units["wavelength"] = wavelength, "m"
        if output is not None:
            write_csv(output, columns, column_units)
        if plot is not None:
            from express.analysis.plots import save_figure

            save_figure(figure_conicity(amplitude, tan_gamma, label), plot)
    for path in [p for p in (output, plot) if p is not None and str(p) != "-"]:
        common.note(f"wrote {path}")
    if as_json:
        data: dict[str, Any] = {"amplitude_m": amplitude, "tan_gamma_e": tan_gamma}
        if wavelength is not None:
            data["wavelength_m"] = wavelength
        common.print_json(data)
    elif output != "-":
        _print_table(label, amplitude, tan_gamma, sys.stdout)
    return 0


def _print_table(label: str, amplitude, tan_gamma, stream) -> None:
    print(f"equivalent conicity (EN 15302), {label}", file=stream)
    for a, value in zip(amplitude, tan_gamma, strict=True):
        if abs(a * 1e3 - round(a * 1e3)) < 1e-9 or len(amplitude) <= 12:
            print(f"  {a * 1e3:6.2f} mm  {value:.4f}", file=stream)


def figure_conicity(amplitude, tan_gamma, title: str):
    """Figure: tan(gamma_e) against the amplitude."""
    import matplotlib
    from matplotlib.figure import Figure

    from express.analysis.plots import STYLE

    with matplotlib.rc_context(STYLE):
        figure = Figure(figsize=(6.4, 3.6))
        axes = figure.subplots()
        axes.plot(amplitude * 1e3, tan_gamma, color="#1f77b4", marker=".", markersize=3)
        axes.set_xlabel("amplitude of the lateral oscillation [mm]")
        axes.set_ylabel("equivalent conicity tan γe")
        axes.set_ylim(bottom=0)
        axes.set_title(title)
        figure.tight_layout()
    return figure


def main(argv: Sequence[str] | None = None) -> int:
    """``express conicity`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
