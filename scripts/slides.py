"""Write a reveal.js lecture deck for every numbered chapter into the built site.

    .venv/bin/python scripts/slides.py                  # every chapter → _build/html/slides/
    .venv/bin/python scripts/slides.py --edit STEM      # slides/STEM.md, to edit by hand

scripts/build-book.sh runs it after jupyter-book: it reads each chapter's source and its
built page, so the numbers, figures and links are the book's. For the chapter ``STEM`` of
_toc.yml (numbered parts, counted as the book counts them) it writes

* ``slides/STEM.md``: the deck's source in reveal.js's Markdown format (slides separated by
  a line ``---``, speaker notes after a line ``Note:``, maths as ``$…$`` and ``$$…$$``);
* ``slides/STEM.html``: the deck, built from that source, with reveal.js, its speaker-notes
  and maths plugins and MathJax from the site's own ``_static/`` (no network).

A deck holds, in the chapter's order:

1. a title slide;
2. the chapter's key equations: every labelled display formula of the source (a
   ``$$ … $$ (label)`` block or a ``{math}`` block with ``:label:``) outside exercises,
   with the book's equation number; formulas next to each other in one section share a
   slide (at most two);
3. the chapter's figures: every numbered figure of the built page outside exercises, with
   its alt text and caption;
4. "In class": the chapter's explorer and its "predict first" exercise, linked to the page;
5. the chapter's "Key points".

Speaker notes hold the text that leads to each formula and the slide's time, ``Time: N
min``; the minutes sum to the chapter's class hours on the teaching page (the table
``CHAPTERS`` of book/teaching.md), or to one 90-minute session for a chapter missing there.
The title slide takes 2 minutes, the key points 5, "In class" a fifth of the rest and the
formula and figure slides share what is left. The deck's ``data-timing`` comes from these
lines, so the speaker view (key S) paces the lecture.

A lecturer edits a deck by putting its source in the repository's ``slides/`` folder:
``--edit STEM`` copies the generated source there (it refuses to replace an edited one
unless ``--force``); from then on the book build uses that file instead of generating one.
Deleting it goes back to the generated deck.
"""

from __future__ import annotations

import argparse
import ast
import html
import math
import re
import sys
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

import yaml
from bs4 import BeautifulSoup, NavigableString, Tag
from markdown_it import MarkdownIt

sys.path.insert(0, str(Path(__file__).resolve().parent))
from sheets import chapter_numbers  # noqa: E402

from dstoolkit.errors import InvalidInputError, OutputExistsError  # noqa: E402
from dstoolkit.utils.console import run_command  # noqa: E402
from dstoolkit.utils.outputs import atomic_write  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
#: Folder of the site (and of the repository, for edited sources) that holds the decks.
SLIDES_FOLDER = "slides"
#: Minutes of one class session (the teaching page's plans count 90-minute sessions).
SESSION_MIN = 90
#: Fixed minutes of the title slide and of the key points.
TITLE_MIN, KEY_POINTS_MIN = 2, 5
#: Share of the remaining time given to the explorer and the "predict first" question.
IN_CLASS_SHARE = 0.2
#: Most formulas on one slide.
FORMULAS_PER_SLIDE = 2

#: A labelled display formula of the source: ``$$ … $$ (label)`` or a ``{math}`` block.
DOLLAR_MATH = re.compile(
    r"^[ \t]*\$\$\n(?P<tex>.*?)\n[ \t]*\$\$ *\((?P<label>[\w.:-]+)\) *$", re.M | re.S
)
MATH_BLOCK = re.compile(
    r"^(?P<fence>```|:::)\{math\}[^\n]*\n(?P<options>(?::[\w-]+:[^\n]*\n)*)"
    r"(?P<tex>.*?)\n(?P=fence) *$",
    re.M | re.S,
)
#: Speaker notes start with this line (reveal.js's Markdown default); time, in the notes.
NOTES = re.compile(r"^notes?:", re.I | re.M)
TIME = re.compile(r"^Time: (\d+) min", re.M)
SEPARATOR = re.compile(r"^---[ \t]*$", re.M)
#: Elements of a page whose content is not the chapter's text (exercises, solutions).
ASIDE_CLASSES = {"exercise", "solution", "dropdown", "toggle"}


