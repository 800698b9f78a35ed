"""Sphinx extension of the book: run it from the site.

- Every numbered chapter is offered as a clean notebook, ``notebooks/chapter_NN_<stem>.ipynb``
  in the site, written when the build finishes from the chapter's source and the values it
  glued (``scripts/chapter_notebook.py`` does the rewriting: no raw MyST, no solutions).
  Its exercise sheet, ``notebooks/*_<stem>.ipynb`` of the repository, is copied beside it.
- Each chapter page links both, in the download menu of the header and in a line under the
  chapter's title, with a link to the page *Run this book* (the label ``run``), and its
  lecture slides, ``slides/<stem>.html``, which scripts/slides.py writes after the build.
- The repository address lives in one place, ``repository.url`` of ``_config.yml``. When it
  is set, the repository button and the launch buttons (Binder by default; they open the
  chapter's exercise sheet) appear; when it is empty, neither does.
- The directive ``{chapter-downloads}`` lists every chapter with its slides and two downloads, and
  ``{repository-address}`` says where the code is (for the page *Run this book*).

Jupyter Book loads it through ``sphinx.local_extensions`` in ``_config.yml``.
"""

from __future__ import annotations

import html
import json
import os
import shutil
import sys
from dataclasses import dataclass
from pathlib import Path

from docutils import nodes
from docutils.nodes import make_id
from sphinx.application import Sphinx
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective
from sphinx.util.osutil import relative_uri

sys.path.insert(0, str(Path(__file__).resolve().parent))
# The chapters' kernels (started by myst-nb with this process's environment) import the
# answer key from the repository's answer_key/, which no wheel installs.
_REPO = str(Path(__file__).resolve().parents[1])
os.environ["PYTHONPATH"] = os.pathsep.join(
    [_REPO, *(p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p and p != _REPO)]
)
from chapter_notebook import References, clean_notebook  # noqa: E402

from slides import deck_path  # noqa: E402

logger = logging.getLogger(__name__)

#: Folder of the site that holds the chapter notebooks and the exercise sheets.
SITE_FOLDER = "notebooks"
#: Folder of the repository that holds the exercise sheets.
SHEETS_FOLDER = "notebooks"
#: Label of the page that says how to run the book.
RUN_LABEL = "run"
#: Classes of the two entries this extension adds to the header's download menu.
NOTEBOOK_BUTTON, SHEET_BUTTON = "download-chapter-notebook", "download-exercise-sheet"

_SET_DOWNLOAD = f"""
document.addEventListener("DOMContentLoaded", () => {{
  for (const a of document.querySelectorAll("a.btn-{NOTEBOOK_BUTTON}, a.btn-{SHEET_BUTTON}")) {{
    a.setAttribute("download", "");
    a.removeAttribute("target");
  }}
}});
"""


# --------------------------------------------------------------------------------------
# Chapters, their notebooks and sheets
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Chapter:
    """A numbered chapter of the book and the two notebooks offered with it."""

    docname: str  # book/mass_functions
    number: str  # "3"
    sheet: Path | None  # notebooks/03_mass_functions.ipynb in the repository, if any

    @property
    def stem(self) -> str:
        return self.docname.rsplit("/", 1)[-1]

    @property
    def notebook_name(self) -> str:
        return f"chapter_{int(self.number):02d}_{self.stem}.ipynb"

    @property
    def notebook_path(self) -> str:
        """Path of the clean chapter notebook in the site."""
        return f"{SITE_FOLDER}/{self.notebook_name}"

    @property
    def sheet_path(self) -> str | None:
        """Path of the exercise sheet in the site."""
        return f"{SITE_FOLDER}/{self.sheet.name}" if self.sheet else None


def chapters(app: Sphinx) -> dict[str, Chapter]:
    """Every numbered chapter (a page with a chapter number), in the book's order."""
    env = app.env
    found = {}
    for docname in env.found_docs:
        number = env.toc_secnumbers.get(docname, {}).get("")
        if not number or len(number) != 1:
            continue
        stem = docname.rsplit("/", 1)[-1]
        sheets = sorted(Path(app.srcdir, SHEETS_FOLDER).glob(f"*_{stem}.ipynb"))
        if len(sheets) > 1:
            logger.warning(
                f"more than one exercise sheet for {docname}: "
                f"{[s.name for s in sheets]}; offering {sheets[0].name}"
            )
        found[docname] = Chapter(docname, str(number[0]), sheets[0] if sheets else None)
    return dict(sorted(found.items(), key=lambda item: int(item[1].number)))


# --------------------------------------------------------------------------------------
# What the build resolved, for the converter
# --------------------------------------------------------------------------------------


