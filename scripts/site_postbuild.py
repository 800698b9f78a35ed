"""After the book is built: pages that show at once on a phone, figures that open full size.

Run by scripts/build-book.sh after ``jupyter-book build`` (``python scripts/site_postbuild.py
_build/html``), after ``node scripts/typeset-maths.js`` has typeset the maths. Each page of
the built site is rewritten once (it is marked), atomically:

* **Explorers drawn before any script runs.** Before every widget view of a page, the view's
  first state (its readouts, its pictures and its notes, from the widget state the page
  carries) is written as plain HTML (``div.dstoolkit-preview``): the reader sees it at once,
  and it stays until the widget manager has drawn the live explorer over it.
* **Widget code loaded when an explorer comes near the screen.** The widget manager
  (``jupyter-widgets/embed.js``) and its MathJax shim leave the page's ``<head>``;
  ``_static/lazy-explorers.js`` loads them, in order, when the first explorer comes within
  a screen of the viewport (an ``IntersectionObserver``), or when the reader moves to it by
  keyboard. ``explorers-a11y.js`` stays as it is (deferred, small).
* **Nothing in the head waits for a script**: Sphinx's helpers and the theme's script are
  deferred (they act once the page is parsed, in the order they are written); the search
  index is left to the search page; Sphinx's page settings (``documentation_options.js``,
  0.3 kB) are written into the page.
* **One stylesheet**: the page's eleven stylesheets are joined into one file of ``_static``
  (fewer round trips before the first paint on a slow network).
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

MARK = '<meta name="dstoolkit-postbuild" content="explorers deferred, figures linked">'
_STATE = re.compile(
    r'(<script type="application/vnd\.jupyter\.widget-state\+json">)(.*?)(</script>)', re.S
)
_VIEW = re.compile(
    r'<script type="application/vnd\.jupyter\.widget-view\+json">(.*?)</script>', re.S
)
#: The widget scripts myst-nb writes into the head, loaded later by lazy-explorers.js.
_LAZY = re.compile(
    r'\s*<script (?:defer="defer" )?src="([^"]*(?:widgets-mathjax3|jupyter-widgets/embed)'
    r'\.js[^"]*)"></script>'
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


def link_state_images(state: dict[str, Any], folder: Path) -> None:
    """Link the pictures of every HTML widget of a widget state to their files."""
    for model in state["state"].values():
        values = model.get("state", {})
        value = values.get("value")
        if model.get("model_name") == "HTMLModel" and isinstance(value, str) and "<img" in value:
            values["value"] = _IMG.sub(
                lambda m: link_image(m.group(0), folder, "dstoolkit-figure" in m.group(0)),
                value,
            )


def _fmt(value: Any, spec: str | None) -> str:
    try:
        return format(value, spec or "")
    except (TypeError, ValueError):
        return str(value)


def preview(models: dict[str, Any], model_id: str) -> str:
    """Return the plain HTML of a widget view's first state: its texts and pictures, in order."""
    model = models.get(model_id)
    if model is None:
        return ""
    name = model["model_name"]
    state = model["state"]

    def ref(value: str) -> str:
        return value.removeprefix("IPY_MODEL_")

    layout = models.get(ref(state.get("layout", "")), {}).get("state", {})
    if layout.get("display") == "none" or layout.get("visibility") == "hidden":
        return ""
    if name in ("VBoxModel", "HBoxModel", "BoxModel", "GridBoxModel"):
        kind = "hbox" if name == "HBoxModel" else "vbox"
        inner = "".join(preview(models, ref(c)) for c in state.get("children", []))
        return f'<div class="dstoolkit-preview-{kind}">{inner}</div>'
    if name == "StackModel":
        children = state.get("children", [])
        index = state.get("selected_index")
        return preview(models, ref(children[index])) if index is not None and children else ""
    if name in ("HTMLModel", "HTMLMathModel"):
        value = state.get("value", "")
        return f'<div class="dstoolkit-preview-html widget-html-content">{value}</div>'
    if name == "LabelModel":
        return f"<p>{html.escape(str(state.get('value', '')))}</p>"
    description = html.escape(str(state.get("description", "")))
    if name in ("SelectionSliderModel", "DropdownModel", "SelectModel", "RadioButtonsModel"):
        labels = state.get("_options_labels", [])
        index = state.get("index")
        shown = labels[index] if isinstance(index, int) and index < len(labels) else ""
    elif name in ("FloatSliderModel", "IntSliderModel", "BoundedFloatTextModel"):
        shown = _fmt(state.get("value"), state.get("readout_format"))
    elif name == "CheckboxModel":
        shown = "on" if state.get("value") else "off"
    elif name == "ButtonModel":
        return ""
    else:
        return ""
    return (
        f'<p class="dstoolkit-preview-control">{description} <b>{html.escape(str(shown))}</b></p>'
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


def rewrite_page(page: Path, site: Path) -> bool:
    """Rewrite one built page (once); True if it changed."""
    text = page.read_text(encoding="utf-8")
    if MARK in text or "</head>" not in text:
        return False
    folder = page.parent
    found = _STATE.search(text)
    if found:
        state = json.loads(found.group(2))
        link_state_images(state, folder)
        dumped = json.dumps(state, ensure_ascii=False).replace("</", "<\\/")
        text = text[: found.start(2)] + dumped + text[found.end(2) :]
        models = state["state"]

        def with_preview(view: re.Match[str]) -> str:
            model_id = json.loads(view.group(1)).get("model_id", "")
            body = preview(models, model_id)
            if not body:
                return view.group(0)
            return (
                f'<div class="dstoolkit-preview" data-model-id="{html.escape(model_id)}">'
                f"{body}<p class='dstoolkit-preview-note'>The controls load when the explorer "
                f"comes into view.</p></div>{view.group(0)}"
            )

        text = _VIEW.sub(with_preview, text)
        lazy = _LAZY.findall(text)
        if lazy:
            text = _LAZY.sub("", text)
            static = lazy[0].split("_static/")[0] + "_static/"
            scripts = html.escape(" ".join(lazy), quote=True)
            text = text.replace(
                "</head>",
                f'<script defer src="{static}lazy-explorers.js" '
                f'data-scripts="{scripts}"></script>\n</head>',
                1,
            )
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
    print(f"site_postbuild: {changed} of {len(pages)} pages rewritten")
    return 0


if __name__ == "__main__":
    sys.exit(main())
