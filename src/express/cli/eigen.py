"""``express eigen``: eigenvalues and modes at one speed
(:func:`express.analysis.stability.eigen_analysis`)."""

from __future__ import annotations

from pathlib import Path

from ..diagnostics import AnalysisError
from . import common

__all__ = ["add_parser", "run"]


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "eigen", help="eigenvalues and modes at one speed",
        description="Eigenvalues of A(v) of the linear vehicle on straight track: frequency, damping "
        "ratio, dominant DOFs and a label for every mode, least stable first.",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--speed", type=common.SPEED, metavar="SPEED", help=common.SPEED.help("running speed", "the model's speed"))
    common.add_json_option(parser)
    parser.set_defaults(handler=run, numeric=True)


def run(model: Path, overrides: dict[str, str], *, speed: float | None = None, as_json: bool = False) -> int:
    """Print the modes; returns the exit status."""
    import numpy as np

    from ..analysis.stability import eigen_analysis

    vehicle = common.load_rail_vehicle(model, overrides, "eigen")
    v = common.running_speed(vehicle, speed)
    state_matrix = vehicle.state_matrix(v)
    if not np.all(np.isfinite(state_matrix)):
        raise AnalysisError(f"eigen: the state matrix A(v) at {v / common.KMH:g} km/h has non-finite entries")
    result = eigen_analysis(vehicle, v)
    eigenvalues = np.linalg.eigvals(state_matrix)
    eigenvalues = eigenvalues[np.lexsort((-eigenvalues.imag, -eigenvalues.real))]
    name = vehicle.equations.name
    if as_json:
        common.print_json({
            "model": str(model), "speed": v, "speed_kmh": v / common.KMH, "stable": bool(result.stable),
            "eigenvalues": [[float(z.real), float(z.imag)] for z in eigenvalues],
            "modes": [
                {"eigenvalue": [mode.real, mode.imag], "frequency_hz": mode.frequency_hz,
                 "damping_ratio": mode.damping_ratio, "dominant": [[dof, share] for dof, share in mode.dominant],
                 "label": mode.kind, "description": mode.describe()}
                for mode in result.modes
            ],
        })
        return 0
    print(f"{name}: {len(result.modes)} modes at {v / common.KMH:.1f} km/h ({v:.3f} m/s), least stable first; "
          f"{'stable' if result.stable else 'UNSTABLE'}")
    header = f"{'Re [1/s]':>11} {'Im [rad/s]':>11} {'f [Hz]':>8} {'zeta':>8}  {'dominant DOFs (share)':<40} mode"
    print(header)
    print("-" * len(header))
    for mode in result.modes:
        dominant = ", ".join(f"{dof} {share:.0%}" for dof, share in mode.dominant[:3])
        print(f"{mode.real:11.4f} {mode.imag:11.4f} {mode.frequency_hz:8.3f} {mode.damping_ratio:8.4f}  "
              f"{dominant:<40} {mode.kind}")
    return 0
