"""The PDF edition: `bash scripts/build-pdf.sh` builds the whole book through XeLaTeX.

Checks the PDF as a reader would get it: every chapter is in it (its title in the text of
the PDF), its figures are there (embedded images, at least one per figure of the web
edition), every figure carries its written description as its alternate text (the ``/Alt``
of a marked-content span around the picture, as on the web), the outline (bookmarks) holds
every chapter and each of its sections, the LaTeX log has no missing glyph and no undefined
reference or citation, and a few pages turned into PNGs (pdftoppm) are not blank. The PNGs
go to test-artifacts/pdf/.

Needs XeLaTeX (TeX Live), latexmk and poppler-utils; without them the test skips, except
when DSTOOLKIT_REQUIRE_PDF=1 (CI), where it fails.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import zlib
from pathlib import Path

import pytest
from conftest import ARTIFACTS, ROOT, toc_pages

pytestmark = pytest.mark.slow

REQUIRE_PDF = os.environ.get("DSTOOLKIT_REQUIRE_PDF") == "1"
LATEX_DIR = ROOT / "_build" / "latex"
SHOTS = ARTIFACTS / "pdf"
TOOLS = ("xelatex", "latexmk", "pdftoppm", "pdftotext", "pdfimages", "pdfinfo", "pdftohtml")
#: Lines of the LaTeX log that mean a reader sees something wrong.
LOG_PROBLEMS = re.compile(
    r"Missing character: There is no .*|"
    r"LaTeX Warning: (Reference|Citation|Hyper reference) .* undefined.*|"
    r"LaTeX Warning: There were undefined references.*|"
    r"! .*"
)


def _run(*args: str | Path) -> str:
    return subprocess.run([str(a) for a in args], check=True, capture_output=True, text=True).stdout


@pytest.fixture(scope="module")
def pdf() -> Path:
    missing = [tool for tool in TOOLS if shutil.which(tool) is None]
    if missing:
        reason = f"the PDF edition needs {missing} (TeX Live, latexmk, poppler-utils)"
        if REQUIRE_PDF:
            pytest.fail(reason + " (DSTOOLKIT_REQUIRE_PDF=1)")
        pytest.skip(reason)
    result = subprocess.run(
        ["bash", str(ROOT / "scripts" / "build-pdf.sh")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=5400,
    )
    ARTIFACTS.mkdir(exist_ok=True)
    (ARTIFACTS / "pdf-build.log").write_text(result.stdout + result.stderr, encoding="utf-8")
    assert result.returncode == 0, (result.stdout + result.stderr)[-3000:]
    found = sorted(LATEX_DIR.glob("*.pdf"), key=lambda p: p.stat().st_mtime)
    assert found, f"no PDF in {LATEX_DIR}"
    return found[-1]


def _chapter_titles() -> dict[str, str]:
    """Return the first heading of every page of the table of contents.

    The root page opens the book without a chapter heading: its first sentence stands for
    it.
    """
    titles = {}
    for page in toc_pages()[1:]:
        text = (ROOT / f"{page}.md").read_text(encoding="utf-8")
        match = re.search(r"^# (.+)$", text, flags=re.M)
        if match:
            titles[page] = match.group(1).strip()
    return titles


def _words(text: str) -> str:
    return re.sub(r"\W+", " ", text).lower()


def test_every_chapter_is_in_the_pdf(pdf: Path) -> None:
    text = _words(_run("pdftotext", "-layout", pdf, "-"))
    titles = _chapter_titles()
    assert len(titles) >= 12
    root = (ROOT / f"{toc_pages()[0]}.md").read_text(encoding="utf-8")
    first_sentence = re.search(r"^# [^\n]+\n\n([^;.]+)", root, flags=re.M)
    assert first_sentence, "the opening sentence of the root page"
    titles["root page"] = first_sentence.group(1)
    missing = [
        f"{page}: {title!r}" for page, title in titles.items() if _words(title).strip() not in text
    ]
    assert not missing, f"chapters missing from the PDF: {missing}"


def test_only_the_numbered_parts_have_chapter_numbers(pdf: Path) -> None:
    """The table of contents numbers the chapters of the numbered parts of _toc.yml only.

    So does the web edition; the back matter (Notation, Glossary, ...) is not numbered.
    """
    import yaml

    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    titles = _chapter_titles()
    contents = [
        " ".join(line.split())
        for line in _run("pdftotext", "-layout", "-l", "8", pdf, "-").splitlines()
    ]
    number = 0
    for part in toc["parts"]:
        for chapter in part["chapters"]:
            title = titles[chapter["file"]]
            line = next(
                (ln for ln in contents if ln.startswith((f"{number + 1} {title}", title))), None
            )
            assert line is not None, f"{title!r} is not in the table of contents"
            if part.get("numbered"):
                number += 1
                assert line.startswith(f"{number} {title}"), line
            else:
                assert line.startswith(title), f"a back-matter chapter is numbered: {line}"


def test_the_latex_log_is_clean(pdf: Path) -> None:
    log = pdf.with_suffix(".log").read_text(encoding="utf-8", errors="replace")
    problems = sorted({m.group(0)[:160] for m in LOG_PROBLEMS.finditer(log)})
    assert not problems, "LaTeX log:\n  " + "\n  ".join(problems[:30])


def _figures_and_explorers() -> tuple[int, int]:
    """Numbered figures (cells with a figure caption) and explorer cells of the chapters."""
    import jupytext

    figures = explorers = 0
    for page in toc_pages():
        for cell in jupytext.read(ROOT / f"{page}.md").cells:
            if cell.cell_type != "code":
                continue
            if cell.metadata.get("mystnb", {}).get("figure"):
                figures += 1
            lines = cell.source.strip().splitlines()
            if lines and re.match(r"^\w*(explorer|widget)\(", lines[-1]):
                explorers += 1
    return figures, explorers


def test_the_figures_are_in_the_pdf(pdf: Path) -> None:
    listing = _run("pdfimages", "-list", pdf).splitlines()[2:]
    images = [line for line in listing if line.split() and line.split()[2] == "image"]
    figures, explorers = _figures_and_explorers()
    assert figures > 30 and explorers > 8, (figures, explorers)
    # every captioned figure and the first figure of every explorer
    assert len(images) >= figures + explorers, (
        f"{len(images)} images in the PDF for {figures} figures and {explorers} explorers"
    )


def test_pages_render_and_are_not_blank(pdf: Path) -> None:
    pages = int(re.search(r"Pages:\s+(\d+)", _run("pdfinfo", pdf)).group(1))
    assert pages > 100, f"only {pages} pages"
    SHOTS.mkdir(parents=True, exist_ok=True)
    from PIL import Image

    for number in sorted({1, 2, pages // 4, pages // 2, 3 * pages // 4, pages}):
        prefix = SHOTS / f"page-{number:03d}"
        _run("pdftoppm", "-png", "-r", "60", "-f", number, "-l", number, "-singlefile", pdf, prefix)
        image = Image.open(prefix.with_suffix(".png")).convert("L")
        dark = image.point(lambda value: 255 if value < 128 else 0).histogram()[255]
        assert dark > 200, f"page {number} looks blank ({dark} dark pixels)"


def _headings(page: str) -> list[str]:
    """Return the chapter heading (``# ``) and the section headings (``## ``) of a page.

    Only those outside code count, with their maths left out (an outline entry cannot hold
    TeX).
    """
    import jupytext

    found = []
    for cell in jupytext.read(ROOT / f"{page}.md").cells:
        if cell.cell_type == "markdown":
            found += re.findall(r"^##? (.+)$", cell.source, flags=re.M)
    return [" ".join(_words(re.sub(r"\$[^$]*\$", " ", title)).split()) for title in found]


def _outline(pdf: Path) -> list[str]:
    """Return the titles of the PDF's outline (bookmarks), at every level (pdftohtml -xml)."""
    xml = _run("pdftohtml", "-xml", "-i", "-q", "-stdout", "-f", "1", "-l", "1", pdf)
    outline = re.search(r"<outline>.*</outline>", xml, flags=re.S)
    assert outline, "the PDF has no outline"
    items = re.findall(r"<item[^>]*>(.*?)</item>", outline.group(0), flags=re.S)
    return [" ".join(_words(re.sub(r"<[^>]+>", "", item)).split()) for item in items]


def test_the_outline_holds_every_chapter_and_section(pdf: Path) -> None:
    outline = _outline(pdf)
    expected = {page: _headings(page) for page in toc_pages()[1:]}
    assert sum(len(titles) for titles in expected.values()) > 100, expected
    missing = [
        f"{page}: {title!r}"
        for page, titles in expected.items()
        for title in titles
        if not any(title in entry for entry in outline)
    ]
    assert not missing, f"{len(missing)} headings not in the outline: {missing[:20]}"


_STREAM = re.compile(rb"stream\r?\n(.*?)\r?\nendstream", re.S)
_ALT = re.compile(rb"/Alt\s*<([0-9A-Fa-f\s]*)>")


def _alternate_texts(pdf: Path) -> list[str]:
    """Every ``/Alt`` of a marked-content span in the PDF's (deflated) content streams."""
    found = []
    for stream in _STREAM.finditer(pdf.read_bytes()):
        try:
            data = zlib.decompress(stream.group(1))
        except zlib.error:
            data = stream.group(1)
        for digits in _ALT.findall(data):
            raw = bytes.fromhex(re.sub(rb"\s", b"", digits).decode())
            text = raw[2:].decode("utf-16-be") if raw[:2] == b"\xfe\xff" else raw.decode()
            found.append(" ".join(text.split()))
    return found


def _figure_descriptions() -> dict[str, str]:
    """Each captioned figure's written description (its ``mystnb.image.alt``)."""
    import jupytext

    described = {}
    for page in toc_pages():
        for cell in jupytext.read(ROOT / f"{page}.md").cells:
            mystnb = cell.metadata.get("mystnb", {})
            alt = mystnb.get("image", {}).get("alt")
            if cell.cell_type == "code" and mystnb.get("figure") and alt:
                described[f"{page}: {mystnb['figure'].get('name')}"] = " ".join(alt.split())
    return described


def test_every_figure_has_its_description_as_alternate_text(pdf: Path) -> None:
    descriptions = _figure_descriptions()
    figures, _ = _figures_and_explorers()
    assert len(descriptions) == figures, "a figure of the book has no written description"
    alternates = set(_alternate_texts(pdf))
    missing = [name for name, alt in descriptions.items() if alt not in alternates]
    assert not missing, f"figures without their description in the PDF: {missing}"
