"""An nbgrader course from the exercise sheets' sources.

    .venv/bin/python scripts/sheets.py --nbgrader DIR [--variant N]

writes ``DIR/nbgrader_config.py`` and one assignment per chapter,
``DIR/source/NN_<stem>/NN_<stem>.ipynb``, with nbgrader's cell metadata:

* the setup cell and the statements are read-only (nbgrader restores them when grading);
* every stub is an autograded answer cell: the learner's stub, then the teacher's answer
  between ``### BEGIN SOLUTION`` and ``### END SOLUTION`` (inside the function for a coding
  exercise), which ``nbgrader generate_assignment`` removes;
* every check cell becomes an autograder test cell with points. It only *hands the answer
  in* (:func:`dstoolkit.teaching.hand_in`): a value as plain data; a function is read by
  the grader from the answer cell's code in the submitted file. The points are decided in
  nbgrader's process, where no student code runs (:mod:`dstoolkit.teaching.grading`,
  registered in the config): a value against the answer computed afresh from the data of
  the course's variant, a function in a fresh isolated interpreter where dstoolkit cannot
  be imported, on the exercise's cases and hidden random ones;
* every written part (a proof, an explanation, the "why" of a prediction) is a manually
  graded answer cell with points, holding the teacher's solution for the formgrader.

Points come from the source: ``%% check N`` gives a check N points (default 1, a coding
check 2); ``%% exercise <label> <kind> N`` gives the exercise's written part N points
(default 2).
"""

from __future__ import annotations

import ast
import inspect
import json
import os
import re
import textwrap
from pathlib import Path
from typing import Any

import sheets

from dstoolkit.teaching._limits import DEFAULT_TIME_LIMIT

#: Seconds each cell may run when nbgrader executes a submission (an endless loop in an
#: answer cell is interrupted after it; the other cells are still graded).
CELL_TIMEOUT = 60
COURSE_ID = "dstoolkit"
#: The environment of the class's Python kernel (its kernel spec's ``env``, the grading guide's
#: ``ipykernel install`` line): glibc returns a freed block of 128 KiB or more to the system at
#: once (an array of 16,384 numbers), instead of raising its thresholds after each large array
#: and keeping the memory for later, so a student's kernel holds what it uses, not its largest
#: past arrays (``benchmarks/chapter_memory.py`` measures each chapter with it). The numbers a
#: kernel computes do not change.
KERNEL_ENV = {"MALLOC_MMAP_THRESHOLD_": "131072", "MALLOC_TRIM_THRESHOLD_": "131072"}
WRITTEN = re.compile(r"^\*(?:Your|My) [^*\n]*:\* …[ \t]*$", re.MULTILINE)
WRITTEN_KINDS = ("proof", "prediction", "explanation")
CODING_POINTS = 2
VALUE_POINTS = 1
WRITTEN_POINTS = 2

