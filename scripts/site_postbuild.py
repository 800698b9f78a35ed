"""After the book is built: pages that show at once on a phone, figures that open full size.

Run by scripts/build-book.sh after ``jupyter-book build`` (``python scripts/site_postbuild.py
_build/html``), after ``node scripts/typeset-maths.js`` has typeset the maths. Each page of
the built site is rewritten once (it is marked), atomically:

* **Explorers as plain HTML, no widget manager.** Every widget view of a page is written,
  from the widget state the page carries, as the final HTML of the explorer
  (``div.dstoolkit-explorer``, :class:`ExplorerHTML`): a live slider becomes a labelled
  ``<input type="range">`` over the indices of its values, with its readout in an
  ``<output>`` and its ``aria-valuetext`` the readout and its label's unit; a live
  drop-down a ``<select>``; every other control is written disabled and described by the
  explorer's note that says where it works; a stack writes all its states, all but the
  selected one ``hidden``, whose pictures wait in ``data-src``. The widget state, the
  widget views and any widget-manager script leave the page; ``_static/explorers.js``
  (async, added by myst-nb's ``nb_ipywidgets_js``) switches the states.
* **Nothing in the head waits for a script**: Sphinx's helpers and the theme's script are
  deferred (they act once the page is parsed, in the order they are written); the search
  index is left to the search page; Sphinx's page settings (``documentation_options.js``,
  0.3 kB) are written into the page.
* **One small stylesheet**: the page's eleven stylesheets are joined into one file of
  ``_static`` (fewer round trips before the first paint on a slow network); the rules no
  page or script of the site can use are dropped (scripts/purge-styles.js, PurgeCSS), and
  its icon fonts (Font Awesome, 156 kB for the solid one) cut to the icons it draws.
* **Every figure opens full size.** Each picture of the article and of every explorer state
  becomes a link to its file (``a.dstoolkit-fullsize``, named by the picture's text
  alternative), reachable by keyboard; the picture gets its ``width`` and ``height`` (no
  layout shift) and, for explorer pictures, ``--dstoolkit-natural-width``: on a narrow
  screen it is drawn at its own size in a box that scrolls sideways (book/_static/
  dstoolkit.css), so its text stays as large as the page's small print.
"""

from __future__ import annotations

import argparse
import hashlib
import html
import json
import os
import re
import struct
import sys
import tempfile
from pathlib import Path
from typing import Any
from urllib.parse import unquote

MARK = '<meta name="dstoolkit-postbuild" content="explorers as HTML, figures linked">'
_STATE = re.compile(
    r'(<script type="application/vnd\.jupyter\.widget-state\+json">)(.*?)(</script>)', re.S
)
_VIEW = re.compile(
    r'<script type="application/vnd\.jupyter\.widget-view\+json">(.*?)</script>', re.S
)
#: Widget-manager scripts a page may still name (the explorers need none of them).
_WIDGET_SCRIPTS = re.compile(
    r'\s*<script (?:defer(?:="defer")? )?src="[^"]*(?:widgets-mathjax3|jupyter-widgets/embed'
    r'|explorers-a11y|lazy-explorers|require(?:\.min)?)\.js[^"]*"[^>]*></script>'
)
#: Scripts the theme writes into every head that nothing needs before the page is parsed
#: (the search index, 47 kB gzipped, only serves the search page): deferred, in order.
_DEFER = re.compile(
    r'<script src="([^"]*(?:/doctools|/sphinx_highlight|/searchtools|/language_data|searchindex'
    r'|/sphinx-book-theme)\.js[^"]*)"></script>'
)
#: The search index and its code, which only the search page uses (the theme's search box
#: sends the reader there; search as you type is off): left out of every other page.
_SEARCH_ONLY = re.compile(
    r'\s*<script defer src="[^"]*(?:/searchtools|/language_data|searchindex)\.js[^"]*"></script>'
)
#: Sphinx's page settings, which the page's inline scripts extend: written into the page.
_OPTIONS = re.compile(r'<script src="([^"]*documentation_options\.js)[^"]*"></script>')
_STYLESHEET = re.compile(r'<link (?=[^>]*rel="stylesheet")[^>]*href="([^"]+)"[^>]*/>')
_CSS_IMPORT = re.compile(r"""@import\s+(?:url\()?["']?([^"')]+)["']?\)?\s*;""")
_CSS_URL = re.compile(r"""url\(\s*(["']?)([^"')]+)\1\s*\)""")
_IMG = re.compile(r"<img\b[^>]*>")
_ATTR = re.compile(r"""\b([a-z-]+)=(?:"([^"]*)"|'([^']*)')""")
_ARTICLE = re.compile(r'(<article class="bd-article"[^>]*>)(.*?)(</article>)', re.S)


