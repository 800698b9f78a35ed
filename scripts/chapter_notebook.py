r"""Turn a chapter of the book (a MyST Markdown notebook) into a clean Jupyter notebook.

The chapters in ``book/`` are written for Jupyter Book: their Markdown holds MyST roles and
directives (``{eq}``, ``{glue:text}``, ``{exercise}``, ``{solution}``, ...) that JupyterLab
shows as raw text, and every exercise is followed by its solution. :func:`clean_notebook`
rewrites a chapter for a reader who runs it in JupyterLab:

- cross-references become the text the book shows: ``{eq}`mf-bel``` -> ``(3.2)``,
  ``{numref}`` -> ``Fig. 3.1``, ``{doc}`` -> the chapter's title and number, citations ->
  ``Xu et al. (2017)``; numbered display equations get their ``\tag{3.2}``;
- ``{glue:text}`` shows the value the chapter glued when the book was built (the code cells
  that compute it are still there); the calls to ``myst_nb.glue`` are removed from the code,
  so that the notebook runs with ``dstoolkit[teaching]`` alone;
- exercises become a quoted block headed "Exercise 3.1"; **solutions are left out**;
- admonitions become quoted blocks with their title in bold; a figure's caption follows the
  cell that draws it.

The module has no Sphinx import: a :class:`References` carries what the book build resolved
(see ``scripts/sphinx_notebooks.py``, the Sphinx extension that calls it).
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable
from dataclasses import dataclass, field

__all__ = ["References", "clean_markdown", "clean_notebook", "split_glue", "strip_glue"]

#: Called with a message for anything the converter cannot render faithfully.
Warn = Callable[[str], None]


def _ignore(message: str) -> None:
    """Default ``warn``: drop the message."""


@dataclass
class References:
    """What the book build resolved, keyed as the chapter's roles name it.

    Attributes
    ----------
    equations : label -> equation number as printed, e.g. ``"3.2"``.
    numbered : label -> numbered reference text, e.g. ``"Fig. 3.1"`` or ``"Exercise 3.2"``.
    sections : label -> the title of the section or page a ``{ref}`` points to.
    documents : docname (``book/notation``) -> its title as the book shows it.
    chapter_numbers : docname -> chapter number, e.g. ``"3"`` (numbered chapters only).
    citations : bibtex key -> ``(authors, year)``, e.g. ``("Xu et al.", "2017")``.
    glue : glued name -> its ``text/plain`` value from the executed chapter.
    glue_markdown : glued name -> its ``text/markdown`` value, for ``{glue:md}``.
    format_glue : formats a glued value with a format spec, as ``{glue:text}`` does.
    eqref_format : how an equation number is printed (Sphinx's ``math_eqref_format``).
    """

    equations: dict[str, str] = field(default_factory=dict)
    numbered: dict[str, str] = field(default_factory=dict)
    sections: dict[str, str] = field(default_factory=dict)
    documents: dict[str, str] = field(default_factory=dict)
    chapter_numbers: dict[str, str] = field(default_factory=dict)
    citations: dict[str, tuple[str, str]] = field(default_factory=dict)
    glue: dict[str, str] = field(default_factory=dict)
    glue_markdown: dict[str, str] = field(default_factory=dict)
    format_glue: Callable[[str, str], str] = lambda text, spec: format(text, spec)
    eqref_format: str = "({number})"


# --------------------------------------------------------------------------------------
# Inline roles
# --------------------------------------------------------------------------------------

# A role, or an inline code span (left as it is, so roles inside code are not touched).
_INLINE = re.compile(r"\{(?P<role>[\w:.+-]+)\}`(?P<content>[^`]*)`|(?P<code>(`+)[^`]+?\4)")
# "text <target>" in a role's content.
_EXPLICIT = re.compile(r"^(?P<text>.*?)\s*<(?P<target>[^<>]+)>$", re.DOTALL)


def _split_explicit(content: str) -> tuple[str | None, str]:
    """``"title <target>"`` -> ``("title", "target")``; ``"target"`` -> ``(None, "target")``."""
    match = _EXPLICIT.match(content)
    if match and match["text"]:
        return match["text"], match["target"].strip()
    return None, content.strip()


def _docname(target: str, docname: str) -> str:
    """Return the docname a ``{doc}`` target names, relative to the chapter's folder."""
    target = target.removesuffix(".md").removesuffix(".ipynb")
    if target.startswith("/"):
        return target.lstrip("/")
    folder = docname.rsplit("/", 1)[0] if "/" in docname else ""
    parts = [*folder.split("/"), *target.split("/")] if folder else target.split("/")
    out: list[str] = []
    for part in parts:
        if part == "..":
            if out:
                out.pop()
        elif part not in ("", "."):
            out.append(part)
    return "/".join(out)


def _cite(keys: str, refs: References, textual: bool, warn: Warn) -> str:
    """Author-year text of a ``{cite:p}`` (parenthetical) or ``{cite:t}`` (textual) role."""
    found = []
    for key in (k.strip() for k in keys.split(",")):
        if key not in refs.citations:
            warn(f"unknown citation key {key!r}")
            found.append((key, ""))
        else:
            found.append(refs.citations[key])
    if textual:
        return "; ".join(f"{authors} ({year})" for authors, year in found)
    return "(" + "; ".join(f"{authors}, {year}" for authors, year in found) + ")"


def split_glue(content: str) -> tuple[str, str]:
    """Split the content of ``{glue:text}`` into its name and format, as myst-nb does.

    ``"name:.2f"`` -> ``("name", ".2f")``; ``"name"`` -> ``("name", "")``.
    """
    key, _, spec = content.rpartition(":")
    return (key, spec) if key else (content, "")


def _role(name: str, content: str, refs: References, docname: str, warn: Warn) -> str:
    """Return the Markdown that stands for one role."""
    if name == "glue:md":
        key = split_glue(content)[0]
        if key not in refs.glue_markdown:
            warn(f"no glued Markdown {key!r}")
            return f"`{key}`"
        return refs.glue_markdown[key]
    if name in ("glue", "glue:text", "glue:any"):
        key, spec = split_glue(content)
        if key not in refs.glue:
            warn(f"no glued value {key!r}")
            return f"`{key}`"
        return refs.format_glue(refs.glue[key], spec)
    if name == "glue:math":
        return f"${refs.glue.get(content, content)}$"
    if name == "eq":
        text, label = _split_explicit(content)
        if label not in refs.equations:
            warn(f"unknown equation label {label!r}")
            return text or f"({label})"
        return text or refs.eqref_format.format(number=refs.equations[label])
    if name == "numref":
        text, label = _split_explicit(content)
        if label not in refs.numbered:
            warn(f"unknown numbered label {label!r}")
            return text or label
        number = refs.numbered[label].rsplit(" ", 1)[-1]
        if text:
            return text.replace("%s", number).replace("{number}", number)
        return refs.numbered[label]
    if name == "ref":
        text, label = _split_explicit(content)
        if text:
            return text
        if label not in refs.sections:
            warn(f"unknown reference label {label!r}")
            return label
        return f"*{refs.sections[label]}*"
    if name == "doc":
        text, target = _split_explicit(content)
        target_doc = _docname(target, docname)
        title = refs.documents.get(target_doc)
        if title is None:
            warn(f"unknown document {target!r}")
        number = refs.chapter_numbers.get(target_doc)
        shown = text or f"*{title or target}*"
        return f"{shown} (chapter {number})" if number else shown
    if name in ("term", "abbr"):
        text, target = _split_explicit(content)
        return text or target
    if name == "download":
        text, target = _split_explicit(content)
        shown = text or target.rsplit("/", 1)[-1]
        return f"`{shown}`" if " " not in shown else shown
    if name in ("cite", "cite:p", "cite:ps"):
        return _cite(content, refs, textual=False, warn=warn)
    if name in ("cite:t", "cite:ts"):
        return _cite(content, refs, textual=True, warn=warn)
    if name == "math":
        return f"${content}$"
    if name in ("sub", "sup"):
        return f"<{name}>{content}</{name}>"
    if name in ("kbd", "code", "file", "command", "samp"):
        return f"`{content}`"
    warn(f"role {{{name}}} has no notebook form; its text is kept")
    return content


def _clean_inline(text: str, refs: References, docname: str, warn: Warn) -> str:
    """Replace every role in ``text`` by its Markdown, leaving code spans alone."""

    def replace(match: re.Match[str]) -> str:
        if match["code"]:
            return match["code"]
        return _role(match["role"], match["content"], refs, docname, warn)

    return _INLINE.sub(replace, text)


# --------------------------------------------------------------------------------------
# Blocks: fences, directives, targets, labelled equations
# --------------------------------------------------------------------------------------

_FENCE = re.compile(r"^(?P<indent> {0,3})(?P<fence>`{3,}|~{3,}|:{3,})\s*(?P<info>.*?)\s*$")
_DIRECTIVE = re.compile(r"^\{(?P<name>[\w:.+-]+)\}\s*(?P<argument>.*)$")
_OPTION = re.compile(r"^:(?P<key>[\w-]+):\s*(?P<value>.*)$")
_TARGET = re.compile(r"^\s*\([\w:.+-]+\)=\s*$")
_LABELLED_MATH_END = re.compile(r"^(?P<before>.*?)\$\$\s*\((?P<label>[\w:.+-]+)\)\s*$")
_COMMENT = re.compile(r"^\s*%")

_ADMONITIONS = {
    "note": "Note",
    "tip": "Tip",
    "hint": "Hint",
    "important": "Important",
    "warning": "Warning",
    "caution": "Caution",
    "attention": "Attention",
    "danger": "Danger",
    "error": "Error",
    "seealso": "See also",
    "margin": "",
    "sidebar": "",
    "topic": "",
    "epigraph": "",
    "admonition": "",
}
#: Directives whose content is not shown in a notebook (solutions above all).
_DROPPED = {
    "solution",
    "solution-start",
    "solution-end",
    "toctree",
    "tableofcontents",
    "bibliography",
    "glossary",
}


def _closing(lines: list[str], start: int, fence: str) -> int:
    """Index of the line that closes the fence opened at ``lines[start]`` (or len(lines))."""
    closer = re.compile(rf"^ {{0,3}}{re.escape(fence[0])}{{{len(fence)},}}\s*$")
    for i in range(start + 1, len(lines)):
        if closer.match(lines[i]):
            return i
    return len(lines)


def _options(body: list[str]) -> tuple[dict[str, str], list[str]]:
    """Split a directive's body into its options and its content.

    The options are ``:key: value`` lines or a ``---`` block.
    """
    options: dict[str, str] = {}
    i = 0
    if body and body[0].strip() == "---":
        end = next((j for j in range(1, len(body)) if body[j].strip() == "---"), len(body))
        for line in body[1:end]:
            key, _, value = line.partition(":")
            options[key.strip()] = value.strip()
        i = end + 1
    else:
        while i < len(body) and (match := _OPTION.match(body[i])):
            options[match["key"]] = match["value"]
            i += 1
    return options, body[i:]


def _quote(markdown: str) -> str:
    """``markdown`` as a Markdown block quote."""
    return "\n".join(f"> {line}" if line else ">" for line in markdown.splitlines())


def _directive(
    name: str, argument: str, body: list[str], refs: References, docname: str, warn: Warn
) -> str:
    """Return the Markdown that stands for one directive (empty for a solution)."""
    options, content = _options(body)
    if name in _DROPPED:
        return ""
    inner = clean_markdown("\n".join(content), refs, docname, warn).strip()
    if name == "exercise":
        label = options.get("label", "")
        heading = refs.numbered.get(label)
        if heading is None:
            warn(f"exercise {label!r} has no number")
            heading = "Exercise"
        title = _clean_inline(argument, refs, docname, warn)
        head = f"**{heading}**" + (f" ({title})" if title else "")
        return _quote(f"{head}\n\n{inner}" if inner else head)
    if name in _ADMONITIONS:
        title = _clean_inline(argument, refs, docname, warn) or _ADMONITIONS[name]
        return _quote(f"**{title}**\n\n{inner}" if title else inner)
    if name in ("math", "equation"):
        label = options.get("label")
        tag = f" \\tag{{{refs.equations[label]}}}" if label in refs.equations else ""
        return f"$$\n{inner}{tag}\n$$"
    if name in ("code-block", "code", "sourcecode"):
        return f"```{argument}\n" + "\n".join(content) + "\n```"
    if name in ("figure", "image"):
        alt = options.get("alt", "")
        caption = f"\n\n*{inner}*" if inner else ""
        return f"![{alt}]({argument}){caption}"
    warn(f"directive {{{name}}} has no notebook form; its content is shown as a quote")
    return _quote(inner)


def clean_markdown(text: str, refs: References, docname: str = "", warn: Warn = _ignore) -> str:
    """Return a chapter's cell's Markdown with every MyST role and directive rewritten.

    Solutions are dropped; see the module docstring for the rest.
    """
    lines = text.splitlines()
    out: list[str] = []
    paragraph: list[str] = []

    def flush() -> None:
        if paragraph:
            out.append(_clean_inline("\n".join(paragraph), refs, docname, warn))
            paragraph.clear()

    i = 0
    while i < len(lines):
        line = lines[i]
        fence = _FENCE.match(line)
        if fence:
            flush()
            end = _closing(lines, i, fence["fence"])
            directive = _DIRECTIVE.match(fence["info"])
            if directive:
                out.append(
                    _directive(
                        directive["name"],
                        directive["argument"],
                        lines[i + 1 : end],
                        refs,
                        docname,
                        warn,
                    )
                )
            else:  # a code block: verbatim
                out.extend(lines[i : end + 1])
            i = end + 1
            continue
        if _TARGET.match(line) or _COMMENT.match(line):
            i += 1
            continue
        math_end = _LABELLED_MATH_END.match(line)
        if math_end:
            label = math_end["label"]
            if label in refs.equations:
                line = f"{math_end['before']}\\tag{{{refs.equations[label]}}}\n$$"
            else:
                warn(f"unknown equation label {label!r}")
                line = f"{math_end['before']}$$"
        paragraph.append(line)
        i += 1
    flush()
    cleaned = "\n".join(out)
    return re.sub(r"\n{3,}", "\n\n", cleaned).strip("\n")


# --------------------------------------------------------------------------------------
# Code cells: remove myst_nb.glue
# --------------------------------------------------------------------------------------


def _glue_names(tree: ast.Module) -> set[str]:
    """Names bound to ``myst_nb.glue`` by ``from myst_nb import glue [as name]``."""
    return {
        alias.asname or alias.name
        for node in ast.walk(tree)
        if isinstance(node, ast.ImportFrom) and node.module == "myst_nb"
        for alias in node.names
        if alias.name == "glue"
    }


def _is_docstring(node: ast.stmt) -> bool:
    return (
        isinstance(node, ast.Expr)
        and isinstance(node.value, ast.Constant)
        and isinstance(node.value.value, str)
    )


class _GlueStatements:
    """Decide which statements only feed ``glue``.

    Those are its import, calls of it or of helper functions whose body only calls it, and
    blocks made of nothing else.
    """

    def __init__(self, names: set[str]):
        self.names = set(names)

    def calls_glue(self, node: ast.stmt) -> bool:
        if not (isinstance(node, ast.Expr) and isinstance(node.value, ast.Call)):
            return False
        func = node.value.func
        if isinstance(func, ast.Name):
            return func.id in self.names
        return (
            isinstance(func, ast.Attribute)
            and func.attr == "glue"
            and isinstance(func.value, ast.Name)
            and func.value.id == "myst_nb"
        )

    def only_glue(self, body: list[ast.stmt]) -> bool:
        statements = [s for s in body if not _is_docstring(s)]
        return bool(statements) and all(self.is_glue(s) for s in statements)

    def is_glue(self, node: ast.stmt) -> bool:
        if isinstance(node, ast.ImportFrom) and node.module == "myst_nb":
            return all(alias.name == "glue" for alias in node.names)
        if isinstance(node, ast.Import):
            return all(alias.name == "myst_nb" for alias in node.names)
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            return node.name in self.names
        if isinstance(node, (ast.For, ast.While, ast.If, ast.With)):
            return self.only_glue(node.body) and (
                not getattr(node, "orelse", []) or self.only_glue(node.orelse)
            )
        return self.calls_glue(node)

    def learn_helpers(self, tree: ast.Module) -> bool:
        """Add the functions whose body only calls glue; True if any was new."""
        new = {
            node.name
            for node in tree.body
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))
            and node.name not in self.names
            and self.only_glue(node.body)
        }
        self.names |= new
        return bool(new)