@dataclass
class Slide:
    """One slide: Markdown body and speaker notes (without the time line)."""

    body: str
    notes: str = ""
    weight: str = "content"  # "title", "content", "in-class", "key-points"
    minutes: int = 0


@dataclass
class Chapter:
    """What a deck is made of, read from a chapter's source and its built page."""

    stem: str
    number: int
    title: str
    minutes: int
    slides: list[Slide] = field(default_factory=list)


# --------------------------------------------------------------------------------------
# Reading the book
# --------------------------------------------------------------------------------------


def class_minutes(root: Path = ROOT) -> dict[str, int]:
    """Return {chapter stem: minutes of class} from the teaching page's ``CHAPTERS`` table.

    The table is the literal ``CHAPTERS = {number: (stem, title, class hours, self-study
    hours)}`` in a code cell of book/teaching.md; an empty dict if it is not there.
    """
    text = (root / "book" / "teaching.md").read_text(encoding="utf-8")
    for cell in re.findall(r"^```\{code-cell\}[^\n]*\n(.*?)^```", text, re.M | re.S):
        code = "\n".join(line for line in cell.splitlines() if not line.startswith(":"))
        try:
            tree = ast.parse(code)
        except SyntaxError:
            continue
        for node in tree.body:
            if isinstance(node, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id == "CHAPTERS" for t in node.targets
            ):
                table = ast.literal_eval(node.value)
                return {row[0]: round(60 * row[2]) for row in table.values()}
    return {}


def labelled_formulas(source: str) -> dict[str, str]:
    """Return {label: TeX} of the source's labelled display formulas, in order."""
    found = [
        (m.start(), m["label"], textwrap.dedent(m["tex"]).strip())
        for m in DOLLAR_MATH.finditer(source)
    ]
    for m in MATH_BLOCK.finditer(source):
        label = re.search(r"^:label: *(\S+)", m["options"], re.M)
        if label:
            found.append((m.start(), label[1], m["tex"].strip()))
    return {label: tex for _, label, tex in sorted(found)}


def _in_aside(element: Tag) -> bool:
    """Whether ``element`` sits in an exercise, a solution or a folded block."""
    for parent in element.parents:
        if parent.name == "details" or ASIDE_CLASSES & set(parent.get("class") or []):
            return True
    return False


def _section_heading(element: Tag) -> Tag | None:
    """Return the heading (h2 or h3) of the section around ``element``."""
    for parent in element.parents:
        if parent.name == "section":
            heading = parent.find(["h2", "h3"], recursive=False)
            if heading is not None:
                return heading
    return None


def _heading_text(heading: Tag | None, stem: str) -> str:
    """Return a heading's text as Markdown (its maths as ``$…$``), without its link mark."""
    if heading is None:
        return ""
    return " ".join(inline_markdown(heading, stem).split())


def _href(href: str, stem: str) -> str:
    """Rewrite a link of the page book/STEM.html for a deck in slides/."""
    if re.match(r"^[a-z][a-z0-9+.-]*:", href) or href.startswith("/"):
        return href
    if href.startswith("#"):
        return f"../book/{stem}.html{href}"
    return "../book/" + href if not href.startswith("../") else href


def _escape(text: str) -> str:
    return re.sub(r"([\\`*_\[\]<$])", r"\\\1", text)


