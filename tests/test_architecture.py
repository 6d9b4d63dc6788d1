"""The package's layers (``docs/architecture.md``; the readers produce the model records, so
they sit just below them): a module imports only modules of its
own layer or of the layers above it in the data flow, and no module grows past the size
the style guide allows without a reason written in it."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "express"

#: Module prefix -> layer, first match wins (the order of docs/architecture.md).
LAYERS = [
    ("express.base", 0), ("express.io.toml_lines", 0), ("express.io.output", 0),
    ("express.model", 1),
    ("express.io", 2),
    ("express.assembly", 3),
    ("express.rail", 4),
    ("express.numeric", 5),
    ("express.analysis", 6),
    ("express.export", 7), ("express.drawing", 7), ("express.report", 7),
    ("express.paper", 8),  # the paper's demo runs every stage, the exports and report included
    ("express.cli", 9), ("express.__main__", 9),
    ("express", 0),  # the package's __init__ only
]


def _layer(module: str) -> int:
    for prefix, layer in LAYERS:
        if module == prefix or (prefix != "express" and module.startswith(prefix + ".")):
            return layer
    raise AssertionError(f"{module}: no layer in LAYERS (add it, as docs/architecture.md places it)")


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        yield name, path


def _imports(name: str, path: Path):
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.startswith("express"):
                yield node.lineno, target
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("express"):
                    yield node.lineno, alias.name


def test_every_import_follows_the_data_flow():
    climbs = []
    for name, path in _modules():
        for line, target in _imports(name, path):
            if _layer(target) > _layer(name):
                climbs.append(f"{path.relative_to(PACKAGE)}:{line}: {name} imports {target}")
    assert not climbs, "\n".join(climbs)


@pytest.mark.parametrize(("limit", "what"), [(650, "module")])
def test_modules_stay_small(limit, what):
    large = []
    for _, path in _modules():
        text = path.read_text(encoding="utf-8")
        if text.count("\n") > limit and "size-reason:" not in text:
            large.append(f"{path.relative_to(PACKAGE)}: {text.count(chr(10))} lines")
    assert not large, f"{what}s over {limit} lines without a 'size-reason:' note:\n" + "\n".join(large)


def test_functions_fit_on_a_screen():
    long = []
    for _, path in _modules():
        text = path.read_text(encoding="utf-8")
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                body = node.body[1:] if ast.get_docstring(node) and len(node.body) > 1 else node.body
                length = node.end_lineno - body[0].lineno + 1  # code lines, the docstring aside
                segment = "\n".join(text.splitlines()[node.lineno - 1: node.end_lineno])
                if length > 80 and "size-reason:" not in segment:
                    long.append(f"{path.relative_to(PACKAGE)}:{node.lineno}: {node.name} ({length} lines)")
    assert not long, "functions with over 80 lines of code without a 'size-reason:' note:\n" + "\n".join(long)
