"""Sphinx configuration of hawksim's API reference (issue 50, item 5): autodoc reads the docstrings of the names in
each package's ``__all__``, napoleon their Google-style sections ("Args:", "Returns:").

Build (what tests/test_api_docs.py runs, warnings as errors):

    python -m sphinx -W --keep-going -b html docs/api docs/api/_build
"""

import os
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, ROOT)  # this tree's hawksim, not an installed one

project = "hawksim"
author = "hawksim contributors"
extensions = ["sphinx.ext.autodoc", "sphinx.ext.napoleon"]
napoleon_google_docstring = True
napoleon_numpy_docstring = False
autodoc_default_options = {"members": True, "member-order": "bysource", "show-inheritance": True}
autodoc_typehints = "signature"
autodoc_preserve_defaults = True
default_role = "code"  # `x` in a docstring is code, as in the Markdown docs
exclude_patterns = ["_build"]
html_theme = "alabaster"
html_static_path = []
suppress_warnings = []