def inline_markdown(element: Tag | NavigableString, stem: str) -> str:
    """Return the Markdown of an inline piece of a built page (maths as ``$…$``)."""
    if isinstance(element, NavigableString):
        return _escape(" ".join(str(element).split(" ")).replace("\n", " "))
    classes = set(element.get("class") or [])
    if "headerlink" in classes or element.name in ("script", "style"):
        return ""
    if "math" in classes:
        tex = element.get_text()
        tex = re.sub(r"^\\\(|\\\)$", "", tex.strip())
        return f"${tex.strip()}$"
    inner = "".join(inline_markdown(c, stem) for c in element.children)
    if element.name in ("em", "i"):
        return f"*{inner}*"
    if element.name in ("strong", "b"):
        return f"**{inner}**"
    if element.name == "code":
        return f"`{element.get_text()}`"
    if element.name == "a" and element.get("href"):
        return f"[{inner}]({_href(element['href'], stem)})"
    if element.name == "p":
        return inner.strip() + "\n\n"
    return inner


def block_markdown(element: Tag, stem: str) -> str:
    """Return the Markdown of a block (paragraphs, lists) with whitespace tidied."""
    text = inline_markdown(element, stem)
    text = re.sub(r"[ \t]+", " ", text)
    return "\n\n".join(p.strip() for p in text.split("\n\n") if p.strip())


def read_chapter(site: Path, stem: str, number: int, minutes: int, root: Path = ROOT) -> Chapter:
    """Read the deck of chapter ``stem`` from its source and its built page."""
    page_file = site / "book" / f"{stem}.html"
    if not page_file.is_file():
        raise InvalidInputError(
            f"{page_file} is missing: build the book first (bash scripts/build-book.sh)"
        )
    page = BeautifulSoup(page_file.read_text(encoding="utf-8"), "html.parser")
    article = page.find("article") or page
    title = _heading_text(article.find("h1"), stem)
    title = re.sub(r"^\d+\.\s*", "", title)
    chapter = Chapter(stem, number, title, minutes)
    book_page = f"../book/{stem}.html"
    chapter.slides.append(
        Slide(
            f"# {number}. {title}\n\n"
            f"Lecture slides for chapter {number} of *{_book_title(root)}*\n\n"
            f"[Read the chapter]({book_page}) · [These slides in Markdown]({stem}.md)",
            f"Chapter {number}, {title}: {minutes} minutes of class, "
            f"{_sessions(minutes)}. "
            "Keys: arrows move, S opens the speaker view with these notes and the timer, "
            "Esc shows every slide.",
            "title",
        )
    )
    # Formulas and figures in the page's order; neighbouring formulas of one section share
    # a slide.
    formulas = labelled_formulas((root / "book" / f"{stem}.md").read_text(encoding="utf-8"))
    wanted = {f"equation-{label}": label for label in formulas}
    group: list[tuple[str, str, str]] = []  # (number, TeX, lead-in) of the pending slide
    group_heading: Tag | None = None

    def flush() -> None:
        nonlocal group
        if not group:
            return
        heading = _heading_text(group_heading, stem) or f"{number}. {title}"
        maths = "\n\n".join(f"$$\n{tex}\n\\tag{{{eqno}}}\n$$" for eqno, tex, _ in group)
        numbers = ", ".join(f"({eqno})" for eqno, _, _ in group)
        anchor = group_heading.parent.get("id") if group_heading is not None else ""
        body = (
            f"## {heading}\n\n{maths}\n\n"
            f'<p class="source">Eq. {numbers} in <a href="{book_page}#{anchor}">'
            f"the chapter</a></p>"
        )
        notes = "\n\n".join(f"({eqno}): {lead}" for eqno, _, lead in group if lead)
        chapter.slides.append(Slide(body, notes))
        group = []

    for element in article.find_all(["div", "figure"]):
        if element.name == "div" and element.get("id") in wanted and not _in_aside(element):
            label = wanted[element["id"]]
            eqno_tag = element.find(class_="eqno")
            eqno = eqno_tag.get_text().strip("()# \n") if eqno_tag else ""
            heading = _section_heading(element)
            if group and (heading is not group_heading or len(group) >= FORMULAS_PER_SLIDE):
                flush()
            group_heading = heading
            lead = element.find_previous_sibling("p")
            group.append(
                (eqno or label, formulas[label], block_markdown(lead, stem) if lead else "")
            )
        elif element.name == "figure" and element.find("img") and not _in_aside(element):
            flush()
            chapter.slides.append(_figure_slide(element, stem, number, title))
    flush()
    chapter.slides.append(_in_class_slide(article, stem))
    key_points = article.find(id="key-points")
    items = key_points.find_all("li") if key_points else []
    points = "\n".join(f"- {block_markdown(li, stem)}" for li in items) or (
        f"The chapter has no key points section: see [the chapter]({book_page})."
    )
    chapter.slides.append(
        Slide(f"## Key points\n\n{points}", "Sum up; set the exercise sheet.", "key-points")
    )
    _set_times(chapter)
    return chapter


