"""``express demo``: every file of the paper's results, and a summary that quotes the paper."""

from __future__ import annotations

import csv
import json
import re

import pytest

from express.cli import main

pytestmark = pytest.mark.slow

FIGURES = ("fig3_lever_step", "fig9_curving", "fig10_frequency_response", "fig11_critical_speed")
VEHICLES = ("forced_steering", "conventional", "lever")


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    """Run the demo once: (output directory, exit status, stdout, stderr)."""
    import io
    from contextlib import redirect_stderr, redirect_stdout

    outdir = tmp_path_factory.mktemp("demo") / "out"
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        status = main(["demo", str(outdir)])
    return outdir, status, out.getvalue(), err.getvalue()


def test_demo_succeeds(demo):
    outdir, status, out, err = demo
    assert status == 0, err
    assert "summary.md" in out
    assert "Fig. 9" in err and "Fig. 11" in err  # progress lines


def test_demo_writes_the_matrices(demo):
    outdir = demo[0]
    for name in VEHICLES:
        for suffix in (".m", ".tex", ".json"):
            path = outdir / "matrices" / f"{name}{suffix}"
            assert path.is_file() and path.stat().st_size > 0, path
        assert "function" in (outdir / "matrices" / f"{name}.m").read_text(encoding="utf-8")
        data = json.loads((outdir / "matrices" / f"{name}.json").read_text(encoding="utf-8"))
        assert data  # parses
    lever = (outdir / "matrices" / "lever.tex").read_text(encoding="utf-8")
    assert "k_{LU}" in lever or "kLU" in lever


def test_demo_writes_every_figure_and_its_data(demo):
    outdir = demo[0]
    for stem in FIGURES:
        png, svg, data = (outdir / f"{stem}{s}" for s in (".png", ".svg", ".csv"))
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", png
        text = svg.read_text(encoding="utf-8")
        assert "<svg" in text and "<dc:date>" not in text, svg  # deterministic: no date
        rows = list(csv.reader(data.open(encoding="utf-8")))
        assert len(rows) > 3 and len(rows[0]) >= 2, data


def test_demo_figure_data_columns(demo):
    outdir = demo[0]

    def header(stem):
        with (outdir / f"{stem}.csv").open(encoding="utf-8") as stream:
            return next(csv.reader(stream))

    assert {"time_s", "q2_case1_rad", "q2_case2_rad", "q2_case3_rad"} <= set(header("fig3_lever_step"))
    assert {"d1_m", "rho1_1_m", "theta_L1_rad", "Q1_steered_N", "Q1_conventional_N",
            "psi_TW2_steered_rad"} <= set(header("fig9_curving"))
    assert {"frequency_hz", "floor_front_steered_acc_m_s2", "floor_rear_conventional_acc_m_s2"} <= set(
        header("fig10_frequency_response"))
    assert {"Gamma", "Vcr_steered_kmh", "Vcr_conventional_kmh"} <= set(header("fig11_critical_speed"))


def test_summary_quotes_each_paper_value(demo):
    text = (demo[0] / "summary.md").read_text(encoding="utf-8")
    for value in ("0.04 rad", "0.06 rad", "0.0029 rad", "32 kN", "14 kN", "Γ ≈ 0.1"):
        assert value in text, value
    assert "| Quantity | Paper | This run | Difference and why |" in text
    # the corrected case 3 of Table 1 is stated
    assert "300 = 300 kN" in text
    assert "not tuned" in text


def test_summary_numbers_reproduce_the_papers_trends(demo):
    numbers = json.loads((demo[0] / "summary.json").read_text(encoding="utf-8"))
    steady = numbers["steady"]
    # lever angle: below the geometric value, as in the paper
    assert 0.02 < numbers["lever_angle_rad"] < numbers["lever_angle_geometric_rad"]
    # steering brings the wheelsets near the radial position; conventional stays far below it
    ideal = numbers["steering_angle_ideal_rad"]
    assert abs(steady["psi_TW1_steered"]) > 0.8 * ideal
    assert abs(steady["psi_TW1_conventional"]) < 0.5 * ideal
    assert abs(steady["psi_TW2_steered"]) < abs(steady["psi_TW1_steered"])
    # Q1 falls with steering and Q2 rises
    assert steady["Q1_steered"] < steady["Q1_conventional"]
    assert steady["Q2_steered"] > steady["Q2_conventional"]
    # V_cr - Gamma shapes of Fig. 11
    shape = numbers["critical_speed_shape"]
    assert shape["conventional_monotonic"]
    assert 0.06 <= shape["steered_max_gamma"] <= 0.2
    assert shape["steered_first_kmh"] < 0.5 * shape["steered_max_kmh"]


def test_summary_rows_state_measured_values(demo):
    text = (demo[0] / "summary.md").read_text(encoding="utf-8")
    rows = [line for line in text.splitlines() if line.startswith("| ") and not line.startswith("| Quantity")]
    assert len(rows) >= 7
    for row in rows:
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", row)[1:-1]]
        assert len(cells) == 4, row
        assert re.search(r"\d", cells[2]), row  # a measured number
        assert len(cells[3]) > 40, row  # a sentence on the difference
