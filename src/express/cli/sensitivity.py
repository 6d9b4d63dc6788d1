"""``express sensitivity``: exact derivatives of the critical speed (or of the least
stable eigenvalue at a speed) with respect to every parameter
(:mod:`express.analysis.study.sensitivity`)."""

from __future__ import annotations

import sys
from pathlib import Path

from express.base.diagnostics import UsageError
from express.cli import common

__all__ = ["add_parser", "run"]


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "sensitivity", help="exact derivatives of the critical speed (or an eigenvalue) with respect to the parameters",
        description="Derivatives from the symbolic matrices: dlambda/dp = y^H (dA/dp) x / (y^H x) for an eigenvalue, "
        "and dV/dp = -(dRe lambda/dp)/(dRe lambda/dV) at the critical speed (implicit function theorem). "
        "Derived parameters follow through the parameter graph. SI units; elasticities (p/V) dV/dp.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--output", dest="quantity", choices=("critical-speed", "eigenvalue"), default="critical-speed",
                        help="critical-speed (default) or eigenvalue: the least stable eigenvalue at --speed")
    parser.add_argument("--parameter", dest="parameters", action="append", metavar="NAME",
                        help="only this parameter (repeatable; default: every given parameter but the speed)")
    parser.add_argument("--all", dest="every", action="store_true",
                        help="rank every given parameter together (default: the design parameters, then the physical "
                        "constants such as g and the parameters without effect on the output in separate lists)")
    parser.add_argument("--speed", type=common.SPEED, metavar="SPEED",
                        help=common.SPEED.help("speed of --output eigenvalue", "the model's speed"))
    common.add_search_arguments(parser)
    parser.add_argument("--plot", type=common.figure_path, metavar="FILE",
                        help="critical speed: ranked tornado chart with the elasticities (.png, .svg, .pdf)")
    common.add_json_option(parser)
    common.add_linearisation_arguments(parser)
    parser.set_defaults(handler=run, numeric=True)


def run(model: Path, overrides: dict[str, str], *, quantity: str = "critical-speed", parameters: list[str] | None = None,
        speed: float | None = None, vmin: float = common.SEARCH.v_min, vmax: float = common.SEARCH.v_max,
        plot: Path | None = None, as_json: bool = False, every: bool = False,
        linearisation: str = "tangent", element_amplitude: float | None = None, element_angle: float | None = None, element_frequency: float | None = None) -> int:
    """Compute and print the sensitivities; returns the exit status."""
    spec = common.linearisation_spec(linearisation, element_amplitude, element_angle, element_frequency)
    from express.io.output import output_transaction

    if not vmax > vmin:
        raise UsageError(f"--vmax {vmax / common.KMH:g} km/h: must be above --vmin {vmin / common.KMH:g} km/h")
    if plot is not None and quantity != "critical-speed":
        raise UsageError("--plot draws the tornado chart of --output critical-speed")
    if speed is not None and quantity != "eigenvalue":
        raise UsageError("--speed is the speed of --output eigenvalue")
    with output_transaction([model]) as transaction:
        if plot is not None:
            transaction.declare(plot, binary=True)
        vehicle = common.linearised_vehicle(common.load_rail_vehicle(model, overrides, "sensitivity"), spec)
        names = _names(vehicle, parameters)
        if quantity == "critical-speed":
            summary = _critical(vehicle, names, vmin, vmax, plot)
        else:
            summary = _eigenvalue(vehicle, names, common.running_speed(vehicle, speed))
        if parameters is None and not every:
            summary = _design_only(vehicle, summary)
    if plot is not None:
        common.note(f"wrote {plot}")
    summary = {"model": str(model), **summary, "linearisation": common.note_linearisation(vehicle)}
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
            if name not in constants and not any(value if isinstance(value, list) else [value])]
    hidden = set(constants) | set(idle)
    kept = {key: {n: v for n, v in value.items() if n not in hidden} if key in ("sensitivities", "elasticities") else value
            for key, value in summary.items()}
    return {**kept, "constants": {n: sensitivities[n] for n in constants}, "without_effect": idle}


def _critical(vehicle, names: list[str], vmin: float, vmax: float, plot: Path | None) -> dict:
    from express.analysis.critical_options import CriticalOptions
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


def _print(name: str, summary: dict, stream=None) -> None:
    stream = stream or sys.stdout  # looked up now: the command line's checked standard output
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


def _print_others(summary: dict, stream) -> None:
    if summary.get("constants"):
        shown = ", ".join(f"{n} {v if not isinstance(v, list) else v[0]:.4g}" for n, v in summary["constants"].items())
        print(f"  physical constants (not ranked; d/dp [SI]): {shown}", file=stream)
    if summary.get("without_effect"):
        print(f"  without effect on the output (no matrix depends on them): {', '.join(summary['without_effect'])}",
              file=stream)
    if "constants" in summary:
        print("  (--all ranks every parameter together)", file=stream)
