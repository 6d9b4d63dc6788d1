"""Property-based tests of the command line (issue 17): generated and mutated option
values, ``--set`` assignments and destinations must end with status 0, 1 or 2, at most
a few ``error:`` lines and no traceback, within a bounded time, and leave no partial
output.  Derandomized, so that a run is reproducible; a failure prints the argv."""

from __future__ import annotations

import contextlib
import io
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cli_support import CONVENTIONAL, LEVER
from express.cli import main

pytestmark = pytest.mark.slow

FUZZ = settings(max_examples=60, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow,
                                                                                     HealthCheck.function_scoped_fixture])
SECONDS = 60.0  # a generous bound on one command on a busy 2-core machine

UNITS = ["", "km/h", "m/s", "mm", "m", "Hz", "s", "ms", "kg", "t", "N", "kN/m", "rad", "deg", "1/s", "km^400",
         "furlong", "blorb", "%", "m/s^2", "N*s/m", "h", "min"]
NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.integers(min_value=-10**30, max_value=10**30),
    st.sampled_from([0, -0.0, 1e-300, 1e300, 1e-14, 3.6, 120, 540, 1000, 1000.0001, 0.005, 1e-5, 0.1]),
)
GARBAGE = st.text(alphabet=st.characters(blacklist_categories=("Cs",)), max_size=30)


@st.composite
def quantity_text(draw):
    """A number with a unit, written in the ways people write them, or garbage."""
    if draw(st.integers(0, 9)) == 0:
        return draw(GARBAGE)
    number = draw(NUMBERS)
    unit = draw(st.sampled_from(UNITS))
    space = draw(st.sampled_from(["", " ", "  "]))
    return f"{number!r}{space}{unit}".strip() if unit else repr(number)


def run_quietly(argv: list[str]) -> tuple[int, str, str, float]:
    out, err = io.StringIO(), io.StringIO()
    start = time.perf_counter()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(argv)
    return status, out.getvalue(), err.getvalue(), time.perf_counter() - start


def check(argv: list[str]) -> int:
    status, out, err, elapsed = run_quietly(argv)
    assert status in (0, 1, 2), (argv, status, err)
    assert "Traceback" not in out + err, (argv, err)
    assert elapsed < SECONDS, (argv, elapsed)
    if status != 0:
        lines = [line for line in err.splitlines() if not line.startswith("warning: ")]  # a negative stiffness warns
        assert lines and all(line.startswith("error: ") for line in lines), (argv, err)
        assert len(lines) <= 20, (argv, err)
    return status


OPTIONS = [
    (["eigen", CONVENTIONAL], "--speed"),
    (["frf", CONVENTIONAL, "--points", "4"], "--fmin"),
    (["frf", CONVENTIONAL, "--points", "4"], "--fmax"),
    (["frf", CONVENTIONAL, "--points", "4"], "--amplitude"),
    (["frf", CONVENTIONAL, "--points", "4"], "--speed"),
    (["critical-speed", CONVENTIONAL, "--vmax", "200"], "--tolerance"),
    (["critical-speed", CONVENTIONAL], "--vmin"),
    (["critical-speed", CONVENTIONAL, "--vmin", "200"], "--vmax"),
    (["simulate", CONVENTIONAL, "--track", str(Path(CONVENTIONAL).parent / "tracks" / "straight_sinusoid.toml")],
     "--dt"),
]


@FUZZ
@given(case=st.sampled_from(OPTIONS), text=quantity_text())
def test_fuzzed_quantities_end_cleanly(case, text):
    """Any value of a quantity option: accepted and run, or refused with one line."""
    prefix, option = case
    argv = [*prefix, f"{option}={text}"]
    if option == "--dt":  # keep accepted runs short: 500 m at a fast speed
        argv += ["--speed", "300"]
    status = check(argv)
    if status == 2:
        _, _, err, _ = run_quietly(argv)
        assert len(err.splitlines()) == 1


NAMES = ["Gamma", "mc", "mt", "mw", "ky1", "ky2", "cy2", "kx1", "v", "mu", "G", "delta", "r0", "a", "b", "gamma",
         "P0", "nope", "Gamma2"]


@FUZZ
@given(assignments=st.lists(st.tuples(st.sampled_from(NAMES), quantity_text()), min_size=1, max_size=3))
def test_fuzzed_set_values_end_cleanly(assignments):
    """``--set`` with any names and values on the eigen analysis: a result, no valid
    result (1) or bad input (2), never an internal error."""
    argv = ["eigen", CONVENTIONAL, "--json"]
    for name, text in assignments:
        argv += ["--set", f"{name}={text}"]
    check(argv)


@FUZZ
@given(item=GARBAGE)
def test_fuzzed_set_syntax_ends_cleanly(item):
    check(["generate", LEVER, "--set", item])


SINUSOID = str(Path(CONVENTIONAL).parent / "tracks" / "straight_sinusoid.toml")
DESTINATIONS = st.sampled_from(["ok.csv", "sub/deeper/ok.npz", "ok.mat", "dir", "dir/", "file/below.csv", "file",
                                "-", "/dev/null", "", "car.csv", "link-to-car.csv", "ok.txt"])


@settings(max_examples=30, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(destinations=st.lists(DESTINATIONS, min_size=1, max_size=3), fail=st.booleans())
def test_fuzzed_destinations_are_all_or_nothing(tmp_path_factory, destinations, fail):
    """``simulate -o A -o B ...`` to a mix of good and bad destinations (directories,
    paths below a file, the input itself, devices, standard output): status 0 and
    every file written, or status 2 and nothing changed."""
    folder = tmp_path_factory.mktemp("out")
    (folder / "dir").mkdir()
    (folder / "file").write_text("keep me")
    model = folder / "car.csv"  # the model itself, under a name that looks like an output
    model.write_text(Path(CONVENTIONAL).read_text(encoding="utf-8"))
    (folder / "link-to-car.csv").symlink_to(model)
    (folder / "ok.csv").write_text("an earlier result")
    before = {p: p.read_bytes() for p in folder.rglob("*") if p.is_file()}
    names = sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))
    argv = ["simulate", str(model), "--track", SINUSOID, "--speed", "300", "--dt", "0.02"]
    for target in destinations:
        argv += ["-o", target if target in ("-", "/dev/null", "") else str(folder / target)]
    if fail:
        argv += ["--set", "Gammma=0.1"]
    status = check(argv)
    after = {p: p.read_bytes() for p in folder.rglob("*") if p.is_file()}
    if status != 0:
        assert after == before
        assert sorted(str(p.relative_to(folder)) for p in folder.rglob("*")) == names
    else:
        assert not fail
        assert after[model] == before[model]
        for target in destinations:
            if target not in ("-", "/dev/null"):
                assert (folder / target).stat().st_size > 100


@FUZZ
@given(hertz=st.floats(1e-3, 999.0), unit=st.sampled_from(["rad/s", "rpm", "deg/s", "Hz", "1/min", "krad/s"]))
def test_angular_frequencies_convert_with_their_two_pi(hertz, unit):
    """Angles are a dimension (issue 26): a frequency option given in any of these units
    is the same number of hertz."""
    import math

    from express.cli.common import FMAX

    per_hertz = {"rad/s": 2 * math.pi, "rpm": 60.0, "deg/s": 360.0, "Hz": 1.0, "1/min": 60.0, "krad/s": 2e-3 * math.pi}
    assert FMAX(f"{hertz * per_hertz[unit]!r} {unit}") == pytest.approx(hertz, rel=1e-12)