def image_size(path: Path) -> tuple[int, int] | None:
    """Return the pixel size of a PNG (from its header), or None for anything else."""
    try:
        with path.open("rb") as handle:
            head = handle.read(24)
    except OSError:
        return None
    if head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        return None
    width, height = struct.unpack(">II", head[16:24])
    return width, height


def link_image(tag: str, folder: Path, explorer: bool) -> str:
    """Wrap one ``<img>`` in a link to its file, with its size; as it was when not a file."""
    attrs = {
        m.group(1): m.group(2) if m.group(2) is not None else m.group(3)
        for m in _ATTR.finditer(tag)
    }
    src = attrs.get("src", "")
    if not src or src.startswith("data:") or "://" in src:
        return tag
    size = image_size(folder / html.unescape(src).split("?")[0])
    new = tag
    if size and "width=" not in tag:
        extra = f' width="{size[0]}" height="{size[1]}"'
        if explorer:
            extra += f' data-natural-width="{size[0]}"'
        new = new[:-1].rstrip("/").rstrip() + extra + ">"
    if explorer and size:
        new = new.replace(
            "style='max-width:100%;height:auto'",
            f"style='max-width:100%;height:auto;--dstoolkit-natural-width:{size[0]}px'",
        )
    return (
        f'<a class="dstoolkit-fullsize" href="{html.escape(src, quote=True)}" '
        f'title="Open the figure full size">{new}</a>'
    )


def link_article_images(text: str, folder: Path) -> str:
    """Link every picture of the page's article to its file (not those already in a link)."""

    def article(found: re.Match[str]) -> str:
        body = found.group(2)
        out: list[str] = []
        last = 0
        for img in _IMG.finditer(body):
            before = body[last : img.start()]
            out.append(before)
            opened = before.rfind("<a ") > before.rfind("</a>") if "<a " in before else False
            inside_link = opened or _open_link(body, img.start())
            out.append(img.group(0) if inside_link else link_image(img.group(0), folder, False))
            last = img.end()
        out.append(body[last:])
        return found.group(1) + "".join(out) + found.group(3)

    return _ARTICLE.sub(article, text)


def _open_link(body: str, at: int) -> bool:
    """Whether position ``at`` of ``body`` lies inside an ``<a>`` element."""
    return body.rfind("<a ", 0, at) > body.rfind("</a>", 0, at)


def _fmt(value: Any, spec: str | None) -> str:
    try:
        return format(value, spec or "")
    except (TypeError, ValueError):
        return str(value)


#: A unit is written at the end of a label, after a space, in parentheses: "level L (m)",
#: "background noise (dB SPL)"; "m({low})" or "m1([0.30, 1.90])" name a set, not a unit.
_UNIT = re.compile(r"\s\(([^()]+)\)\s*$")
#: The explorer's note that says where its disabled controls work (dstoolkit.teaching).
_NOTE = re.compile(r"""<p class=(["'])dstoolkit-site-note\1""")
_BOXES = {"VBoxModel": "vbox", "HBoxModel": "hbox", "BoxModel": "vbox", "GridBoxModel": "vbox"}
_CHOICES = ("SelectionSliderModel", "DropdownModel", "SelectModel", "RadioButtonsModel")
_NUMBERS = ("FloatSliderModel", "IntSliderModel", "BoundedFloatTextModel", "BoundedIntTextModel")


def unit_of(label: str) -> str:
    """Return the unit a control's label ends with ("level L (m)" -> "m"), or ""."""
    found = _UNIT.search(" ".join(label.split()))
    return found.group(1) if found else ""


def value_text(shown: str, label: str) -> str:
    """Return a control's value as read out: its readout and its label's unit ("9.6 m")."""
    unit = unit_of(label)
    return f"{shown} {unit}" if unit else shown


