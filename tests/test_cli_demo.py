"""``express demo`` (``express.cli.demo``): bad destinations refused before any work,
and the demo's files replaced all together or not at all (the full run is in
``test_demo.py``)."""

from __future__ import annotations

import pytest

from cli_support import EXAMPLES, assert_input_error, run
from express.cli import demo as command


def test_outdir_that_is_a_file_is_refused(capsys, tmp_path):
    plain = tmp_path / "plain"
    plain.write_text("x")
    assert_input_error(capsys, "demo", plain, mentions="not a directory")
    assert_input_error(capsys, "demo", plain / "below", mentions="plain")


def test_examples_without_the_models_are_refused(capsys, tmp_path):
    assert_input_error(capsys, "demo", tmp_path / "out", "--examples", tmp_path, mentions="--examples")
    assert not (tmp_path / "out").exists()


def _fake_demo(fail: bool):
    def run_demo(outdir, *, examples=None, log=print):
        from express.io.output import write_text

        outdir.mkdir(parents=True, exist_ok=True)
        write_text(outdir / "fig.csv", "new figure data\n")
        if fail:
            raise RuntimeError("figure 11 failed")
        write_text(outdir / "summary.md", "# new summary\n")
        return outdir / "summary.md"

    return run_demo


@pytest.mark.parametrize("fail", [False, True])
def test_demo_files_are_all_or_nothing(capsys, monkeypatch, tmp_path, fail):
    """A demo that fails half-way leaves the earlier files of the output directory as
    they were (status 70: an internal failure); one that succeeds replaces them all."""
    import express.paper.demo as library

    outdir = tmp_path / "out"
    outdir.mkdir()
    (outdir / "fig.csv").write_text("old figure data\n")
    (outdir / "summary.md").write_text("# old summary\n")
    monkeypatch.setattr(library, "run_demo", _fake_demo(fail))
    status, out, err = run(capsys, "demo", outdir, "--examples", EXAMPLES)
    if fail:
        assert status == 70 and "figure 11 failed" in err
        assert (outdir / "fig.csv").read_text() == "old figure data\n"
        assert (outdir / "summary.md").read_text() == "# old summary\n"
    else:
        assert status == 0 and "summary.md" in out
        assert (outdir / "fig.csv").read_text() == "new figure data\n"
        assert (outdir / "summary.md").read_text() == "# new summary\n"
    assert sorted(p.name for p in outdir.iterdir()) == ["fig.csv", "summary.md"]
    assert command.run.__module__ == "express.cli.demo"
