"""Sphinx extension: the learning outcomes of every chapter and of the course.

A chapter ``book/<stem>.md`` with a data file ``book/outcomes/<stem>.yml`` shows, right
under its title, a box "After this chapter you can…" listing its outcomes, each with links
to the exercises that assess it. Nothing in the chapter's source asks for it: any chapter
that has a yml file gets the box, so a new chapter needs only its yml file.

The teaching page shows the course's outcomes (``book/outcomes/course.yml``, whose
``exercises:`` name chapter outcomes) with the directive ``{course-outcomes}``, and a table
of every chapter's outcomes and exercises with ``{chapter-outcomes}``.

The file's format (one per chapter)::

    outcomes:
      - id: rs-o1          # <the chapter's exercise-label prefix>-o<k>, unique in the book
        text: compute the image of a focal box ...   # completes "After this chapter you can"
        exercises: [rs-ex-product, rs-ex-monotone]   # exercise labels of that chapter

Every outcome starts with a measurable verb of :data:`VERBS`, has at least one exercise,
names only exercises of its chapter, and every exercise of the chapter serves at least one
outcome. :func:`problems` says what breaks these rules; the build warns on each (a warning
fails the book's build) and ``tests/test_outcomes.py`` checks every chapter of _toc.yml.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import yaml
from docutils import nodes
from docutils.parsers.rst import Directive
from sphinx import addnodes
from sphinx.application import Sphinx
from sphinx.transforms.post_transforms import SphinxPostTransform
from sphinx.util import logging
from sphinx.util.texescape import escape as tex_escape

logger = logging.getLogger(__name__)

#: The verbs an outcome may start with: each names something a learner does that an
#: exercise can observe ("understand" or "know" would not be).
VERBS = (
    "apply",
    "bound",
    "build",
    "calibrate",
    "choose",
    "combine",
    "compare",
    "compute",
    "construct",
    "decide",
    "derive",
    "design",
    "diagnose",
    "estimate",
    "evaluate",
    "explain",
    "identify",
    "implement",
    "interpret",
    "justify",
    "measure",
    "predict",
    "prove",
    "quantify",
    "run",
    "show",
    "test",
)
#: The heading of a chapter's box, completed by each outcome.
CHAPTER_LEAD = "After this chapter you can…"
COURSE_LEAD = "After this course you can…"
COURSE_FILE = "course"
FOLDER = "outcomes"
ID = re.compile(r"^[a-z]+-o[1-9][0-9]*$")


class OutcomesError(ValueError):
    """A learning-outcomes file that cannot be read as the shared format."""


def outcomes_path(chapter: Path) -> Path:
    """Return ``book/outcomes/<stem>.yml`` for the chapter ``book/<stem>.md``."""
    return chapter.parent / FOLDER / f"{chapter.stem}.yml"


def load(path: Path) -> list[dict[str, Any]]:
    """Return the outcomes of ``path``: dicts with ``id``, ``text`` and ``exercises``.

    Raises
    ------
    OutcomesError
        When the file is not a mapping with a list ``outcomes`` whose entries have a
        string ``id``, a string ``text`` and a list of strings ``exercises``.
    """
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError) as err:
        raise OutcomesError(f"{path}: cannot read it as YAML: {err}") from None
    found = data.get("outcomes") if isinstance(data, dict) else None
    if not isinstance(found, list) or not found:
        raise OutcomesError(f"{path}: write a non-empty list under the key 'outcomes:'")
    for k, item in enumerate(found, 1):
        ok = (
            isinstance(item, dict)
            and set(item) == {"id", "text", "exercises"}
            and isinstance(item["id"], str)
            and isinstance(item["text"], str)
            and isinstance(item["exercises"], list)
            and all(isinstance(x, str) for x in item["exercises"])
        )
        if not ok:
            raise OutcomesError(
                f"{path}: outcome {k} must have exactly the keys id (text), text (text) "
                f"and exercises (a list of labels); it is {item!r}"
            )
    return found


def problems(
    outcomes: list[dict[str, Any]], labels: list[str], where: str, prefix: str | None = None
) -> list[str]:
    """Return what breaks the format's rules, one sentence each (empty when nothing does).

    ``labels`` are what the outcomes may name: a chapter's exercise labels, or for the
    course every chapter outcome's id. With ``prefix``, every id must read
    ``<prefix>-o<k>``.
    """
    out = []
    ids = [o["id"] for o in outcomes]
    for dup in sorted({i for i in ids if ids.count(i) > 1}):
        out.append(f"{where}: the id {dup} is used twice")
    for o in outcomes:
        if not ID.match(o["id"]) or (prefix and not o["id"].startswith(f"{prefix}-o")):
            want = f"{prefix}-o<k>" if prefix else "<prefix>-o<k>"
            out.append(f"{where}: the id {o['id']!r} should read {want}")
        verb = first_word(o["text"])
        if verb not in VERBS:
            out.append(
                f"{where}: {o['id']} starts with {verb!r}; start it with a measurable verb "
                f"({', '.join(VERBS)})"
            )
        if not o["exercises"]:
            out.append(f"{where}: {o['id']} names no exercise that assesses it")
        for label in o["exercises"]:
            if label not in labels:
                out.append(f"{where}: {o['id']} names {label}, which is not one of {labels}")
    served = {label for o in outcomes for label in o["exercises"]}
    for label in labels:
        if label not in served:
            out.append(f"{where}: the exercise {label} serves no outcome; add it to one")
    return out


def first_word(text: str) -> str:
    """Return the first word of ``text`` (letters only: "design," reads "design")."""
    found = re.match(r"[A-Za-z]*", text.strip())
    return found.group(0) if found else ""


def label_prefix(labels: list[str]) -> str | None:
    """Return the prefix most of the chapter's exercise labels share (``rs`` of rs-ex-…)."""
    heads = [label.split("-", 1)[0] for label in labels]
    return max(set(heads), key=heads.count) if heads else None