def _ref(value: Any) -> str:
    return str(value).removeprefix("IPY_MODEL_")


def _attr(value: Any) -> str:
    return html.escape(str(value), quote=True)


class ExplorerHTML:
    """Writes the widget views of one page as plain HTML with native controls.

    ``models`` is the page's widget state (model id -> model). A control whose ``index`` a
    ``jslink`` (LinkModel) ties to stacks' ``selected_index`` is live: a slider over its
    options becomes an ``<input type="range">`` over their indices, a drop-down a
    ``<select>``, each with ``data-switches`` naming the stacks it switches (explorers.js).
    Every other control is written disabled and described by its explorer's note. A stack
    writes all its children, all but the selected one ``hidden``, with their pictures'
    ``src`` kept in ``data-src`` (fetched when the state is shown).
    """

    def __init__(self, models: dict[str, Any], folder: Path) -> None:
        self.models = models
        self.folder = folder
        self.count = 0
        self.switches: dict[str, list[str]] = {}
        for model in models.values():
            state = model.get("state", {})
            if model.get("model_name") != "LinkModel":
                continue
            source, target = state.get("source") or [], state.get("target") or []
            if (
                len(source) == 2
                and len(target) == 2
                and (source[1], target[1])
                == (
                    "index",
                    "selected_index",
                )
            ):
                self.switches.setdefault(_ref(source[0]), []).append(_ref(target[0]))

    def _id(self, prefix: str) -> str:
        self.count += 1
        return f"dstoolkit-{prefix}-{self.count}"

    def _layout(self, state: dict[str, Any]) -> dict[str, Any]:
        layout = self.models.get(_ref(state.get("layout", "")), {}).get("state", {})
        return layout if isinstance(layout, dict) else {}

    def _style(self, state: dict[str, Any]) -> str:
        layout = self._layout(state)
        css = []
        for key in ("width", "min_height", "flex_flow"):
            if layout.get(key):
                css.append(f"{key.replace('_', '-')}:{layout[key]}")
        return f' style="{_attr(";".join(css))}"' if css else ""

    def view(self, model_id: str) -> str:
        """Return the HTML of the widget view whose root is ``model_id`` ("" if none)."""
        self.note = ""
        self.has_note = self._find_note(model_id, set())
        self.live_region = self._has_class(model_id, "dstoolkit-announce", set())
        body = self.render(model_id, top=True)
        if not body:
            return ""
        return f'<div class="dstoolkit-explorer widget-subarea">{body}</div>'

    def _children(self, model_id: str) -> list[str]:
        state = self.models.get(model_id, {}).get("state", {})
        return [_ref(c) for c in state.get("children", []) or []]

    def _find_note(self, model_id: str, seen: set[str]) -> bool:
        if model_id in seen:
            return False
        seen.add(model_id)
        value = self.models.get(model_id, {}).get("state", {}).get("value")
        if isinstance(value, str) and _NOTE.search(value):
            return True
        return any(self._find_note(c, seen) for c in self._children(model_id))

    def _has_class(self, model_id: str, name: str, seen: set[str]) -> bool:
        if model_id in seen:
            return False
        seen.add(model_id)
        if name in (self.models.get(model_id, {}).get("state", {}).get("_dom_classes") or []):
            return True
        return any(self._has_class(c, name, seen) for c in self._children(model_id))

    def _note_id(self) -> str:
        if not self.note and self.has_note:
            self.note = self._id("note")
        return self.note

    def render(self, model_id: str, top: bool = False, hidden: bool = False) -> str:
        """Return the HTML of one model and its children."""
        model = self.models.get(model_id)
        if model is None:
            return ""
        name = model.get("model_name", "")
        state = model.get("state", {})
        layout = self._layout(state)
        if layout.get("display") == "none" or layout.get("visibility") == "hidden":
            return ""
        classes = [c for c in state.get("_dom_classes") or [] if re.fullmatch(r"[\w-]+", c)]
        if name in _BOXES:
            inner = "".join(self.render(c, hidden=hidden) for c in self._children(model_id))
            kind = _BOXES[name]
            cls = " ".join([f"dstoolkit-{kind}", *classes])
            return f'<div class="{cls}"{self._style(state)}>{inner}</div>'
        if name == "StackModel":
            return self._stack(model_id, state, classes, hidden)
        if name in ("HTMLModel", "HTMLMathModel"):
            return self._html(str(state.get("value", "")), classes, hidden)
        if name == "LabelModel":
            return f"<p>{html.escape(str(state.get('value', '')))}</p>"
        if name == "OutputModel":
            return self._output(state)
        if name in _CHOICES or name in _NUMBERS:
            return self._control(model_id, name, state)
        if name in ("CheckboxModel", "ToggleButtonModel"):
            return self._checkbox(state)
        if name == "ButtonModel":
            return self._button(state)
        return ""

    def _stack(self, model_id: str, state: dict[str, Any], classes: list[str], hidden: bool) -> str:
        children = self._children(model_id)
        index = state.get("selected_index")
        parts = []
        for i, child in enumerate(children):
            shown = i == index
            body = self.render(child, hidden=hidden or not shown)
            parts.append(f'<div class="dstoolkit-state"{"" if shown else " hidden"}>{body}</div>')
        cls = " ".join(["dstoolkit-stack", *classes])
        # a stack switched by a control of an explorer that has no sentence region of its own
        # is itself a polite live region (its shown state is what changed)
        live = ""
        if not self.live_region and not hidden and "dstoolkit-states" not in classes:
            live = ' aria-live="polite"'
        return (
            f'<div class="{cls}" data-stack="{_attr(model_id)}"{live}{self._style(state)}>'
            f"{''.join(parts)}</div>"
        )

    def _html(self, value: str, classes: list[str], hidden: bool) -> str:
        if "dstoolkit-announce" in classes:
            return (
                '<div class="dstoolkit-announce" role="status" aria-live="polite" '
                'aria-atomic="true"></div>'
            )
        value = _IMG.sub(lambda m: self._image(m.group(0), hidden), value)
        if self.has_note and _NOTE.search(value):
            value = _NOTE.sub(lambda m: f'{m.group(0)} id="{self._note_id()}"', value, count=1)
        cls = " ".join(["dstoolkit-html", "widget-html-content", *classes])
        return f'<div class="{cls}">{value}</div>'

    def _image(self, tag: str, hidden: bool) -> str:
        """Link one picture to its file; in a hidden state its ``src`` waits in data-src.

        The picture of the state shown is fetched with the page (a slider's first answer
        needs it); those of the other states when explorers.js shows them.
        """
        linked = link_image(tag, self.folder, "dstoolkit-figure" in tag)
        img = _IMG.search(linked)
        assert img is not None
        new = img.group(0)
        if hidden:  # fetched when its state is shown; the shown state's picture at once
            new = re.sub(r"""\bsrc=(["'])""", r"data-src=\1", new, count=1)
            if "loading=" not in new:
                new = new[:-1].rstrip("/").rstrip() + ' loading="lazy">'
        return linked[: img.start()] + new + linked[img.end() :]

    def _output(self, state: dict[str, Any]) -> str:
        parts = []
        for output in state.get("outputs") or []:
            data = output.get("data") or {}
            if output.get("output_type") == "stream":
                text = "".join(output.get("text") or "")
                parts.append(f"<pre>{html.escape(text)}</pre>")
            elif "text/html" in data:
                parts.append("".join(data["text/html"]))
            elif "image/png" in data:
                alt = "".join(data.get("text/plain") or "")
                png = "".join(data["image/png"]).replace("\n", "")
                parts.append(f'<img src="data:image/png;base64,{png}" alt="{_attr(alt)}">')
            elif "text/plain" in data:
                parts.append(f"<pre>{html.escape(''.join(data['text/plain']))}</pre>")
        if not parts:
            return ""
        return f'<div class="dstoolkit-output">{"".join(parts)}</div>'

    def _label(self, state: dict[str, Any], for_id: str, label_id: str) -> str:
        description = str(state.get("description", ""))
        style = self.models.get(_ref(state.get("style", "")), {}).get("state", {})
        width = style.get("description_width") if isinstance(style, dict) else ""
        css = f' style="width:{_attr(width)}"' if width and width != "initial" else ""
        if width == "":
            css = ' style="width:var(--dstoolkit-label-width)"'
        return (
            f'<label class="dstoolkit-label" for="{for_id}" id="{label_id}"{css}>'
            f"{html.escape(description)}</label>"
        )

    def _disabled(self, live: bool) -> str:
        if live:
            return ""
        note = self._note_id()
        described = f' aria-describedby="{note}"' if note else ""
        return f' disabled aria-disabled="true"{described}'

    def _control(self, model_id: str, name: str, state: dict[str, Any]) -> str:
        stacks = self.switches.get(model_id, [])
        live = bool(stacks) and not state.get("disabled")
        control, label = self._id("control"), ""
        label_id = f"{control}-label"
        label = self._label(state, control, label_id)
        description = str(state.get("description", ""))
        switches = f' data-switches="{_attr(" ".join(stacks))}"' if live else ""
        disabled = self._disabled(live)
        if name in _CHOICES:
            options = [str(o) for o in state.get("_options_labels") or []]
            index = state.get("index") or 0
            index = index if isinstance(index, int) and 0 <= index < len(options) else 0
            shown = options[index] if options else ""
            if name == "SelectionSliderModel":
                last = max(len(options) - 1, 0)
                said = _attr(value_text(shown, description))
                field = (
                    f'<input type="range" id="{control}" min="0" max="{last}" step="1" '
                    f'value="{index}" aria-valuetext="{said}"'
                    f' data-labels="{_attr(json.dumps(options, ensure_ascii=False))}"'
                    f' data-unit="{_attr(unit_of(description))}" data-index="{index}"'
                    f"{switches}{disabled}>"
                )
                return self._slider(state, label, field, control, label_id, shown)
            items = "".join(
                f'<option value="{i}"{" selected" if i == index else ""}>{html.escape(o)}</option>'
                for i, o in enumerate(options)
            )
            return (
                f'<div class="dstoolkit-control dstoolkit-dropdown"{self._style(state)}>{label}'
                f'<select id="{control}" data-index="{index}"{switches}{disabled}>{items}'
                "</select></div>"
            )
        value = state.get("value", 0)
        integer = name.startswith(("Int", "BoundedInt"))
        spec = state.get("readout_format") or ("d" if integer else ".2f")
        shown = _fmt(value, spec)
        field = (
            f'<input type="range" id="{control}" min="{_attr(state.get("min", 0))}" '
            f'max="{_attr(state.get("max", 100))}" step="{_attr(state.get("step", 1) or "any")}" '
            f'value="{_attr(value)}" aria-valuetext="{_attr(value_text(shown, description))}"'
            f"{disabled}>"
        )
        return self._slider(state, label, field, control, label_id, shown)

    def _slider(
        self, state: dict[str, Any], label: str, field: str, control: str, label_id: str, shown: str
    ) -> str:
        readout = ""
        if state.get("readout", True):
            readout = (
                f'<output class="dstoolkit-readout" for="{control}" aria-labelledby="{label_id}">'
                f"{html.escape(shown)}</output>"
            )
        return (
            f'<div class="dstoolkit-control dstoolkit-slider"{self._style(state)}>'
            f"{label}{field}{readout}</div>"
        )

    def _checkbox(self, state: dict[str, Any]) -> str:
        control = self._id("control")
        checked = " checked" if state.get("value") else ""
        description = html.escape(str(state.get("description", "")))
        return (
            f'<div class="dstoolkit-control dstoolkit-checkbox"{self._style(state)}>'
            f'<input type="checkbox" id="{control}"{checked}{self._disabled(False)}>'
            f'<label for="{control}">{description}</label></div>'
        )

    def _button(self, state: dict[str, Any]) -> str:
        description = html.escape(str(state.get("description", "")))
        tooltip = state.get("tooltip")
        title = f' title="{_attr(tooltip)}"' if tooltip else ""
        kind = state.get("button_style") or ""
        cls = " ".join(["dstoolkit-button", *([f"dstoolkit-button-{kind}"] if kind else [])])
        return (
            f'<button type="button" class="{cls}"{title}{self._style(state)}'
            f"{self._disabled(False)}>{description}</button>"
        )


