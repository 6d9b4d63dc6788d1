"""The demo's ``summary.md`` (the table of verdicts, how they are decided, the files) and
``summary.json`` (the numbers behind it), from the verdicts of
:mod:`express.paper.demo_summary`."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict
from typing import Any

from express.paper.demo_curving import Curving
from express.paper.demo_frequency import FloorResponse
from express.paper.demo_lever import LeverStep
from express.paper.demo_stability import StabilitySweep, vcr_shape
from express.paper.demo_summary import (
    CONICITY_FACTOR,
    DIFFERENT,
    FORCE_TOLERANCE,
    GEOMETRY_TOLERANCE,
    LEVER_TOLERANCE,
    MERGE,
    NEARLY_EQUAL,
    RADIAL_TOLERANCE,
    SHARP_FALL,
    Verdict,
)
from express.paper.numbers import PAPER

__all__ = ["TOLERANCES", "summary_markdown", "summary_numbers"]

#: The tolerances of the verdicts, named as ``summary.md`` states them.
TOLERANCES = (
    ("forces", FORCE_TOLERANCE), ("lever angle share", LEVER_TOLERANCE), ("input geometry", GEOMETRY_TOLERANCE),
    ("steering angle against a/R", RADIAL_TOLERANCE), ("Q2/Q1 'nearly equal'", NEARLY_EQUAL),
    ("front/rear floor 'differ'", DIFFERENT), ("V_cr curves 'merge'", MERGE),
)


def summary_markdown(rows: Sequence[Verdict], curving: Curving, elapsed: float) -> str:
    """``summary.md``: the table of verdicts, how they are decided, and the files."""
    agreeing = sum(row.agrees for row in rows)
    lines = [
        "# EXPRESS demo: the paper's results with the bundled vehicles",
        "",
        "Tanifuji & Suzuki (2001), section 4.4, re-created with `examples/forced-steering.toml` and "
        "`examples/conventional.toml` (parameters: `docs/parameters.md`, chosen from published data and "
        "**not tuned** to the paper's figures), and the paper's lever `examples/lever.exp`.",
        f"Steady values are means over the leading wheelset at d1 = {curving.window[0]:.0f}–{curving.window[1]:.0f} m, "
        "where the whole car is in the circular curve. Paper values are the ones its text states (its figures are "
        "not machine-readable).",
        "",
        f"{agreeing} of {len(rows)} rows agree with the paper.",
        "",
        "| Quantity | Paper | This run | Verdict | Why |",
        "|---|---|---|---|---|",
    ]
    for row in rows:
        lines.append("| " + " | ".join(cell.replace("|", "\\|") for cell in row.cells()) + " |")
    lines += [
        "",
        "## How the verdicts are decided",
        "",
        "Each verdict is the outcome of a test on the numbers (`summary.json`, `verdicts`); the tolerances are "
        "ours: " + "; ".join(f"{name} {_percent(value)}" for name, value in TOLERANCES)
        + f"; the steered V_cr maximum within a factor {CONICITY_FACTOR:g} of the paper's Γ, and a fall below "
        f"{_percent(SHARP_FALL)} of it at the smallest Γ.",
        "",
    ]
    lines += [f"- {row.key}: {row.test} → {'agrees' if row.agrees else 'differs'}" for row in rows]
    lines += [
        "",
        "## Files",
        "",
        "- `matrices/`: symbolic M, C, K, P, Pd of each vehicle and of the lever (`.m`, `.tex`, `.json`)",
        "- `fig3_lever_step`, `fig9_curving`, `fig10_frequency_response`, `fig11_critical_speed`: "
        "`.png`, `.svg` and the data as `.csv` (SI units)",
        "- `stability_root_locus`, `stability_damping`: the steered car's eigenvalues against speed (`.png`, `.svg`;"
        " the modes followed across speeds in `stability_modes.csv`)",
        "- `summary.json`: the numbers and verdicts of this table",
        "",
        f"Run time: {elapsed:.1f} s.",
        "",
    ]
    return "\n".join(lines)


def summary_numbers(rows: Sequence[Verdict], lever: LeverStep, curving: Curving, response: FloorResponse,
                    sweep: StabilitySweep) -> dict:
    """``summary.json``: the numbers behind the table (SI unless the key says otherwise)."""
    paper: dict[str, Any] = {name: asdict(value) for name, value in vars(PAPER).items() if name != "table1"}
    paper["table1"] = [asdict(case) for case in PAPER.table1]
    return {
        "paper": paper,
        "verdicts": [asdict(row) | {"difference": row.difference} for row in rows],
        "lever_angle_rad": curving.steady["theta_L1"],
        "lever_angle_geometric_rad": curving.geometric_lever,
        "steering_angle_ideal_rad": curving.ideal_yaw,
        "curve": asdict(curving.geometry),
        "steady": dict(curving.steady),
        "peaks": dict(curving.peaks),
        "cant_deficiency_m_s2": curving.cant_deficiency,
        "bogie_lateral_force_N": curving.bogie_force,
        "link_force_N": curving.link_force,
        "link_stiffness_for_paper_angle_N_m": curving.link_stiffness_for_paper_angle,
        "lever_angle_check_rad": curving.lever_angle_check,
        "critical_speed_shape": asdict(vcr_shape(sweep)),
        "critical_speed_kmh": {"Gamma": sweep.conicities, **dict(sweep.speeds_kmh.items())},
        "low_conicity": asdict(sweep.low_conicity) if sweep.low_conicity is not None else None,
        "lever_static_q2_rad": {str(c.case): v for c, v in zip(lever.cases, lever.static_q2, strict=True)},
        "floor_acceleration_peaks": {k: {"amplitude_m_s2": a, "frequency_hz": f} for k, (a, f) in response.peaks.items()},
        "floor_front_rear_difference": dict(response.front_rear_difference),
    }


def _percent(fraction: float) -> str:
    return f"{fraction * 100:.0f} %"
