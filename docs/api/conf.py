"""Sphinx configuration of the rotaflex API reference (built by tests/core/test_api_reference.py).

Build locally from the repository root (output in build/api, which git ignores)::

    sphinx-build -b html -W --keep-going docs/api build/api
"""

import re
import sys
from pathlib import Path

# the package from this checkout (src layout) rather than an installed copy; a copy of this folder
# elsewhere (the test builds one) takes rotaflex from PYTHONPATH
_SRC = Path(__file__).resolve().parents[2] / "src"
if (_SRC / "rotaflex").is_dir():
    sys.path.insert(0, str(_SRC))

project = "rotaflex"
author = "rotaflex developers"
extensions = ["sphinx.ext.autodoc", "sphinx.ext.autosummary", "sphinx.ext.napoleon"]
templates_path = ["_templates"]
exclude_patterns = ["_build"]

# numpydoc docstrings through napoleon; the package's __all__ decides what is public
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_use_param = False  # numpydoc types are prose ("ndarray, shape (N, 3)"), not references
autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "signature"

# every reference must resolve (-W turns the warning into a failure); types of the libraries we
# build on are not documented here (no network for intersphinx in CI)
nitpicky = True
nitpick_ignore_regex = [
    (
        r"py:.*",
        r"(np|numpy|xr|xarray|pd|matplotlib|plt|scipy|sympy|numba|dask|concurrent|typing|collections|pathlib)(\..*)?",
    ),
    (r"py:.*", r"(Path|Figure|Axes|Callable|Iterable|Mapping|Sequence|Iterator|Any|Literal|NDArray|ArrayLike)"),
]
html_theme = "alabaster"


#: a dotted Python name (what a cross-reference names); anything else is a type written in words
_IDENTIFIER = re.compile(r"[~.]?[A-Za-z_]\w*(\.[A-Za-z_]\w*)*")


def _importable(target: str, module: str | None, cls: str | None) -> bool:
    """True when ``target`` names an object: as written, relative to the module or class of the
    docstring that names it, or (not fully qualified) relative to any rotaflex module already
    imported (a docstring documented through its package's ``__all__`` is read in the package's
    context, not in the context of the module that defines it)."""
    import importlib

    def resolve(obj, parts) -> bool:
        try:
            for p in parts:
                obj = getattr(obj, p)
        except AttributeError:
            return False
        return True

    def resolve_dotted(dotted: str) -> bool:
        parts = dotted.split(".")
        for i in range(len(parts), 0, -1):
            try:
                return resolve(importlib.import_module(".".join(parts[:i])), parts[i:])
            except ImportError:
                continue
        return False

    target = target.lstrip("~.")
    bases = [b for b in (f"{module}.{cls}" if module and cls else None, module) if b]
    if any(resolve_dotted(f"{b}.{target}") for b in bases) or resolve_dotted(target):
        return True
    if target.startswith("rotaflex."):
        return False
    loaded = [m for n, m in list(sys.modules.items()) if n.startswith("rotaflex.") and m is not None]
    return any(resolve(m, target.split(".")) for m in loaded)


def _internal_reference(app, env, node, contnode):
    """A reference to an object that exists but is not in this reference (a helper a docstring
    points to) is shown as code; a reference to nothing stays unresolved and fails the build."""
    if node.get("refdomain") != "py":
        return None
    if not _IDENTIFIER.fullmatch(node["reftarget"]):  # a type in words: "(3,) floats", '{"a", "b"}'
        return contnode
    if _importable(node["reftarget"], node.get("py:module"), node.get("py:class")):
        return contnode
    return None


def setup(app):
    app.connect("missing-reference", _internal_reference)
