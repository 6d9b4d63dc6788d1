"""Regenerate the open reference benchmark of the bundled vehicles (docs/reference-benchmark.md).

Usage::

    python benchmarks/reference/make_reference.py [--out DIR] [--vehicles lever,conventional]

For each vehicle it writes ``<name>.json`` (parameters, conventions, critical speeds and
the precision achieved) and the CSV tables ``<name>-matrices.csv``,
``<name>-eigenvalues.csv``, ``<name>-critical-speeds.csv`` and
``<name>-frequency-response.csv``. Every reference number is computed from the exact
symbolic matrices with mpmath at 50 significant digits (:mod:`highprecision`), recomputed
at 30 digits as a check, and printed to 15 significant digits; the library's own
double-precision results (``express.numeric``, ``express.analysis``) are compared with
them and their agreement is stated. The output is byte-identical from run to run (sorted
keys, fixed digit counts, no dates); the files are written all or none
(:func:`express.io.output.output_transaction`). Takes a few minutes (mpmath's ``eig``).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from decimal import Decimal
from pathlib import Path

import mpmath

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import highprecision as hp  # noqa: E402
from reference_format import csv_table, json_document, number, relative_errors  # noqa: E402

ROOT = HERE.parents[1]
#: Working precision of the reference [significant decimal digits], and of the check.
DPS, CHECK_DPS = 50, 30
#: Significant digits printed.
DIGITS = 15


@dataclass(frozen=True)
class Case:
    """One vehicle of the benchmark and the points at which it is tabulated."""

    name: str
    model: str
    speeds: tuple[float, ...] = ()
    conicities: tuple[float, ...] = ()
    response_speed: float = 0.0
    frequencies: tuple[float, ...] = ()
    values: dict[str, float] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)


#: The lever of the paper's Figs. 2 and 5 (examples/lever.exp has no values; these are
#: the ones of the ground_response example, express.analysis.frequency.frequency).
LEVER_VALUES = {"J1": 2.0, "J2": 0.5, "b": 0.4, "c": 300.0, "kLL": 5.5e6, "kLU": 5e5, "lLL": 0.06, "lLU": 0.3,
                "m": 20.0}
LEVER_UNITS = {"J1": "kg*m^2", "J2": "kg*m^2", "b": "m", "c": "kg/s", "kLL": "kg/s^2", "kLU": "kg/s^2",
               "lLL": "m", "lLU": "m", "m": "kg"}
RAIL = {"speeds": (10.0, 30.0, 90.0), "conicities": (0.05, 0.1, 0.2, 0.3, 0.4), "response_speed": 30.0,
        "frequencies": (0.5, 1.0, 2.0, 5.0, 10.0, 20.0)}
CASES = (
    Case("lever", "examples/lever.exp", frequencies=(0.0, 1.0, 10.0, 50.0, 100.0, 200.0), values=LEVER_VALUES,
         units=LEVER_UNITS),
    Case("forced-steering", "examples/forced-steering.toml", **RAIL),
    Case("conventional", "examples/conventional.toml", **RAIL),
    Case("manchester", "examples/manchester.toml", **RAIL),
)
#: The scan of the critical speed [m/s] (express.analysis.stability.stability.critical_speed).
SCAN: dict[str, float | int] = {"v_min": 1.0, "v_max": 300.0, "points": 200}


def load(case: Case):
    """The library's numerical vehicle of a case (express.numeric.statespace)."""
    from express.io import load_model
    from express.model.parameters import with_values
    from express.numeric.statespace import load_vehicle, vehicle_model

    if case.values:
        return vehicle_model(with_values(load_model(ROOT / case.model), case.values))
    return load_vehicle(ROOT / case.model)


def decimal_values(vehicle, changes: dict[str, float] | None = None) -> dict[str, str]:
    """Every parameter value [SI] as the decimal text (shortest round trip of the double)
    that the reference takes as exact."""
    values = {name: float(value) for name, value in vehicle.model.values().items()}
    values |= changes or {}
    return {name: repr(value) for name, value in values.items()}


# ---------------------------------------------------------------------------------------
# The reference at high precision
# ---------------------------------------------------------------------------------------