def _numbers(app: Sphinx, docname: str, labelid: str) -> tuple[str, str] | None:
    """(figtype, "3.1") of a numbered object of ``docname``, or None."""
    for figtype, ids in app.env.toc_fignumbers.get(docname, {}).items():
        if labelid in ids:
            return figtype, ".".join(map(str, ids[labelid]))
    return None


def _authors(entry) -> str:
    """Author-year names of a pybtex entry: "Xu", "Xu and Li", or "Xu et al."."""
    people = entry.persons.get("author") or entry.persons.get("editor") or []
    last = [" ".join(p.last_names).replace("{", "").replace("}", "") for p in people]
    if len(last) >= 3:
        return f"{last[0]} et al."
    return " and ".join(last) or entry.key


def references(app: Sphinx, docname: str) -> References:
    """Everything the chapter ``docname`` refers to, as the built book shows it."""
    from myst_nb.core.variables import format_plain_text

    env, config = app.env, app.config
    refs = References(
        format_glue=format_plain_text, eqref_format=config.math_eqref_format or "({number})"
    )
    for label, (doc, _number) in env.get_domain("math").equations.items():
        found = _numbers(app, doc, make_id(f"equation-{label}"))
        if found:
            refs.equations[label] = found[1]
    std = env.get_domain("std")
    for label, (doc, labelid, *rest) in {**std.anonlabels, **std.labels}.items():
        found = _numbers(app, doc, labelid)
        if found:
            figtype, number = found
            fmt = config.numfig_format.get(figtype, f"{figtype.capitalize()} %s")
            refs.numbered[label] = fmt % number
        if rest and rest[0]:
            refs.sections[label] = rest[0]
    for doc, title in env.titles.items():
        refs.documents[doc] = title.astext()
        number = env.toc_secnumbers.get(doc, {}).get("")
        if number:
            refs.chapter_numbers[doc] = ".".join(map(str, number))
    cite = env.domains.get("cite")
    if cite is not None:
        for key, entry in cite.bibdata.data.entries.items():
            refs.citations[key] = (_authors(entry), entry.fields.get("year", "n.d."))
    glue_file = Path(app.outdir).parent / "jupyter_execute" / f"{docname}.glue.json"
    if glue_file.exists():
        glued = json.loads(glue_file.read_text(encoding="utf-8"))
        for name, out in glued.items():
            data = out.get("data", {})
            if "text/plain" in data:
                refs.glue[name] = data["text/plain"]
            if "text/markdown" in data:
                refs.glue_markdown[name] = data["text/markdown"]
    return refs


# --------------------------------------------------------------------------------------
# Writing the notebooks
# --------------------------------------------------------------------------------------


def _preface(app: Sphinx, chapter: Chapter) -> str:
    title = app.env.titles[chapter.docname].astext()
    sheet = (
        f" Its exercises, with check cells that give feedback, are in the sheet "
        f"`{chapter.sheet.name}`."
        if chapter.sheet
        else ""
    )
    return (
        f'*Chapter {chapter.number} of **{app.config.html_title}**, "{title}", as a '
        f"notebook. Run it with `dstoolkit[teaching]` installed (the book's page "
        f"*Run this book* says how). The numbers in the text were computed when the "
        f"book was built; the code cells compute them again. Solutions are in the "
        f"book.{sheet}*"
    )


def write_notebooks(app: Sphinx, exception: Exception | None) -> None:
    """Write every chapter's clean notebook and copy its exercise sheet into the site."""
    if exception is not None or app.builder.format != "html":
        return
    import jupytext

    folder = Path(app.outdir) / SITE_FOLDER
    shutil.rmtree(folder, ignore_errors=True)  # written only here: no stale chapter or sheet
    folder.mkdir(parents=True)
    for chapter in chapters(app).values():
        source = Path(app.env.doc2path(chapter.docname))

        def warn(message: str, source: Path = source) -> None:
            logger.warning(f"chapter notebook: {message}", location=str(source))

        cells = jupytext.read(source, fmt="md:myst").cells
        notebook = clean_notebook(
            cells,
            references(app, chapter.docname),
            chapter.docname,
            preface=_preface(app, chapter),
            warn=warn,
        )
        text = json.dumps(notebook, indent=1, ensure_ascii=False) + "\n"
        (folder / chapter.notebook_name).write_text(text, encoding="utf-8")
        # With launch buttons on, the theme copies the executed chapter (raw MyST and its
        # solutions) to _sources/ for download; put the clean notebook in its place.
        theme_copy = Path(app.outdir) / "_sources" / f"{chapter.docname}.ipynb"
        if theme_copy.exists():
            theme_copy.write_text(text, encoding="utf-8")
        if chapter.sheet:
            shutil.copyfile(chapter.sheet, folder / chapter.sheet.name)


