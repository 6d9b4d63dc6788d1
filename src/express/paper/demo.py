"""``express demo``: the paper's results with the bundled vehicles, in well under a minute.

:func:`run_demo` writes into one directory:

``matrices/``
    The symbolic matrices of ``forced_steering``, ``conventional`` and the paper's
    Fig. 2/5 ``lever``, each as MATLAB (``.m``), LaTeX (``.tex``) and JSON.
``fig3_lever_step``, ``fig9_curving``, ``fig10_frequency_response``, ``fig11_critical_speed``
    Each as ``.png``, ``.svg`` and the data behind it as ``.csv`` (SI units).
``stability_root_locus``, ``stability_damping``
    The steered car's eigenvalues in the complex plane and its damping ratios against
    speed (``.png``, ``.svg``; the modes in ``stability_modes.csv``).
``summary.md``
    Key figures next to the paper's stated values, each with a verdict computed from
    the numbers and a sentence on why (:mod:`express.paper.demo_summary`);
    ``summary.json`` holds the same numbers and verdicts.

This module runs the steps; each figure has its own module (``demo_lever``,
``demo_curving``, ``demo_frequency``, ``demo_stability``) that measures a typed record
and draws it; ``demo_summary`` turns the records into verdicts and ``demo_report``
into ``summary.md`` and ``summary.json``; the paper's numbers live in
:mod:`express.paper.numbers`.  Nothing
here is tuned to the paper: the vehicle parameters are the bundled ones
(``docs/parameters.md``).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from express.base.diagnostics import ArgumentError
from express.paper.demo_common import Cars
from express.paper.demo_curving import Curving, measure_curving, write_curving
from express.paper.demo_frequency import FloorResponse, measure_floor_response, write_floor_response
from express.paper.demo_lever import LeverStep, lever_cases, lever_step_response, measure_lever, write_lever
from express.paper.demo_report import summary_markdown, summary_numbers
from express.paper.demo_stability import (
    StabilityMap,
    StabilitySweep,
    measure_stability,
    measure_stability_map,
    write_stability,
    write_stability_map,
)
from express.paper.demo_summary import Verdict, summary_rows
from express.paper.numbers import PAPER

__all__ = [
    "LEVER_CASES",
    "PAPER",
    "DemoResults",
    "find_examples",
    "lever_step_response",
    "measure_demo",
    "run_demo",
]

#: Table 1's leverage cases as used for Fig. 3 (case 3 with its arms swapped), as mappings.
LEVER_CASES = tuple({"case": c.case, "condition": c.condition, "lLU": c.upper_arm, "lLL": c.lower_arm,
                     "kLU": c.upper_stiffness, "kLL": c.lower_stiffness} for c in lever_cases())

_MODELS = {"steered": "forced-steering.toml", "conventional": "conventional.toml", "lever": "lever.exp"}


def find_examples(examples: Path | None = None) -> Path:
    """The directory of the bundled models (``examples/`` of the source tree)."""
    candidates = [examples] if examples is not None else [
        Path(__file__).resolve().parents[3] / "examples",
        Path.cwd() / "examples",
    ]
    for candidate in candidates:
        if candidate is not None and (candidate / "forced-steering.toml").is_file():
            return candidate
    where = ", ".join(str(c) for c in candidates if c is not None)
    raise ArgumentError(f"cannot find the bundled models (forced-steering.toml) in {where}; give --examples DIR")


def load_cars(examples: Path, overrides: Mapping[str, float] | None = None) -> Cars:
    """The two bundled cars, with ``overrides`` (SI) applied where a car has the parameter."""
    from express.numeric.statespace import load_vehicle

    cars = Cars(load_vehicle(examples / _MODELS["steered"]), load_vehicle(examples / _MODELS["conventional"]))
    return cars.with_values(overrides) if overrides else cars


@dataclass(frozen=True)
class DemoResults:
    """Everything the demo measured, and the verdicts drawn from it."""

    lever: LeverStep
    curving: Curving
    floor: FloorResponse
    stability: StabilitySweep
    stability_map: StabilityMap | None
    verdicts: tuple[Verdict, ...]


def measure_demo(cars: Cars, lever_equations, *, stability_map: bool = False) -> DemoResults:
    """All the demo's measurements and verdicts, without writing anything.

    Parameters
    ----------
    cars : Cars
        The steered and the conventional car (possibly changed, to see how the verdicts
        follow the model).
    lever_equations : EquationsOfMotion
        Of ``examples/lever.exp``.
    stability_map : bool
        Also compute the steered car's root locus.
    """
    lever = measure_lever(lever_equations)
    curving = measure_curving(cars)
    floor = measure_floor_response(cars)
    sweep = measure_stability(cars)
    locus = measure_stability_map(cars.steered) if stability_map else None
    return DemoResults(lever, curving, floor, sweep, locus, tuple(summary_rows(lever, curving, floor, sweep)))


def _matrices(outdir: Path, equations: Mapping[str, Any], log: Callable[[str], None]) -> None:
    """The symbolic matrices of each model as MATLAB (the name is the file's), LaTeX and JSON."""
    from express.export import to_json, to_latex, to_matlab
    from express.io.output import write_text

    counts = []
    for eq in equations.values():
        write_text(outdir / "matrices" / f"{eq.name}.m", to_matlab(eq))
        write_text(outdir / "matrices" / f"{eq.name}.tex", to_latex(eq))
        write_text(outdir / "matrices" / f"{eq.name}.json", to_json(eq))
        counts.append(f"{eq.name} ({len(eq.dofs)} DOFs)")
    log("  matrices: " + ", ".join(counts))


def run_demo(outdir: str | Path = "demo-out", *, examples: Path | None = None,
             log: Callable[[str], None] = print) -> Path:
    """Write every result of the paper's section 4.4 into ``outdir``; return the path of
    ``summary.md``.

    Parameters
    ----------
    outdir : path
        Created if needed; files in it are replaced.
    examples : path, optional
        Directory of the bundled models (found automatically in a source checkout).
    log : callable
        Receives one line per step (progress and key numbers).
    """
    from express.io import load_model
    from express.io.output import write_text
    from express.io.text_formats import json_text
    from express.rail.build import generate_vehicle

    start = time.perf_counter()
    outdir = Path(outdir)
    examples = find_examples(examples)
    log(f"express demo: writing {outdir}/")
    cars = load_cars(examples)
    lever_equations = generate_vehicle(load_model(examples / _MODELS["lever"])).equations
    _matrices(outdir, {"steered": cars.steered.equations, "conventional": cars.conventional.equations,
                       "lever": lever_equations}, log)
    results = measure_demo(cars, lever_equations, stability_map=True)
    write_lever(outdir, results.lever, log)
    write_curving(outdir, results.curving, cars, log)
    write_floor_response(outdir, results.floor, log)
    write_stability(outdir, results.stability, cars, log)
    assert results.stability_map is not None
    write_stability_map(outdir, results.stability_map, cars.steered.equations.name)
    rows = list(results.verdicts)
    write_text(outdir / "summary.json", json_text(summary_numbers(rows, results.lever, results.curving,
                                                                  results.floor, results.stability)))
    summary = outdir / "summary.md"
    write_text(summary, summary_markdown(rows, results.curving, time.perf_counter() - start))
    log(f"  {sum(r.agrees for r in rows)} of {len(rows)} verdicts agree with the paper; "
        f"done in {time.perf_counter() - start:.1f} s")
    return summary
