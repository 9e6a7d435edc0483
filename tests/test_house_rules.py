"""The house rules of the package's code: no module over 400 lines, no function body over 60 lines
(docstrings excluded), and `simulation/` imports nothing from the rest of the package but the numba
decorator."""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "sindy_impulse"
MODULES = sorted(PACKAGE.rglob("*.py"))
MAX_MODULE_LINES, MAX_FUNCTION_LINES = 400, 60
#: Known violations being split on a branch; strict: the entry must go once the module complies.
PENDING = {"features.py": "483 lines"}
#: Infrastructure below every layer (the numba decorator): all simulation/ may import from the package.
BELOW_SIMULATION = {"_jit"}


def _function_lengths(tree: ast.AST):
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            first = body[0]
            if isinstance(first, ast.Expr) and isinstance(getattr(first, "value", None), ast.Constant):
                body = body[1:]
            if body:
                yield node.name, node.lineno, body[-1].end_lineno - body[0].lineno + 1


def _case(path):
    rel = str(path.relative_to(PACKAGE))
    marks = [pytest.mark.xfail(reason=PENDING[rel], strict=True)] if rel in PENDING else []
    return pytest.param(path, id=rel, marks=marks)


@pytest.mark.parametrize("path", [_case(p) for p in MODULES])
def test_module_and_function_sizes(path):
    source = path.read_text()
    assert len(source.splitlines()) <= MAX_MODULE_LINES, f"{path.name}: split it along its jobs"
    long = [
        (name, line, n) for name, line, n in _function_lengths(ast.parse(source)) if n > MAX_FUNCTION_LINES
    ]
    assert not long, f"functions over {MAX_FUNCTION_LINES} lines: {long}"


def test_simulation_imports_nothing_from_above():
    for path in sorted((PACKAGE / "simulation").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level >= 2 and node.module not in BELOW_SIMULATION:
                raise AssertionError(f"{path.name} imports {'.' * node.level}{node.module} from above")
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("sindy_impulse"):
                assert (node.module or "").startswith("sindy_impulse.simulation"), path.name