def reference(case: Case, vehicle, dps: int) -> dict:
    """Every reference quantity of ``case`` at ``dps`` digits (mpmath numbers)."""
    with mpmath.workdps(dps):
        exact = hp.exact_vehicle(vehicle)
        values = decimal_values(vehicle)
        split = hp.speed_split(exact, values)
        result = {"matrices": split}
        result["eigenvalues"] = {v: hp.eigenvalues(split["M"], hp.damping(split, v or 1.0), split["K"])
                                 for v in case.speeds or (None,)}
        result["critical"] = {g: _critical(vehicle, exact, g) for g in case.conicities}
        if exact.speed is None:
            result["response"] = hp.ground_response(exact, split, case.frequencies)
        else:
            result["response"] = hp.track_response(exact, split, values, case.response_speed, case.frequencies)
        return result


def _critical(vehicle, exact, conicity: float):
    """``(speed, eigenvalue)`` at high precision, or None (no crossing in the scan)."""
    from express.analysis.stability.stability import critical_speed

    changed = vehicle.with_values({"Gamma": conicity})
    found = critical_speed(changed, tolerance_kmh=1e-9, threshold=0.0, **SCAN)
    if not found.found or found.unstable_at_min:
        return None
    split = hp.speed_split(exact, decimal_values(vehicle, {"Gamma": conicity}))
    value, vector = hp.start_eigenpair(changed, found.speed)
    speed, eigenvalue, _ = hp.critical_speed(split, found.speed, value, vector)
    return speed, eigenvalue


# ---------------------------------------------------------------------------------------
# The library in double precision
# ---------------------------------------------------------------------------------------


def library(case: Case, vehicle) -> dict:
    """The same quantities from the library's public functions (double precision)."""
    from express.analysis.frequency.frequency import frequency_response, ground_response
    from express.analysis.stability.stability import critical_speed, root_locus

    matrices = {"M": vehicle.mass, "K": vehicle.stiffness, "C0": vehicle.damping_base,
                "C1": vehicle.damping_creep, "P0": vehicle.forcing_base, "P2": vehicle.forcing_speed2,
                "Pd": vehicle.forcing_rate_matrix}
    result: dict = {"matrices": matrices}
    if case.speeds:
        result["eigenvalues"] = dict(zip(case.speeds, root_locus(vehicle, case.speeds), strict=True))
    else:
        result["eigenvalues"] = {None: vehicle.eigenvalues(1.0)}
    result["critical"] = {}
    for g in case.conicities:
        found = critical_speed(vehicle.with_values({"Gamma": g}), tolerance_kmh=1e-9, threshold=0.0, **SCAN)
        result["critical"][g] = None if not found.found or found.unstable_at_min else found.speed
    if case.speeds:
        frf = frequency_response(vehicle, case.frequencies, amplitude=1.0, speed=case.response_speed)
        result["response"] = {name: frf.amplitude_of(name) for name in frf.names}
    else:
        tf = ground_response(vehicle, case.frequencies)
        result["response"] = {(d, u): tf.of(d, u) for d in tf.dofs for u in tf.inputs}
    return result


# ---------------------------------------------------------------------------------------
# Tables
# ---------------------------------------------------------------------------------------


def matrix_rows(vehicle, matrices) -> list[list[str]]:
    """``matrix, row, column, value`` of every non-zero entry."""
    dofs, inputs = vehicle.dofs, vehicle.inputs
    rows = []
    for name in hp.MATRICES:
        if name not in matrices:
            continue
        matrix = matrices[name]
        scale = max((abs(matrix[i, j]) for i in range(matrix.rows) for j in range(matrix.cols)), default=0)
        columns = dofs if name in ("M", "K", "C0", "C1") else inputs
        for i in range(matrix.rows):
            for j in range(matrix.cols):
                text = number(matrix[i, j], DIGITS, scale)
                if Decimal(text) != 0:
                    rows.append([name, dofs[i], columns[j], text])
    return rows


def eigenvalue_rows(eigenvalues: dict) -> list[list[str]]:
    """``speed_m_s, rank, real, imag``, sorted by descending real then imaginary part."""
    rows = []
    for speed, values in eigenvalues.items():
        scale = max(abs(z) for z in values)
        printed = [(number(z.real, DIGITS, scale), number(z.imag, DIGITS, scale)) for z in values]
        printed.sort(key=lambda pair: (-Decimal(pair[0]), -Decimal(pair[1])))
        speed_text = number(speed, DIGITS) if speed is not None else ""
        rows += [[speed_text, str(k), re, im] for k, (re, im) in enumerate(printed)]
    return rows


def critical_rows(critical: dict) -> list[list[str]]:
    """``conicity, speed_m_s, speed_km_h, imag_rad_s, frequency_hz`` (empty when none)."""
    rows = []
    for g, found in critical.items():
        if found is None:
            rows.append([number(g, DIGITS), "", "", "", ""])
            continue
        speed, eigenvalue = found
        imag = abs(eigenvalue.imag)
        rows.append([number(g, DIGITS), number(speed, DIGITS), number(speed * mpmath.mpf(36) / 10, DIGITS),
                     number(imag, DIGITS), number(imag / (2 * mpmath.pi), DIGITS)])
    return rows


