"""The private exam bank and the sample exams: worked solutions and marking schemes, as PDFs.

    .venv/bin/python scripts/exams.py DIR    # DIR/<exam>.pdf and DIR/<exam>-teacher.pdf

Every chapter's exam problems (its exercises titled "Exam, difficulty d of 3") have their
statement in the book, and their worked solution and marking scheme only in the bank,
``instructor/exams/<chapter stem>.yml`` (see ``instructor/exams/README.md``): neither the book's
site nor the students' sheets show them. :func:`with_exam_solutions` gives the teacher's
edition of the sheets (``scripts/sheets.py --teacher DIR``) each exam problem's solution
and marking scheme, and the same command calls :func:`build` to write the sample exams of
``instructor/exams/exams.yml`` to ``DIR/exams/``: for each, a student edition (the problems,
with the points of each part) and a teacher's edition (with the worked solutions and the
marking schemes), typeset by XeLaTeX as the lab handout is.

Each exam is built from the exam problems of the chapters it covers, with the statements of
the exercise sheets (plain numbers instead of the book's cross-references). Its duration is
the time of the longest problems a candidate may choose, at the teaching page's time per
difficulty (:data:`MINUTES`).
"""

from __future__ import annotations

import re
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

ROOT = Path(__file__).resolve().parents[1]
BANK = Path("instructor") / "exams"
#: Minutes a problem takes by difficulty, as the teaching page states them.
MINUTES = {1: 10, 2: 30, 3: 60}
#: Points of every exam problem: its marking scheme's parts add up to this.
POINTS = 25
MATHS = re.compile(r"\$\$.*?\$\$|\$[^$]*\$|\\\(.*?\\\)|\\\[.*?\\\]", re.DOTALL)
PLACEHOLDER = re.compile(r"\{\{(\w+)\}\}")
PART = re.compile(r"\*\*\(([a-z])\)\*\*")
YOUR_ANSWER = re.compile(r"\n*\*Your answer:\*.*\Z", re.DOTALL)


# -- numbers the solutions print, computed with dstoolkit ----------------------------------


def _offsets() -> dict[str, str]:
    """sg-ex-offsets: the sweep's and the latency's shares of a reading at 4.6 m, 26.5 °C."""
    from dstoolkit.gauge import PAPER_SWEEP, speed_of_sound

    kappa, c, latency_s = float(PAPER_SWEEP.rate), float(speed_of_sound(26.5)), 0.010
    sweep, late = kappa * 4.6 / c, kappa * latency_s
    return {
        "sweep_offset": f"{sweep:.2f}",
        "latency_offset": f"{late:.2f}",
        "mode": f"{-(sweep + late):.1f}".replace("-", "−"),  # the minus sign of the text
    }


def _resample() -> dict[str, str]:
    """bp-ex-resample: systematic resampling of weights 0.1–0.4 from u0 = 0.2."""
    import numpy as np

    weights = np.array([0.1, 0.2, 0.3, 0.4])
    u = 0.2 + np.arange(4) / 4  # u_i = u_0 + i/N
    picked = np.searchsorted(np.cumsum(weights), u)  # the first cumulative weight >= u_i
    return {
        "resample_u": ", ".join(f"{x:.2f}" for x in u),
        "resampled": ", ".join(str(int(i) + 1) for i in picked),
    }


def _random_walk() -> dict[str, str]:
    """or-ex-exam: one Kalman step of a random walk (q = r = 1, P_1 = 1, z = 0, 2), smoothed."""
    from dstoolkit.filters import nis, rts_smoother

    x1, p1, z2 = 0.0, 1.0, 2.0
    p2_pred = p1 + 1.0  # P⁻_2 = P_1 + q
    gain = p2_pred / (p2_pred + 1.0)  # G = P⁻_2 / (P⁻_2 + r)
    x2, p2 = x1 + gain * (z2 - x1), (1.0 - gain) * p2_pred
    smoothed = rts_smoother([[x1], [x2]], [[[p1]], [[p2]]], [[1.0]], [[1.0]])
    return {
        "gain": f"{gain:.3f}",
        "x2": f"{x2:.3f}",
        "p2": f"{p2:.3f}",
        "nis": f"{float(nis([[z2 - x1]], [[[p2_pred + 1.0]]])[0]):.2f}",
        "j": f"{smoothed.gains[0, 0, 0]:.1f}",
        "xs1": f"{smoothed.estimates[0, 0]:.3f}",
        "ps1": f"{smoothed.covariances[0, 0, 0]:.3f}",
    }


