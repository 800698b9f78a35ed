"""Numbers for people: no chapter output shows a float with more than 6 significant digits.

Scans every output a reader sees in the executed chapters of the built book
(_build/jupyter_execute/book/*.ipynb): printed text, reprs, Markdown and HTML tables, error
messages. Numbers glued into the prose are not shown as outputs (their formats are set in
the prose) and widget views are skipped; their readouts are formatted by the explorers.
"""

from __future__ import annotations

import re

import nbformat
import pytest
from conftest import ROOT, BookBuild, toc_pages

EXECUTED = ROOT / "_build" / "jupyter_execute"
MAX_DIGITS = 6
#: A decimal number (optionally in scientific notation), not part of a word or a version.
FLOAT = re.compile(r"(?<![\w.])-?(\d+)\.(\d+)(?:[eE][+-]?\d+)?(?![\w.]*\d)")
SHOWN = ("text/plain", "text/markdown", "text/html", "text/latex")
WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"


def significant_digits(integer: str, fraction: str) -> int:
    """Significant digits of integer.fraction as written (trailing zeros count)."""
    digits = (integer + fraction).lstrip("0")
    return len(digits)


def long_floats(text: str) -> list[str]:
    """Return the numbers in ``text`` written with more than MAX_DIGITS significant digits."""
    return [
        m.group(0)
        for m in FLOAT.finditer(text)
        if significant_digits(m.group(1), m.group(2)) > MAX_DIGITS
    ]


def shown_texts(output: nbformat.NotebookNode) -> list[str]:
    """Return what a reader sees of one output cell output."""
    if output.get("metadata", {}).get("scrapbook"):
        return []  # glued for the prose, not displayed
    if output.output_type == "stream":
        return [output.text]
    if output.output_type == "error":
        return [f"{output.ename}: {output.evalue}"]
    data = output.get("data", {})
    if WIDGET_VIEW in data:
        return []
    return [
        data[kind] if isinstance(data[kind], str) else "".join(data[kind])
        for kind in SHOWN
        if kind in data
    ][:1]


def test_the_counter_counts() -> None:
    assert long_floats("joint_energy=0.44999999999999996, degree=0.75") == ["0.44999999999999996"]
    assert long_floats("TriangularBounds(lower=-10.901339920443462") == ["-10.901339920443462"]
    assert long_floats("0.4500 1.234e-05 2026.12.1 v1.19.6 3.14159") == []
    assert long_floats("1234.5678 0.000012345678") == ["1234.5678", "0.000012345678"]


def test_the_printed_results_are_short() -> None:
    """The results chapters print are short.

    They are: dependence, noise bounds, recording conditions and metadata, a run's summary.
    """
    from dstoolkit.audio import RecordingMetadata
    from dstoolkit.evidence import IntervalEvidence, TriangularBounds, dependence
    from dstoolkit.teaching import GAUGE_CONDITIONS

    e1 = IntervalEvidence.from_pairs([[-0.3, 2.6, 0.3], [0.3, 1.9, 0.7]])
    e2 = IntervalEvidence.from_pairs([[0.41, 1.61, 0.3], [0.3, 1.9, 0.7]])
    shown = [
        repr(dependence(e1, e2)),
        repr(TriangularBounds(-10.901339920443462, -6.732151115173963, -2.5629623)),
        repr(GAUGE_CONDITIONS),
        repr(RecordingMetadata(latency_s=0.13700680272108842, extra={"lag": 0.13700680272108842})),
    ]
    for text in shown:
        assert not long_floats(text), text
    assert "TriangularBounds(lower=-10.9, mode=-6.732, upper=-2.563)" in shown[1]


@pytest.mark.slow
def test_no_chapter_prints_float_noise(built_book: BookBuild) -> None:
    assert built_book.returncode == 0, built_book.tail(30)
    problems = []
    chapters = [page for page in toc_pages() if (EXECUTED / f"{page}.ipynb").is_file()]
    assert len(chapters) >= 10, f"executed chapters missing in {EXECUTED}: {chapters}"
    for page in chapters:
        notebook = nbformat.read(EXECUTED / f"{page}.ipynb", as_version=4)
        for index, cell in enumerate(notebook.cells):
            for output in cell.get("outputs", []):
                for text in shown_texts(output):
                    found = long_floats(text)
                    if found:
                        source = cell.source.strip().splitlines()
                        problems.append(
                            f"{page}, cell {index} ({source[-1][:50] if source else ''}"
                            f"): {found[:4]}"
                        )
    assert not problems, "floats with more than 6 significant digits:\n  " + "\n  ".join(problems)