# --------------------------------------------------------------------------------------
# Links on the pages
# --------------------------------------------------------------------------------------


def _download_link(href: str, text: str) -> str:
    """Return a link that downloads ``href`` (the file's name is its tooltip)."""
    name = html.escape(href.rsplit("/", 1)[-1])
    return (
        f'<a class="reference download" download title="{name}" '
        f'href="{html.escape(href)}">{text}</a>'
    )


def _run_page(app: Sphinx) -> str | None:
    label = app.env.get_domain("std").labels.get(RUN_LABEL)
    return label[0] if label else None


def _chapter_line(app: Sphinx, chapter: Chapter) -> nodes.raw:
    """Return the line under a chapter's title: its notebook, its sheet, how to run them."""
    base = app.builder.get_target_uri(chapter.docname)
    parts = [
        _download_link(relative_uri(base, chapter.notebook_path), "this chapter as a notebook")
    ]
    if chapter.sheet_path:
        parts.append(_download_link(relative_uri(base, chapter.sheet_path), "its exercise sheet"))
    run = _run_page(app)
    how = ""
    if run:
        href = app.builder.get_relative_uri(chapter.docname, run)
        how = f' (<a class="reference internal" href="{href}">how to run them</a>)'
    slides = relative_uri(base, deck_path(chapter.stem))
    text = (
        f'<p class="run-this-chapter">Run it in JupyterLab: {" · ".join(parts)}{how}. '
        f'Teach it: <a class="reference external" href="{slides}">lecture slides</a>.</p>'
    )
    return nodes.raw("", text, format="html")


def _downloads_table(app: Sphinx, docname: str) -> nodes.raw:
    """Return a table of every chapter with its lecture slides, notebook and exercise sheet."""
    base = app.builder.get_target_uri(docname)
    rows = []
    for chapter in chapters(app).values():
        title = html.escape(app.env.titles[chapter.docname].astext())
        page = app.builder.get_relative_uri(docname, chapter.docname)
        sheet = (
            _download_link(relative_uri(base, chapter.sheet_path), "sheet (.ipynb)")
            if chapter.sheet and chapter.sheet_path
            else "—"
        )
        rows.append(
            f'<tr><td>{chapter.number}</td><td><a class="reference internal" href="{page}">'
            f"{title}</a></td><td>"
            f'<a class="reference external" href="{relative_uri(base, deck_path(chapter.stem))}">'
            f"slides</a></td><td>"
            f"{_download_link(relative_uri(base, chapter.notebook_path), 'notebook (.ipynb)')}"
            f"</td><td>{sheet}</td></tr>"
        )
    table = (
        '<table class="table chapter-downloads"><thead><tr><th>#</th><th>Chapter</th>'
        "<th>Lecture slides</th><th>Chapter notebook</th><th>Exercise sheet</th></tr>"
        "</thead><tbody>" + "".join(rows) + "</tbody></table>"
    )
    return nodes.raw("", table, format="html")


def _download_pages(env) -> set[str]:
    """Return the pages that hold a ``{chapter-downloads}`` table (kept in the environment)."""
    if not hasattr(env, "dstoolkit_download_pages"):
        env.dstoolkit_download_pages = set()
    return env.dstoolkit_download_pages


def _forget_page(app: Sphinx, env, docname: str) -> None:
    _download_pages(env).discard(docname)


def _merge_pages(app: Sphinx, env, docnames, other) -> None:
    _download_pages(env).update(_download_pages(other) & set(docnames))


def pages_to_rewrite(app: Sphinx, env) -> list[str]:
    """Write the chapter pages and the tables of downloads again on every build.

    They depend on what Sphinx does not watch (the sheets in notebooks/, the list of
    chapters).
    """
    return sorted(set(chapters(app)) | _download_pages(env))


class chapter_downloads(nodes.General, nodes.Element):  # noqa: N801 (docutils node style)
    """Placeholder for the table of downloads, filled in once every chapter is known."""


class ChapterDownloads(SphinxDirective):
    """``{chapter-downloads}``: every chapter with its notebook and exercise sheet."""

    def run(self) -> list[nodes.Node]:
        _download_pages(self.env).add(self.env.docname)
        return [chapter_downloads()]


