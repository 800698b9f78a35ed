"""Editorial rules of the book that a script can check.

- no chapter has more than about 4,000 words of prose (code cells and maths not counted);
- no internal working document is named anywhere a reader or user looks (the book, the
  package, the notebooks, the tests): cite the paper instead;
- every work cited with {cite} is in book/references.bib with author, title and year;
- the lab's widget starts at the volume the lab's safety advice gives;
- the notation page's promises hold in the sources: the sweep rate is κ, never k (the
  step); K is the conflict, never a count; no parameter named c is a triangle's mode.
"""

from __future__ import annotations

import ast
import inspect
import re
from collections.abc import Iterator

import jupytext
import pytest
from conftest import ROOT, toc_pages

MAX_PROSE_WORDS = 4000
INTERNAL = re.compile(r"\b(SPEC|DESIGN)(\.md)?\b")
CITE = re.compile(r"\{cite(?::[a-z]+)?\}`([^`]+)`")
FENCED_CODE = re.compile(r"```(?:python|bash|text|console)?\n.*?```", flags=re.S)
DISPLAY_MATHS = re.compile(r"\$\$.*?\$\$", flags=re.S)


def prose_words(page: str) -> int:
    notebook = jupytext.read(ROOT / f"{page}.md")
    words = 0
    for cell in notebook.cells:
        if cell.cell_type == "markdown":
            text = DISPLAY_MATHS.sub(" ", FENCED_CODE.sub(" ", cell.source))
            words += len(re.findall(r"[A-Za-z][A-Za-z'’-]+", text))
    return words


@pytest.mark.parametrize("page", toc_pages())
def test_no_chapter_is_a_wall_of_prose(page: str) -> None:
    words = prose_words(page)
    assert words <= MAX_PROSE_WORDS, f"{page}: {words} words of prose"


def test_the_counter_counts_prose() -> None:
    assert 600 < prose_words("book/intro") < 2000


def test_no_internal_document_is_named() -> None:
    found = []
    for folder, pattern in (
        ("book", "*.md"),
        ("dstoolkit", "*.py"),
        ("tests", "*.py"),
        ("notebooks", "*.ipynb"),
        ("scripts", "*.sh"),
    ):
        for path in sorted((ROOT / folder).rglob(pattern)):
            if path.name == "test_book_text.py":
                continue
            for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                if INTERNAL.search(line):
                    found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()[:80]}")
    assert not found, "internal documents named:\n  " + "\n  ".join(found)


def test_every_cited_work_is_in_the_bibliography() -> None:
    bib = (ROOT / "book" / "references.bib").read_text(encoding="utf-8")
    entries = dict(re.findall(r"@\w+\{(\w+),(.*?)\n\}", bib, flags=re.S))
    cited = set()
    for path in (ROOT / "book").glob("*.md"):
        for keys in CITE.findall(path.read_text(encoding="utf-8")):
            cited.update(key.strip() for key in keys.split(","))
    assert {"wu1996", "cramer1993", "xu2017"} <= cited
    missing = sorted(cited - set(entries))
    assert not missing, f"cited but not in references.bib: {missing}"
    incomplete = [
        key
        for key in cited
        if not all(
            re.search(rf"\b{field}\s*=", entries[key]) for field in ("author", "title", "year")
        )
    ]
    assert not incomplete, f"entries without author, title or year: {incomplete}"


def test_the_lab_widget_starts_at_the_safe_volume() -> None:
    from dstoolkit.teaching import LabSettings

    lab = (ROOT / "book" / "lab.md").read_text(encoding="utf-8")
    advice = re.search(r"volume low \((\d\.\d+) in the widget\)", lab)
    assert advice, "the lab's safety advice on the volume is gone"
    assert LabSettings().volume == pytest.approx(float(advice.group(1)))


#: The sweep rate written k (the step's letter): k L/c, kτ, f₀ + k t, "sweep rate k".
SWEEP_RATE_AS_K = re.compile(
    r"\bk ?L ?/ ?c\b|\bk ?τ|\bk ?\\tau\b|\+ ?k ?t\b|sweep rate k\b|\bk ?Δ|\bk ?\\Delta\b"
)


def _notation_sources() -> list:
    return [
        *sorted((ROOT / "book").glob("*.md")),
        *sorted((ROOT / "notebooks" / "source").glob("*.md")),
        *sorted((ROOT / "dstoolkit").rglob("*.py")),
        ROOT / "scripts" / "lab_handout.py",
    ]