def book_root(srcdir: Path) -> Path:
    """Return the folder of _toc.yml: ``srcdir`` or the nearest folder above it.

    A one-page build (``jupyter-book build book/x.md``) has the page's folder as source.
    """
    for folder in (srcdir, *srcdir.parents):
        if (folder / "_toc.yml").exists():
            return folder
    raise OutcomesError(f"no _toc.yml in {srcdir} or above it")


def toc_chapters(root: Path) -> list[str]:
    """Return the docnames of the numbered parts' chapters in ``root``/_toc.yml, in order."""
    toc = yaml.safe_load((root / "_toc.yml").read_text(encoding="utf-8"))
    return [
        str(Path(chapter["file"]).with_suffix(""))
        for part in toc.get("parts", [])
        if part.get("numbered")
        for chapter in part.get("chapters", [])
    ]


# -- the nodes -------------------------------------------------------------------------------


def _exercise_ref(label: str) -> addnodes.pending_xref:
    """Return a link to an exercise that reads "Exercise N.k" (sphinx-exercise's numref)."""
    ref = addnodes.pending_xref(
        "", refdomain="std", reftype="numref", reftarget=label, refexplicit=False, refwarn=True
    )
    ref += nodes.literal(label, label)
    return ref


def _doc_ref(docname: str, text: str | None = None) -> addnodes.pending_xref:
    """Return a link to a page (its title unless ``text``)."""
    ref = addnodes.pending_xref(
        "",
        refdomain="std",
        reftype="doc",
        reftarget=f"/{docname}",
        refexplicit=text is not None,
        refwarn=True,
    )
    ref += nodes.inline(text or docname, text or docname)
    return ref


def _refs(labels: list[str]) -> list[nodes.Node]:
    out: list[nodes.Node] = []
    for k, label in enumerate(labels):
        if k:
            out.append(nodes.Text(", "))
        out.append(_exercise_ref(label))
    return out