def _first_line(node: ast.stmt) -> int:
    decorators = getattr(node, "decorator_list", [])
    return min([node.lineno, *(d.lineno for d in decorators)])


def _edits(
    body: list[ast.stmt], glue: _GlueStatements, keep_one: bool
) -> list[tuple[int, int, str | None]]:
    """Line ranges (1-based, inclusive) to delete from ``body``.

    A range with text is replaced by that text (``pass`` where a block would otherwise be
    left empty).
    """
    edits: list[tuple[int, int, str | None]] = []
    removed = [s for s in body if glue.is_glue(s)]
    for node in body:
        if node in removed:
            edits.append((_first_line(node), node.end_lineno or node.lineno, None))
            continue
        for attr in ("body", "orelse", "finalbody"):
            block = getattr(node, attr, None)
            if block and isinstance(block, list) and isinstance(block[0], ast.stmt):
                edits += _edits(block, glue, keep_one=True)
        for handler in getattr(node, "handlers", []):
            edits += _edits(handler.body, glue, keep_one=True)
    if keep_one and removed and len(removed) == len(body):
        first = removed[0]
        edits[0] = (edits[0][0], edits[0][1], " " * first.col_offset + "pass")
    return edits


def _parse(source: str) -> ast.Module | None:
    """Parse a code cell, reading IPython's line magics and shell escapes as ``pass``.

    The ``pass`` keeps the line numbers. Return the syntax tree, or None for a cell magic
    (``%%``).
    """
    if source.lstrip().startswith("%%"):
        return None
    return ast.parse(re.sub(r"(?m)^(\s*)[%!].*$", r"\1pass", source))