CONFIG = '''\
"""nbgrader configuration of the dstoolkit exercises (written by scripts/sheets.py)."""

c = get_config()  # noqa: F821 - nbgrader provides it

c.CourseDirectory.course_id = "{course}"
# Each cell of a submission may run {timeout} s; an endless loop is interrupted and the
# other cells are still graded.
c.Execute.timeout = {timeout}
c.Execute.interrupt_on_timeout = True
# A busy hub may be slow to send a cell's output after its reply: wait for it.
c.Execute.iopub_timeout = 30
c.Execute.startup_timeout = 120
# A released answer cell keeps the learner's stub (``name = ...`` or the function's
# signature and docstring); the teacher's answer is cleared without a trace.
c.ClearSolutions.code_stub = {{"python": ""}}
c.ClearSolutions.text_stub = "*Your answer:* …"
# The scores are decided in nbgrader's own process, where no student code runs: after a
# submission has run, GradeOutsideTheKernel grades the answers its test cells handed in
# (a function from its answer cell's code, run in a fresh isolated interpreter) and writes
# each test's verdict as the cell's only output (see the grading guide).
c.Autograde.autograde_preprocessors = [
    "nbgrader.preprocessors.Execute",
    "dstoolkit.teaching.grading.GradeOutsideTheKernel",
    "nbgrader.preprocessors.IgnorePattern",
    "nbconvert.preprocessors.ClearMetadataPreprocessor",
    "nbgrader.preprocessors.LimitOutput",
    "nbgrader.preprocessors.SaveAutoGrades",
    "nbgrader.preprocessors.AssignLatePenalties",
    "nbgrader.preprocessors.CheckCellMetadata",
]
c.GradeOutsideTheKernel.variant = {variant}
c.GradeOutsideTheKernel.case_seconds = {case_seconds}
import os  # noqa: E402

c.GradeOutsideTheKernel.course_root = os.path.dirname(os.path.abspath(__file__))
# The CSV names a submission whose autograding was aborted (score left empty, not 0).
c.ExportApp.plugin_class = "dstoolkit.teaching.grading.CsvExportNamingUngraded"
# The formgrader shows the teacher's solution after each written part; the feedback
# pages leave it out.
c.GenerateFeedback.preprocessors = [
    "nbgrader.preprocessors.GetGrades",
    "dstoolkit.teaching.grading.LeaveOutTeachersSolutions",
    "nbconvert.preprocessors.CSSHTMLHeaderPreprocessor",
]
# Releasing on JupyterHub: uncomment and point at the exchange folder of your hub.
# c.Exchange.root = "/srv/nbgrader/exchange"

# Feedback pages load nothing from the internet: the assignments write their formulas in
# Unicode, and templates/feedback/mathjax.html.j2 (next to this file) replaces the MathJax
# loader of nbgrader's feedback page, a script from a CDN, by a style that wraps long
# lines of the tests' output.
import os  # noqa: E402
import nbgrader  # noqa: E402

# (generate_feedback picks its "feedback" template itself; the formgrader its own pages.)
c.HTMLExporter.extra_template_basedirs = [
    os.path.join(os.path.dirname(os.path.abspath(__file__)), "templates"),
    os.path.join(os.path.dirname(nbgrader.__file__), "server_extensions", "formgrader",
                 "templates"),
]
'''
#: Replaces nbconvert's MathJax loader in the head of the feedback pages (see CONFIG): no
#: script; instead, long lines of a test's output (a verdict) wrap at narrow widths.
NO_MATHJAX = """\
{#- The course's formulas are Unicode: the feedback pages load no MathJax (no CDN). -#}
{%- macro mathjax(url="") -%}
<style>div.output_area pre { white-space: pre-wrap; overflow-wrap: break-word; }</style>
{%- endmacro %}
"""


# -- maths without MathJax -------------------------------------------------------------------
# nbgrader's feedback pages load no MathJax, so the course writes its formulas in Unicode:
# "$\\mathrm{Bel}(\\{\\text{low}\\})$" reads "Bel({low})" in the notebook and on the page.