def css_for_bundle(css: Path, static: Path, seen: set[Path] | None = None) -> str:
    """Return a stylesheet as read from ``static``: imports inlined, URLs re-based."""
    seen = set() if seen is None else seen
    if css in seen:
        return ""
    seen.add(css)
    text = css.read_text(encoding="utf-8")

    def rebase(found: re.Match[str]) -> str:
        quote, url = found.group(1), found.group(2)
        if url.startswith(("data:", "#", "/")) or "://" in url:
            return found.group(0)
        target = os.path.normpath(os.path.join(css.parent, url.split("?")[0].split("#")[0]))
        rest = url[len(url.split("?")[0].split("#")[0]) :]
        return f"url({quote}{Path(os.path.relpath(target, static)).as_posix()}{rest}{quote})"

    # an import's URL is resolved against this file, not re-based: imports go in last
    parts = _CSS_IMPORT.split(text.replace('@charset "UTF-8";', ""))
    out = []
    for i, part in enumerate(parts):
        if i % 2:
            out.append(css_for_bundle((css.parent / part).resolve(), static, seen))
        else:
            out.append(_CSS_URL.sub(rebase, part))
    return "".join(out)


def bundle_styles(page: Path, text: str, site: Path) -> str:
    """Put the page's stylesheets into one file of _static (one request instead of ten).

    The files are joined in the page's order (the cascade is the same), their imports
    inlined and their URLs re-based; the file is named by its content's hash.
    """
    links = list(_STYLESHEET.finditer(text))
    if len(links) < 2:
        return text
    static = (site / "_static").resolve()
    files = [(page.parent / unquote(m.group(1).split("?")[0])).resolve() for m in links]
    if not all(f.is_file() and f.is_relative_to(static) for f in files):
        return text
    seen: set[Path] = set()
    body = "\n".join(css_for_bundle(f, static, seen) for f in files)
    name = "styles-" + hashlib.sha1(body.encode("utf-8")).hexdigest()[:16] + ".css"
    target = static / name
    if not target.is_file():
        write_atomic(target, body)
    href = Path(os.path.relpath(target, page.parent.resolve())).as_posix()
    first, rest = links[0], links[1:]
    for link in reversed(rest):
        text = text[: link.start()] + text[link.end() :]
    return (
        text[: first.start()]
        + f'<link rel="stylesheet" type="text/css" href="{href}" />'
        + text[first.end() :]
    )


