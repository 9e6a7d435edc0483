"""The house rules of the package's layout: no import circle (function-level imports counted), `simulation/`
imports nothing above it, nothing loose at the root, every module named on the architecture page (and only
modules that exist), and no function body over 60 lines (docstrings excluded)."""

import ast
import re
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "sindy_impulse"
ARCHITECTURE = PACKAGE.parent / "docs" / "architecture.md"
MODULES = sorted(PACKAGE.rglob("*.py"))
MAX_FUNCTION_LINES = 60
#: What may sit at the package's root: the public names, the errors and warnings, the version.
ROOT_MODULES = {"__init__.py", "exceptions.py", "_version.py"}
#: What `simulation/` may import from the package: the infrastructure below every layer.
BELOW_SIMULATION = ("sindy_impulse._utils", "sindy_impulse.exceptions")


def _name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


NAMES = {_name(p): p for p in MODULES}


def _imports(path: Path) -> set[str]:
    """The package modules ``path`` imports anywhere in its body (module level and inside functions)."""
    name = _name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            # `from pkg import sub` imports the module pkg.sub
            targets = [f"{module}.{a.name}" if f"{module}.{a.name}" in NAMES else module for a in node.names]
        else:
            continue
        for target in targets:
            if not target.startswith("sindy_impulse"):
                continue
            # importing a.b.c runs a/__init__, a/b/__init__ and c: every package not already importing
            parts = target.split(".")
            for k in range(1, len(parts) + 1):
                ancestor = ".".join(parts[:k])
                if ancestor in NAMES and not (name == ancestor or name.startswith(ancestor + ".")):
                    found.add(ancestor)
    return found


GRAPH = {name: _imports(path) for name, path in NAMES.items()}


def _cycle() -> list[str] | None:
    """One import circle of the package, or None."""
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for nxt in sorted(GRAPH.get(node, ())):
            if state.get(nxt) == 1:
                return stack[stack.index(nxt) :] + [nxt]
            if nxt not in state and (found := visit(nxt)):
                return found
        stack.pop()
        state[node] = 2
        return None

    for node in sorted(GRAPH):
        if node not in state and (found := visit(node)):
            return found
    return None


def test_the_walker_sees_function_level_imports_and_packages_run_by_an_import():
    assert "sindy_impulse.identification.estimator" in GRAPH["sindy_impulse.modes.band_fit"]  # in a function
    # importing a module of another package runs that package's __init__ too
    assert "sindy_impulse.poles" in GRAPH["sindy_impulse.diagnostics.model"]


def test_no_import_circle():
    assert _cycle() is None, " -> ".join(_cycle())


def test_simulation_imports_nothing_from_above():
    for name, imported in GRAPH.items():
        if name.startswith("sindy_impulse.simulation"):
            above = [m for m in imported if not m.startswith(("sindy_impulse.simulation", *BELOW_SIMULATION))]
            assert not above, f"{name} imports {above}"


def test_infrastructure_imports_nothing_above_it():
    for name, imported in GRAPH.items():
        if name.startswith("sindy_impulse._utils") and not name.endswith("warmup"):
            # the warm-up alone imports the kernels, to compile them
            assert all(m.startswith(BELOW_SIMULATION) for m in imported), (name, imported)


def test_only_the_public_face_at_the_root():
    loose = {p.name for p in PACKAGE.glob("*.py")} - ROOT_MODULES
    assert not loose, f"modules loose at the package root: {sorted(loose)}"


def _documented() -> set[str]:
    """Module paths named in the architecture page's tables (first column, `path/module.py`)."""
    names = set()
    for line in ARCHITECTURE.read_text().splitlines():
        if line.startswith("|"):
            first = line.split("|")[1]
            names.update(re.findall(r"`([\w/]+\.py)`", first))
    return names


def test_the_architecture_page_names_every_module_and_only_those():
    modules = {str(p.relative_to(PACKAGE)) for p in MODULES}
    documented = _documented()
    missing, extra = sorted(modules - documented), sorted(documented - modules)
    assert not missing, f"modules missing from docs/architecture.md: {missing}"
    assert not extra, f"docs/architecture.md names modules that do not exist: {extra}"


def _function_lengths(tree: ast.AST):
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            first = body[0]
            if isinstance(first, ast.Expr) and isinstance(getattr(first, "value", None), ast.Constant):
                body = body[1:]
            if body:
                yield node.name, node.lineno, body[-1].end_lineno - body[0].lineno + 1


@pytest.mark.parametrize("path", MODULES, ids=[str(p.relative_to(PACKAGE)) for p in MODULES])
def test_function_sizes(path):
    lengths = _function_lengths(ast.parse(path.read_text()))
    long = [(name, line, n) for name, line, n in lengths if n > MAX_FUNCTION_LINES]
    assert not long, f"functions over {MAX_FUNCTION_LINES} lines: {long}"