MATH = re.compile(r"\$\$(.+?)\$\$|\$(?!\s)((?:[^$\n]|\n(?!\n))+?)(?<!\s)\$", re.DOTALL)
WRAPPERS = re.compile(r"\\(?:mathrm|text|operatorname|mathit|mathbf|mathcal)\s*\{([^{}]*)\}")
#: A fraction of two simple parts, written a/b (parenthesised when a part is longer).
FRAC = re.compile(r"\\[dt]?frac\s*(?:\{([^{}]*)\}|(\w))\s*(?:\{([^{}]*)\}|(\w))")
ACCENTS = {"hat": "\u0302", "bar": "\u0304", "tilde": "\u0303"}
ACCENT = re.compile(r"\\(hat|bar|tilde)\s*(?:\{([^{}]*)\}|([A-Za-z]))")
SQRT = re.compile(r"\\sqrt\s*\{([^{}]*)\}")
SYMBOLS = {
    "alpha": "α",
    "beta": "β",
    "gamma": "γ",
    "delta": "δ",
    "varepsilon": "ε",
    "epsilon": "ε",
    "theta": "θ",
    "kappa": "κ",
    "lambda": "λ",
    "mu": "μ",
    "xi": "ξ",
    "pi": "π",
    "rho": "ρ",
    "sigma": "σ",
    "tau": "τ",
    "omega": "ω",
    "Theta": "Θ",
    "Delta": "Δ",
    "Sigma": "Σ",
    "cdot": "·",
    "times": "×",
    "le": "≤",
    "leq": "≤",
    "ge": "≥",
    "geq": "≥",
    "approx": "≈",
    "pm": "±",
    "in": "∈",
    "ni": "∋",
    "cap": "∩",
    "cup": "∪",
    "oplus": "⊕",
    "odot": "⊙",
    "chi": "χ",
    "setminus": "∖",
    "smallsetminus": "∖",
    "supseteq": "⊇",
    "supset": "⊃",
    "sim": "∼",
    "top": "ᵀ",
    "ln": "ln",
    "lvert": "|",
    "rvert": "|",
    "wedge": "∧",
    "vee": "∨",
    "neg": "¬",
    "infty": "∞",
    "to": "→",
    "dots": "…",
    "ldots": "…",
    "lfloor": "⌊",
    "rfloor": "⌋",
    "lceil": "⌈",
    "rceil": "⌉",
    "neq": "≠",
    "ne": "≠",
    "min": "min",
    "max": "max",
    "sin": "sin",
    "cos": "cos",
    "log": "log",
    "exp": "exp",
    "emptyset": "∅",
    "subseteq": "⊆",
    "subset": "⊂",
    "mid": "|",
    "quad": "  ",
    "sum": "Σ",
    "prod": "Π",
    "bigl": "",
    "bigr": "",
    "Bigl": "",
    "Bigr": "",
    "left": "",
    "right": "",
    "eta": "η",
    "phi": "φ",
    "psi": "ψ",
    "nu": "ν",
}
#: Double-struck letters (\mathbb{E} is an expectation).
DOUBLE_STRUCK = {"E": "𝔼", "R": "ℝ", "N": "ℕ", "Z": "ℤ", "P": "ℙ", "Q": "ℚ", "C": "ℂ"}
BLACKBOARD = re.compile(r"\\mathbb\s*\{([A-Z])\}")
SPACES = {",": "\u2009", ";": " ", ":": " ", "!": "", " ": " ", "{": "\u27ee", "}": "\u27ef"}
SUB = dict(zip("0123456789+-=()aehijklmnoprstuvx", "₀₁₂₃₄₅₆₇₈₉₊₋₌₍₎ₐₑₕᵢⱼₖₗₘₙₒₚᵣₛₜᵤᵥₓ", strict=True))
SUP = dict(zip("0123456789+-=()in", "⁰¹²³⁴⁵⁶⁷⁸⁹⁺⁻⁼⁽⁾ⁱⁿ", strict=True))
SCRIPT = re.compile(r"([_^])(?:\{([^{}]*)\}|(\\?[A-Za-z0-9]))")
#: A matrix environment, written in plain text row by row: [2 1; 1 2].
MATRIX = re.compile(r"\\begin\{([pb]?matrix)\}(.*?)\\end\{\1\}", re.S)


def _fraction(match: re.Match[str]) -> str:
    top, bottom = match.group(1) or match.group(2), match.group(3) or match.group(4)
    parts = [top.strip(), bottom.strip()]
    return "/".join(p if re.fullmatch(r"[\w.]+", p) else f"({p})" for p in parts)


def _matrix(match: re.Match[str]) -> str:
    rows = [row.strip() for row in re.split(r"\\\\", match.group(2)) if row.strip()]
    return "[" + "; ".join(" ".join(c.strip() for c in row.split("&")) for row in rows) + "]"