def strip_glue(sources: list[str]) -> list[str]:
    """Return the code cells ``sources`` without ``myst_nb.glue``.

    Removed are its import, its calls, and the helper functions that only call it. A cell
    left without code becomes ``""``.

    Raises
    ------
    ValueError
        If a cell does not parse after the edit, or still uses a glue name.
    """
    trees = [_parse(source) for source in sources]
    glue = _GlueStatements(set().union(set(), *(_glue_names(t) for t in trees if t)))
    if not glue.names:
        return list(sources)
    while any(glue.learn_helpers(tree) for tree in trees if tree):
        pass
    cleaned = []
    for source, tree in zip(sources, trees, strict=True):
        edits = _edits(tree.body, glue, keep_one=False) if tree else []
        if not edits:
            cleaned.append(source)
            continue
        lines = source.splitlines()
        for start, end, text in sorted(edits, reverse=True):
            lines[start - 1 : end] = [text] if text is not None else []
        result = re.sub(r"\n{3,}", "\n\n", "\n".join(lines)).strip("\n")
        new_tree = _parse(result)
        left = {n.id for n in ast.walk(new_tree) if isinstance(n, ast.Name)} & glue.names
        if left:
            raise ValueError(
                f"a code cell still uses {sorted(left)} after removing glue:\n{result}"
            )
        cleaned.append(result if new_tree.body else "")
    return cleaned


