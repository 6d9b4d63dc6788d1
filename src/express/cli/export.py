"""``express export``: the numerical linear model at one speed as data
(:mod:`express.export.linear_system`): ``.mat``, ``.npz`` or an FMI 2 FMU."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

from express.base.diagnostics import UsageError
from express.cli import common
from express.cli.runner import run_command

__all__ = ["add_parser", "main", "run"]

FORMATS = {"mat": ".mat", "npz": ".npz", "fmu": ".fmu"}


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "export", help="numeric M, C, K, P, A, B at one speed (.mat, .npz) or an FMU",
        description="The numerical matrices at the model's parameters and one speed: M, C, K, P, Pd, "
        "A, B, Bd with the DOF and input names (.mat for MATLAB/Octave/scipy.io.loadmat, .npz for "
        "NumPy), or an FMI 2 co-simulation FMU of the linear model (needs pythonfmu).",
    )
    common.add_model_arguments(parser)
    parser.add_argument("--format", dest="fmt", choices=tuple(FORMATS), help="default: from the suffix of -o")
    parser.add_argument("--speed", type=common.SPEED, metavar="SPEED", help=common.SPEED.help("speed", "the model's speed"))
    parser.add_argument("-o", "--output", required=True, metavar="FILE", help="output file")
    parser.set_defaults(handler=run, numeric=True)


def run(model: Path, overrides: dict[str, str], *, output: str, fmt: str | None = None,
        speed: float | None = None) -> int:
    """Write the numerical model; returns the exit status."""
    from express.export.linear_system import linear_system, numeric_matrices
    from express.io.output import mat_bytes, npz_bytes, output_transaction, write_bytes

    suffix = Path(output).suffix.lower()
    fmt = fmt or next((name for name, s in FORMATS.items() if s == suffix), None)
    if fmt is None:
        raise UsageError(f"-o {output}: unknown format; give --format {'|'.join(FORMATS)} or a suffix .mat, .npz, .fmu")
    if fmt == "fmu":
        common.require_package("pythonfmu", "interop", "--format fmu")
    with output_transaction(inputs=[model]) as outputs:
        outputs.declare(output, binary=True)
        vehicle = common.load_rail_vehicle(model, overrides, "export")
        v = common.running_speed(vehicle, speed)
        if fmt == "fmu":
            from express.export.fmu import to_fmu_bytes

            data = to_fmu_bytes(linear_system(vehicle, v), vehicle.equations.name,
                                f"{vehicle.equations.name} at {v / common.KMH:g} km/h (EXPRESS)")
        else:
            data = (mat_bytes if fmt == "mat" else npz_bytes)(numeric_matrices(vehicle, v))
        write_bytes(output, data)
    common.note(f"wrote {output} ({vehicle.n} DOFs, {len(vehicle.inputs)} inputs, {v / common.KMH:g} km/h)")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """``express export`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