def _script(match: re.Match[str]) -> str:
    kind, body = match.group(1), match.group(2) if match.group(2) is not None else match.group(3)
    table = SUB if kind == "_" else SUP
    body = body.replace(" ", "")
    if all(ch in table for ch in body):
        return "".join(table[ch] for ch in body)
    return f"{kind}({body})" if len(body) > 1 else f"{kind}{body}"


def plain_maths(text: str) -> str:
    """Markdown with its ``$…$`` formulas written in Unicode (no MathJax needed).

    Raises ValueError when a formula uses a command this conversion does not know, so a new
    one in a source is noticed when the course is written.
    """

    def convert(match: re.Match[str]) -> str:
        tex = match.group(1) if match.group(1) is not None else match.group(2)
        out = MATRIX.sub(_matrix, tex)
        for _ in range(3):  # nested wrappers: \mathrm{\text{…}}
            out = WRAPPERS.sub(r"\1", out)
        out = BLACKBOARD.sub(lambda m: DOUBLE_STRUCK.get(m.group(1), m.group(1)), out)
        out = ACCENT.sub(lambda m: (m.group(2) or m.group(3)) + ACCENTS[m.group(1)], out)
        out = re.sub(r"\^\s*\{?\\top\}?", "ᵀ", out)  # a transpose
        out = re.sub(r"\\([,;:! {}])", lambda m: SPACES[m.group(1)], out)
        out = re.sub(r"\\([A-Za-z]+)", lambda m: SYMBOLS.get(m.group(1), m.group(0)), out)
        out = SCRIPT.sub(_script, out).replace("-", "−")
        for _ in range(2):  # a root or fraction of a subscripted symbol: after the scripts
            out = FRAC.sub(_fraction, SQRT.sub(r"√(\1)", out))
        if "\\" in out:
            raise ValueError(
                f"no plain form for the formula ${tex}$ (add its commands to course.SYMBOLS)"
            )
        out = out.replace("{", "").replace("}", "")
        return out.replace("\u27ee", "{").replace("\u27ef", "}")

    return MATH.sub(convert, text)


def _meta(
    grade_id: str,
    *,
    grade: bool = False,
    solution: bool = False,
    locked: bool = False,
    points: float | None = None,
) -> dict:
    meta: dict[str, Any] = {
        "grade": grade,
        "grade_id": grade_id,
        "locked": locked,
        "schema_version": 3,
        "solution": solution,
    }
    if points is not None:
        meta["points"] = points
    return {"nbgrader": meta}


def _body_region(exercise_id: str) -> str:
    """Return the learner's stub with the reference body between solution markers."""
    from answer_key import HELPERS
    from answer_key import plain as plain_solution

    plain = plain_solution(exercise_id)
    answer = sheets.coding_answer(exercise_id)
    stub = sheets.coding_stub(exercise_id)
    head = stub[: stub.rindex("\n")]  # signature and docstring
    source = textwrap.dedent(inspect.getsource(plain))
    node = ast.parse(source).body[0]
    lines = source.splitlines()
    body = "\n".join(lines[node.body[0].end_lineno :])
    before = answer[: answer.rindex(f"def {plain.__name__}(")].rstrip().splitlines()
    imports = [line for line in before if line.startswith("import ")]
    helpers = "\n".join(line for line in before if not line.startswith("import ")).strip()
    if imports:
        body = "\n".join(f"    {line}" for line in imports) + "\n" + body
    parts = []
    if helpers:
        names = ", ".join(HELPERS.get(plain.__name__, ()))
        parts.append(
            f"# your {names} here, if this notebook has not got them yet\n"
            f"### BEGIN SOLUTION\n{helpers}\n### END SOLUTION\n\n"
        )
    parts.append(f"{head}\n    ### BEGIN SOLUTION\n{body}\n    ### END SOLUTION")
    return "".join(parts)


