"""What a course needs from every chapter.

A recap, annotated reading, solutions that end with their reasoning, the instructors'
page in the table of contents, and a 6-week plan whose sessions hold its class hours.
"""

from __future__ import annotations

import re

import jupytext
import pytest
from conftest import ROOT

CHAPTERS = [
    "why_bounded_noise",
    "mass_functions",
    "combining_evidence",
    "dependent_evidence",
    "random_sets",
    "noise_to_evidence",
    "recursive_filter",
    "level_gauge",
    "simulated_gauge",
    "estimating_level",
    "beyond_the_paper",
    "lab",
    "one_recursion",
    "beyond_dempster",
]


def section(text: str, title: str) -> str:
    found = re.search(rf"^## {title}\n(.*?)(?=^## |\Z)", text, flags=re.M | re.S)
    return found.group(1) if found else ""


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_chapter_ends_with_key_points_and_further_reading(chapter: str) -> None:
    text = (ROOT / "book" / f"{chapter}.md").read_text(encoding="utf-8")
    headings = re.findall(r"^## (.+)$", text, flags=re.M)
    assert headings[-2:] == ["Key points", "Further reading"], headings[-3:]
    points = re.findall(r"^- ", section(text, "Key points"), flags=re.M)
    assert 3 <= len(points) <= 6, f"{chapter}: {len(points)} key points"
    reading = section(text, "Further reading")
    entries = re.findall(r"^- (.+?)(?=^- |\Z)", reading, flags=re.M | re.S)
    assert entries, f"{chapter}: no further reading"
    for entry in entries:
        assert "{cite" in entry, f"{chapter}: an entry cites nothing: {entry[:60]}"
        annotation = re.sub(r"\{cite:[a-z]+\}`[^`]+`", "", entry)
        assert len(annotation.split()) >= 6, f"{chapter}: entry not annotated: {entry[:60]}"


@pytest.mark.parametrize(
    "key",
    [
        "shafer1976",
        "smets1994",
        "denoeux2008",
        "jaulin2001",
        "sarkka2013",
        "barshalom2001",
        "pierce2019",
    ],
)
def test_the_core_reading_is_cited_with_a_doi(key: str) -> None:
    bib = (ROOT / "book" / "references.bib").read_text(encoding="utf-8")
    entry = re.search(rf"@\w+\{{{key},(.*?)\n\}}", bib, flags=re.S)
    assert entry and "doi" in entry.group(1), key
    cited = "".join((ROOT / "book" / f"{c}.md").read_text(encoding="utf-8") for c in CHAPTERS)
    assert key in cited


def test_no_solution_ends_with_a_bare_final_answer() -> None:
    found = [
        f"{path.name}"
        for path in sorted((ROOT / "book").glob("*.md"))
        if "The final answer" in path.read_text(encoding="utf-8")
    ]
    assert not found, found


def test_the_teaching_page_is_in_the_back_matter() -> None:
    toc = (ROOT / "_toc.yml").read_text(encoding="utf-8")
    back = toc.split("caption: Back matter", 1)[1]
    assert "file: book/teaching" in back


def _teaching_plan() -> dict:
    """CHAPTERS and SIX_WEEKS of the teaching page, from its own code cells."""
    notebook = jupytext.read(ROOT / "book" / "teaching.md")
    found: dict = {}
    for cell in notebook.cells:
        if cell.cell_type != "code":
            continue
        for name in ("CHAPTERS", "SIX_WEEKS"):
            block = re.search(rf"^{name} = [\[{{].*?^[\]}}]$", cell.source, flags=re.M | re.S)
            if block:
                exec(block.group(0), found)  # a literal: chapter hours, the weekly plan
    return found


def test_the_six_week_plan_fits_its_sessions() -> None:
    plan = _teaching_plan()
    hours = [sum(plan["CHAPTERS"][k][2] for k in ks) for ks, _ in plan["SIX_WEEKS"]]
    text = (ROOT / "book" / "teaching.md").read_text(encoding="utf-8")
    prose = section(text, "A 6-week graduate module")
    words = {"one": 1, "two": 2, "three": 3, "four": 4}
    fixed = re.search(r"\b(one|two|three|four) sessions a week of 90 minutes", prose, re.I)
    if fixed:  # a fixed number of sessions a week must hold the longest week
        assert max(hours) <= 1.5 * words[fixed.group(1).lower()], (fixed.group(0), hours)
    # otherwise the table gives each week's sessions, computed from the same hours
    assert "sessions of 90 min" in prose and "math.ceil(h / SESSION_H)" in prose
    assert sorted(k for ks, _ in plan["SIX_WEEKS"] for k in ks) == sorted(plan["CHAPTERS"])


def test_the_plan_reader_finds_the_plan() -> None:
    plan = _teaching_plan()
    assert len(plan["CHAPTERS"]) == 14 and len(plan["SIX_WEEKS"]) == 6
