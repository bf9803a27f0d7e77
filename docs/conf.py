"""Sphinx configuration of the solverplan documentation (``make docs`` builds it into docs/_build/html).

The API page (api.rst) and the CLI reference are generated from the code on every build: the API page from the
public namespace ``solverplan._EXPORTS`` (its comment lines become the sections), the CLI reference from the typer
app's click command tree (docs/_ext/click_tree.py). The gallery runs the scripts of ``examples/`` (sphinx-gallery).
"""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))  # the source tree wins over an installed copy: document what is being built
sys.path.insert(0, str(DOCS / "_ext"))
os.environ.setdefault("MPLBACKEND", "Agg")  # no display while the gallery runs
os.environ.setdefault("SOLVERPLAN_GRAPH_CACHE", "off")  # the build writes nothing to the user's cache

import solverplan  # noqa: E402  (after the path is set)
from public_api import write_api_page  # noqa: E402

write_api_page(DOCS / "api.rst")

# The tutorial runs the real commands (sphinxcontrib-programoutput): ``solverplan`` is the script next to the
# Python running Sphinx, importing this source tree; its files go to docs/tutorial/out (not kept in git).
os.environ["PATH"] = os.path.dirname(sys.executable) + os.pathsep + os.environ.get("PATH", "")
os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))
if shutil.which("solverplan") is None:
    raise RuntimeError(f"no 'solverplan' command next to {sys.executable}: install the project (pip install '.[docs]')")
(DOCS / "tutorial" / "out").mkdir(exist_ok=True)

project = "solverplan"
author = "the solverplan authors"
copyright = "the solverplan authors, MIT licence"
release = version = solverplan.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "click_tree",
    "sphinxcontrib.programoutput",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "tutorial/out", "Thumbs.db", ".DS_Store", "_ext", "**/sg_execution_times.rst"]
templates_path = ["_templates"]

# MyST: docs/contract.md is a page as it stands; its headings become link targets.
myst_enable_extensions = ["dollarmath", "deflist", "colon_fence"]
myst_heading_anchors = 4

# autodoc + numpydoc: docstrings are numpydoc; annotations go into the description, not the signature.
autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
add_module_names = False
smartquotes = False  # option names such as --env-format must stay two hyphens, not an en dash


# sphinx-gallery: examples/plot_*.py run during the build; their figures become the gallery.
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "reset_modules": ("matplotlib",),
    "abort_on_example_error": True,
    "run_stale_examples": True,  # the answers depend on the library too, not only on the script's text
    "show_memory": False,
    "write_computation_times": False,
    "doc_module": ("solverplan",),
    "backreferences_dir": None,
    "image_scrapers": ("figure_scraper.solverplan_figures", "matplotlib"),
}

html_theme = "pydata_sphinx_theme"
html_title = f"solverplan {version}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 6,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_static_path: list[str] = []
html_show_sourcelink = False

# The commands of the tutorial: shown with a prompt, and a command that exits otherwise than its
# :returncode: fails the build.
programoutput_prompt_template = "$ {command}\n{output}"
programoutput_use_ansi = False


def setup(app):
    # Run the tutorial's commands before Sphinx collects the images of a page, so that the pictures they draw are
    # found on the first build (programoutput runs them at priority 500, after the image collector; its own pass
    # then finds nothing left to run).
    from sphinxcontrib.programoutput import run_programs

    app.connect("doctree-read", run_programs, priority=100)