def strip_solution(source: str) -> str:
    """Return ``source`` without the answer key (``from answer_key import solution``).

    Removed are its import and the statements that call what it imported (the book glues the
    exercises' solutions into its pages from hidden cells; a reader's notebook carries none).

    Raises
    ------
    ValueError
        If a statement that is kept still uses the answer key (e.g. inside a function).
    """
    tree = _parse(source)
    if tree is None or ("answer_key" not in source and "solution(" not in source):
        return source
    keys = {"solution"} | {  # the answer key's function, imported in this cell or an earlier one
        a.asname or a.name
        for n in tree.body
        if isinstance(n, ast.ImportFrom) and n.module == "answer_key"
        for a in n.names
    }
    lines = source.splitlines()
    for node in sorted(tree.body, key=lambda n: n.lineno, reverse=True):
        start = (
            node.decorator_list[0].lineno
            if getattr(node, "decorator_list", None)
            else (node.lineno)
        )
        if isinstance(node, ast.ImportFrom) and node.module == "answer_key":
            lines[start - 1 : node.end_lineno] = []
        elif not isinstance(node, ast.FunctionDef | ast.ClassDef) and any(
            isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id in keys
            for n in ast.walk(node)
        ):
            lines[start - 1 : node.end_lineno] = []
    result = re.sub(r"\n{3,}", "\n\n", "\n".join(lines)).strip("\n")
    left = [
        n
        for n in ast.walk(_parse(result) or ast.Module(body=[], type_ignores=[]))
        if isinstance(n, ast.Name) and n.id in keys
    ]
    if left or "answer_key" in result:
        raise ValueError(f"a code cell of a reader's notebook uses the answer key:\n{result}")
    return result


