"""Sphinx configuration of phmech's documentation (`make docs`, docs/requirements.txt).

The pages are the Markdown files of docs/ (myst-parser) and the API reference (api.rst), which
the ``phmech-api`` directive below fills from ``phmech.__all__``: every public name is documented
from its docstring (autodoc; numpy- and Google-style sections through napoleon), so a name added
to ``__all__`` appears without editing the docs. The build is run with -W: a warning fails it.
"""
import inspect
import types

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

import phmech
from phmech._builder import Builder

project = "phmech"
author = "phmech developers"
copyright = "phmech developers"
release = version = phmech.__version__

extensions = ["sphinx.ext.autodoc", "sphinx.ext.napoleon", "sphinx.ext.mathjax", "myst_parser"]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "requirements.txt"]
myst_heading_anchors = 3              # [text](#1-what-is-modelled) links of the pages
myst_enable_extensions = ["dollarmath"]
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "show-inheritance": False}
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False
html_theme = "alabaster"
# the user guide's code lines reach ~100 columns: a wider page, and no body width cap, so that
# its code blocks are shown whole rather than clipped at alabaster's 800 px
html_theme_options = {"page_width": "1240px", "body_max_width": "none"}
html_title = f"phmech {release}"


def _kind(obj) -> str:
    if isinstance(obj, types.ModuleType):
        return "module"
    if inspect.isclass(obj) and issubclass(obj, BaseException):
        return "exception"
    if inspect.isclass(obj):
        return "class"
    if callable(obj):
        return "function"
    return "data"


_GROUPS = [("class", "Classes"), ("function", "Functions"), ("exception", "Exceptions and warnings"),
           ("data", "Data"), ("module", "Modules")]


class PublicAPI(SphinxDirective):
    """``.. phmech-api::``: one section per kind of object, one autodoc entry per name of
    ``phmech.__all__``, in the order of ``__all__``."""

    def run(self):
        by_kind = {k: [] for k, _ in _GROUPS}
        for name in phmech.__all__:
            by_kind[_kind(getattr(phmech, name))].append(name)
        lines = []
        for kind, title in _GROUPS:
            if not by_kind[kind]:
                continue
            lines += [title, "-" * len(title), ""]
            for name in by_kind[kind]:
                if kind == "module":
                    lines += [f"phmech.{name}", "^" * (len(name) + 7), "",
                              f".. automodule:: phmech.{name}", "   :members:", ""]
                elif isinstance(getattr(phmech, name), type) and issubclass(getattr(phmech, name), Builder):
                    # Mechanism: its add_* methods are the builder's (python/phmech/_builder.py)
                    lines += [f".. auto{kind}:: phmech.{name}", "   :inherited-members:", ""]
                else:
                    lines += [f".. auto{kind}:: phmech.{name}", ""]
        node = nodes.section()
        node.document = self.state.document
        nested_parse_with_titles(self.state, StringList(lines, "phmech.__all__"), node)
        return node.children


def setup(app):
    app.add_directive("phmech-api", PublicAPI)
