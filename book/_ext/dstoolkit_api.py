"""Sphinx extension for the API reference (book/api.md): the public constants of each layer.

Each subpackage of dstoolkit re-exports its public names from private modules
(``dstoolkit/gauge/__init__.py`` imports ``FIRST_ARRIVAL`` from ``_latency``). autodoc
documents a module-level constant only when a ``#:`` comment sits next to its assignment
in the module being documented, so the re-exported constants would be left out. This
documenter finds the ``#:`` comment in the private module that assigns the constant, and
shows the value only when it is short.

The docstrings write |x| for an absolute value or a cardinality (|A|, |error|); in
reStructuredText that is a substitution, so the bars are escaped (outside inline literals
and examples).

Napoleon reads the first line of a constant's or a property's docstring as ``type: text``
("Lower ends: shape (n,)" would make "Lower ends" a type); these docstrings are prose, so
napoleon is applied to the other docstrings only.

The page's contents sidebar names each member by itself (``toc_object_entries_show_parents``
in _config.yml), but some names are longer than the sidebar is wide
(``dependent_combination_explorer()``). The browser may break a code name only where a
word ends, so the names in the page's local table of contents (Sphinx's ``toc`` page
context) get a line break opportunity (``<wbr>``) after each underscore and dot and
between the words of a CamelCase name.
"""

from __future__ import annotations

import importlib
import pkgutil
import re
from functools import cache
from typing import Any

from sphinx.application import Sphinx
from sphinx.errors import PycodeError
from sphinx.ext import napoleon
from sphinx.ext.autodoc import DataDocumenter, ModuleDocumenter
from sphinx.pycode import ModuleAnalyzer
from sphinx.util.inspect import object_description

#: Longest value shown in a constant's header; longer ones (arrays, tables) are left out.
MAX_VALUE_CHARS = 80


@cache
def _comments(package: str) -> dict[str, list[str]]:
    """``#:`` comments of the module-level names assigned in ``package``'s modules."""
    found: dict[str, list[str]] = {}
    module = importlib.import_module(package)
    names = [package] + [f"{package}.{info.name}"
                         for info in pkgutil.iter_modules(getattr(module, "__path__", []))]
    for name in names:
        try:
            analyzer = ModuleAnalyzer.for_module(name)
            analyzer.analyze()
        except PycodeError:
            continue
        for (scope, attr), lines in analyzer.attr_docs.items():
            if scope == "":
                found.setdefault(attr, list(lines))
    return found


class PublicConstantDocumenter(DataDocumenter):
    """A constant re-exported by a dstoolkit subpackage, with its comment from its module."""

    priority = DataDocumenter.priority + 1

    @classmethod
    def can_document_member(cls, member: Any, membername: str, isattr: bool,
                            parent: Any) -> bool:
        return (isinstance(parent, ModuleDocumenter)
                and parent.modname.startswith("dstoolkit.")
                and membername in _comments(parent.modname))

    def get_module_comment(self, attrname: str) -> list[str] | None:
        return _comments(self.modname).get(attrname) or super().get_module_comment(attrname)

    def should_suppress_value_header(self) -> bool:
        return (len(object_description(self.object)) > MAX_VALUE_CHARS
                or super().should_suppress_value_header())


def _escape_bars(line: str) -> str:
    """``|`` as ``\\|`` except inside ``inline literals`` and in doctest lines."""
    if line.lstrip().startswith((">>>", "...")):
        return line
    parts = line.split("``")
    parts[::2] = [part.replace("|", "\\|") for part in parts[::2]]
    return "``".join(parts)


def _napoleon_except_prose(app: Sphinx, what: str, name: str, obj: Any, options: Any,
                           lines: list[str]) -> None:
    lines[:] = [_escape_bars(line) for line in lines]
    if what not in ("data", "attribute", "property"):
        napoleon._process_docstring(app, what, name, obj, options, lines)


_CODE_NAME = re.compile(r'(<span class="pre">)([^<]*)(</span>)')
#: Where a word of a name ends: after ``_`` or ``.``, or between a lower-case letter and
#: the capital of the next word (``Dependent|Evidence|Filter``).
_WORD_END = re.compile(r"(?<=[_.])(?=.)|(?<=[a-z])(?=[A-Z])")


def break_names_at_words(toc: str) -> str:
    """Return the local table of contents with ``<wbr>`` where a word of a code name ends.

    >>> break_names_at_words('<a><code><span class="pre">noise_bounds()</span></code></a>')
    '<a><code><span class="pre">noise_<wbr>bounds()</span></code></a>'
    >>> break_names_at_words('<span class="pre">IntervalEvidence</span>')
    '<span class="pre">Interval<wbr>Evidence</span>'
    """
    return _CODE_NAME.sub(
        lambda m: m[1] + _WORD_END.sub("<wbr>", m[2]) + m[3], toc
    )


def _breakable_toc(app: Sphinx, pagename: str, templatename: str, context: dict[str, Any],
                   doctree: Any) -> None:
    if isinstance(context.get("toc"), str):
        context["toc"] = break_names_at_words(context["toc"])


def setup(app: Sphinx) -> dict[str, Any]:
    app.setup_extension("sphinx.ext.autodoc")
    app.setup_extension("sphinx.ext.napoleon")
    for listener in list(app.events.listeners.get("autodoc-process-docstring", [])):
        if listener.handler is napoleon._process_docstring:
            app.disconnect(listener.id)
    app.connect("autodoc-process-docstring", _napoleon_except_prose)
    app.add_autodocumenter(PublicConstantDocumenter, override=True)
    app.connect("html-page-context", _breakable_toc)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