def _cautious_pair() -> dict[str, str]:
    """bd-ex-exam: m1 = {a}: 0.6, Θ: 0.4 and m2 = {a}: 0.3, {a, b}: 0.3, Θ: 0.4 fused."""
    from dstoolkit.evidence import MassFunction, canonical_weights, cautious, dempster

    frame = ("a", "b", "c")
    m1 = MassFunction({"a": 0.6, "abc": 0.4}, frame)
    m2 = MassFunction({"a": 0.3, "ab": 0.3, "abc": 0.4}, frame)
    d, c = dempster(m1, m2), cautious(m1, m2)
    return {
        "d_a": f"{d.mass_of('a'):.2f}",
        "d_ab": f"{d.mass_of('ab'):.2f}",
        "d_theta": f"{d.mass_of('abc'):.2f}",
        "w2_ab": f"{canonical_weights(m2)[frozenset('ab')]:.3f}",
        "c_a": f"{c.mass_of('a'):.2f}",
        "c_ab": f"{c.mass_of('ab'):.3f}",
        "c_theta": f"{c.mass_of('abc'):.3f}",
        "betp_a": f"{c.pignistic()['a']:.3f}",
    }


#: {exam problem's label: the function that computes its solution's {{numbers}}}.
NUMBERS = {
    "sg-ex-offsets": _offsets,
    "bp-ex-resample": _resample,
    "or-ex-exam": _random_walk,
    "bd-ex-exam": _cautious_pair,
}


# -- the bank -------------------------------------------------------------------------------


@dataclass
class Problem:
    label: str
    stem: str
    number: int  # the chapter's number
    order: int  # k of "Exercise number.k"
    difficulty: int
    statement: str  # Markdown, as the exercise sheet states it
    solution: str  # Markdown, numbers filled in
    marking: list[dict[str, Any]]

    @property
    def minutes(self) -> int:
        return MINUTES[self.difficulty]


def _sheets() -> Any:
    here = str(Path(__file__).resolve().parent)
    if here not in sys.path:
        sys.path.insert(0, here)
    import sheets

    return sheets


def exam_labels(stem: str, root: Path = ROOT) -> list[str]:
    """Return the labels of the chapter's exam problems, in order."""
    captions = _sheets().chapter_captions(root / "book" / f"{stem}.md")
    return [label for label, caption in captions.items() if caption.startswith("Exam,")]


def bank(stem: str, root: Path = ROOT) -> dict[str, dict[str, Any]]:
    """Return {label: {"solution": Markdown, "marking": [...]}} of the chapter's bank file.

    The solution's ``{{name}}`` are filled in from :data:`NUMBERS`. A chapter without exam
    problems has no file and an empty bank.

    Raises
    ------
    ValueError
        When the file lacks an exam problem of the chapter, names another exercise, or a
        problem's marking scheme does not add up to :data:`POINTS`.
    """
    labels = exam_labels(stem, root)
    path = root / BANK / f"{stem}.yml"
    if not labels and not path.exists():
        return {}
    if not path.exists():
        raise ValueError(f"{stem}: its exam problems {labels} have no {BANK / path.name}")
    data = yaml.safe_load(path.read_text(encoding="utf-8")) or {}
    if sorted(data) != sorted(labels):
        raise ValueError(
            f"{path.name} holds {sorted(data)}; the chapter's exam problems are {labels}"
        )
    out = {}
    for label, entry in data.items():
        total = sum(part["points"] for part in entry["marking"])
        if total != POINTS:
            raise ValueError(
                f"{path.name}: the marking of {label} adds up to {total}, not {POINTS}"
            )
        values = NUMBERS[label]() if label in NUMBERS else {}

        def fill(match: re.Match[str], values: dict[str, str] = values, label: str = label) -> str:
            if match.group(1) not in values:
                raise ValueError(
                    f"{path.name}: {label} has {{{{{match.group(1)}}}}}, not in NUMBERS"
                )
            return values[match.group(1)]

        out[label] = {
            "solution": PLACEHOLDER.sub(fill, entry["solution"].strip()),
            "marking": entry["marking"],
        }
    return out


def marking_markdown(marking: list[dict[str, Any]]) -> str:
    """Return the marking scheme as a Markdown list: part, points, what earns them."""
    rows = [
        f"- **{'whole problem' if m['part'] == 'all' else '(' + m['part'] + ')'}**, "
        f"{m['points']:g} points: {m['earns']}"
        for m in marking
    ]
    return f"**Marking scheme** ({POINTS} points)\n\n" + "\n".join(rows)


