"""Sphinx extension: the written HTML pages made lighter and accessible.

* **Explorer pictures leave the page.** When the HTML builder has written every page
  (``build-finished``), every PNG that an explorer's precomputed state carries as a
  ``data:`` URL (``dstoolkit.teaching``'s ``image_html``) in the page's widget state is
  written to ``_states/<hash>.png`` in the page's folder, and the state refers to that
  file (idempotent: pages Sphinx did not write again are left as they are). The widget
  manager draws only the state a control selects, so a picture is fetched when it is
  shown, with its ``alt``.
* **Icons from a subset of Font Awesome.** The theme loads all of Font Awesome as a script
  (1.5 MB) to draw a dozen icons. ``_static/scripts/fontawesome.js`` is replaced by a
  script that holds only the icons the pages name (found in the written pages) and draws
  them the same way: each ``<i class="fa-solid fa-...">`` becomes an inline ``<svg>``.
* **Markup that fails WCAG 2.1 AA, written right in the first place**, through Sphinx's
  public extension points: myst-nb's toggles of hidden code and the bibliography's entries
  get visitors of their own (:func:`visit_hidden_cell`, :func:`visit_citation`), and
  every figure is fetched when it comes near the screen (:class:`LazyImages`). The theme's
  own markup is mended by small template overrides in ``book/_templates`` (the search
  button, the colour-mode button, the deferred scripts).
"""

from __future__ import annotations

import hashlib
import json
import re
from base64 import b64decode
from pathlib import Path

from html import escape

from docutils import nodes
from myst_nb.sphinx_ import HideCodeCellNode, depart_HideCellInput
from sphinx.application import Sphinx
from sphinx.transforms.post_transforms import SphinxPostTransform
from sphinx.util import logging
from sphinx.util.docutils import SphinxTranslator

logger = logging.getLogger(__name__)

#: The folder, beside each page, that holds its explorers' pictures.
STATES_DIR = "_states"
_STATE_SCRIPT = re.compile(
    r'(<script type="application/vnd\.jupyter\.widget-state\+json">)(.*?)(</script>)', re.S)
_DATA_PNG = re.compile(r"data:image/png;base64,([A-Za-z0-9+/=]+)")

def externalise_pictures(page: Path, text: str) -> str:
    """Move the ``data:`` PNGs of ``text``'s widget state into files beside ``page``."""
    folder = page.parent / STATES_DIR

    def save(found: re.Match[str]) -> str:
        data = b64decode(found.group(1))
        name = hashlib.sha1(data).hexdigest()[:20] + ".png"
        target = folder / name
        if not target.is_file():
            folder.mkdir(exist_ok=True)
            target.write_bytes(data)
        return f"{STATES_DIR}/{name}"

    def state(found: re.Match[str]) -> str:
        return found.group(1) + _DATA_PNG.sub(save, found.group(2)) + found.group(3)

    return _STATE_SCRIPT.sub(state, text)


#: Font Awesome's bundled icon sets, in the order the theme's bundle defines them.
_FA_PACKS = ("brands", "regular", "solid")
_FA_PREFIX = {"fa-solid": "solid", "fas": "solid", "fa-regular": "regular", "far": "regular",
              "fa-brands": "brands", "fab": "brands"}
_FA_ICON = re.compile(r'(?:"([a-z0-9-]+)"|\b([a-z][a-z0-9]*)):\[(\d+),(\d+),\[[^\]]*\],'
                      r'"[0-9a-f]+",("(?:[^"\\]|\\.)*")\]')
