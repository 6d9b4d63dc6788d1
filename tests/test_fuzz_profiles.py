"""Fuzzing of profile files (issue 17): rolling-radius-difference (Δr) CSV files
generated with extreme and broken rows through ``express conicity --delta-r``, and the
shipped S1002 wheel and 60E1 rail profiles mutated line by line through ``express
conicity`` and ``express contact-geometry``.  Every run ends with status 0, 1 or 2, no
traceback, within a time bound, an error quoting at most a short excerpt of the file,
and the earlier output intact when refused.  Derandomized (``tests/fuzz_support.py``).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from express.rail import profiles
from fuzz_support import assert_untouched, check, fuzz, mutated, snapshot

pytestmark = pytest.mark.slow

DATA = Path(profiles.__file__).resolve().parents[1] / "data" / "profiles"
WHEEL = (DATA / "S1002.csv").read_text(encoding="utf-8")
RAIL = (DATA / "60E1.csv").read_text(encoding="utf-8")
EARLIER = "an earlier result\n"

CELLS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=64).map(repr),
    st.sampled_from(["", "x", "1e999", "-0", "0x10", "1_000", "1,5", "nan", "٣", "１"]),
)


SEPARATORS = [",", ";", " ", "\t", ",,"]


@st.composite
def delta_r_files(draw) -> str:
    """A Δr table: a header (right or wrong), then rows of ``y, delta_r`` — mostly a
    smooth, odd function such as a real one, with a few rows drawn from anything."""
    header = draw(st.sampled_from(["y_m,delta_r_m", "y_mm,delta_r_mm", "y_m,delta_r_m", "y,dr", "", "y_m;delta_r_m"]))
    scale = 1e3 if "mm" in header else 1.0
    count = 40 - draw(st.integers(0, 40))  # Hypothesis favours small integers: mostly full tables
    slope = draw(st.sampled_from([0.1, 0.3, 0.0, -0.2, 1e-12, 10.0]))
    curve = draw(st.sampled_from([0.0, 50.0, -30.0, 1e6]))
    rows = []
    for i in range(count):
        y = -0.01 + 0.02 * i / max(count - 1, 1)
        rows.append(f"{y * scale!r},{(slope * y + curve * y**3) * scale!r}")
    for _ in range(draw(st.integers(0, 3))):
        where = draw(st.integers(0, len(rows)))
        rows.insert(where, draw(CELLS) + draw(st.sampled_from(SEPARATORS)) + draw(CELLS))
    return "\n".join([header, *rows]) + "\n"


def _output_ok(target: Path) -> None:
    with target.open(newline="") as file:
        rows = list(csv.reader(file))
    assert len(rows) >= 2 and all(len(row) == len(rows[0]) for row in rows)
    for row in rows[1:]:
        for name, cell in zip(rows[0], row, strict=True):
            if cell == "" and name.startswith("secondary_gap"):
                continue  # the documented empty cell: no second contact
            assert math.isfinite(float(cell)), (name, row)


def _run(folder: Path, argv: list, target: Path) -> int:
    target.write_text(EARLIER)
    before = snapshot(folder)
    status, _, err = check([*argv, "-o", target])
    if status != 0:
        assert_untouched(before, folder, argv)
        assert err.count("'") <= 8  # one short excerpt of the file, at most (a header and a row)
    else:
        _output_ok(target)
    return status


@fuzz(80)
@given(text=delta_r_files())
def test_generated_delta_r_files_end_cleanly(tmp_path_factory, text):
    folder = tmp_path_factory.mktemp("dr")
    path = folder / "dr.csv"
    path.write_text(text, encoding="utf-8")
    _run(folder, ["conicity", "--delta-r", path], folder / "out.csv")


@fuzz(25)
@given(data=st.data())
def test_mutated_wheel_profiles_end_cleanly(tmp_path_factory, data):
    text = data.draw(mutated(WHEEL), label="wheel")
    folder = tmp_path_factory.mktemp("wheel")
    path = folder / "wheel.csv"
    path.write_text(text, encoding="utf-8")
    _run(folder, ["conicity", path, "60E1"], folder / "out.csv")


@fuzz(15)
@given(data=st.data())
def test_mutated_rail_profiles_end_cleanly(tmp_path_factory, data):
    text = data.draw(mutated(RAIL), label="rail")
    folder = tmp_path_factory.mktemp("rail")
    path = folder / "rail.csv"
    path.write_text(text, encoding="utf-8")
    _run(folder, ["contact-geometry", "S1002", path, "--y-range=-8:8:0.5"], folder / "out.csv")


@fuzz(12)
@given(data=st.data())
def test_profiles_in_a_wrong_role_are_refused_and_never_give_nan(tmp_path_factory, data):
    """Wrong roles (issue 26): a wheel and a rail, possibly mirrored, given in any order
    and either role: unless they are the wheel and the rail as they are, status 2 naming
    the role, nothing written, no nan."""
    folder = tmp_path_factory.mktemp("roles")
    files = {}
    for name, text in (("wheel", WHEEL), ("rail", RAIL)):
        rows = [line.split(",") for line in text.splitlines() if line[:1] in "-0123456789"]
        mirrored = data.draw(st.booleans(), label=f"{name} mirrored")
        if mirrored:
            rows = [[f"{-float(y):.6f}", z] for y, z in reversed(rows)]
        path = folder / f"{name}{'-mirrored' if mirrored else ''}.csv"
        path.write_text("y_mm,z_mm\n" + "".join(f"{y},{z}\n" for y, z in rows), encoding="utf-8")
        files[name] = (path, mirrored)
    order = data.draw(st.sampled_from([("wheel", "rail"), ("rail", "wheel"), ("wheel", "wheel"), ("rail", "rail")]))
    command = data.draw(st.sampled_from(["conicity", "contact-geometry"]))
    (first, first_mirrored), (second, second_mirrored) = files[order[0]], files[order[1]]
    target = folder / "out.csv"
    status = _run(folder, [command, first, second], target)
    proper = order == ("wheel", "rail") and not first_mirrored
    assert (status == 0) == proper, (order, first_mirrored, second_mirrored, status)
