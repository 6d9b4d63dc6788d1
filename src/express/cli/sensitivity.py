"""``express sensitivity``: exact derivatives of the critical speed (or of the least
stable eigenvalue at a speed, or of the steady-curving outputs in a curve) with respect
to every parameter (:mod:`express.analysis.study.sensitivity`,
:mod:`express.analysis.study.curving_sensitivity`); checked central differences of the
time-run outputs of a track run (:mod:`express.analysis.study.time_run_sensitivity`)."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

from express.base.diagnostics import UsageError
from express.cli import common
from express.cli.runner import run_command

__all__ = ["CANT", "RADIUS", "add_parser", "main", "relative_step", "run"]

#: ``--radius`` and ``--cant`` of ``--output steady-curving``, as ``express curving`` reads them.
RADIUS = common.Quantity("--radius", "length", "m", 0.0, 1e6, open_low=True)
CANT = common.Quantity("--cant", "length", "mm", -500.0, 500.0)


def relative_step(text: str) -> float:
    """``--step``: a relative step, a number in (0, 0.5)."""
    import argparse
    import math

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a relative step such as 1e-3, got {text!r}") from None
    if not (math.isfinite(value) and 0.0 < value < 0.5):
        raise argparse.ArgumentTypeError(f"{text}: a relative step must lie in (0, 0.5), e.g. 1e-3")
    return value


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "sensitivity", help="exact derivatives of the critical speed (or an eigenvalue) with respect to the parameters",
        description="Derivatives from the symbolic matrices: dlambda/dp = y^H (dA/dp) x / (y^H x) for an eigenvalue, "
        "and dV/dp = -(dRe lambda/dp)/(dRe lambda/dV) at the critical speed (implicit function theorem); in a "
        "steady curve (--output steady-curving) dx/dp = -(dr/dx)^-1 dr/dp of the steady state r(x, p) = 0, then the "
        "leading wheelset's angle of attack, the largest Y/Q and the largest |SY|. "
        "Derived parameters follow through the parameter graph. SI units; elasticities (p/V) dV/dp. "
        "--output time-run: central differences of the whole track run (EN 14363 (Y/Q)2m, (SY)2m, dQ/Q0) at "
        "p(1 +- step), checked at half the step; a derivative whose two estimates disagree, or whose maximum "
        "switches wheel, is flagged as not differentiable.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--output", dest="quantity",
                        choices=("critical-speed", "eigenvalue", "steady-curving", "time-run"),
                        default="critical-speed",
                        help="critical-speed (default), eigenvalue: the least stable eigenvalue at --speed, "
                        "steady-curving: the steady-curving outputs in the curve of --radius and --cant at --speed, "
                        "or time-run: the EN 14363 outputs of the run along --track at --speed")
    parser.add_argument("--parameter", dest="parameters", action="append", metavar="NAME",
                        help="only this parameter (repeatable; default: every given parameter but the speed)")
    parser.add_argument("--all", dest="every", action="store_true",
                        help="rank every given parameter together (default: the design parameters, then the physical "
                        "constants such as g and the parameters without effect on the output in separate lists)")
    parser.add_argument("--speed", type=common.SPEED, metavar="SPEED",
                        help=common.SPEED.help("speed of --output eigenvalue or steady-curving", "the model's speed"))
    parser.add_argument("--radius", type=RADIUS, metavar="R", help=RADIUS.help("curve radius of --output steady-curving"))
    parser.add_argument("--cant", type=CANT, default=None, metavar="C",
                        help=CANT.help("cant (rail height difference) of --output steady-curving", "0"))
    parser.add_argument("--direction", choices=("left", "right"), default=None,
                        help="curve direction of --output steady-curving; default right")
    parser.add_argument("--contact", choices=("tables", "deadband"), default=None,
                        help="wheel/rail contact of --output steady-curving: the profiles' tables (default when the "
                        "model has profiles) or the dead-band flange and creep saturation")
    parser.add_argument("--track", metavar="NAME|FILE", default=None,
                        help="track of --output time-run: a track file or a bundled curve (R250, R400, R600, R1000, "
                        "R3000, paper); default the paper's curve at the model's speed")
    parser.add_argument("--dt", type=common.DT, default=None, metavar="DT",
                        help=common.DT.help("time step of --output time-run (the nominal run's step checked as a "
                                            "study does, every run at that step)", "0.005 s"))
    parser.add_argument("--step", type=relative_step, default=None, metavar="REL",
                        help="relative step of the central differences of --output time-run (default 1e-3; each "
                        "derivative also at half of it)")
    parser.add_argument("--no-step-check", dest="step_check", action="store_false",
                        help="--output time-run: run at --dt without checking it against twice the step")
    common.add_search_arguments(parser)
    parser.add_argument("--plot", type=common.figure_path, metavar="FILE",
                        help="critical speed: ranked tornado chart with the elasticities (.png, .svg, .pdf)")
    common.add_json_option(parser)
    common.add_linearisation_arguments(parser)
    parser.set_defaults(handler=run, numeric=True)


def run(model: Path, overrides: dict[str, str], *, quantity: str = "critical-speed", parameters: list[str] | None = None,
        speed: float | None = None, vmin: float = common.SEARCH.v_min, vmax: float = common.SEARCH.v_max,
        plot: Path | None = None, as_json: bool = False, every: bool = False,
        linearisation: str = "tangent", element_amplitude: float | None = None, element_angle: float | None = None, element_frequency: float | None = None,
        radius: float | None = None, cant: float | None = None, direction: str | None = None,
        contact: str | None = None, track: str | None = None, dt: float | None = None, step: float | None = None,
        step_check: bool = True) -> int:
    """Compute and print the sensitivities; returns the exit status."""
    spec = common.linearisation_spec(linearisation, element_amplitude, element_angle, element_frequency)
    from express.io.output import output_transaction

    if not vmax > vmin:
        raise UsageError(f"--vmax {vmax / common.KMH:g} km/h: must be above --vmin {vmin / common.KMH:g} km/h")
    if plot is not None and quantity != "critical-speed":
        raise UsageError("--plot draws the tornado chart of --output critical-speed")
    if speed is not None and quantity == "critical-speed":
        raise UsageError("--speed is the speed of --output eigenvalue or steady-curving")
    curve_options = [name for name, value in (("--radius", radius), ("--cant", cant), ("--direction", direction),
                                              ("--contact", contact)) if value is not None]
    if quantity == "steady-curving":
        if radius is None:
            raise UsageError("--output steady-curving: give the curve's --radius R (and --cant C, --speed V)")
        if linearisation != "tangent":
            raise UsageError(f"--linearisation {linearisation}: steady curving runs the nonlinear elements "
                             "themselves; the linearisation is of the linear analyses (critical-speed, eigenvalue)")
    elif curve_options:
        raise UsageError(f"{', '.join(curve_options)}: the curve of --output steady-curving")
    run_options = [name for name, value in (("--track", track), ("--dt", dt), ("--step", step),
                                            ("--no-step-check", None if step_check else False)) if value is not None]
    if quantity == "time-run":
        if linearisation != "tangent":
            raise UsageError(f"--linearisation {linearisation}: a time run runs the nonlinear elements themselves; "
                             "the linearisation is of the linear analyses (critical-speed, eigenvalue)")
    elif run_options:
        raise UsageError(f"{', '.join(run_options)}: the track run of --output time-run")
    inputs = [model] + ([Path(track)] if track is not None and Path(track).is_file() else [])
    with output_transaction(inputs) as transaction:
        if plot is not None:
            transaction.declare(plot, binary=True)
        vehicle = common.linearised_vehicle(common.load_rail_vehicle(model, overrides, "sensitivity"), spec)
        names = _names(vehicle, parameters)
        if quantity == "critical-speed":
            summary = _critical(vehicle, names, vmin, vmax, plot)
        elif quantity == "eigenvalue":
            summary = _eigenvalue(vehicle, names, common.running_speed(vehicle, speed))
        elif quantity == "time-run":
            summary = _time_run(vehicle, names, track, speed, 0.005 if dt is None else dt, step, step_check)
        else:
            assert radius is not None
            summary = _steady_curving(vehicle, names, radius, cant or 0.0, direction or "right",
                                      common.running_speed(vehicle, speed), contact)
        if parameters is None and not every:
            summary = _design_only(vehicle, summary)
    if plot is not None:
        common.note(f"wrote {plot}")
    summary = {"model": str(model), **summary}
    if quantity not in ("steady-curving", "time-run"):  # a steady curve runs the nonlinear elements: no linearisation to tell
        summary["linearisation"] = common.note_linearisation(vehicle)
    if as_json:
        common.print_json(summary)
    else:
        _print(vehicle.equations.name, summary)
    return 0


def _names(vehicle, parameters: list[str] | None) -> list[str]:
    from express.analysis.study.sensitivity import sensitivity_parameters

    known = sensitivity_parameters(vehicle)
    if parameters is None:
        return known
    unknown = [name for name in parameters if name not in known]
    if unknown:
        from express.base.names import did_you_mean

        raise UsageError("; ".join(f"--parameter {name}: not a given parameter of the model (nor the speed)"
                                   f"{did_you_mean(name, known)}" for name in unknown))
    return list(dict.fromkeys(parameters))


def _design_only(vehicle, summary: dict) -> dict:
    """The summary with the physical constants and the parameters without effect (a
    derivative exactly 0: no matrix depends on them) moved out of ``sensitivities``."""
    from express.analysis.study.sensitivity import physical_constants

    constants = [name for name in physical_constants(vehicle) if name in summary["sensitivities"]]
    sensitivities = summary["sensitivities"]
    idle = [name for name, value in sensitivities.items()
            if name not in constants and not any(number is None or number != 0 for number in _numbers(value))]
    hidden = set(constants) | set(idle)
    keyed = ("sensitivities", "elasticities", "estimates", "steps")
    kept = {key: {n: v for n, v in value.items() if n not in hidden} if key in keyed else value
            for key, value in summary.items()}
    return {**kept, "constants": {n: sensitivities[n] for n in constants}, "without_effect": idle}


def _numbers(value) -> list:
    """A sensitivity's numbers: one, a [re, im] pair or ``{output: d}`` (None: a time-run
    derivative flagged as not differentiable, an effect all the same)."""
    if isinstance(value, dict):
        return list(value.values())
    return value if isinstance(value, list) else [value]


def _critical(vehicle, names: list[str], vmin: float, vmax: float, plot: Path | None) -> dict:
    from express.analysis.stability.critical_options import CriticalOptions
    from express.analysis.study.sensitivity import critical_speed_sensitivity

    result = critical_speed_sensitivity(vehicle, names, CriticalOptions(v_min=vmin, v_max=vmax, tolerance=0.0))
    if plot is not None:
        from express.analysis.plots import save_figure
        from express.analysis.study.figures import figure_tornado

        save_figure(figure_tornado(result, title=f"{vehicle.equations.name}: critical speed "
                                   f"{result.critical_speed / common.KMH:.1f} km/h, sensitivities"), plot)
    return {"output": "critical_speed", **result.as_dict(), "critical_speed_kmh": result.critical_speed / common.KMH}


def _eigenvalue(vehicle, names: list[str], speed: float) -> dict:
    from express.analysis.study.sensitivity import eigenvalue_derivatives

    eigenvalues, derivatives = eigenvalue_derivatives(vehicle, speed, names)
    k = 0
    while k < len(eigenvalues) and eigenvalues[k].imag < 0:
        k += 1  # the member of the least stable pair with Im >= 0
    lam = complex(eigenvalues[k])
    return {
        "output": "eigenvalue", "speed": speed, "eigenvalue": [lam.real, lam.imag],
        "sensitivities": {name: [derivatives[name][k].real, derivatives[name][k].imag] for name in names},
    }


def _steady_curving(vehicle, names: list[str], radius: float, cant: float, direction: str, speed: float,
                    contact: str | None) -> dict:
    from express.analysis.curving.steady import SteadyCurve
    from express.analysis.study.curving_sensitivity import steady_curving_sensitivity

    result = steady_curving_sensitivity(vehicle, SteadyCurve(radius, cant, direction), speed=speed, parameters=names,
                                        contact=contact)
    for line in result.notes:
        common.note(line)
    return {"output": "steady_curving", **result.as_dict()}


def _time_run(vehicle, names: list[str], track: str | None, speed: float | None, dt: float, step: float | None,
              step_check: bool) -> dict:
    from express.analysis.study.time_run_sensitivity import STEP, time_run_sensitivity
    from express.analysis.time.simulate import running_speed
    from express.cli.simulate import MAX_STEPS

    road, where = common.track_and_name(track)  # a clear --track error before any run
    v = running_speed(vehicle, road, speed)[0]
    steps = road.length / (v * dt)
    if steps > MAX_STEPS:
        raise UsageError(f"--dt {dt:g} s: {steps:,.0f} steps for {road.length:g} m at {v / common.KMH:g} km/h; "
                         f"at most {MAX_STEPS:,} (give a larger --dt)")
    from express.analysis.curving.curves import track_problems

    problems = track_problems(vehicle, road, v)
    if problems:
        raise UsageError("\n".join(f"sensitivity: {problem}" for problem in problems))
    result = time_run_sensitivity(vehicle, road, speed=v, dt=dt, parameters=names, step=STEP if step is None else step,
                                  step_check=step_check)
    for line in result.notes:
        common.note(line)
    return {"output": "time_run", **result.as_dict(), "track": where}


def _print(name: str, summary: dict, stream=None) -> None:
    stream = stream or sys.stdout  # looked up now: the command line's checked standard output
    if summary["output"] == "steady_curving":
        _print_curving(name, summary, stream)
        return
    if summary["output"] == "time_run":
        _print_time_run(name, summary, stream)
        return
    if summary["output"] == "critical_speed":
        print(f"{name}: critical speed {summary['critical_speed_kmh']:.2f} km/h "
              f"({summary['critical_speed']:.4f} m/s, {summary['frequency_hz']:.3f} Hz); largest elasticity first",
              file=stream)
        print(f"  {'parameter':<12} {'dV/dp [SI]':>14} {'elasticity':>11}", file=stream)
        rows = sorted(summary["sensitivities"], key=lambda n: (-abs(summary["elasticities"][n]), n))
        for n in rows:
            print(f"  {n:<12} {summary['sensitivities'][n]:14.6g} {summary['elasticities'][n]:11.4f}", file=stream)
        _print_others(summary, stream)
        return
    re, im = summary["eigenvalue"]
    print(f"{name}: least stable eigenvalue {re:.5g} {im:+.5g}j 1/s at {summary['speed'] / common.KMH:.1f} km/h",
          file=stream)
    print(f"  {'parameter':<12} {'dRe/dp [SI]':>14} {'dIm/dp [SI]':>14}", file=stream)
    for n, (dre, dim) in sorted(summary["sensitivities"].items(), key=lambda item: (-abs(item[1][0]), item[0])):
        print(f"  {n:<12} {dre:14.6g} {dim:14.6g}", file=stream)
    _print_others(summary, stream)


def _print_curving(name: str, summary: dict, stream) -> None:
    values = summary["values"]
    print(f"{name}: steady curving in R = {summary['radius']:g} m, cant {summary['cant'] * 1e3:g} mm, "
          f"{summary['speed'] / common.KMH:.1f} km/h ({summary['contact']}): angle of attack "
          f"{values['steady_aoa'] * 1e3:.4g} mrad, largest Y/Q {values['steady_YQ']:.4g}, largest |SY| "
          f"{values['steady_SY'] / 1e3:.4g} kN; elasticities (p/y) dy/dp, largest first", file=stream)
    print(f"  {'parameter':<12} {'aoa':>9} {'Y/Q':>9} {'|SY|':>9}   {'d aoa/dp':>11} {'d Y/Q/dp':>11} {'d|SY|/dp':>11}",
          file=stream)
    outputs = ("steady_aoa", "steady_YQ", "steady_SY")
    elasticities, sensitivities = summary["elasticities"], summary["sensitivities"]
    rows = sorted(sensitivities, key=lambda n: (-max(abs(elasticities[n][o]) for o in outputs), n))
    for n in rows:
        e, d = elasticities[n], sensitivities[n]
        print(f"  {n:<12} " + " ".join(f"{e[o]:9.4f}" for o in outputs) + "   "
              + " ".join(f"{d[o]:11.4g}" for o in outputs), file=stream)
    if summary["differenced"]:
        print(f"  contact forces differenced (central) for: {', '.join(summary['differenced'])}; the rest from the "
              "symbolic K and P", file=stream)
    _print_others(summary, stream)


def _print_time_run(name: str, summary: dict, stream) -> None:
    import math

    values, maxima = summary["values"], summary["maxima"]
    print(f"{name}: {summary['track']}; {summary['speed'] / common.KMH:.1f} km/h, dt {summary['dt']:g} s: "
          f"(Y/Q)2m {values['max_YQ2m']:.4g} (wheel {maxima['max_YQ2m']['holder']} at "
          f"{maxima['max_YQ2m']['distance']:.1f} m), (SY)2m {values['max_SY2m'] / 1e3:.4g} kN (wheelset "
          f"{maxima['max_SY2m']['holder']} at {maxima['max_SY2m']['distance']:.1f} m), dQ/Q0 "
          f"{values['max_dQQ0']:.4g} (wheel {maxima['max_dQQ0']['holder']} at {maxima['max_dQQ0']['distance']:.1f} m)",
          file=stream)
    print(f"  central differences at p(1 +- {summary['step']:g}), checked at half the step (+- the difference); "
          f"'not diff.': the two disagree by more than {summary['tolerance']:.0%} or the maximum switches wheel",
          file=stream)
    outputs = ("max_YQ2m", "max_SY2m", "max_dQQ0")
    print(f"  {'parameter':<12} " + " ".join(f"{'d ' + o + '/dp':>24}" for o in outputs) + "   elasticities",
          file=stream)
    estimates, elasticities = summary["estimates"], summary["elasticities"]

    def size(n: str) -> float:
        return max((abs(e) for e in elasticities[n].values() if e is not None), default=math.inf)

    for n in sorted(estimates, key=lambda n: (-size(n), n)):
        cells = [f"{e['h']:11.4g} +-{e['error']:9.2g}" if e["differentiable"] else f"{'not diff.':>22}"
                 for e in (estimates[n][o] for o in outputs)]
        shown = " ".join(f"{elasticities[n][o]:8.4f}" if elasticities[n][o] is not None else f"{'-':>8}"
                         for o in outputs)
        print(f"  {n:<12} " + " ".join(f"{c:>24}" for c in cells) + f"   {shown}", file=stream)
    for line in summary["not_differentiable"]:
        print(f"  not differentiable: {line}", file=stream)
    for n in estimates:
        for o in outputs:
            if estimates[n][o]["switched"]:
                print(f"  {n}: {o}: {estimates[n][o]['switched']}", file=stream)
    _print_others(summary, stream)


def _print_others(summary: dict, stream) -> None:
    if summary.get("constants"):
        shown = ", ".join(f"{n} {_constant_text(v)}" for n, v in summary["constants"].items())
        print(f"  physical constants (not ranked; d/dp [SI]): {shown}", file=stream)
    if summary.get("without_effect"):
        why = {"steady_curving": "neither the matrices nor the contact depend on them",
               "time_run": "the runs are the same to the last bit"}.get(summary["output"], "no matrix depends on them")
        print(f"  without effect on the output ({why}): {', '.join(summary['without_effect'])}", file=stream)
    if "constants" in summary:
        print("  (--all ranks every parameter together)", file=stream)


def _constant_text(value) -> str:
    """A physical constant's derivative: the number (the real part of an eigenvalue's), or
    the steady-curving outputs' ``aoa/Y/Q/|SY|`` derivatives."""
    if isinstance(value, dict):
        return "/".join("-" if number is None else f"{number:.4g}" for number in value.values())
    return f"{value if not isinstance(value, list) else value[0]:.4g}"


def main(argv: Sequence[str] | None = None) -> int:
    """``express sensitivity`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
