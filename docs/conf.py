"""Sphinx configuration of the sindy-impulse documentation site.

Build it with ``python -m sphinx -W --keep-going -b html docs docs/_build/html`` (see docs/contributing.md).
The API pages and the benchmark results pages are written at build time by the two local extensions in
``docs/_ext`` (from the package's public names and from ``benchmarks/results/*.json``); the gallery's
examples in ``docs/examples`` run at build time (sphinx-gallery).
"""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(DOCS / "_ext"))

import sindy_impulse  # noqa: E402

project = "sindy-impulse"
author = "sindy-impulse developers"
copyright = "sindy-impulse developers, BSD-3-Clause"  # noqa: A001
release = sindy_impulse.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.intersphinx",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "myst_parser",
    "api_pages",
    "results_pages",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = [
    "_build",
    "**.ipynb_checkpoints",
    "examples/README.txt",
    "auto_examples/*.ipynb",
    "auto_examples/*.py",
    "auto_examples/*.zip",
    "auto_examples/*.md5",
    "auto_examples/*.json",
    "*.html",
]
templates_path = ["_templates"]

# -- Markdown pages (MyST): the narrative pages stay Markdown so that they read on GitHub too ----------
myst_enable_extensions = ["colon_fence", "dollarmath"]
myst_heading_anchors = 3
suppress_warnings = ["myst.header"]

# -- API pages ----------------------------------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": True, "inherited-members": False}
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()
add_module_names = False

intersphinx_mapping: dict[str, tuple[str, None]] = {}  # nothing fetched from the network at build time

# -- The gallery: examples executed at build time, figures shown -------------------------------------------
os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("SINDY_IMPULSE_PROGRESS", "0")
sphinx_gallery_conf = {
    "examples_dirs": str(DOCS / "examples"),
    "gallery_dirs": str(DOCS / "auto_examples"),
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": False,
    "only_warn_on_example_error": False,
    "matplotlib_animations": False,
    "show_memory": False,
    "plot_gallery": "True",
}
# the examples' own warnings (a DataWarning of the package, a matplotlib notice) are part of what they
# show; they are not the build's warnings
warnings.filterwarnings("ignore", category=UserWarning, message=".*non-interactive.*")

# -- The site -----------------------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"sindy-impulse {release}"
html_static_path: list[str] = []
html_show_sourcelink = False
html_copy_source = False
html_last_updated_fmt = None


def _skip_metadata_requests(app, what, name, obj, skip, options):
    """scikit-learn's generated ``set_*_request`` methods: routing plumbing, documented by scikit-learn."""
    if name.startswith("set_") and name.endswith("_request"):
        return True
    return None


def setup(app):
    app.connect("autodoc-skip-member", _skip_metadata_requests)