def _sessions(minutes: int) -> str:
    count = math.ceil(minutes / SESSION_MIN)
    return (
        f"one {SESSION_MIN}-minute session" if count == 1 else f"{count} sessions of {SESSION_MIN}"
    )


def _figure_slide(figure: Tag, stem: str, number: int, title: str) -> Slide:
    img = figure.find("img")
    alt = " ".join((img.get("alt") or "").split())
    caption = figure.find("figcaption")
    fig_number = caption.find(class_="caption-number") if caption else None
    label = fig_number.get_text().strip() if fig_number else "Figure"
    text = caption.find(class_="caption-text") if caption else None
    if not alt and text is not None:  # the book gives every figure one; the caption else
        alt = " ".join(text.get_text().split())
    heading = _heading_text(_section_heading(figure), stem) or f"{number}. {title}"
    # an HTML image: Markdown's image syntax loses escaped characters from the alt text;
    # loaded when its slide comes near, as the book's figures are
    src, alt_attr = html.escape(img["src"]), html.escape(alt)
    body = f'## {heading}\n\n<img src="{src}" alt="{alt_attr}" loading="lazy">'
    notes = f"What the figure shows (its alt text): {alt}"
    if text is not None:
        caption_md = block_markdown(text, stem)
        # the caption's first sentence on the slide, all of it in the notes
        first = re.match(r"(.+?[.!?])\s+(?=[A-Z])", caption_md, re.S)
        body += f"\n\n{label} {first[1] if first else caption_md}"
        notes += f"\n\nCaption: {caption_md}"
    return Slide(body, notes)


def _in_class_slide(article: Tag, stem: str) -> Slide:
    """Return the slide that links the chapter's explorer and its "predict first" exercise."""
    book_page = f"../book/{stem}.html"
    lines = []
    widget = article.find("script", type="application/vnd.jupyter.widget-view+json")
    if widget is not None:
        heading = _section_heading(widget)
        where = heading.parent.get("id") if heading is not None else ""
        lines.append(
            f"- The explorer: [{_heading_text(heading, stem) or 'on the chapter page'}]"
            f"({book_page}#{where}); move its controls live."
        )
    predict = article.find(id=re.compile(r"-ex-predict$"))
    notes = "Show the explorer on the chapter page; ask for predictions before moving a control."
    if predict is not None:
        name = predict.find(class_="caption-number")
        exercise = name.get_text().strip() if name else "The predict-first exercise"
        lines.append(f"- Predict first: [{exercise}]({book_page}#{predict['id']})")
        content = predict.find(id="exercise-content") or predict
        notes += "\n\n" + block_markdown(content, stem)
    if not lines:
        lines.append(f"- Work through [the chapter's exercises]({book_page}).")
    return Slide("## In class\n\n" + "\n".join(lines), notes, "in-class")


def _book_title(root: Path) -> str:
    config = yaml.safe_load((root / "_config.yml").read_text(encoding="utf-8"))
    return str(config.get("title", "the book"))


# --------------------------------------------------------------------------------------
# Timing
# --------------------------------------------------------------------------------------