def response_rows(case: Case, response: dict) -> list[list[str]]:
    """``frequency_hz, name[, input], real, imag`` of every DOF (and output point)."""
    rows = []
    scale = max(abs(x) for values in response.values() for x in values)
    for key, values in response.items():
        names = list(key) if isinstance(key, tuple) else [key]
        for f, x in zip(case.frequencies, values, strict=True):
            rows.append([number(f, DIGITS), *names, number(x.real, DIGITS, scale), number(x.imag, DIGITS, scale)])
    return rows


def tables(case: Case, vehicle, result: dict) -> dict[str, list[list[str]]]:
    """The rows of every table of ``result``, by file suffix."""
    out = {"matrices": matrix_rows(vehicle, result["matrices"]),
           "eigenvalues": eigenvalue_rows(result["eigenvalues"]),
           "frequency-response": response_rows(case, result["response"])}
    if case.conicities:
        out["critical-speeds"] = critical_rows(result["critical"])
    return out


HEADERS = {
    "matrices": ["matrix", "row", "column", "value"],
    "eigenvalues": ["speed_m_s", "rank", "real_1_s", "imag_rad_s"],
    "critical-speeds": ["conicity", "speed_m_s", "speed_km_h", "imag_rad_s", "frequency_hz"],
    "frequency-response": ["frequency_hz", "name", "real", "imag"],
    "transfer-functions": ["frequency_hz", "dof", "input", "real", "imag"],
}


# ---------------------------------------------------------------------------------------
# Agreement
# ---------------------------------------------------------------------------------------


def agreement(case: Case, computed: dict, result: dict) -> dict[str, float]:
    """Largest error of ``computed`` against ``result`` per quantity, as the documented
    comparison rule measures it (:func:`reference_format.relative_errors`)."""
    errors = {"matrices": 0.0, "eigenvalues": 0.0, "frequency_response": 0.0}
    for name, matrix in result["matrices"].items():
        errors["matrices"] = max(errors["matrices"], relative_errors(computed["matrices"][name], matrix).max())
    for speed, values in result["eigenvalues"].items():
        errors["eigenvalues"] = max(errors["eigenvalues"], relative_errors(computed["eigenvalues"][speed], values,
                                                                          match=True).max())
    keys = list(result["response"])
    errors["frequency_response"] = relative_errors([x for key in keys for x in computed["response"][key]],
                                                   [x for key in keys for x in result["response"][key]]).max()
    if case.conicities:
        pairs = [(computed["critical"][g], found) for g, found in result["critical"].items() if found is not None]
        errors["critical_speeds"] = max(
            relative_errors([c if not isinstance(c, tuple) else c[0] for c, _ in pairs], [r[0] for _, r in pairs]).max(),
            0.0,
        )
    return errors


#: What the numbers mean, in the files themselves (docs/reference-benchmark.md says more).
CONVENTIONS = {
    "axes": "x forward, y left, z up; rotations rx, ry, rz by the right-hand rule; DOF <body>.<dof>",
    "units": "SI: m, rad, kg, N, s; speed in m/s; frequency in Hz; eigenvalues 1/s (real), rad/s (imag)",
    "equations": "M q'' + C(v) q' + K q = P(v) u + Pd u', C(v) = C0 + C1/v, P(v) = P0 + P2 v^2",
    "eigenvalues": "all roots of det(lambda^2 M + lambda C(v) + K) = 0",
    "critical_speed": "lowest speed in the scan at which the largest real part of the eigenvalues "
                      "crosses zero, at the conicity Gamma given, the other values as listed",
    "frequency_response": "q_i = Im(X_i exp(i w t)) per metre of alignment yR_n = Im(exp(i w (t - t_n))), "
                          "t_n = (x_lead - x_n)/v; outputs: lateral displacement y + rz lx - rx lz of a point",
    "comparison": "|a - b| <= rtol max(|b|, 1e-6 s), s the largest magnitude of the group; "
                  "|a| <= rtol s where the reference is an exact zero",
}
LEVER_CONVENTIONS = {
    key: CONVENTIONS[key] for key in ("axes", "comparison")
} | {
    "units": "SI: m, rad, kg, N, s; frequency in Hz; eigenvalues 1/s (real), rad/s (imag)",
    "equations": "M q'' + C q' + K q = P u + Pd u'",
    "eigenvalues": "all roots of det(lambda^2 M + lambda C + K) = 0",
    "transfer_functions": "q_i = Im(H_ij exp(i w t)) for u_j = Im(exp(i w t)), one input at a time",
}


