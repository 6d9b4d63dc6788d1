"""Every figure function takes ``ax=`` (issue 35, item 2): given an Axes (or, for a figure of
several panels, a sequence of them) it draws into it and returns it, leaving the caller's
figure alone otherwise; without it, it returns a new Figure as before.  Drawn with the Agg
canvas (no pyplot)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from express.analysis import plots
from express.analysis.plots.bifurcation import figure_bifurcation
from express.analysis.plots.curving import figure_steady_curving
from express.analysis.ride.figures import figure_ride_spectra
from express.analysis.study.figures import figure_study_map, figure_tornado
from express.base.diagnostics import ArgumentError
from express.report.figures import figure_assessment

SPEEDS = np.linspace(10.0, 100.0, 12)
F = np.linspace(0.5, 10.0, 20)


def _locus(v):
    hunting = (-0.5 + 0.01 * v) + 2j * np.pi * 1.0
    values = np.stack([hunting, hunting.conj(), -5.0 + 0 * v], axis=1)
    order = np.lexsort((-values.imag, -values.real), axis=-1)
    return np.take_along_axis(values, order, axis=-1)


def _curving_run():
    d = np.linspace(0.0, 100.0, 30)
    return {"d1": d, "rho1": d / 4e4, "theta_L1": d * 1e-5, "psi_TW1": d * 1e-5, "psi_TW2": -d * 1e-5,
            "Q1": 1e3 * d, "Q2": 5e2 * d}


def _steady(radius):
    wheel_rail = SimpleNamespace(angle_of_attack=np.full((1, 2), 1e-3), y_over_q=np.full((1, 2, 2), 0.2),
                                 track_shift_force=np.full((1, 2), 5e3), vehicle_unloading=np.array([0.1]),
                                 wheelsets=2)
    return SimpleNamespace(curve=SimpleNamespace(radius=radius), speed=30.0, unbalanced_acceleration=0.5,
                           wheel_rail=wheel_rail)


def _sensitivity():
    rows = tuple(SimpleNamespace(name=n, value=v, derivative=d, elasticity=e)
                 for n, v, d, e in (("kx1", 1e6, 1e-5, 0.2), ("Gamma", 0.1, -100.0, -0.1)))
    return SimpleNamespace(critical_speed=100.0, ranked=lambda: list(rows))


#: name -> (panels, draw(ax)): each figure function called with its smallest inputs.
FIGURES = {
    "bifurcation": (1, lambda ax: figure_bifurcation([200, 190], [3.0, 2.0], [True, False], title="t",
                                                     linear_kmh=195.0, ax=ax)),
    "steady curving": (4, lambda ax: figure_steady_curving([_steady(400.0), _steady(600.0)], ax=ax)),
    "lever step": (1, lambda ax: plots.figure_lever_step(
        np.linspace(0, 0.1, 10), [{"label": "a", "q2": np.linspace(0, 1e-3, 10), "steady": 1e-3}], step=1e-3, ax=ax)),
    "curving": (3, lambda ax: plots.figure_curving(_curving_run(), _curving_run(), ideal_yaw=1e-3, ax=ax)),
    "frequency response": (1, lambda ax: plots.figure_frequency_response(F, [{"label": "a", "values": F}], ax=ax)),
    "frequency responses": (2, lambda ax: plots.figure_frequency_responses(
        F, {"m/s^2": [{"label": "a", "values": F}], "m": [{"label": "b", "values": F}]}, ax=ax)),
    "critical speed": (1, lambda ax: plots.figure_critical_speed(
        [{"label": "a", "conicity": np.array([0.1, 0.2]), "speed_kmh": np.array([300.0, 250.0])}], ax=ax)),
    "simulation": (3, lambda ax: plots.figure_simulation(
        np.linspace(0, 10, 5), {"rho1": np.zeros(5), "psi_TW1": np.zeros(5), "Y1": np.ones(5)}, title="t", ax=ax)),
    "eigen locus": (1, lambda ax: plots.figure_eigen_locus(SPEEDS, _locus(SPEEDS), title="t", ax=ax)),
    "root locus": (1, lambda ax: plots.figure_root_locus_complex(SPEEDS, _locus(SPEEDS), ax=ax)),
    "damping": (1, lambda ax: plots.figure_damping_vs_speed(SPEEDS, plots.mode_branches(_locus(SPEEDS)), ax=ax)),
    "ride spectra": (2, lambda ax: figure_ride_spectra(F, {"floor": {"y": F ** -2, "z": F ** -2}}, ax=ax)),
    "study map": (1, lambda ax: figure_study_map([("kx1", [1.0, 2.0, 3.0], 1.0, "")], np.array([1.0, 2.0, 1.5]),
                                                 label="V", title="t", ax=ax)),
    "tornado": (1, lambda ax: figure_tornado(_sensitivity(), ax=ax)),
    "assessment": (1, lambda ax: figure_assessment(
        [SimpleNamespace(name="YQ1L", value=0.4, limit=0.8, passed=True)], ax=ax)),
}


@pytest.mark.parametrize("name", list(FIGURES))
def test_a_figure_draws_into_the_axes_given(name):
    panels, draw = FIGURES[name]
    figure = Figure(figsize=(6, 4))
    FigureCanvasAgg(figure)
    axes = figure.subplots(panels, 1, squeeze=False)[:, 0]
    given = axes[0] if panels == 1 else list(axes)
    returned = draw(given)
    assert returned is given
    assert all(axis.has_data() for axis in axes), name  # something drawn in every panel
    assert figure.get_suptitle() == ""  # the caller's figure keeps its title
    figure.canvas.draw()  # renders with Agg
    alone = draw(None)
    assert isinstance(alone, Figure) and alone is not figure


def test_a_wrong_number_of_axes_is_refused():
    figure = Figure()
    with pytest.raises(ArgumentError, match="3 panel"):
        plots.figure_simulation(np.linspace(0, 1, 3), {"rho1": np.zeros(3)}, title="t", ax=figure.subplots())
