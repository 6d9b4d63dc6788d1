"""The library guide (issue 35): ``examples/library-guide.ipynb`` answers a researcher's
question end to end — the primary and secondary yaw stiffnesses of the Manchester car
against its linear critical speed and its curving in R 600 and R 400 m — and runs in a
real kernel (nbclient); its exact sensitivity agrees with a central difference of the
exact crossing to the printed digits."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_the_library_guide_runs_and_answers_its_question():
    import nbformat
    from nbclient import NotebookClient

    notebook = nbformat.read(ROOT / "examples" / "library-guide.ipynb", as_version=4)
    NotebookClient(notebook, timeout=600, kernel_name="python3",
                   resources={"metadata": {"path": str(ROOT / "examples")}}).execute()
    outputs = [output for cell in notebook.cells if cell.cell_type == "code" for output in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    html = "".join(o.get("data", {}).get("text/html", "") for o in outputs)
    assert "critical speed [km/h]" in html and "aoa1 R400 [mrad]" in html and "Y/Q max R600" in html
    assert any("image/png" in o.get("data", {}) for o in outputs)
    text = "".join(o.get("text", "") for o in outputs)
    exact, difference = (float(x) for x in re.search(r"exact (\S+), central difference (\S+) ", text).groups())
    assert exact == pytest.approx(difference, rel=1e-5)  # printed to 7 digits: achieved equal