def with_exam_solutions(src: Any, root: Path = ROOT) -> Any:
    """Return the sheet source with each exam problem's solution and marking scheme.

    They come as ``solution`` blocks at the end of the problem's blocks, so that only the
    teacher's edition of the sheets (and the grader's copy of an nbgrader course) has them.
    """
    sheets = _sheets()
    found = bank(src.stem, root)
    blocks: list[Any] = []
    current = None
    for block in [*src.blocks, None]:
        starts = block is None or block.kind == "exercise"
        if starts and current in found:
            entry = found[current]
            text = entry["solution"] + "\n\n" + marking_markdown(entry["marking"])
            blocks.append(sheets.Block("solution", "", text))
        if block is None:
            break
        if block.kind == "exercise":
            current = block.arg.split()[0]
        blocks.append(block)
    return sheets.Source(src.stem, src.intro, blocks)


def problems(stems: list[str], root: Path = ROOT) -> list[Problem]:
    """Return the exam problems of the chapters ``stems``, in their order."""
    sheets = _sheets()
    numbers = sheets.chapter_numbers(root / "_toc.yml")
    out = []
    for stem in stems:
        found = bank(stem, root)
        chapter = root / "book" / f"{stem}.md"
        labels = sheets.chapter_exercises(chapter)
        captions = sheets.chapter_captions(chapter)
        src = sheets.in_variant(sheets.parse(root / "notebooks" / "source" / f"{stem}.md"), 0)
        statements = {b.arg.split()[0]: b.text for b in src.blocks if b.kind == "exercise"}
        for label, entry in found.items():
            out.append(
                Problem(
                    label=label,
                    stem=stem,
                    number=numbers[stem],
                    order=labels.index(label) + 1,
                    difficulty=int(sheets.CAPTION.match(captions[label]).group(2)),
                    statement=YOUR_ANSWER.sub("", statements[label]).strip(),
                    solution=entry["solution"],
                    marking=entry["marking"],
                )
            )
    return out


def exams(root: Path = ROOT) -> dict[str, dict[str, Any]]:
    """Return the sample exams of ``exams.yml``, each section with its problems."""
    data = yaml.safe_load((root / BANK / "exams.yml").read_text(encoding="utf-8"))
    for exam in data.values():
        for section in exam["sections"]:
            section["problems"] = problems(section["chapters"], root)
            if not 0 < section["answer"] <= len(section["problems"]):
                raise ValueError(
                    f"{exam['title']}: answer {section['answer']} of "
                    f"{len(section['problems'])} problems"
                )
        exam["minutes"] = sum(
            sum(sorted((p.minutes for p in s["problems"]), reverse=True)[: s["answer"]])
            for s in exam["sections"]
        )
    return data


# -- LaTeX ----------------------------------------------------------------------------------

_SPECIAL = {c: "\\" + c for c in "&%#_{}$"}
_SPECIAL.update({"\\": r"\textbackslash{}", "~": r"\textasciitilde{}", "^": r"\^{}"})


def _text(text: str) -> str:
    """LaTeX of Markdown prose without maths: escapes, bold, emphasis, code."""
    text = "".join(_SPECIAL.get(c, c) for c in text)
    text = re.sub(r"\*\*(.+?)\*\*", r"\\textbf{\1}", text, flags=re.DOTALL)
    text = re.sub(r"(?<![\w*])\*(?!\s)(.+?)(?<!\s)\*(?![\w*])", r"\\emph{\1}", text)
    return re.sub(r"`([^`]+)`", r"\\texttt{\1}", text)


def latex(markdown: str) -> str:
    """LaTeX of a statement or a solution: its maths as written, its prose escaped.

    A Markdown list becomes an itemize.
    """
    parts, last = [], 0
    for found in MATHS.finditer(markdown):
        parts.append(_text(markdown[last : found.start()]))
        maths = found.group(0)
        parts.append(r"\[" + maths[2:-2] + r"\]" if maths.startswith("$$") else maths)
        last = found.end()
    parts.append(_text(markdown[last:]))
    out = "".join(parts)
    if re.search(r"^- ", out, re.M):
        out = re.sub(r"^- ", r"\\item ", out, flags=re.M)
        out = re.sub(
            r"((?:^\\item .*\n?)+)", r"\\begin{itemize}\n\1\\end{itemize}\n", out, flags=re.M
        )
    return out


PREAMBLE = r"""\documentclass[11pt,a4paper]{article}
\usepackage[margin=20mm]{geometry}
\usepackage{amsmath,amssymb}
\usepackage{fontspec}
\setmainfont{FreeSerif}
\usepackage{array,booktabs,tabularx,enumitem}
\setlength{\parindent}{0pt}
\setlength{\parskip}{5pt}
\emergencystretch=3em
\pagestyle{plain}
\begin{document}
"""