def test_the_sweep_rate_is_never_written_k() -> None:
    found = [
        f"{path.relative_to(ROOT)}:{number}: {line.strip()[:80]}"
        for path in _notation_sources()
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if SWEEP_RATE_AS_K.search(line)
    ]
    assert not found, "the sweep rate is κ (k is the step):\n  " + "\n  ".join(found)


def test_the_pattern_finds_the_sweep_rate_written_k() -> None:
    for wrong in ("−(kL/c + kτ)", "a constant k L / c higher", "f₀ + k t", "$f_L + kt$", "k Δ²"):
        assert SWEEP_RATE_AS_K.search(wrong), wrong
    for right in ("−(κL/c + κτ)", "n_k f_F", "z_k/(z_{k+1} - z_k)", "step k of"):
        assert not SWEEP_RATE_AS_K.search(right), right


def test_the_conflict_letter_is_not_a_count() -> None:
    # K is the conflict; a run's number of readings is N_z
    found = [
        f"{path.name}:{number}: {line.strip()[:80]}"
        for path in sorted((ROOT / "book").glob("*.md"))
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if re.search(r"z_K\b|_\{?K\}?\$? readings|el_K\b|\bK\$? readings", line)
    ]
    assert not found, found


def _parameters(tree: ast.AST) -> Iterator[tuple[str, int, list[str]]]:
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            args = node.args
            names = [a.arg for a in (*args.posonlyargs, *args.args, *args.kwonlyargs)]
            yield getattr(node, "name", "lambda"), node.lineno, names


def test_no_parameter_named_c_is_a_mode() -> None:
    # c is the speed of sound; a triangle's (a, c, b) would make c its mode
    sources = {
        str(path.relative_to(ROOT)): path.read_text(encoding="utf-8")
        for path in sorted((ROOT / "dstoolkit").rglob("*.py"))
    }
    for page in sorted((ROOT / "book").glob("*.md")):
        if "file_format: mystnb" not in page.read_text(encoding="utf-8"):
            continue  # a page without code cells (its fences are shell commands)
        notebook = jupytext.read(page)
        cells = [c.source for c in notebook.cells if c.cell_type == "code"]
        code = "\n".join(
            "\n".join(line for line in cell.splitlines() if not line.startswith(("%", "!")))
            for cell in cells
        )
        sources[str(page.relative_to(ROOT))] = code
    found = [
        f"{name}:{line} {function}({', '.join(names)})"
        for name, text in sources.items()
        for function, line, names in _parameters(ast.parse(text))
        if "c" in names and {"a", "b"} & set(names)
    ]
    assert not found, found


def test_the_triangle_exercises_name_their_mode() -> None:
    from answer_key import plain_solutions as plain

    for function in (plain.triangular_rows, plain.triangle_sigma):
        names = list(inspect.signature(function).parameters)
        assert names[:3] == ["lower", "mode", "upper"], (function.__name__, names)


#: Slips a reader found, each with what the corrected source says: (page, wrong, right).
FIXED_SLIPS = [
    # the noise enters Step 2 twice (eq. rf-predict); the loop figure's Step 2 says so
    ("why_bounded_noise", r"f\(\\\\hat\{x\}_k \+ E_v\)\$", r"f\(\\\\hat\{x\}_k \+ E_v\) \+ E_v\$"),
    # classical discounting is the paper's eq. 26; eqs. 9–10 are the decorrelation
    ("combining_evidence", r"more on \$\\Theta\$ \(the paper's eqs\. 9–10\)", r"eq\. 26"),
    # the filter restarts from its estimate at every step: nothing shrinks across steps
    ("combining_evidence", r"shrink the state evidence step after step", r"at every step"),
    # humid air makes the level short: the error of Fig. 8.2 is negative
    (
        "level_gauge",
        r"positive error: the estimate is too long",
        r"negative \(the estimate too short\)",
    ),
    # a typed ratio of run times went stale; the ratio is glued
    ("beyond_the_paper", r"a thousand times cheaper", r"bp_kalman_cheaper"),
    # the key point on long tubes holds only with eq. 43's orders
    ("estimating_level", r"^- On long tubes every method ends near", r"el_ratio_96"),
    # subdivision is an inner approximation, not "a method that is right"
    ("random_sets", r"falls back to a method that is right", r"never narrower"),
]


@pytest.mark.parametrize(("page", "wrong", "right"), FIXED_SLIPS)
def test_a_fixed_slip_stays_fixed(page: str, wrong: str, right: str) -> None:
    text = (ROOT / "book" / f"{page}.md").read_text(encoding="utf-8")
    assert not re.search(wrong, text, flags=re.M), f"{page}: {wrong}"
    assert re.search(right, text, flags=re.M), f"{page}: {right}"