def share(total: int, weights: list[float]) -> list[int]:
    """Split ``total`` whole minutes in proportion to ``weights`` (largest remainders).

    Examples
    --------
    >>> share(10, [1, 1, 1])
    [4, 3, 3]
    >>> sum(share(173, [1] * 12))
    173
    """
    if not weights:
        return []
    exact = [total * w / sum(weights) for w in weights]
    whole = [math.floor(x) for x in exact]
    order = sorted(range(len(exact)), key=lambda i: (whole[i] - exact[i], i))
    for i in order[: total - sum(whole)]:
        whole[i] += 1
    return whole


def _set_times(chapter: Chapter) -> None:
    """Give every slide its minutes; they sum to the chapter's class minutes."""
    content = [s for s in chapter.slides if s.weight == "content"]
    rest = chapter.minutes - TITLE_MIN - KEY_POINTS_MIN
    in_class = round(IN_CLASS_SHARE * rest) if content else rest
    for slide, minutes in zip(content, share(rest - in_class, [1.0] * len(content)), strict=True):
        slide.minutes = minutes
    for slide in chapter.slides:
        slide.minutes = {
            "title": TITLE_MIN,
            "key-points": KEY_POINTS_MIN,
            "in-class": in_class,
        }.get(slide.weight, slide.minutes)


# --------------------------------------------------------------------------------------
# Markdown source
# --------------------------------------------------------------------------------------


def deck_markdown(chapter: Chapter) -> str:
    """Return the deck's source: reveal.js Markdown, the time of each slide in its notes."""
    parts = []
    start = 0
    for slide in chapter.slides:
        end = start + slide.minutes
        timing = f"Time: {slide.minutes} min (minutes {start}–{end} of {chapter.minutes})."
        for brk in range(SESSION_MIN, chapter.minutes, SESSION_MIN):
            if start == brk:
                timing += f" Session {brk // SESSION_MIN + 1} starts with this slide."
            elif start < brk < end:
                timing += f" Session {brk // SESSION_MIN + 1} starts during it, at minute {brk}."
        start = end
        notes = f"{timing}\n\n{slide.notes}".strip()
        parts.append(f"{slide.body}\n\nNote:\n{notes}")
    header = (
        f"<!-- Lecture slides of chapter {chapter.number}, generated by scripts/slides.py from "
        f"book/{chapter.stem}.md and its built page. To edit: python scripts/slides.py --edit "
        f"{chapter.stem} (see slides/README.md). -->\n\n"
    )
    return header + "\n\n---\n\n".join(parts) + "\n"


# --------------------------------------------------------------------------------------
# HTML
# --------------------------------------------------------------------------------------

_MD = MarkdownIt("commonmark", {"html": True}).enable("table")
_DISPLAY = re.compile(r"\$\$(.+?)\$\$", re.S)
_INLINE = re.compile(r"(?<![\\$])\$(?!\$)(.+?)(?<!\\)\$")

CSS = """\
/* Lecture decks: reveal.js's white theme, with AA contrast for links and small text. */
.reveal { color: #1a1a1a; }
.reveal a { color: #0b4f9c; text-decoration: underline; }
.reveal a:focus-visible { outline: 3px solid #0b4f9c; outline-offset: 2px; }
.reveal h1, .reveal h2 { text-transform: none; }
.reveal h1 { font-size: 2em; }
.reveal h2 { font-size: 1.2em; }
.reveal .display-math { font-size: 0.6em; margin: 0.6em 0; }
.reveal section img { max-height: 420px; max-width: 100%; margin: 0.2em auto; }
.reveal p.source, .reveal p.caption { font-size: 0.5em; color: #333; }
.reveal p.caption { text-align: center; }
.reveal ul { font-size: 0.75em; }
/* MathJax's hidden MathML for screen readers is as tall as the formula; kept 1 px high so
   that it does not push the slide's content off centre. */
.reveal mjx-assistive-mml { height: 1px !important; overflow: hidden !important; }
.reveal .controls { color: #0b4f9c; }
.reveal .progress { color: #0b4f9c; }
.reveal .slide-number { background-color: #1a1a1a; color: #fff; }
"""


