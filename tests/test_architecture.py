"""The package's rooms hold: imports run only down the layers (lazy ones
included), never in a circle, never into another package's private module
or name; no module over 600 lines and no function over 100 outside the
compiled kernels; no issue numbers in the package's text.

Read from the source with :mod:`ast`, so every import counts, also one made
inside a function."""

from __future__ import annotations

import ast
import os
import re

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PKG = os.path.join(ROOT, "mat_hopper")

# Lowest first. A module may import modules of its own layer or of layers
# below; the entry points (cli, book, sphinx_ext, __main__) sit on top. The
# package face (mat_hopper/__init__.py) hands on the core's names lazily.
LAYERS = (
    ("util",),
    ("core",),
    ("physics",),
    ("analysis", "batch"),
    ("viz",),
    ("experiments",),
    ("optimize",),
    ("cli", "book", "sphinx_ext", "__main__", "__init__"),
)
RANK = {room: i for i, rooms in enumerate(LAYERS) for room in rooms}

# Functions compiled for numba or Warp: one kernel each, kept whole for speed.
KERNELS = {("core/_loop.py", "rollout_loop")}
MAX_MODULE_LINES = 600
MAX_FUNCTION_LINES = 100


def _modules():
    for folder, _, files in os.walk(PKG):
        for name in sorted(files):
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                yield os.path.relpath(path, PKG).replace(os.sep, "/"), path


def _module_name(rel: str) -> str:
    parts = rel[:-3].split("/")
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(["mat_hopper", *parts])


def _package(rel: str) -> str:
    name = _module_name(rel)
    return name if rel.endswith("__init__.py") else name.rsplit(".", 1)[0]


def _imports(rel: str, tree) -> list[tuple[str, list[str], int]]:
    """(absolute module, names taken, line) for every import of the package."""
    out = []
    pkg = _package(rel).split(".")
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = pkg[: len(pkg) - (node.level - 1)]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            if mod == "mat_hopper" or mod.startswith("mat_hopper."):
                out.append((mod, [a.name for a in node.names], node.lineno))
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("mat_hopper"):
                    out.append((a.name, [], node.lineno))
    return out


def _room(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def _is_module(module: str) -> bool:
    path = os.path.join(ROOT, *module.split("."))
    return os.path.isdir(path) or os.path.isfile(path + ".py")


def _targets(module: str, names: list[str]) -> list[str]:
    """The modules an import reaches: `from pkg import submodule` reaches the submodule."""
    subs = [f"{module}.{n}" for n in names if _is_module(f"{module}.{n}")]
    return subs or [module]


@pytest.fixture(scope="module")
def graph():
    edges, trees = {}, {}
    for rel, path in _modules():
        with open(path, encoding="utf-8") as f:
            tree = ast.parse(f.read())
        trees[rel] = tree
        edges[rel] = _imports(rel, tree)
    return edges, trees


def test_imports_run_down_the_layers_only(graph):
    edges, _ = graph
    up = []
    for rel, imports in edges.items():
        mine = _room(_module_name(rel))
        for mod, names, line in imports:
            for target in _targets(mod, names):
                theirs = _room(target)
                if target == "mat_hopper" and names == ["__version__"]:
                    theirs = "util"
                if RANK.get(theirs, 0) > RANK[mine]:
                    up.append(f"{rel}:{line} ({mine}) imports {target} ({theirs})")
    assert not up, "imports that run back up a layer:\n" + "\n".join(up)


def test_no_import_circle(graph):
    edges, _ = graph
    names = {_module_name(rel): rel for rel in edges}
    adj = {
        rel: {names[t] for mod, ns, _ in imports for t in _targets(mod, ns) if t in names and names[t] != rel}
        for rel, imports in edges.items()
    }
    # A package's __init__ is reached by every import of a submodule: leave
    # faces that only re-export out, as Python runs them before the submodule anyway.
    state, stack, circles = {}, [], []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for nxt in adj[node]:
            if nxt.endswith("__init__.py"):
                continue
            if state.get(nxt) == 1:
                circles.append(stack[stack.index(nxt) :] + [nxt])
            elif nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for rel in sorted(adj):
        if rel not in state:
            visit(rel)
    assert not circles, "import circles:\n" + "\n".join(" -> ".join(c) for c in circles)


def _private_owner(module: str) -> str | None:
    parts = module.split(".")
    for i, p in enumerate(parts):
        if p.startswith("_") and not p.startswith("__"):
            return ".".join(parts[:i])
    return None


def _inside(pkg: str, owner: str) -> bool:
    return pkg == owner or pkg.startswith(owner + ".")


def test_no_import_of_another_packages_private_module_or_name(graph):
    edges, _ = graph
    bad = []
    for rel, imports in edges.items():
        me = _package(rel)
        for mod, names, line in imports:
            owner = _private_owner(mod)
            if owner is not None and not _inside(me, owner):
                bad.append(f"{rel}:{line} imports the private module {mod}")
                continue
            home = mod if os.path.isdir(os.path.join(ROOT, *mod.split("."))) else mod.rsplit(".", 1)[0]
            for n in names:
                if n.startswith("_") and not n.startswith("__") and not _inside(me, home):
                    bad.append(f"{rel}:{line} imports the private name {mod}.{n}")
    assert not bad, "\n".join(bad)


def test_modules_and_functions_are_small(graph):
    _, trees = graph
    big = []
    for rel, path in _modules():
        with open(path, encoding="utf-8") as f:
            n = len(f.read().splitlines())
        if n > MAX_MODULE_LINES:
            big.append(f"{rel}: {n} lines")
        for node in ast.walk(trees[rel]):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and (rel, node.name) not in KERNELS:
                length = node.end_lineno - node.lineno + 1
                if length > MAX_FUNCTION_LINES and not _is_kernel(node):
                    big.append(f"{rel}: {node.name}() {length} lines")
    assert not big, "\n".join(big)


def _is_kernel(node) -> bool:
    """A Warp kernel or function (``@wp.kernel``, ``@wp.func``)."""
    for d in node.decorator_list:
        text = ast.unparse(d)
        if re.match(r"^(wp|warp)\.(kernel|func)\b", text):
            return True
    return False


def test_no_issue_numbers_in_the_package():
    """History (issue numbers) belongs in CHANGELOG.md and docs/, not in the code."""
    found = []
    for rel, path in _modules():
        with open(path, encoding="utf-8") as f:
            for i, line in enumerate(f, 1):
                if re.search(r"issue [0-9]", line, re.IGNORECASE):
                    found.append(f"{rel}:{i}: {line.strip()}")
    assert not found, "\n".join(found)


def test_the_public_api_imports():
    import mat_hopper

    for name in mat_hopper.__all__:
        assert getattr(mat_hopper, name) is not None, name