def _value_region(stub: str, checks: str, answer: str | None) -> str:
    """``name = ...`` lines, then the teacher's values between solution markers."""
    filled = answer if answer is not None else sheets.filled_stub(stub, checks)
    return f"{stub}\n### BEGIN SOLUTION\n{filled}\n### END SOLUTION"


def _test_source(exercise_id: str, variable: str) -> str:
    """Return a test cell: it hands the answer in; the grader decides its points."""
    return (
        "# Hands your answer in; it is graded when your notebook is collected.\n"
        "from dstoolkit.teaching import hand_in\n\n"
        f'hand_in("{exercise_id}", {variable})'
    )


def _written_cell(label: str, n: int, points: float, solution: str) -> tuple:
    text = solution or "(The teacher's solution is in the instructor sheets.)"
    return (
        "markdown",
        text,
        _meta(f"{label}-written-{n}", grade=True, solution=True, points=points),
    )


def _split_written(text: str) -> tuple[str, int]:
    """Return the Markdown without its written-answer placeholders, and how many there were."""
    count = len(WRITTEN.findall(text))
    return WRITTEN.sub("", text).rstrip(), count


def _exercise_solutions(src: sheets.Source) -> dict[str, str]:
    """{exercise label: its ``%% solution`` text}."""
    out: dict[str, str] = {}
    label = ""
    for block in src.blocks:
        if block.kind == "exercise":
            label = block.arg.split()[0]
        elif block.kind == "solution":
            out[label] = (out.get(label, "") + "\n\n" + block.text).strip()
    return out


def course_notebook(
    src: sheets.Source,
    number: int,
    title: str,
    labels: list[str],
    variant: int = 0,
    per_student: bool = False,
) -> dict:
    """Build the nbgrader source notebook of one chapter (nbformat 4 JSON).

    It holds the numbers of ``variant`` (0: the book's). With ``per_student`` the cells
    that show data (the introduction, setup, statements and text) are left out of
    nbgrader's bookkeeping, so that each student's copy keeps the data of their own
    variant when it is graded (:func:`release_for_students`).
    """
    from dstoolkit.teaching._variants import using_variant

    with using_variant(variant):
        notebook = _course_notebook(sheets.in_variant(src, variant), number, title, labels)
    if per_student:
        for cell in notebook["cells"]:
            meta = cell["metadata"]["nbgrader"]
            if meta["locked"] and not meta["grade"] and not meta["solution"]:
                cell["metadata"] = {"editable": False, "deletable": False}
    return notebook


