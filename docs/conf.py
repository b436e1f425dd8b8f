"""Sphinx configuration of the spectralshell documentation (built by `make docs`).

Builds from this checkout (not an installed copy): the API reference, the gallery over
``examples/`` (run at their small sizes), the notebooks of ``notebooks/`` (executed), and the
pages generated at build time from the package's own reports (``_generated.py``).
"""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(DOCS))
# the notebook kernels are separate processes: they import this checkout too
os.environ["PYTHONPATH"] = os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])

import spectralshell  # noqa: E402
from _generated import write_generated_pages  # noqa: E402

project = "spectralshell"
author = "the spectralshell developers"
copyright = "2026, the spectralshell developers"
release = version = spectralshell.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "myst_nb",
]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
templates_path = ["_templates"]
exclude_patterns = ["_build", "jupyter_execute", "auto_examples/*.ipynb", "**.ipynb_checkpoints",
                    "generated/validation/figures"]
html_theme = "alabaster"
html_theme_options = {"description": "Floquet stability of pumped elastic membranes",
                      "fixed_sidebar": True}

# API reference: numpydoc docstrings through autosummary (one page per entry)
autosummary_generate = True
autodoc_default_options = {"members": True}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

# pages written at build time from the package's reports (errata, validation)
write_generated_pages(DOCS / "generated")

# MyST: $...$ and $$...$$ maths in the pages and notebooks
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3

# the gallery: every examples/plot_*.py is run, in examples/; the scripts save PNGs (no pyplot),
# which _generated.png_scraper moves into the gallery; the sweep example's store starts afresh
shutil.rmtree(ROOT / "examples" / "map.zarr", ignore_errors=True)
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"plot_",
    "image_scrapers": ("_generated.png_scraper",),
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "copyfile_regex": r".*\.toml$",
}

# the notebooks: executed at every build, in a scratch directory; an error fails the build
nb_execution_mode = "force"
nb_execution_in_temp = True
nb_execution_timeout = 600
nb_execution_raise_on_error = True
nb_execution_show_tb = True
