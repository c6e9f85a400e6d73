"""The layering rules of docs/architecture.md, checked on the source tree.

- no import cycle among the ``axir.*`` modules (lazy imports inside functions included);
- no module over 600 lines in models/, fmus/, orchestrator/;
- imports go one way: models ← fmus, models ← orchestrator; models imports neither, and nothing
  FMI (fmpy, pythonfmu); fmus never imports the orchestrator.

The graph is built from the sources with :mod:`ast` (nothing is imported or run).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
ROOTS = {"models": "axir.models", "fmus": "axir.fmus", "orchestrator": "axir.orchestrator"}
MAX_LINES = 600


def _modules() -> dict[str, Path]:
    out = {}
    for folder, pkg in ROOTS.items():
        for f in sorted((REPO / folder).rglob("*.py")):
            parts = [p for p in f.relative_to(REPO / folder).with_suffix("").parts
                     if p != "__init__"]
            out[".".join([pkg, *parts])] = f
    return out


MODULES = _modules()


def _imports(module: str, path: Path) -> set[str]:
    """Every module name ``module`` imports (absolute names; ``from a import b`` gives both
    ``a`` and ``a.b``), top level and inside functions."""
    base = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                anchor = base[: len(base) - (node.level - 1)]
                mod = ".".join(anchor + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            names |= {mod} | {f"{mod}.{a.name}" for a in node.names}
    return names


def _graph() -> dict[str, set[str]]:
    g: dict[str, set[str]] = {}
    for m, f in MODULES.items():
        g[m] = set()
        for t in _imports(m, f):
            while t and t not in MODULES:
                t = t.rpartition(".")[0]
            if t and t != m:
                g[m].add(t)
    return g


def _cycles(g: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (iterative Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    for root in g:
        if root in index:
            continue
        work = [(root, iter(sorted(g[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on.add(root)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(g[w]))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    x = stack.pop()
                    on.discard(x)
                    comp.append(x)
                    if x == v:
                        break
                if len(comp) > 1:
                    out.append(sorted(comp))
    return out


def test_cycle_finder_finds_a_known_cycle() -> None:
    """The checker itself: a planted cycle a → b → c → a (and a self-contained d) is found."""
    g = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert _cycles(g) == [["a", "b", "c"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_no_import_cycle() -> None:
    assert _cycles(_graph()) == []


@pytest.mark.parametrize("module", sorted(MODULES))
def test_module_size(module: str) -> None:
    n = len(MODULES[module].read_text(encoding="utf-8").splitlines())
    assert n <= MAX_LINES, f"{module} has {n} lines (> {MAX_LINES}): split it by concern"


def test_imports_go_one_way() -> None:
    """models imports no FMI library and no other axir layer; fmus never the orchestrator."""
    problems = []
    for m, f in MODULES.items():
        names = _imports(m, f)
        top = {n.split(".")[0] for n in names}
        if m.startswith("axir.models"):
            bad = {n for n in names if n.startswith(("axir.fmus", "axir.orchestrator"))}
            bad |= top & {"fmpy", "pythonfmu"}
        elif m.startswith("axir.fmus"):
            bad = {n for n in names if n.startswith("axir.orchestrator")}
        else:
            bad = set()
        problems += [f"{m} imports {b}" for b in sorted(bad)]
    assert problems == []