def _course_notebook(src: sheets.Source, number: int, title: str, labels: list[str]) -> dict:
    sheets.unshadowed(src)
    solutions = _exercise_solutions(src)
    head = (
        f"# Chapter {number}: {title}, graded exercises\n\n"
        f"Exercise {number}.k here is Exercise {number}.k of the book. Run the setup "
        f"cell first; write your answers in the answer cells; the test cells (they have "
        f"points) check them as the sheet's check cells do.\n\n{src.intro}"
    ).strip()
    raw: list[tuple[str, str, dict]] = [("markdown", head, _meta("intro", locked=True))]
    order, label, kind, written, points_of_written = 0, "", "", 0, WRITTEN_POINTS
    names: dict[str, int] = {}

    def unique(base: str) -> str:
        names[base] = names.get(base, 0) + 1
        return base if names[base] == 1 else f"{base}-{names[base]}"

    def close_exercise() -> None:
        if label and kind in WRITTEN_KINDS and not written:
            raw.append(_written_cell(label, 1, points_of_written, solutions.get(label, "")))

    for i, block in enumerate(src.blocks):
        if block.kind == "exercise":
            close_exercise()
            parts = block.arg.split()
            label, kind = parts[0], parts[1]
            points_of_written = float(parts[2]) if len(parts) > 2 else WRITTEN_POINTS
            order += 1
            written = 0
            text, found = _split_written(block.text)
            raw.append(
                (
                    "markdown",
                    f"{sheets.exercise_heading(src.stem, number, order, label)}\n\n{text}",
                    _meta(unique(f"{label}-statement"), locked=True),
                )
            )
            for _ in range(found):
                written += 1
                raw.append(
                    _written_cell(label, written, points_of_written, solutions.get(label, ""))
                )
            continue
        if block.kind in ("answer", "solution"):
            continue
        if block.kind == "md":
            text, found = _split_written(block.text)
            raw.append(("markdown", text, _meta(unique(f"{label or 'text'}-text"), locked=True)))
            for _ in range(found):
                written += 1
                raw.append(
                    _written_cell(label, written, points_of_written, solutions.get(label, ""))
                )
            continue
        if block.kind == "setup":
            raw.append(("code", block.text, _meta(unique("setup"), locked=True)))
            continue
        if block.kind == "stub":
            if block.arg:
                text = _body_region(block.arg)
            else:
                follows = src.blocks[i + 1] if i + 1 < len(src.blocks) else None
                answer = follows.text if follows and follows.kind == "answer" else None
                text = _value_region(block.text, sheets._checks_of(src.blocks, i), answer)
            raw.append(("code", text, _meta(unique(f"{label}-answer"), solution=True)))
            continue
        if block.kind == "check":
            found = sheets.CHECK.search(block.text)
            if found is None:
                raise ValueError(f"{src.stem}: a check cell without check(...): {block.text}")
            exercise_id, variable = found.groups()
            coding = exercise_id.endswith("-code")
            points = float(block.arg) if block.arg else (CODING_POINTS if coding else VALUE_POINTS)
            raw.append(
                (
                    "code",
                    _test_source(exercise_id, variable),
                    _meta(
                        unique(f"{exercise_id.replace('.', '-')}-test"),
                        grade=True,
                        locked=True,
                        points=points,
                    ),
                )
            )
            continue
        # code and explorer cells: read-only, as in the sheets
        raw.append(("code", block.text, _meta(unique(f"{label or 'code'}-code"), locked=True)))
    close_exercise()
    if order != len(labels):
        raise ValueError(
            f"{src.stem}: the sheet has {order} exercises, the chapter {len(labels)} ({labels})"
        )
    cells = [
        sheets._cell(kind, plain_maths(text) if kind == "markdown" else text, n, src.stem, meta)
        for n, (kind, text, meta) in enumerate(raw)
    ]
    return {
        "cells": cells,
        "metadata": {
            "kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
            "language_info": {"name": "python"},
        },
        "nbformat": 4,
        "nbformat_minor": 5,
    }


def assignment_name(stem: str, number: int) -> str:
    """Return the assignment (and notebook) name of a chapter: ``NN_<stem>``."""
    return f"{number:02d}_{stem}"


def course_id_of(folder: Path) -> str:
    """Return the default course id: the folder's name in nbgrader's spelling.

    Two courses on one JupyterHub need two ids (a release replaces the other's otherwise).
    """
    name = re.sub(r"[^A-Za-z0-9_-]+", "-", folder.resolve().name).strip("-")
    return name or COURSE_ID


#: The course's secret (students' variants derive from it), next to nbgrader_config.py.
SECRET_FILE = "course_secret.txt"
PER_STUDENT = """
# Each student has numbers of their own: their variant derives from their id and the secret
# in {secret_file} (keep it; never release it). Give each student their copy from
# students/<id>/ (python scripts/sheets.py --nbgrader . --students FILE).
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "{secret_file}")) as f:
    c.GradeOutsideTheKernel.secret = f.read().strip()
"""