def _render(markdown: str) -> str:
    """Render a slide's Markdown; its maths is kept as TeX for MathJax to typeset."""
    kept: list[str] = []

    def keep(tex: str, display: bool) -> str:
        escaped = html.escape(tex.strip(), quote=False)
        kept.append(f"\\[{escaped}\\]" if display else f"\\({escaped}\\)")
        return f"\ue000{len(kept) - 1}\ue000"

    text = _DISPLAY.sub(lambda m: "\n\n" + keep(m[1], True) + "\n\n", markdown)
    text = _INLINE.sub(lambda m: keep(m[1], False), text)
    out = _MD.render(text)
    out = re.sub(r"<p>(\ue000\d+\ue000)</p>", r'<div class="display-math">\1</div>', out)
    out = re.sub(r"\ue000(\d+)\ue000", lambda m: kept[int(m[1])], out)
    # figure captions: the paragraph after an image
    return out


def split_slides(markdown: str) -> list[tuple[str, str]]:
    """Return (body, notes) of each slide of a reveal.js Markdown source."""
    markdown = re.sub(r"<!--.*?-->", "", markdown, flags=re.S)
    slides = []
    for part in SEPARATOR.split(markdown):
        if not part.strip():
            continue
        pieces = NOTES.split(part, maxsplit=1)
        body, notes = (pieces[0], pieces[1]) if len(pieces) == 2 else (part, "")
        slides.append((body.strip(), notes.strip()))
    return slides


def deck_html(markdown: str, title: str, lang: str = "en") -> str:
    """Return the deck's page, built from its Markdown source."""
    sections = []
    for i, (body, notes) in enumerate(split_slides(markdown), start=1):
        minutes = TIME.search(notes)
        timing = f' data-timing="{int(minutes[1]) * 60}"' if minutes else ""
        rendered = _render(body)
        rendered = re.sub(
            r"(<img [^>]*>(?:</p>)?\n)<p>", r'\1<p class="caption">', rendered, count=1
        )
        sections.append(
            f'<section id="slide-{i}"{timing}>\n{rendered}'
            f'<aside class="notes">\n{_render(notes)}</aside>\n</section>'
        )
    static = "../_static"
    return f"""<!DOCTYPE html>
<html lang="{lang}">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{html.escape(title)}</title>
<link rel="icon" href="{static}/favicon.svg">
<link rel="stylesheet" href="{static}/reveal/reset.css">
<link rel="stylesheet" href="{static}/reveal/reveal.css">
<link rel="stylesheet" href="{static}/reveal/theme/white.css">
<link rel="stylesheet" href="deck.css">
</head>
<body>
<main class="reveal">
<div class="slides">
{chr(10).join(sections)}
</div>
</main>
<script src="{static}/reveal/reveal.js"></script>
<script src="{static}/reveal/plugin/notes.js"></script>
<script src="{static}/reveal/plugin/math.js"></script>
<script>
// A formula wider than its slide is drawn smaller until it fits (MathJax 3 does not break
// lines); measured on the slide shown, whose layout is known.
function fitFormulas(slide) {{
  for (const box of slide.querySelectorAll(".display-math")) {{
    box.style.fontSize = "";
    const ratio = box.clientWidth / box.scrollWidth;
    if (ratio < 1) box.style.fontSize = (0.6 * ratio * 0.98) + "em";
  }}
}}
Reveal.initialize({{
  hash: true,
  slideNumber: "c/t",
  transition: "none",
  // the speaker view's pacing timer: each slide's data-timing, 2 minutes where none is set
  defaultTiming: 120,
  plugins: [RevealNotes, RevealMath.MathJax3],
  mathjax3: {{
    mathjax: "{static}/mathjax/tex-chtml.js",
    tex: {{ inlineMath: [["\\\\(", "\\\\)"]], displayMath: [["\\\\[", "\\\\]"]] }},
    options: {{ menuOptions: {{ settings: {{ inTabOrder: false, assistiveMml: true }} }} }},
    startup: {{
      ready: () => {{
        MathJax.startup.defaultReady();
        MathJax.startup.promise.then(() => {{
          fitFormulas(Reveal.getCurrentSlide());
          Reveal.layout();
        }});
      }}
    }}
  }}
}});
Reveal.on("slidechanged", (event) => {{
  if (window.MathJax && MathJax.startup && MathJax.startup.promise)
    MathJax.startup.promise.then(() => {{ fitFormulas(event.currentSlide); Reveal.layout(); }});
}});
</script>
</body>
</html>
"""