_FA_CLASSES = re.compile(r'class="([^"]*\bfa-[^"]*)"')
_FA_SCRIPT = """/* Font Awesome Free (CC BY 4.0 icons, MIT code; https://fontawesome.com/license/free):
 * only the icons this book's pages use, written by book/_ext/dstoolkit_a11y.py in place of
 * the theme's full bundle. Each <i class="fa-solid fa-NAME"> becomes an inline SVG. */
(function () {
  "use strict";
  var ICONS = %(icons)s;
  var PACKS = %(packs)s;
  var style = document.createElement("style");
  style.textContent = ".svg-inline--fa{display:inline-block;height:1em;overflow:visible;" +
    "vertical-align:-.125em;box-sizing:content-box}.svg-inline--fa.fa-lg{font-size:1.25em;" +
    "line-height:.05em;vertical-align:-.2em}";
  document.head.appendChild(style);
  function draw(icon) {
    var pack = "solid", name = null;
    icon.classList.forEach(function (c) { if (PACKS[c]) pack = PACKS[c]; });
    icon.classList.forEach(function (c) {
      if (!name && ICONS[pack + ":" + c.slice(3)] && c.indexOf("fa-") === 0) name = c;
    });
    if (!name) return;
    var data = ICONS[pack + ":" + name.slice(3)];
    var ns = "http://www.w3.org/2000/svg";
    var svg = document.createElementNS(ns, "svg");
    svg.setAttribute("class", icon.getAttribute("class") + " svg-inline--fa");
    svg.setAttribute("viewBox", "0 0 " + data[0] + " " + data[1]);
    svg.setAttribute("aria-hidden", "true");
    svg.setAttribute("focusable", "false");
    if (icon.getAttribute("style")) svg.setAttribute("style", icon.getAttribute("style"));
    var path = document.createElementNS(ns, "path");
    path.setAttribute("fill", "currentColor");
    path.setAttribute("d", data[2]);
    svg.appendChild(path);
    icon.replaceWith(svg);
  }
  function drawAll(root) {
    root.querySelectorAll("i[class*='fa-'], i.fa, i.fas, i.far, i.fab").forEach(draw);
  }
  function start() {
    drawAll(document);
    new MutationObserver(function () { drawAll(document); })
      .observe(document.body, {childList: true, subtree: true});
  }
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start);
  else start();
})();
"""


def fontawesome_icons(bundle: str) -> dict[str, tuple[int, int, str]]:
    """Every icon of the theme's Font Awesome bundle, as "pack:name" -> (width, height,
    SVG path). The bundle defines the packs as three object literals, one after another."""
    runs: list[list[re.Match[str]]] = []
    last_end = -1
    for found in _FA_ICON.finditer(bundle):
        if runs and bundle[last_end:found.start()] == ",":
            runs[-1].append(found)
        else:
            runs.append([found])
        last_end = found.end()
    runs = [run for run in runs if len(run) > 100]  # the three packs
    icons: dict[str, tuple[int, int, str]] = {}
    for pack, run in zip(_FA_PACKS, runs, strict=False):
        for found in run:
            name = found.group(1) or found.group(2)
            icons.setdefault(f"{pack}:{name}",
                             (int(found.group(3)), int(found.group(4)),
                              json.loads(found.group(5))))
    return icons


def used_icons(pages: list[Path]) -> set[str]:
    """The "pack:name" of every Font Awesome icon the pages name in a class attribute."""
    used: set[str] = set()
    for page in pages:
        for classes in _FA_CLASSES.findall(page.read_text(encoding="utf-8")):
            tokens = classes.split()
            pack = next((_FA_PREFIX[t] for t in tokens if t in _FA_PREFIX), "solid")
            used |= {f"{pack}:{t[3:]}" for t in tokens if t.startswith("fa-")}
    return used


def subset_fontawesome(static: Path, pages: list[Path]) -> int:
    """Replace the theme's Font Awesome bundle in ``static``/scripts by the subset of the
    icons that ``pages`` use; return the number of icons kept (0: nothing to replace)."""
    bundle = static / "scripts" / "fontawesome.js"
    if not bundle.is_file():
        return 0
    text = bundle.read_text(encoding="utf-8")
    if "only the icons this book's pages use" in text:
        return -1  # already the subset (an incremental build)
    icons = fontawesome_icons(text)
    kept = {key: icons[key] for key in sorted(used_icons(pages)) if key in icons}
    packs = json.dumps(_FA_PREFIX)
    bundle.write_text(_FA_SCRIPT % {"icons": json.dumps(kept), "packs": packs},
                      encoding="utf-8")
    for extra in ("fontawesome.js.map", "fontawesome.js.LICENSE.txt"):
        (static / "scripts" / extra).unlink(missing_ok=True)
    return len(kept)


