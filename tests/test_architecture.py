"""The package's layers (``docs/architecture.md``; the readers produce the model records, so
they sit just below them): a module imports only modules of its
own layer or of the layers above it in the data flow; no two modules import each other,
directly or around a ring (module-level and function-level imports alike); no module
imports another module's private (``_name``) names; and no module grows past the size
the style guide allows without a reason written in it."""

from __future__ import annotations

import ast
from collections import deque
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "express"

#: Module prefix -> layer, first match wins (the order of docs/architecture.md).
LAYERS = [
    ("express.base", 0), ("express.io.toml_lines", 0), ("express.io.output", 0), ("express.io.text_formats", 0), ("express.io.archives", 0), ("express.io.finite", 0),
    ("express.model", 1),
    ("express.io", 2),
    ("express.assembly", 3),
    ("express.rail", 4),
    ("express.numeric", 5),
    ("express.forces", 5.5),  # the nonlinear force elements, between the state space and the analyses
    ("express.analysis", 6),
    ("express.export", 7), ("express.drawing", 7), ("express.report", 7),
    ("express.paper", 8),  # the paper's demo runs every stage, the exports and report included
    ("express.notebook", 8),  # Jupyter displays: the drawing of a vehicle
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


def _import_edges(name: str, path: Path, modules: set[str]):
    """``(line, module, imported name or None)`` of every import of the package in a module:
    ``from package import submodule`` is an import of the submodule."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")[: len(package.split(".")) - node.level + 1] if node.level else []
            target = ".".join(base + ([node.module] if node.module else []))
            if not target.startswith("express"):
                continue
            for alias in node.names:
                submodule = f"{target}.{alias.name}"
                yield (node.lineno, submodule, None) if submodule in modules else (node.lineno, target, alias.name)
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("express"):
                    yield node.lineno, alias.name, None


def _private(part: str) -> bool:
    return part.startswith("_") and not part.startswith("__")


def _import_graph():
    """Module -> {imported module: (file, line)} over every import, function-level ones too."""
    modules = dict(_modules())
    graph: dict[str, dict[str, str]] = {name: {} for name in modules}
    for name, path in modules.items():
        for line, target, _ in _import_edges(name, path, set(modules)):
            if target in modules and target != name:
                graph[name].setdefault(target, f"{path.relative_to(PACKAGE)}:{line}")
    return graph


def _ring(graph, start: str, members: set[str]) -> list[str]:
    """A shortest import ring through ``start`` inside one strongly connected set."""
    previous: dict[str, str] = {}
    queue = deque([start])
    while queue:
        node = queue.popleft()
        for target in sorted(graph[node]):
            if target == start:
                ring = [node]
                while ring[-1] != start:
                    ring.append(previous[ring[-1]])
                return [start, *reversed(ring[:-1]), start] if node != start else [start, start]
            if target in members and target not in previous:
                previous[target] = node
                queue.append(target)
    raise AssertionError(f"no ring through {start}")


def _strongly_connected(graph) -> list[set[str]]:
    """Tarjan's strongly connected components of more than one module (iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, targets = work[-1]
            target = next(targets, None)
            if target is not None:
                if target not in index:
                    index[target] = low[target] = len(index)
                    stack.append(target)
                    on_stack.add(target)
                    work.append((target, iter(sorted(graph[target]))))
                elif target in on_stack:
                    low[node] = min(low[node], index[target])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                members = set()
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    members.add(member)
                    if member == node:
                        break
                if len(members) > 1:
                    found.append(members)
    return found


def test_no_import_cycles():
    graph = _import_graph()
    rings = []
    for members in _strongly_connected(graph):
        ring = _ring(graph, min(members), members)
        steps = [f"{a} ({graph[a][b]}) -> {b}" for a, b in zip(ring, ring[1:])]
        rings.append("import ring: " + "; ".join(steps))
    assert not rings, "\n".join(rings)


def test_cycle_finder_finds_a_ring():
    graph = {"a": {"b": "a.py:1"}, "b": {"c": "b.py:1"}, "c": {"a": "c.py:1"}, "d": {"a": "d.py:1"}}
    assert _strongly_connected(graph) == [{"a", "b", "c"}]
    assert _ring(graph, "a", {"a", "b", "c"}) == ["a", "b", "c", "a"]


def test_no_private_names_imported_across_modules():
    """``from module import _name`` only inside one module; a private module (``_base``) is
    imported only by the modules of its own package."""
    modules = dict(_modules())
    borrowed = []
    for name, path in modules.items():
        for line, target, imported in _import_edges(name, path, set(modules)):
            where = f"{path.relative_to(PACKAGE)}:{line}: {name}"
            if imported is not None and _private(imported) and target != name:
                borrowed.append(f"{where} imports the private {target}.{imported}")
            parts = target.split(".")
            for depth, part in enumerate(parts):
                owner = ".".join(parts[:depth])
                if _private(part) and not (name == owner or name.startswith(owner + ".")):
                    borrowed.append(f"{where} imports the private module {target} from outside {owner}")
    assert not borrowed, "\n".join(borrowed)


#: The paper's demo is a command of its own; no other command imports the paper's modules.
PAPER_COMMANDS = {"express.cli.demo"}


def test_commands_import_the_library_not_the_paper():
    """A real command calls the analyses (:mod:`express.analysis`), never the demo of the paper."""
    modules = dict(_modules())
    found = [f"{path.relative_to(PACKAGE)}:{line}: {name} imports {target}"
             for name, path in modules.items() if name.startswith("express.cli") and name not in PAPER_COMMANDS
             for line, target, _ in _import_edges(name, path, set(modules)) if target.startswith("express.paper")]
    assert not found, "\n".join(found)


def test_every_package_says_what_it_owns():
    """Each package's ``__init__`` opens with a docstring whose first paragraph (at most
    two lines) says what the package owns."""
    missing = []
    for name, path in _modules():
        if path.name != "__init__.py":
            continue
        docstring = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8")))
        summary = docstring.split("\n\n")[0].splitlines() if docstring else []
        if not 1 <= len(summary) <= 2:
            missing.append(f"{path.relative_to(PACKAGE)}: {len(summary)} lines of summary")
    assert not missing, "\n".join(missing)


#: Stages whose errors are the project's own (``express.base.diagnostics``), not a bare ValueError.
OWN_ERRORS = ("express.analysis", "express.rail", "express.numeric")


def test_the_analyses_raise_the_projects_errors():
    """``analysis/``, ``rail/`` and ``numeric/`` raise :class:`ArgumentError` and the other
    errors of :mod:`express.base.diagnostics`, so that the command line need not re-wrap them."""
    bare = []
    for name, path in _modules():
        if not name.startswith(OWN_ERRORS):
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Raise) and isinstance(node.exc, ast.Call) and \
                    isinstance(node.exc.func, ast.Name) and node.exc.func.id == "ValueError":
                bare.append(f"{path.relative_to(PACKAGE)}:{node.lineno}: raise ValueError(...)")
    assert not bare, "\n".join(bare)


def test_the_entry_point_is_lazy_and_names_real_modules():
    """``express/__init__.py`` imports no stage at module level (``import express`` and
    ``express --help`` stay quick); each public name points at a module of the package."""
    init = PACKAGE / "__init__.py"
    tree = ast.parse(init.read_text(encoding="utf-8"))
    eager = [f"line {node.lineno}" for node in tree.body if isinstance(node, (ast.Import, ast.ImportFrom))
             and any(alias.name.startswith("express") for alias in node.names)
             or isinstance(node, ast.ImportFrom) and (node.module or "").startswith("express")]
    assert not eager, f"express/__init__.py imports the package at module level: {eager}"
    public = next(node.value for node in tree.body if isinstance(node, ast.AnnAssign | ast.Assign)
                  and "_PUBLIC" in ast.unparse(node.targets[0] if isinstance(node, ast.Assign) else node.target))
    modules = dict(_modules())
    targets = ast.literal_eval(public)
    unknown = [f"{name}: {target}" for name, target in targets.items() if target.partition(":")[0] not in modules]
    assert not unknown, "public names from no module of the package:\n" + "\n".join(unknown)


@pytest.mark.parametrize(("limit", "what"), [(600, "module")])
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