def describe(case: Case, vehicle, check: dict, double: dict) -> dict:
    """The JSON document of a case (everything but the tables)."""
    model = vehicle.model
    parameters = {}
    for name, value in decimal_values(vehicle).items():
        parameter = model.parameters.get(name)
        unit = case.units.get(name) or (parameter.dimension.si() if parameter and parameter.dimension else "")
        kind = "given"
        if name == hp.speed_name(vehicle):
            kind = "the model's own speed, not used: every table states its speed"
        elif parameter is not None and parameter.expression is not None:
            kind = f"derived: {parameter.expression}"
        elif parameter is not None and parameter.derived_by:
            kind = f"derived by [{parameter.derived_by}] (Kalker), taken as given here"
        parameters[name] = {"value": number(value), "si_unit": unit, "kind": kind,
                            "unit_in_model": (parameter.unit if parameter is not None else "")}
    document = {
        "conventions": CONVENTIONS if case.speeds else LEVER_CONVENTIONS,
        "documentation": "docs/reference-benchmark.md",
        "vehicle": case.name,
        "model_file": case.model,
        "title": model.title if getattr(model, "title", None) else case.name,
        "dofs": list(vehicle.dofs),
        "inputs": list(vehicle.inputs),
        "parameters": parameters,
        "speeds_m_s": [number(v) for v in case.speeds],
        "conicities": [number(g) for g in case.conicities],
        "response": {"frequencies_hz": [number(f) for f in case.frequencies]},
        "files": sorted(f"{case.name}-{suffix}.csv" for suffix in _suffixes(case)),
        "precision": {
            "working_digits": DPS,
            "check_digits": CHECK_DPS,
            "printed_significant_digits": DIGITS,
            "max_error_check_vs_working": {k: number(v, 2) for k, v in sorted(check.items())},
            "max_error_double_precision_library": {k: number(v, 2) for k, v in sorted(double.items())},
        },
    }
    if case.speeds:
        document["response"] |= {"speed_m_s": number(case.response_speed), "amplitude_m": number(1.0),
                                 "outputs": [point.name for point in model.rail.outputs]}
        document["critical_speed_scan"] = {k: v if isinstance(v, int) else number(v) for k, v in SCAN.items()}
    return document


def _suffixes(case: Case) -> list[str]:
    names = ["matrices", "eigenvalues", "frequency-response" if case.speeds else "transfer-functions"]
    return names + (["critical-speeds"] if case.conicities else [])


def build(case: Case) -> dict[str, str]:
    """The files of one case: ``{file name: text}``."""
    start = time.perf_counter()
    vehicle = load(case)
    result = reference(case, vehicle, DPS)
    checked = reference(case, vehicle, CHECK_DPS)
    with mpmath.workdps(DPS):  # printed from the working precision
        check = agreement(case, checked, result)
        double = agreement(case, library(case, vehicle), result)
        printed = tables(case, vehicle, result)
    files = {}
    for suffix, rows in printed.items():
        header = HEADERS["transfer-functions" if suffix == "frequency-response" and not case.speeds else suffix]
        suffix = "transfer-functions" if suffix == "frequency-response" and not case.speeds else suffix
        files[f"{case.name}-{suffix}.csv"] = csv_table(header, rows)
    files[f"{case.name}.json"] = json_document(describe(case, vehicle, check, double))
    print(f"{case.name}: {time.perf_counter() - start:.0f} s; check {check}; double {double}", flush=True)
    return files


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=HERE, help="directory of the files (default: this one)")
    parser.add_argument("--vehicles", default=",".join(c.name for c in CASES), help="comma-separated names")
    options = parser.parse_args(argv)
    chosen = [c for c in CASES if c.name in options.vehicles.split(",")]
    unknown = set(options.vehicles.split(",")) - {c.name for c in CASES}
    if unknown:
        print(f"make_reference: unknown vehicle(s) {', '.join(sorted(unknown))}; "
              f"known: {', '.join(c.name for c in CASES)}", file=sys.stderr)
        return 2
    from express.io.output import output_transaction, write_text

    files = {}
    for case in chosen:
        files |= build(case)
    options.out.mkdir(parents=True, exist_ok=True)
    with output_transaction():
        for name, text in sorted(files.items()):
            write_text(options.out / name, text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