def rewrite(page: Path) -> bool:
    """Move one page's explorer pictures into files; True if it changed."""
    text = page.read_text(encoding="utf-8")
    new = externalise_pictures(page, text)
    if new != text:
        page.write_text(new, encoding="utf-8")
        return True
    return False


def build_finished(app: Sphinx, exception: Exception | None) -> None:
    """Rewrite every HTML page of a successful HTML build."""
    if exception is not None or app.builder.format != "html":
        return
    out = Path(app.outdir)
    pages = [page for page in sorted(out.rglob("*.html")) if "_static" not in page.parts]
    changed = sum(rewrite(page) for page in pages)
    icons = subset_fontawesome(out / "_static", pages)
    logger.info("dstoolkit_a11y: %d pages rewritten; Font Awesome: %s", changed,
                "subset kept" if icons < 0 else f"{icons} icons kept")


def visit_hidden_cell(self: SphinxTranslator, node: HideCodeCellNode) -> None:
    """Open myst-nb's toggle of hidden code, as myst-nb does, named by its visible text.

    myst-nb names the toggle "Toggle hidden content" while it shows "Show code cell
    source" (WCAG 2.5.3 Label in Name): here the ``<summary>`` has no ``aria-label``.
    """
    classes = " ".join(node["classes"])
    self.body.append(f'<details class="admonition hide {classes}">\n<summary>\n')
    self.body.append(f'<p class="collapsed admonition-title">{escape(node["prompt_show"])}</p>\n')
    self.body.append(f'<p class="expanded admonition-title">{escape(node["prompt_hide"])}</p>\n')
    self.body.append("</summary>\n")


def visit_citation(self: SphinxTranslator, node: nodes.citation) -> None:
    """Open a bibliography entry as docutils does, as a ``listitem`` of its ``role="list"``.

    docutils marks each entry with the deprecated DPUB role ``doc-biblioentry`` inside a
    ``role="list"``, whose items must be list items.
    """
    if not isinstance(node.previous_sibling(), type(node)):
        self.body.append('<div role="list" class="citation-list">\n')
    self.body.append(self.starttag(node, "div", classes=[node.tagname], role="listitem"))


def depart_citation(self: SphinxTranslator, node: nodes.citation) -> None:
    """Close a bibliography entry (and the list after its last one), as docutils does."""
    self.body.append("</div>\n")
    if not isinstance(node.next_node(descend=False, siblings=True), type(node)):
        self.body.append("</div>\n")


class LazyImages(SphinxPostTransform):
    """Fetch every figure when it comes near the screen, not with the page.

    docutils writes ``loading="lazy"`` for an image node whose ``loading`` is ``"lazy"``
    (the ``:loading:`` option of the image directive), which this sets on every image.
    """

    default_priority = 800
    formats = ("html",)

    def run(self, **kwargs: object) -> None:
        """Mark every image of the document to load lazily."""
        for image in self.document.findall(nodes.image):
            image.setdefault("loading", "lazy")


def setup(app: Sphinx) -> dict[str, object]:
    """Register the visitors, the lazy images and the post-build step.

    The PDF's figures get their alternate texts from ``dstoolkit_pdf``.
    """
    app.setup_extension("dstoolkit_pdf")
    app.setup_extension("myst_nb")  # its visitors are registered first, then replaced
    app.add_node(HideCodeCellNode, override=True, html=(visit_hidden_cell, depart_HideCellInput))
    app.add_node(nodes.citation, override=True, html=(visit_citation, depart_citation))
    app.add_post_transform(LazyImages)
    # boxes that scroll sideways take the keyboard focus (book/_static/scroll-boxes.js)
    app.add_js_file("scroll-boxes.js", loading_method="defer")
    app.connect("build-finished", build_finished)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