#: The stylesheet bundle_styles writes, as a page links it.
_BUNDLE_LINK = re.compile(
    r'(<link rel="stylesheet" type="text/css" href=")([^"]*)'
    r'(styles-[0-9a-f]{16}\.css)(" />)'
)
#: The first line of a stylesheet slim_styles wrote (it is not purged twice).
SLIM = (
    "/* dstoolkit: the rules no page of the site uses are left out (scripts/purge-styles.js) */\n"
)
PURGE_SCRIPT = Path(__file__).resolve().parent / "purge-styles.js"
_FONT_FACE = re.compile(r"@font-face\s*\{[^{}]*\}")
_ICON_FAMILY = re.compile(r"font-family:[^;}]*Font\s*\\?\s*Awesome", re.I)
_TRUETYPE = re.compile(r"""url\(\s*["']?([^"')]+\.ttf)["']?\s*\)""")
_SRC = re.compile(r"src:[^;}]*")
#: A declaration that can hold an icon: ``content`` or a custom property (``--pst-icon-x``).
_ICON_VALUE = re.compile(r"(?:\bcontent|--[\w-]+)\s*:([^;}]*)")
_CSS_STRING = re.compile(r'"((?:[^"\\]|\\.)*)"' + r"|'((?:[^'\\]|\\.)*)'")
_CSS_ESCAPE = re.compile(r"\\(?:([0-9a-fA-F]{1,6})\s?|(.))", re.S)


