"""Write the API reference's pages at build time from the package's own lists of public names.

The front page of the reference lists the names of ``sindy_impulse._PUBLIC`` (what ``from sindy_impulse
import ...`` offers), each linked to where it is documented; every subpackage with an ``__all__`` gets a
page whose autosummary table covers that ``__all__``. A name a subpackage re-exports from another documented
subpackage is documented once, where it is defined, and linked from the other page. A subpackage that
appears later (``sindy_impulse.tracking``) gets its page without a change here.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
from pathlib import Path

import sindy_impulse

#: Modules at the package's root with a public list of their own.
ROOT_MODULES = ("exceptions",)
HEADER = ".. This page is written by docs/_ext/api_pages.py at build time; edit that file, not this one.\n\n"


def documented_modules() -> list[str]:
    """The subpackages (and root modules) whose ``__all__`` the reference covers, in import order."""
    names = []
    for info in pkgutil.iter_modules(sindy_impulse.__path__):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"sindy_impulse.{info.name}")
        if getattr(module, "__all__", None) is not None and (info.ispkg or info.name in ROOT_MODULES):
            names.append(module.__name__)
    return sorted(names)


def _home(obj, modules: list[str]) -> str | None:
    """The documented module an object is defined under (the longest prefix of its ``__module__``)."""
    where = getattr(obj, "__module__", None) or ""
    if inspect.ismodule(obj):
        where = obj.__name__
    found = [m for m in modules if where == m or where.startswith(m + ".")]
    return max(found, key=len) if found else None


def _role(obj) -> str:
    if inspect.isclass(obj):
        return "class"
    if inspect.isfunction(obj) or inspect.isbuiltin(obj) or callable(obj):
        return "func"
    if inspect.ismodule(obj):
        return "mod"
    return "data"


def _summary(obj) -> str:
    doc = inspect.getdoc(obj) if (callable(obj) or inspect.ismodule(obj)) else None
    first = (doc or "").strip().split("\n\n")[0].replace("\n", " ")
    return first.replace("|", "/").replace("`", "") or "-"


def module_page(name: str, modules: list[str]) -> str:
    """The reST page of one documented module: its docstring's first paragraph and its names' table."""
    module = importlib.import_module(name)
    own, elsewhere = [], []
    for public in module.__all__:
        obj = getattr(module, public)
        home = _home(obj, modules)
        if home is not None and home != name and not inspect.ismodule(obj):
            elsewhere.append(f":{_role(obj)}:`{home}.{public} <{home}.{public}>`")
        else:
            own.append(public)
    title = f"``{name}``"
    lines = [HEADER, title, "=" * len(title), "", f".. automodule:: {name}", "   :no-members:", ""]
    lines += [f".. currentmodule:: {name}", "", ".. autosummary::", "   :toctree: generated/", ""]
    lines += [f"   {public}" for public in own]
    if elsewhere:
        also = "Also importable from here, documented where they are defined: "
        lines += ["", also + ", ".join(elsewhere) + "."]
    return "\n".join(lines) + "\n"


def index_page(modules: list[str]) -> str:
    """The reference's front page: the top-level names, then one link per module page."""
    rows = []
    for public in sorted(sindy_impulse._PUBLIC, key=str.lower):
        obj = getattr(sindy_impulse, public)
        home = _home(obj, modules)
        target = obj.__name__ if inspect.ismodule(obj) else f"{home}.{public}"
        rows.append(f"   * - :{_role(obj)}:`~{target}`\n     - {_summary(obj)}")
    lines = [
        HEADER,
        "API reference",
        "=============",
        "",
        "Generated from the docstrings. ``from sindy_impulse import NAME`` offers these names "
        "(imported lazily, so ``import sindy_impulse`` stays fast):",
        "",
        ".. list-table::",
        "   :header-rows: 1",
        "   :widths: 30 70",
        "",
        "   * - name",
        "     - what it is",
        *rows,
        "",
        "Every subpackage, with all its public names:",
        "",
        ".. toctree::",
        "   :maxdepth: 1",
        "",
        *[f"   {m}" for m in modules],
    ]
    return "\n".join(lines) + "\n"


def _write(path: Path, text: str) -> None:
    if not path.exists() or path.read_text() != text:  # unchanged pages keep their time: no rebuild
        path.write_text(text)


def write_pages(app) -> None:
    folder = Path(app.srcdir) / "api"
    folder.mkdir(exist_ok=True)
    modules = documented_modules()
    for stale in folder.glob("sindy_impulse.*.rst"):
        if stale.stem not in modules:
            stale.unlink()
    for name in modules:
        _write(folder / f"{name}.rst", module_page(name, modules))
    _write(folder / "index.rst", index_page(modules))


def setup(app):
    app.connect("config-inited", lambda app, config: write_pages(app))
    return {"parallel_read_safe": True, "parallel_write_safe": True}