# --------------------------------------------------------------------------------------
# Command
# --------------------------------------------------------------------------------------


def deck_path(stem: str) -> str:
    """Return the path of a chapter's deck in the site, e.g. ``slides/lab.html``."""
    return f"{SLIDES_FOLDER}/{stem}.html"


def chapters(root: Path = ROOT) -> dict[str, int]:
    """Return {stem: number} of the numbered chapters of _toc.yml."""
    return chapter_numbers(root / "_toc.yml")


def write_decks(site: Path, root: Path = ROOT) -> list[Path]:
    """Write every chapter's Markdown source and deck into ``site``/slides/."""
    minutes = class_minutes(root)
    written = []
    atomic_write(site / SLIDES_FOLDER / "deck.css", lambda fh: fh.write(CSS.encode("utf-8")))
    for stem, number in chapters(root).items():
        if stem not in minutes:
            print(
                f"slides.py: book/teaching.md gives no class hours for {stem}; "
                f"timing its deck for one {SESSION_MIN}-minute session",
                file=sys.stderr,
            )
        chapter = read_chapter(site, stem, number, minutes.get(stem, SESSION_MIN), root)
        edited = root / SLIDES_FOLDER / f"{stem}.md"
        source = edited.read_text(encoding="utf-8") if edited.is_file() else deck_markdown(chapter)
        if edited.is_file():
            print(f"slides.py: {stem}: using the edited source {edited.relative_to(root)}")
        title = f"{number}. {chapter.title}: lecture slides · {_book_title(root)}"
        deck = site / deck_path(stem)
        for path, text in ((deck.with_suffix(".md"), source), (deck, deck_html(source, title))):
            atomic_write(path, lambda fh, text=text: fh.write(text.encode("utf-8")))
            written.append(path)
    return written


def edit(stem: str, site: Path, root: Path = ROOT, *, force: bool = False) -> Path:
    """Copy the generated source of ``stem``'s deck to slides/STEM.md for editing."""
    numbers = chapters(root)
    if stem not in numbers:
        raise InvalidInputError(
            f"--edit: no numbered chapter {stem!r}; the chapters are {', '.join(numbers)}"
        )
    target = root / SLIDES_FOLDER / f"{stem}.md"
    if target.exists() and not force:
        raise OutputExistsError(
            f"--edit: {target} exists (an edited deck); pass --force to replace it with the "
            "generated source"
        )
    minutes = class_minutes(root).get(stem, SESSION_MIN)
    text = deck_markdown(read_chapter(site, stem, numbers[stem], minutes, root))
    return atomic_write(target, lambda fh: fh.write(text.encode("utf-8")))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--site", type=Path, default=ROOT / "_build" / "html", help="the built book"
    )
    parser.add_argument(
        "--edit",
        metavar="STEM",
        default=None,
        help="write the generated source of a chapter's deck to slides/STEM.md, to edit",
    )
    parser.add_argument(
        "--force", action="store_true", help="with --edit: replace an edited source"
    )
    args = parser.parse_args(argv)

    def body() -> int:
        if args.edit:
            print(edit(args.edit, args.site, force=args.force))
            return 0
        decks = [p for p in write_decks(args.site) if p.suffix == ".html"]
        print(f"slides.py: {len(decks)} decks in {args.site / SLIDES_FOLDER}")
        return 0

    return run_command(body)


if __name__ == "__main__":
    sys.exit(main())