def css_string(body: str) -> str:
    """Return the text a CSS string literal's body stands for (its escapes decoded)."""

    def one(found: re.Match[str]) -> str:
        if found.group(1):
            code = int(found.group(1), 16)
            return chr(code) if 0 < code <= 0x10FFFF else "\ufffd"
        return "" if found.group(2) == "\n" else found.group(2)

    return _CSS_ESCAPE.sub(one, body)


def icon_codepoints(css: str) -> set[int]:
    """Return the characters a stylesheet can draw from an icon font.

    Those of the strings in its ``content`` declarations and custom properties (an icon
    font draws nothing else: its glyphs are reached through ``::before``/``::after``).
    """
    points: set[int] = set()
    for value in _ICON_VALUE.finditer(css):
        for found in _CSS_STRING.finditer(value.group(1)):
            text = css_string(found.group(1) if found.group(1) is not None else found.group(2))
            points.update(ord(c) for c in text if ord(c) > 0x20)
    return points


def subset_font(source: Path, codepoints: set[int]) -> bytes:
    """Return the WOFF font of ``source`` (TrueType) with only the glyphs of ``codepoints``."""
    import io

    # fontTools comes with matplotlib
    from fontTools import subset  # type: ignore[import-untyped]
    from fontTools.ttLib import TTFont  # type: ignore[import-untyped]

    options = subset.Options()
    options.flavor = "woff"  # zlib: WOFF 2 would need brotli
    options.layout_features = ["*"]
    options.name_IDs = ["*"]
    options.notdef_outline = True
    font = TTFont(source, recalcTimestamp=False)  # the same bytes from the same font
    subsetter = subset.Subsetter(options)
    subsetter.populate(unicodes=sorted(codepoints))
    subsetter.subset(font)
    out = io.BytesIO()
    font.flavor = "woff"
    font.save(out)
    return out.getvalue()