def outcome_item(outcome: dict[str, Any], with_id: bool = True) -> nodes.list_item:
    """Return one outcome's item: its text, then "(assessed by Exercise N.k, …)"."""
    para = nodes.paragraph()
    para += nodes.Text(outcome["text"][0].upper() + outcome["text"][1:] + " (assessed by ")
    para.extend(_refs(outcome["exercises"]))
    para += nodes.Text(").")
    item = nodes.list_item("", para)
    if with_id:
        item["ids"].append(outcome["id"])
    return item


def outcomes_box(outcomes: list[dict[str, Any]]) -> nodes.admonition:
    """Return the box "After this chapter you can…" with one item per outcome."""
    box = nodes.admonition(classes=["dstoolkit-outcomes"])
    box += nodes.title(CHAPTER_LEAD, CHAPTER_LEAD)
    box += nodes.bullet_list("", *(outcome_item(o) for o in outcomes), bullet="-")
    return box


def _chapter_labels(doctree: nodes.document) -> list[str]:
    from sphinx_exercise.nodes import exercise_enumerable_node, exercise_node

    kinds = (exercise_enumerable_node, exercise_node)
    return [
        node["label"] for node in doctree.findall(lambda n: isinstance(n, kinds) and n.get("label"))
    ]


def _on_doctree_read(app: Sphinx, doctree: nodes.document) -> None:
    """Put the chapter's outcomes under its title, when it has an outcomes file."""
    env = app.env
    path = outcomes_path(Path(env.doc2path(env.docname)))
    if not path.exists() or path.stem == COURSE_FILE:
        return
    env.note_dependency(str(path))
    try:
        outcomes = load(path)
    except OutcomesError as err:
        logger.warning(str(err), location=env.docname)
        return
    labels = _chapter_labels(doctree)
    for problem in problems(outcomes, labels, path.name, label_prefix(labels)):
        logger.warning(problem, location=env.docname)
    section = next(iter(doctree.findall(nodes.section)), None)
    if section is None or not isinstance(section[0], nodes.title):
        logger.warning(
            f"{path.name}: the page has no title to put its outcomes under", location=env.docname
        )
        return
    section.insert(1, outcomes_box(outcomes))
    std = env.get_domain("std")
    for outcome in outcomes:  # the course outcomes on the teaching page link to each
        std.note_hyperlink_target(outcome["id"], env.docname, outcome["id"], outcome["id"])


# -- the teaching page -----------------------------------------------------------------------


def _chapters(directive: Directive) -> list[tuple[int, str, list[dict[str, Any]]]]:
    """Return (number, docname, outcomes) of every numbered chapter with an outcomes file."""
    env = directive.state.document.settings.env
    root = book_root(Path(env.srcdir))
    out = []
    for number, docname in enumerate(toc_chapters(root), 1):
        path = outcomes_path(root / f"{docname}.md")
        env.note_dependency(str(path))
        if path.exists():
            out.append((number, docname, load(path)))
    return out


class CourseOutcomes(Directive):
    """The course's outcomes, each with the chapter outcomes that build it (linked)."""

    def run(self) -> list[nodes.Node]:
        """Return the lead line and the list of the course's outcomes."""
        env = self.state.document.settings.env
        path = book_root(Path(env.srcdir)) / "book" / FOLDER / f"{COURSE_FILE}.yml"
        env.note_dependency(str(path))
        chapters = self._chapter_outcomes()
        course = load(path)
        for problem in problems(course, list(chapters), path.name):
            logger.warning(problem, location=env.docname)
        items = []
        for outcome in course:
            para = nodes.paragraph()
            para += nodes.Text(outcome["text"][0].upper() + outcome["text"][1:] + ". Built in ")
            by_chapter: dict[int, list[str]] = {}
            for oid in outcome["exercises"]:
                if oid in chapters:
                    by_chapter.setdefault(chapters[oid][0], []).append(oid)
            for k, (number, oids) in enumerate(sorted(by_chapter.items())):
                para += nodes.Text(("; " if k else "") + f"chapter {number} (")
                for j, oid in enumerate(oids):
                    if j:
                        para += nodes.Text(", ")
                    link = addnodes.pending_xref(
                        "",
                        refdomain="std",
                        reftype="ref",
                        reftarget=oid,
                        refexplicit=True,
                        refwarn=True,
                    )
                    link += nodes.inline(oid, oid)
                    para += link
                para += nodes.Text(")")
            para += nodes.Text(".")
            items.append(nodes.list_item("", para, ids=[outcome["id"]]))
        lead = nodes.paragraph(COURSE_LEAD, COURSE_LEAD)
        return [lead, nodes.bullet_list("", *items, bullet="-")]

    def _chapter_outcomes(self) -> dict[str, tuple[int, str]]:
        return {
            o["id"]: (number, docname) for number, docname, outs in _chapters(self) for o in outs
        }