def _parts(problem: Problem) -> str:
    return "; ".join(
        f"{'whole problem' if m['part'] == 'all' else '(' + m['part'] + ')'} {m['points']:g}"
        for m in problem.marking
    )


def exam_tex(key: str, teacher: bool, root: Path = ROOT) -> str:
    """Return the LaTeX of the sample exam ``key`` of exams.yml, one edition."""
    exam = exams(root)[key]
    hours, minutes = divmod(exam["minutes"], 60)
    duration = f"{hours} h {minutes:02d} min" if minutes else f"{hours} h"
    total = POINTS * sum(s["answer"] for s in exam["sections"])
    edition = " --- teacher's edition" if teacher else ""
    lines = [
        PREAMBLE,
        rf"{{\LARGE\bfseries {_text(exam['title'])}{edition}}}\par",
        rf"\emph{{Evidence under bounded noise}}: {_text(exam['covers'])}. Time allowed: "
        rf"{duration}. Total: {total} points.\par",
    ]
    if teacher:
        lines.append(
            r"\textbf{Confidential.} Worked solutions and marking schemes: not for students."
            r"\par"
        )
    else:
        lines.append(r"Name: \rule{70mm}{0.4pt} \quad Student number: \rule{40mm}{0.4pt}\par")
    lines.append(
        rf"Each problem carries {POINTS} points; the points of its parts are given after it. "
        "Show your reasoning: a result without its argument earns part of the points at "
        "most. No computer; a calculator is allowed.\\par"
    )
    count = 0
    for section in exam["sections"]:
        n = len(section["problems"])
        if section.get("name"):
            lines.append(rf"\section*{{{_text(section['name'])}}}")
        lines.append(rf"\textbf{{Answer {section['answer']} of the {n} problems below.}}\par")
        for problem in section["problems"]:
            count += 1
            lines.append(
                rf"\subsection*{{Problem {count} (from Exercise {problem.number}."
                rf"{problem.order} of the book)}}"
            )
            lines.append(latex(problem.statement))
            lines.append(rf"\par\emph{{Points: {_parts(problem)}.}}")
            if teacher:
                lines.append(r"\paragraph{Worked solution.} " + latex(problem.solution))
                rows = "\n".join(
                    rf"{'all' if m['part'] == 'all' else '(' + m['part'] + ')'} & "
                    rf"{m['points']:g} & {_text(m['earns'])} \\"
                    for m in problem.marking
                )
                lines.append(
                    r"\par\medskip\textbf{Marking scheme.}\par\nopagebreak"
                    "\n\\noindent\\begin{tabularx}{\\linewidth}{@{}l r X@{}}\n\\toprule\n"
                    r"part & points & what earns them \\ \midrule"
                    f"\n{rows}\n\\bottomrule\n\\end{{tabularx}}"
                )
    lines.append(r"\end{document}")
    return "\n".join(lines) + "\n"


def build(folder: Path, root: Path = ROOT) -> list[Path]:
    """Write every sample exam, student and teacher's edition, as PDFs in ``folder``.

    Raises
    ------
    RuntimeError
        When latexmk or xelatex is missing, or LaTeX fails (the message points at the log).
    """
    from lab_handout import typeset

    out = []
    for key in exams(root):
        for teacher in (False, True):
            name = f"{key}-teacher" if teacher else key
            out.append(typeset(folder, name, exam_tex(key, teacher, root), f"the exam {name}"))
    return out


# -- what must not leave the teacher's edition ------------------------------------------------


def words(text: str) -> str:
    """Return the words of ``text`` without its maths, lower case, one space apart."""
    return " ".join(re.findall(r"[a-z]+", MATHS.sub(" ", text).lower()))


def telltales(root: Path = ROOT, least: int = 8) -> dict[str, list[str]]:
    """Return {exam problem: the runs of words of its solution that give it away}.

    A run is a clause of the solution (between punctuation marks) of at least ``least``
    words, maths left out; found in a page, it shows that the page holds the solution.
    A page that shows the maths as text (a PDF's) has words where the maths was, so the
    stretches of prose between two formulas count as runs too.
    """
    out = {}
    numbers = _sheets().chapter_numbers(root / "_toc.yml")
    for stem in numbers:
        for label, entry in bank(stem, root).items():
            runs = []
            for between in (" ", " ; "):  # maths left out, or maths as a clause's end
                prose = MATHS.sub(between, entry["solution"])
                clauses = [words(c) for c in re.split(r"[.;:()]", prose)]
                runs += [c for c in clauses if len(c.split()) >= least and c not in runs]
            out[label] = runs
    return out


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    for path in build(Path(args[0]) if args else ROOT / "teacher" / "exams"):
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