# --------------------------------------------------------------------------------------
# The notebook
# --------------------------------------------------------------------------------------

#: Cell tags that hide a cell's code in the book; the notebook folds it instead.
_FOLDED = {"remove-cell", "remove-input", "hide-input", "hide-cell"}

KERNELSPEC = {"display_name": "Python 3", "language": "python", "name": "python3"}


def _markdown_cell(source: str) -> dict:
    return {"cell_type": "markdown", "metadata": {}, "source": source}


def clean_notebook(
    cells: list[dict], refs: References, docname: str, preface: str = "", warn: Warn = _ignore
) -> dict:
    """Build a clean nbformat-4 notebook (a JSON-ready dict) from a chapter's cells.

    Parameters
    ----------
    cells : the chapter's cells as nbformat dicts (``cell_type``, ``source``, ``metadata``),
        e.g. read with jupytext; outputs are not kept.
    refs : what the book build resolved (numbers, titles, citations, glued values).
    docname : the chapter's docname (``book/mass_functions``), for relative ``{doc}`` links.
    preface : Markdown of a first cell (where the notebook comes from), or ``""``.
    warn : called with a message for anything that has no faithful notebook form.
    """
    code = [c for c in cells if c["cell_type"] == "code"]
    stripped = iter(strip_glue([_text(c["source"]) for c in code]))
    out: list[dict] = [_markdown_cell(preface)] if preface else []
    for cell in cells:
        if cell["cell_type"] == "markdown":
            text = clean_markdown(_text(cell["source"]), refs, docname, warn)
            if text:
                out.append(_markdown_cell(text))
            continue
        if cell["cell_type"] != "code":
            continue
        source = strip_solution(next(stripped))
        if not source:
            continue
        metadata: dict = {}
        if _FOLDED & set(cell.get("metadata", {}).get("tags", [])):
            metadata["jupyter"] = {"source_hidden": True}
        out.append(
            {
                "cell_type": "code",
                "execution_count": None,
                "metadata": metadata,
                "outputs": [],
                "source": source,
            }
        )
        figure = cell.get("metadata", {}).get("mystnb", {}).get("figure", {})
        if figure.get("caption"):
            caption = clean_markdown(str(figure["caption"]).strip(), refs, docname, warn)
            number = refs.numbered.get(figure.get("name", ""), "")
            out.append(_markdown_cell(f"**{number}.** {caption}" if number else caption))
    for index, cell in enumerate(out):
        cell["id"] = f"cell-{index:03d}"
    return {
        "cells": out,
        "metadata": {"kernelspec": dict(KERNELSPEC), "language_info": {"name": "python"}},
        "nbformat": 4,
        "nbformat_minor": 5,
    }


def _text(source: str | list[str]) -> str:
    return source if isinstance(source, str) else "".join(source)