def subset_icon_fonts(css: str, static: Path) -> str:
    """Serve the icon fonts of a stylesheet (Font Awesome) with only the glyphs it uses.

    Font Awesome's solid font is 156 kB as WOFF 2 for the dozen icons the site's
    stylesheet draws (admonitions, drop-downs, the theme's buttons before their SVG is
    written). Each of its ``@font-face`` rules is pointed at a WOFF file of its TrueType
    font cut down to the characters of the stylesheet's ``content`` strings and custom
    properties, named by its content's hash, beside the original.
    """
    points = icon_codepoints(css)

    def face(found: re.Match[str]) -> str:
        rule = found.group(0)
        ttf = _TRUETYPE.search(rule)
        if not _ICON_FAMILY.search(rule) or not ttf:
            return rule
        source = (static / unquote(ttf.group(1))).resolve()
        if not source.is_file() or not source.is_relative_to(static.resolve()):
            return rule
        data = subset_font(source, points)
        name = f"{source.stem}-{hashlib.sha1(data).hexdigest()[:16]}.woff"
        target = source.with_name(name)
        if not target.is_file():
            write_bytes_atomic(target, data)
        url = Path(os.path.relpath(target, static.resolve())).as_posix()
        return _SRC.sub(lambda _: f'src:url({url}) format("woff")', rule, count=1)

    return _FONT_FACE.sub(face, css)


def purge_css(stylesheet: Path, content: list[Path]) -> str:
    """Return ``stylesheet`` without the rules nothing in ``content`` can match (PurgeCSS)."""
    import subprocess

    try:
        done = subprocess.run(
            ["node", str(PURGE_SCRIPT), str(stylesheet), *map(str, content)],
            capture_output=True,
            text=True,
            check=False,
        )
    except FileNotFoundError as error:
        raise SystemExit(
            "site_postbuild.py: 'node' is not on PATH; it runs scripts/purge-styles.js "
            "(install Node.js 18 or newer, then `npm ci` for PurgeCSS)."
        ) from error
    if done.returncode != 0 or not done.stdout.strip():
        raise SystemExit(
            f"site_postbuild.py: scripts/purge-styles.js failed on {stylesheet} "
            f"(exit {done.returncode}); run `npm ci` (PurgeCSS is a devDependency).\n" + done.stderr
        )
    return done.stdout


def relink(page: Path, old: str, new: str) -> None:
    """Make ``page`` link the stylesheet ``new`` of _static where it linked ``old``."""

    def one(found: re.Match[str]) -> str:
        if found.group(3) != old:
            return found.group(0)
        return found.group(1) + found.group(2) + new + found.group(4)

    write_atomic(page, _BUNDLE_LINK.sub(one, page.read_text(encoding="utf-8")))