class RepositoryAddress(SphinxDirective):
    """``{repository-address}``: where to get the code, from ``repository.url``."""

    def run(self) -> list[nodes.Node]:
        url = repository_url(self.config)
        if not url:
            text = (
                "This copy of the book was published without a repository address: "
                "use the folder of the repository you were given (it holds "
                "pyproject.toml, book/ and notebooks/)."
            )
            return [nodes.paragraph(text, text)]
        para = nodes.paragraph()
        para += nodes.Text("The code of the book and of dstoolkit is at ")
        para += nodes.reference(url, url, refuri=url)
        para += nodes.Text(". Get a copy with git:")
        code = f"git clone {url}"
        return [para, nodes.literal_block(code, code, language="bash")]


def resolve_page(app: Sphinx, doctree: nodes.document, docname: str) -> None:
    """Put the run line under each chapter's title and fill in the table of downloads."""
    is_html = app.builder.format == "html"
    for placeholder in list(doctree.findall(chapter_downloads)):
        if is_html:
            placeholder.replace_self(_downloads_table(app, docname))
        else:
            text = "The chapter notebooks and sheets are downloaded from the book's web pages."
            placeholder.replace_self(nodes.paragraph(text, text))
    chapter = chapters(app).get(docname)
    if not (is_html and chapter):
        return
    section = next(iter(doctree.findall(nodes.section)), None)
    if section is not None and isinstance(section[0], nodes.title):
        section.insert(1, _chapter_line(app, chapter))


# --------------------------------------------------------------------------------------
# Header buttons
# --------------------------------------------------------------------------------------


def repository_url(config) -> str:
    """Return the repository address (``repository.url`` of _config.yml), or ""."""
    return (config.html_theme_options.get("repository_url") or "").strip()


def switch_repository_buttons(app: Sphinx, config) -> None:
    """Repository and launch buttons on when the address is set, off (none dead) when not."""
    options = config.html_theme_options
    url = repository_url(config)
    options["use_repository_button"] = bool(url)
    if not url:
        for key in ("use_issues_button", "use_edit_page_button", "use_source_button"):
            options[key] = False
        launch = dict(options.get("launch_buttons") or {})
        for key in list(launch):
            if key.endswith("_url"):
                launch[key] = ""
        launch["thebe"] = False
        options["launch_buttons"] = launch


def _group(buttons: list[dict], label: str) -> dict | None:
    return next((b for b in buttons if b.get("label") == label), None)


def add_header_entries(
    app: Sphinx, pagename: str, templatename: str, context: dict, doctree
) -> None:
    """Chapter notebook and sheet in the download menu; launch buttons open the sheet."""
    chapter = chapters(app).get(pagename)
    buttons = context.get("header_buttons", [])
    launch = _group(buttons, "launch-buttons")
    if launch is not None:
        if chapter is None or chapter.sheet is None:
            buttons.remove(launch)
        else:
            page_path = str(Path(app.env.doc2path(pagename)).relative_to(app.srcdir))
            sheet_path = f"{SHEETS_FOLDER}/{chapter.sheet.name}"
            for button in launch["buttons"]:
                if "url" in button:
                    button["url"] = button["url"].replace(page_path, sheet_path)
                    button["tooltip"] = f"Open the exercise sheet on {button['text']}"
    downloads = _group(buttons, "download-buttons")
    if chapter is None or downloads is None:
        return
    pathto = context["pathto"]
    entries = [
        {
            "type": "link",
            "url": pathto(chapter.notebook_path, 1),
            "text": ".ipynb",
            "icon": "fas fa-book",
            "tooltip": "This chapter as a notebook, to run in JupyterLab (no solutions)",
            "label": NOTEBOOK_BUTTON,
        }
    ]
    if chapter.sheet_path:
        entries.append(
            {
                "type": "link",
                "url": pathto(chapter.sheet_path, 1),
                "text": "sheet",
                "icon": "fas fa-pencil",
                "tooltip": "The chapter's exercise sheet (.ipynb)",
                "label": SHEET_BUTTON,
            }
        )
    kept = [b for b in downloads["buttons"] if b.get("label") != "download-notebook-button"]
    downloads["buttons"] = entries + kept


def setup(app: Sphinx) -> dict:
    app.connect("config-inited", switch_repository_buttons)
    app.connect("env-purge-doc", _forget_page)
    app.connect("env-merge-info", _merge_pages)
    app.connect("env-updated", pages_to_rewrite)
    app.connect("doctree-resolved", resolve_page)
    app.connect("html-page-context", add_header_entries, priority=600)
    app.connect("build-finished", write_notebooks)
    app.add_node(chapter_downloads)
    app.add_directive("chapter-downloads", ChapterDownloads)
    app.add_directive("repository-address", RepositoryAddress)
    app.add_js_file(None, body=_SET_DOWNLOAD)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
