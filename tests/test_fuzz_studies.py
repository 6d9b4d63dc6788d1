"""Fuzzing of study files (issue 17): the bundled study mutated line by line through the
reader, and small generated studies (extreme ranges, counts, options and outputs) run by
``express study`` in this process: status 0, 1 or 2, no traceback, within a time bound,
the earlier results intact when refused; a study that runs writes one complete table
(points outside a parameter's valid range are recorded as points without a value, not
as a failure of the study).  Derandomized (``tests/fuzz_support.py``).
"""

from __future__ import annotations

import csv
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cli_support import CONVENTIONAL
from express.analysis.study.spec import parse_study
from express.base.diagnostics import InputError
from fuzz_support import NASTY_NUMBERS, assert_untouched, check, fuzz, mutated, snapshot, time_limit

pytestmark = pytest.mark.slow

EXAMPLES = Path(CONVENTIONAL).parent
STUDY = (EXAMPLES / "studies" / "critical_speed_map.toml").read_text(encoding="utf-8").replace(
    '"../forced-steering.toml"', f'"{(EXAMPLES / "forced-steering.toml").as_posix()}"')


@fuzz(60)
@given(data=st.data())
def test_mutated_study_files_are_read_or_refused(tmp_path_factory, data):
    text = data.draw(mutated(STUDY), label="study")
    path = tmp_path_factory.mktemp("study") / "study.toml"
    path.write_text(text, encoding="utf-8")
    try:
        with time_limit(30):
            spec = parse_study(text, path)
    except InputError as error:
        assert all(line and len(line) < 800 for line in str(error).splitlines())
        return
    assert spec.parameters or spec.kind != "grid"


AMOUNT = st.one_of(st.sampled_from(NASTY_NUMBERS), st.sampled_from(['"0.5 MN/m"', '"3 kg"', "1", "2"]))
OUTPUT_NAMES = ["least_damping_ratio", "least_damping_frequency", "frf_peak_acceleration", "frf_peak_frequency",
                "critical_speed", "max_Y", "nope"]
#: Ranges that make sense (some points of mu, ky2 and cy2 outside the valid range or
#: unstable: the study records them as points without a value).
GOOD_RANGES = {
    "Gamma": "{ from = 0.05, to = 0.2, count = 2 }",
    "kx1": '{ from = "0.5 MN/m", to = "4 MN/m", count = 2, scale = "log" }',
    "mu": "{ values = [0, 0.3] }",
    "ky2": "{ values = [-150000, 150000] }",
    "cy2": '{ values = ["-300 kN*s/m", "30 kN*s/m"] }',
    "gamma": "{ values = [0.1] }",
}


@st.composite
def small_studies(draw) -> str:
    """A grid of at most four points on the conventional car, with drawn ranges,
    outputs and options: each part sensible most of the time, extreme otherwise (the
    outputs are kept to the quick ones most of the time)."""
    outputs = draw(st.lists(st.sampled_from(OUTPUT_NAMES[:4]), min_size=1, max_size=2, unique=True))
    if draw(st.integers(0, 4)) == 4:
        outputs.append(draw(st.sampled_from(OUTPUT_NAMES[4:])))
    lines = ["[study]", f'model = "{Path(CONVENTIONAL).as_posix()}"', 'kind = "grid"',
             "outputs = [" + ", ".join(f'"{name}"' for name in outputs) + "]", "", "[study.parameters]"]
    for name in draw(st.lists(st.sampled_from(list(GOOD_RANGES)), min_size=1, max_size=2, unique=True)):
        if draw(st.integers(0, 3)) < 3:  # Hypothesis favours small integers: mostly sensible
            lines.append(f"{name} = {GOOD_RANGES[name]}")
        elif draw(st.booleans()):
            lines.append(f"{name} = {{ from = {draw(AMOUNT)}, to = {draw(AMOUNT)}, "
                         f"count = {draw(st.sampled_from(['1', '2', '0', '-1', '2.5', '1e9']))} }}")
        else:
            values = draw(st.lists(AMOUNT, min_size=0, max_size=2))
            lines.append(f"{name} = {{ values = [{', '.join(values)}] }}")
    lines += ["", "[study.options]", "frf_points = 8"]
    for key, choices in (("speed", ['"120 km/h"', '"0 km/h"', '"1e6 km/h"', "1e-300"]),
                         ("frf_fmax", ['"5 Hz"', "0", "1e9", '"x"']), ("v_max", ['"200 km/h"', "-1", '"3 kg"'])):
        if draw(st.integers(0, 3)) == 3:
            lines.append(f"{key} = {draw(st.sampled_from(choices))}")
    return "\n".join(lines) + "\n"


@fuzz(12)
@given(text=small_studies())
def test_small_generated_studies_end_cleanly(tmp_path_factory, text):
    folder = tmp_path_factory.mktemp("run")
    study = folder / "study.toml"
    study.write_text(text, encoding="utf-8")
    target = folder / "results.csv"
    target.write_text("an earlier result\n")
    before = snapshot(folder)
    argv = ["study", study, "-o", target, "--workers", "1"]
    status, _, _ = check(argv, seconds=120)
    if status != 0:
        assert_untouched(before, folder, argv)
        return
    with target.open(newline="") as file:
        rows = list(csv.reader(file))
    assert rows and rows[0][-1] == "error" and all(len(row) == len(rows[0]) for row in rows)
