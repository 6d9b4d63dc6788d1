"""EXPRESS in a notebook (issue 25 item 7): objects display themselves, and the shipped
example notebook runs from a model file to a critical-speed map (nbclient, a real kernel)."""

from __future__ import annotations

from pathlib import Path

import pytest

from express.analysis.stability.stability import eigen_analysis
from express.assembly.generator import generate
from express.io import read_classic
from express.numeric.statespace import load_vehicle

ROOT = Path(__file__).resolve().parents[1]


def test_equations_display_as_latex():
    latex = generate(read_classic(ROOT / "examples" / "lever.exp")).equations._repr_latex_()
    assert latex.startswith("$$") and latex.endswith("$$")
    assert r"M = \left[\begin{matrix}J_{1} + b^{2} m & 0\\0 & J_{2}\end{matrix}\right]" in latex


def test_modes_display_as_a_table_with_units():
    modes = eigen_analysis(load_vehicle(ROOT / "examples" / "conventional.toml"))
    frame = modes.to_pandas()
    assert list(frame.columns[:4]) == ["Re [1/s]", "Im [rad/s]", "f [Hz]", "damping ratio [-]"]
    assert frame.index[0] == 1 and len(frame) == len(modes.modes)
    assert "<table" in modes._repr_html_() and "km/h" in modes._repr_html_()


def test_a_vehicle_draws_itself_as_svg_through_the_extension():
    from express.notebook import load_ipython_extension, vehicle_svg
    from express.numeric.statespace import VehicleModel

    registered = {}

    class Formatter:
        def for_type(self, kind, function):
            registered[kind] = function

    class Shell:
        display_formatter = type("F", (), {"formatters": {"image/svg+xml": Formatter()}})()

    load_ipython_extension(Shell())
    car = load_vehicle(ROOT / "examples" / "conventional.toml")
    svg = registered[VehicleModel](car)
    assert svg.startswith("<svg") and "<title>CB: car body" in svg and svg == vehicle_svg(car)


@pytest.mark.slow
def test_the_example_notebook_runs(tmp_path):
    import nbformat
    from nbclient import NotebookClient

    notebook = nbformat.read(ROOT / "examples" / "notebook.ipynb", as_version=4)
    NotebookClient(notebook, timeout=600, kernel_name="python3",
                   resources={"metadata": {"path": str(ROOT / "examples")}}).execute()
    outputs = [output for cell in notebook.cells if cell.cell_type == "code" for output in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    kinds = {mime for o in outputs for mime in o.get("data", {})}
    assert {"image/svg+xml", "text/latex", "text/html", "image/png"} <= kinds
    text = "".join(o.get("data", {}).get("text/html", "") for o in outputs)
    assert "critical speed [km/h]" in text and "hunting" in text
