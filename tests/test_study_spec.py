"""The study file (express.analysis.study.spec): the issue's file as written, and
malformed files refused with file:line, exit status 2 and nothing written."""

from __future__ import annotations

import math
import re
import shutil
from pathlib import Path

import pytest

from express.analysis.study.sampling import grid_points, saltelli_points, sample_points
from express.analysis.study.spec import parse_study, read_study
from express.base.diagnostics import ModelError
from express.cli import main

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "forced-steering.toml"

#: The study file of issue 13, verbatim.
ISSUE_STUDY = """\
[study]
model = "examples/forced-steering.toml"   # relative to the study file
kind = "grid"                             # grid | lhs | sobol | optimise | sobol-indices
outputs = ["critical_speed"]
[study.parameters]
Gamma = { values = [0.05, 0.1, 0.2] }
kx1 = { from = "1 MN/m", to = "4 MN/m", count = 2 }
[study.set]                               # fixed overrides for every point
cyaw = "200 kN*s/m"
"""

PROBLEM = re.compile(r"^error: (?P<file>[^:]+):(?P<line>\d+): (?P<item>[^:]+): (?P<message>.+)$")


@pytest.fixture()
def home(tmp_path: Path) -> Path:
    """A folder with the study's model where the issue's file expects it."""
    (tmp_path / "examples").mkdir()
    shutil.copy(MODEL, tmp_path / "examples" / "forced-steering.toml")
    return tmp_path


def test_issue_study_file_as_written(home: Path) -> None:
    path = home / "study.toml"
    path.write_text(ISSUE_STUDY)
    spec = read_study(path)
    assert spec.kind == "grid" and spec.outputs == ("critical_speed",)
    assert spec.model == home / "examples" / "forced-steering.toml"
    assert [(r.name, r.values) for r in spec.parameters] == [("Gamma", (0.05, 0.1, 0.2)), ("kx1", (1e6, 4e6))]
    assert spec.fixed == {"cyaw": pytest.approx(2e5, rel=1e-12)}
    points = grid_points(spec.parameters)
    assert points.tolist() == [[0.05, 1e6], [0.05, 4e6], [0.1, 1e6], [0.1, 4e6], [0.2, 1e6], [0.2, 4e6]]
    assert spec.text == ISSUE_STUDY


#: (what, replaced text, replacement, line of the problem, words of the message)
MALFORMED = [
    ("unknown parameter", "kx1 = {", "kx9 = {", 7, ["kx9", "no such parameter", "did you mean"]),
    ("empty values", "values = [0.05, 0.1, 0.2]", "values = []", 6, ["Gamma", "empty range"]),
    ("empty count", "count = 2", "count = 0", 7, ["kx1", "empty range"]),
    ("reversed range", 'from = "1 MN/m", to = "4 MN/m"', 'from = "4 MN/m", to = "1 MN/m"', 7, ["kx1", "empty range"]),
    ("bad unit", '"4 MN/m"', '"4 MN*s/m"', 7, ["kx1", "bad unit", "stiffness"]),
    ("unknown unit", '"200 kN*s/m"', '"200 kN*s/glorp"', 9, ["cyaw", "glorp"]),
    ("unknown output", '["critical_speed"]', '["critical_sped"]', 4, ["critical_sped", "unknown output", "critical_speed"]),
    ("unknown kind", 'kind = "grid"', 'kind = "gird"', 3, ["kind", "gird"]),
    ("unknown key", 'outputs = ["critical_speed"]', 'outputs = ["critical_speed"]\nspead = 3', 5, ["spead", "unknown key"]),
]


@pytest.mark.parametrize("what, old, new, line, words", MALFORMED, ids=[m[0] for m in MALFORMED])
def test_malformed_study_refused_with_file_line(home: Path, capsys, what, old, new, line, words) -> None:
    assert old in ISSUE_STUDY
    path = home / "study.toml"
    path.write_text(ISSUE_STUDY.replace(old, new, 1))
    output = home / "out.csv"
    status = main(["study", str(path), "-o", str(output)])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2
    assert len(err) == 1, err
    match = PROBLEM.match(err[0])
    assert match is not None, err[0]
    assert match["file"] == str(path) and int(match["line"]) == line
    for word in words:
        assert word in err[0]
    assert sorted(p.name for p in home.iterdir()) == ["examples", "study.toml"]  # nothing written