def write_course(
    folder: Path,
    root: Path = sheets.ROOT,
    chapters: list[str] | None = None,
    variant: int = 0,
    course_id: str | None = None,
    per_student: bool = False,
    *,
    overwrite: bool = True,
) -> list[Path]:
    """Write the nbgrader course to ``folder`` and return the paths written.

    The course is the config and one source assignment per chapter (or only for the
    ``chapters`` stems given), with the numbers of ``variant`` (0: the book's). Every
    notebook is made before anything is written: a generation that fails leaves no folder.
    An existing file is replaced only with ``overwrite`` (:func:`sheets.write_output`).
    ``course_id`` defaults to the folder's name. With ``per_student`` every student gets
    numbers of their own (a secret is written next to the config, kept if it exists).
    """
    if course_id is not None and not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_-]*", course_id):
        raise ValueError(
            f"course id {course_id!r}: use letters, digits, '-' and '_' (e.g. ds-2027-group-b)"
        )
    notebooks = {}
    for stem, (number, title, src, labels) in sheets.sheets(root).items():
        if chapters is not None and stem not in chapters:
            continue
        name = assignment_name(stem, number)
        notebook = course_notebook(src, number, title, labels, variant, per_student)
        notebooks[name] = sheets.dump(notebook)
    config_text = CONFIG.format(
        course=course_id or course_id_of(folder),
        timeout=CELL_TIMEOUT,
        variant=variant,
        case_seconds=DEFAULT_TIME_LIMIT,
    )
    if per_student:
        config_text += PER_STUDENT.format(secret_file=SECRET_FILE)
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    secret = folder / SECRET_FILE
    if per_student and not secret.exists():
        import secrets

        # created readable by its owner only, never through a link or over a file
        fd = os.open(secret, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(secrets.token_hex(16) + "\n")
        written.append(secret)
    config = folder / "nbgrader_config.py"
    sheets.write_output(config, config_text, overwrite=overwrite)
    template = folder / "templates" / "feedback" / "mathjax.html.j2"
    sheets.write_output(template, NO_MATHJAX, overwrite=overwrite)
    written += [config, template]
    for name, text in notebooks.items():
        path = folder / "source" / name / f"{name}.ipynb"
        sheets.write_output(path, text, overwrite=overwrite)
        written.append(path)
    return written


def release_for_students(
    folder: Path, students: list[str], root: Path = sheets.ROOT, chapters: list[str] | None = None
) -> list[Path]:
    """Write each student's copy of the released assignments, with their own numbers.

    Run after ``nbgrader generate_assignment``: the copy of student ``s`` is
    ``folder/students/<s>/<assignment>/<assignment>.ipynb``, the released notebook whose
    data cells show the numbers of ``s``'s variant (from the course's secret); the
    grader computes ``s``'s answers from the same variant.
    """
    from dstoolkit.teaching._variants import student_variant

    secret = (folder / SECRET_FILE).read_text(encoding="utf-8").strip()
    written = []
    for stem, (number, title, src, labels) in sheets.sheets(root).items():
        if chapters is not None and stem not in chapters:
            continue
        name = assignment_name(stem, number)
        release = folder / "release" / name / f"{name}.ipynb"
        if not release.exists():
            if chapters is None:
                continue  # an assignment not released yet
            raise FileNotFoundError(f"{release}: run nbgrader generate_assignment {name} first")
        released = json.loads(release.read_text(encoding="utf-8"))
        copies = {}
        for student in students:
            own = course_notebook(
                src, number, title, labels, student_variant(secret, student), per_student=True
            )
            data_cells = {
                c["id"]: c["source"] for c in own["cells"] if "nbgrader" not in c["metadata"]
            }
            notebook = json.loads(json.dumps(released))
            for cell in notebook["cells"]:
                if "nbgrader" not in cell["metadata"] and cell["id"] in data_cells:
                    cell["source"] = data_cells[cell["id"]]
            copies[student] = sheets.dump(notebook)
        for student, text in copies.items():
            path = folder / "students" / student / name / f"{name}.ipynb"
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text, encoding="utf-8")
            written.append(path)
    return written
