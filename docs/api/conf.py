# Sphinx configuration of rotleak's Python API page: the docstrings of python/rotleak (NumPy convention,
# read by sphinx.ext.napoleon). scripts/api_docs.py builds it as text into docs/python-api.md; for HTML:
#   PYTHONPATH=build/python python3 -m sphinx -b html docs/api runs/api-html
project = "rotleak"
author = "the rotleak developers"
extensions = ["sphinx.ext.autodoc", "sphinx.ext.napoleon"]
napoleon_google_docstring = False
napoleon_numpy_docstring = True
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_preserve_defaults = True
exclude_patterns = []
# the package's aliases by name, not expanded into their unions
autodoc_type_aliases = {"Value": "rotleak.Value", "PathLike": "rotleak.PathLike", "Progress": "rotleak.Progress",
                        "Drawable": "rotleak.plot.Drawable"}