def test_every_problem_at_once(home: Path, capsys) -> None:
    text = (ISSUE_STUDY.replace("kx1 = {", "kx9 = {").replace("[0.05, 0.1, 0.2]", "[]")
            .replace('"200 kN*s/m"', '"200 kg"').replace('["critical_speed"]', '["critical_sped"]'))
    path = home / "study.toml"
    path.write_text(text)
    assert main(["study", str(path), "-o", str(home / "out.parquet"), "--json"]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert captured.out == ""
    assert sorted(int(PROBLEM.match(line)["line"]) for line in lines) == [4, 6, 7, 9]
    assert not (home / "out.parquet").exists() and not (home / "out.parquet.checkpoint.jsonl").exists()


@pytest.mark.parametrize("text, words", [
    ("[study\n", ["not valid TOML"]),
    ('[other]\nx = 1\n', ["[study]"]),
    ('[study]\nmodel = "missing.toml"\n[study.parameters]\nGamma = { values = [0.1] }\n', ["no such model file"]),
    ('[study]\nmodel = "examples"\n[study.parameters]\nGamma = { values = [0.1] }\n', ["is a folder, not a model file"]),
    ('[study]\nmodel = "/dev/zero"\n[study.parameters]\nGamma = { values = [0.1] }\n', ["is not a regular file"]),
    ('[study]\nmodel = "examples/forced-steering.toml"\nkind = "lhs"\n[study.parameters]\nGamma = { from = 0.05, to = 0.2 }\n',
     ["samples"]),
    ('[study]\nmodel = "examples/forced-steering.toml"\n[study.parameters]\nGamma = { values = [0.1] }\n'
     '[study.options]\nv_max = "5 kg"\ntrack = "nowhere.toml"\n', ["v_max", "track"]),
], ids=["toml syntax", "no study table", "missing model", "a folder as the model", "a device as the model",
        "lhs without samples", "bad options"])
def test_other_mistakes(home: Path, text: str, words: list[str]) -> None:
    with pytest.raises(ModelError) as caught:
        parse_study(text, home / "s.toml")
    message = str(caught.value)
    for word in words:
        assert word in message
    assert all(p.file == str(home / "s.toml") or p.file.endswith(".toml") for p in caught.value.problems)


def test_sampled_points_are_seeded_and_inside_the_bounds(home: Path) -> None:
    text = ('[study]\nmodel = "examples/forced-steering.toml"\nkind = "lhs"\nsamples = 50\nseed = 7\n'
            '[study.parameters]\nGamma = { from = 0.05, to = 0.2 }\nkx1 = { from = "0.5 MN/m", to = "8 MN/m", scale = "log" }\n')
    spec = parse_study(text, home / "s.toml")
    first = sample_points(spec.parameters, "lhs", 50, 7)
    assert first.shape == (50, 2)
    assert (first == sample_points(spec.parameters, "lhs", 50, 7)).all()
    assert first[:, 0].min() >= 0.05 and first[:, 0].max() <= 0.2
    assert first[:, 1].min() >= 5e5 and first[:, 1].max() <= 8e6
    # a Latin hypercube has one point in each of the 50 strata of every parameter (log strata for kx1)
    assert len({int(50 * (v - 0.05) / 0.15) for v in first[:, 0]}) == 50
    assert len({int(50 * math.log(v / 5e5) / math.log(16.0)) for v in first[:, 1]}) == 50
    sobol = sample_points(spec.parameters, "sobol", 16, 7)
    assert sobol.shape == (16, 2) and (sobol == sample_points(spec.parameters, "sobol", 16, 7)).all()
    saltelli = saltelli_points(spec.parameters, 8, 7)
    assert saltelli.shape == (8 * (2 + 2), 2)
