"""Writing outputs whole, and reading ``--set NAME=VALUE`` overrides.

Shared by the command line and the analyses' commands: an output file is written to a
temporary file beside it and renamed into place, so it is complete or absent; an input
file is never overwritten.
"""

from __future__ import annotations

import math
import os
import tempfile
from collections.abc import Sequence
from pathlib import Path

from ..diagnostics import UsageError
from ..expressions import ExpressionError, is_valid_name, parse_expression
from ..units import UnitError, parse_quantity

__all__ = ["json_safe", "parse_assignments", "write_output"]


def parse_assignments(items: Sequence[str]) -> dict[str, float]:
    """``["v=100 km/h", "Gamma=0.05"]`` -> ``{"v": 27.77..., "Gamma": 0.05}`` (SI)."""
    values: dict[str, float] = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not is_valid_name(name):
            raise UsageError(f'--set "{item}": expected NAME=VALUE, e.g. --set Gamma=0.05')
        try:
            value, _ = parse_quantity(text)
        except UnitError:
            try:
                expression = parse_expression(text)
            except ExpressionError as error:
                raise UsageError(f'--set "{item}": "{text}" is not a number ({error})') from None
            if expression.free_symbols or not expression.is_number:
                raise UsageError(f'--set "{item}": "{text}" is not a number')
            value = float(expression)
        if not math.isfinite(value):
            raise UsageError(f'--set "{item}": "{text}" is not a finite number')
        values[name] = value
    return values


def write_output(path: Path, text: str, inputs: Sequence[Path] = ()) -> None:
    """Write ``text`` to ``path`` whole or not at all; refuse to overwrite an input."""
    target = path.resolve()
    for source in inputs:
        if Path(source).resolve() == target:
            raise UsageError(f"{path}: refusing to overwrite the input file")
    if target.is_dir():
        raise UsageError(f"{path}: is a directory, not a file")
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    except OSError as error:
        raise UsageError(f"{path}: cannot write ({error.strerror or error})") from None
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline="\n") as stream:
            stream.write(text)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(temporary, 0o666 & ~umask)
        os.replace(temporary, target)
    except OSError as error:
        Path(temporary).unlink(missing_ok=True)
        raise UsageError(f"{path}: cannot write ({error.strerror or error})") from None
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def json_safe(value):
    """A copy of ``value`` that :func:`json.dumps` accepts with ``allow_nan=False``:
    NumPy arrays and scalars become lists and Python numbers, nan/inf become None."""
    import numpy as np

    if isinstance(value, dict):
        return {str(k): json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    if isinstance(value, np.ndarray):
        return json_safe(value.tolist())
    if isinstance(value, (float, np.floating)):
        number = float(value)
        return number if math.isfinite(number) else None
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    return value
