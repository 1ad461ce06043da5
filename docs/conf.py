"""Sphinx configuration of the API reference: `python -m sphinx -W -b html docs docs/_build/html`.

The reference is generated from the docstrings of `gfmd_contact` (autodoc, numpy style via
napoleon); tests/test_docs.py builds it with warnings as errors.
"""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the checkout's packages, installed or not

project = "gfmd-contact"
author = "gfmd-contact developers"
extensions = ["sphinx.ext.autodoc", "sphinx.ext.napoleon"]
napoleon_google_docstring = False
napoleon_numpy_docstring = True
autodoc_member_order = "bysource"
autodoc_typehints = "none"
default_role = "code"  # `name` in a docstring is code, as in the source
exclude_patterns = ["_build"]
html_theme = "alabaster"
html_static_path = []