class ChapterOutcomes(Directive):
    """A table: each chapter, its outcomes, and the exercises that assess each."""

    def run(self) -> list[nodes.Node]:
        """Return the table, one row per chapter outcome."""
        table = nodes.table(classes=["dstoolkit-outcomes-table"])
        group = nodes.tgroup(cols=3)
        table += group
        for width in (20, 60, 20):
            group += nodes.colspec(colwidth=width)
        head = nodes.thead()
        head += self._row([nodes.Text(t) for t in ("Chapter", "Outcome", "Exercises")])
        group += head
        body = nodes.tbody()
        for number, docname, outcomes in _chapters(self):
            for k, outcome in enumerate(outcomes):
                chapter: list[nodes.Node] = []
                if k == 0:
                    chapter = [nodes.Text(f"{number} "), _doc_ref(docname)]
                text = outcome["text"][0].upper() + outcome["text"][1:]
                body += self._row(
                    [chapter, [nodes.Text(f"{outcome['id']}: {text}")], _refs(outcome["exercises"])]
                )
        group += body
        return [table]

    @staticmethod
    def _row(cells: list[Any]) -> nodes.row:
        row = nodes.row()
        for content in cells:
            para = nodes.paragraph()
            para.extend(content if isinstance(content, list) else [content])
            row += nodes.entry("", para)
        return row


class LatexAnchors(SphinxPostTransform):
    """In the PDF, the outcomes' anchors exist and their links to exercises resolve.

    LaTeX writes no label for a list item's id, so each outcome's id moves to a target at
    the start of its item (the web page keeps ``<li id=…>``). sphinx-exercise labels an
    exercise ``exercise:<label>`` in LaTeX, while a numbered reference to another page
    points at ``<page>:<label>``; such a reference is written against the exercise's label.
    """

    default_priority = 25  # after the references resolve (10) and sphinx-exercise's (22)
    formats = ("latex",)

    def run(self, **kwargs: Any) -> None:
        """Move the outcomes' ids to targets; point the exercises' references at their labels."""
        for item in list(self.document.findall(nodes.list_item)):
            ids = [i for i in item["ids"] if ID.match(i)]
            if ids and item.children and isinstance(item[0], nodes.paragraph):
                item["ids"] = [i for i in item["ids"] if i not in ids]
                item[0].insert(0, nodes.target("", "", ids=ids))
        exercises = set(_chapter_labels(self.document))
        for ref in list(self.document.findall(nodes.reference)):
            uri = ref.get("refuri", "")
            label = uri.rpartition("#")[2] if uri.startswith("%") else ""
            if label in exercises:
                text = tex_escape(ref.astext())
                ref.replace_self(
                    nodes.raw("", rf"\hyperref[exercise:{label}]{{{text}}}", format="latex")
                )


def setup(app: Sphinx) -> dict[str, Any]:
    """Sphinx: the outcomes box on every chapter with a file, and the teaching page's parts."""
    app.connect("doctree-read", _on_doctree_read)
    app.add_directive("course-outcomes", CourseOutcomes)
    app.add_directive("chapter-outcomes", ChapterOutcomes)
    app.add_post_transform(LatexAnchors)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