def slim_styles(site: Path, pages: list[Path]) -> int:
    """Cut the pages' joined stylesheet down to what the site uses; return how many were.

    Every stylesheet bundle_styles wrote is purged against every page of the site and the
    site's own scripts (scripts/purge-styles.js), its icon fonts cut to the icons it
    draws, and written under its new content's hash; the pages link the new file and the
    old one is removed. A stylesheet already slim is left as it is.
    """
    static = site / "_static"
    users: dict[Path, list[Path]] = {}
    for page in pages:
        for link in _BUNDLE_LINK.finditer(page.read_text(encoding="utf-8")):
            target = (page.parent / link.group(2) / link.group(3)).resolve()
            users.setdefault(target, []).append(page)
    scripts = sorted(static.glob("*.js")) + sorted((static / "scripts").glob("*.js"))
    slimmed = 0
    for bundle, linked in sorted(users.items()):
        if not bundle.is_file() or bundle.read_text(encoding="utf-8").startswith(SLIM):
            continue
        css = SLIM + subset_icon_fonts(purge_css(bundle, pages + scripts), static)
        name = "styles-" + hashlib.sha1(css.encode("utf-8")).hexdigest()[:16] + ".css"
        write_atomic(static / name, css)
        for page in linked:
            relink(page, bundle.name, name)
        if name != bundle.name:
            bundle.unlink()
        slimmed += 1
    return slimmed


def render_explorers(page: Path, text: str, site: Path) -> str:
    """Write every widget view of a page as plain HTML; drop the widget state and scripts."""
    found = _STATE.search(text)
    if not found:
        return text
    renderer = ExplorerHTML(json.loads(found.group(2))["state"], page.parent)

    def view(match: re.Match[str]) -> str:
        return renderer.view(json.loads(match.group(1)).get("model_id", ""))

    text = text[: found.start()] + text[found.end() :]
    text = _VIEW.sub(view, text)
    text = _WIDGET_SCRIPTS.sub("", text)
    if "explorers.js" not in text:
        static = Path(os.path.relpath(site / "_static", page.parent)).as_posix()
        text = text.replace(
            "</head>", f'<script async src="{static}/explorers.js"></script>\n</head>', 1
        )
    return text


def rewrite_page(page: Path, site: Path) -> bool:
    """Rewrite one built page (once); True if it changed."""
    text = page.read_text(encoding="utf-8")
    if MARK in text or "</head>" not in text:
        return False
    folder = page.parent
    text = render_explorers(page, text, site)
    text = _DEFER.sub(r'<script defer src="\1"></script>', text)
    if page.name != "search.html":
        text = _SEARCH_ONLY.sub("", text)
    options = _OPTIONS.search(text)
    if options:
        code = (folder / options.group(1)).read_text(encoding="utf-8").replace("</", "<\\/")
        text = text[: options.start()] + f"<script>{code}</script>" + text[options.end() :]
    text = link_article_images(text, folder)
    text = bundle_styles(page, text, site)
    text = text.replace("</head>", MARK + "\n</head>", 1)
    write_atomic(page, text)
    return True


def write_atomic(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file in the same folder."""
    handle, tmp = tempfile.mkstemp(dir=path.parent, prefix=".postbuild-", suffix=path.suffix)
    try:
        with os.fdopen(handle, "w", encoding="utf-8") as out:
            out.write(text)
        os.chmod(tmp, 0o644)  # mkstemp makes the file private; a web server must read it
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def write_bytes_atomic(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same folder."""
    handle, tmp = tempfile.mkstemp(dir=path.parent, prefix=".postbuild-", suffix=path.suffix)
    try:
        with os.fdopen(handle, "wb") as out:
            out.write(data)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def main(argv: list[str] | None = None) -> int:
    """Rewrite every page of the built site given on the command line."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("html", type=Path, help="the built site (_build/html)")
    args = parser.parse_args(argv)
    if not (args.html / "index.html").is_file():
        print(
            f"site_postbuild.py: {args.html} has no index.html; build the book first",
            file=sys.stderr,
        )
        return 2
    pages = [
        p
        for p in sorted(args.html.rglob("*.html"))
        if not any(part.startswith("_") for part in p.relative_to(args.html).parts)
        and p.relative_to(args.html).parts[0] != "slides"  # the lecture decks: reveal.js pages
    ]
    changed = sum(rewrite_page(page, args.html) for page in pages)
    slimmed = slim_styles(args.html, pages)
    print(
        f"site_postbuild: {changed} of {len(pages)} pages rewritten, {slimmed} stylesheet(s) purged"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
