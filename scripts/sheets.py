"""Write the exercise sheets from their one source: student sheets and the teacher's edition.

    .venv/bin/python scripts/sheets.py                 # student sheets → notebooks/
    .venv/bin/python scripts/sheets.py --teacher DIR   # also the instructor sheets and the
                                                       # sample exams (DIR/exams/) → DIR
    .venv/bin/python scripts/sheets.py --nbgrader DIR  # an nbgrader course → DIR (course.py)
    .venv/bin/python scripts/sheets.py --variant 3 --out DIR   # variant 3's sheets → DIR
    .venv/bin/python scripts/sheets.py --nbgrader DIR --variant 3  # … as an nbgrader course

Each chapter with exercises has one source, ``notebooks/source/<chapter stem>.md``. The
sheet of chapter N is ``notebooks/NN_<stem>.ipynb``: N comes from _toc.yml (chapters are
numbered across parts, as in the book), and its k-th exercise is "Exercise N.k", the k-th
``{exercise}`` of the chapter. Student sheets hold no solution in any form (no hidden cell,
no metadata); the instructor sheets add the solutions, the answers the check cells expect
(computed with dstoolkit) and the reference implementations of the coding exercises.

A source is Markdown cut into blocks by marker lines (text before the first marker is the
sheet's introduction):

    %% setup                      code, both editions (imports, data)
    %% exercise <label> <kind>    the exercise's statement; kind: coding, proof,
                                  prediction, explanation or substitution
    %% md / %% code               Markdown / code, both editions
    %% stub [<coding id>]         the learner's cell: ``name = ...`` lines, or (with the id
                                  of a coding exercise) the function's stub, generated from
                                  its reference solution; the teacher's edition fills it in
    %% answer                     code for the teacher's edition instead of the stub above
    %% check                      a check cell, both editions
    %% explore                    an explorer cell, both editions
    %% solution                   Markdown, the teacher's edition only

The exam problems' worked solutions and marking schemes are not in these sources: they come
from the teacher-only bank ``instructor/exams/`` (scripts/exams.py) into the teacher's edition.

``{{name}}`` (or ``{{name[i]}}``) in a block stands for a number of the chapter's data
(:mod:`dstoolkit.teaching._variants`): the book's in the sheets under ``notebooks/``, and
variant N's with ``--variant N``, whose setup cell calls ``set_variant(N)`` so that the
checks compute the answers from the same numbers. Chapters without variant data are the
book's in every variant.
"""

from __future__ import annotations

import argparse
import ast
import inspect
import json
import re
import sys
import textwrap
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml
from exams import with_exam_solutions

from dstoolkit.errors import InvalidInputError, OutputPathError
from dstoolkit.utils.console import run_command
from dstoolkit.utils.outputs import atomic_write, check_outputs

ROOT = Path(__file__).resolve().parents[1]
# the answer key (the teacher's edition's answers) is the repository's answer_key/, not installed
if str(ROOT) not in sys.path:
    sys.path.append(str(ROOT))
KINDS = ("coding", "proof", "prediction", "explanation", "substitution")
MARKER = re.compile(r"^%% (setup|exercise|md|code|stub|answer|check|explore|solution)\b ?(.*)$")
CHECK = re.compile(r'check\("([a-z]+\.[a-z0-9-]+)",\s*(\w+)\)')
ASSIGN = re.compile(r"^(\w+) = \.\.\.[ \t]*(?:#.*)?$", re.MULTILINE)
EXERCISE_BLOCK = re.compile(
    r"^(`{3,}|:{3,})\{exercise\}[ \t]*(?P<caption>[^\n]*)\n"
    r":label: (?P<label>[\w-]+)",
    re.MULTILINE,
)
#: What a reader sees of an exercise: its kind and a difficulty from 1 to 3, written once, as
#: the title of the chapter's ``{exercise}`` (the site and the PDF show it after the number),
#: and repeated from there in the sheets' headings.
SHOWN_KINDS = ("Compute", "Code", "Predict", "Proof", "Explain", "Exam")
CAPTION = re.compile(rf"^({'|'.join(SHOWN_KINDS)}), difficulty ([1-3]) of 3$")
STUB_BODY = '    raise NotImplementedError("write the body of this function")'
#: First line of every check cell: a check run before the setup cell says what to do.
SETUP_GUARD = 'if "check" not in dir(): raise RuntimeError("run the setup cell first")'
PLACEHOLDER = re.compile(r"\{\{(\w+)(?:\[(\d+)\])?\}\}")
TEACHING_IMPORT = re.compile(r"^from dstoolkit\.teaching import [\w, ]+$", re.MULTILINE)


# -- the book's numbering -------------------------------------------------------------------


def chapter_numbers(toc_file: Path = ROOT / "_toc.yml") -> dict[str, int]:
    """Return {chapter stem: number} for the chapters of numbered parts.

    The chapters are taken in order and counted across parts (``use_multitoc_numbering``);
    unnumbered parts (back matter) are left out.
    """
    toc = yaml.safe_load(toc_file.read_text(encoding="utf-8"))
    numbers: dict[str, int] = {}
    for part in toc.get("parts", []):
        if not part.get("numbered"):
            continue
        for chapter in part.get("chapters", []):
            numbers[Path(chapter["file"]).stem] = len(numbers) + 1
    return numbers


def chapter_exercises(chapter: Path) -> list[str]:
    """Return the labels of the chapter's ``{exercise}`` blocks, in order."""
    return [m.group("label") for m in EXERCISE_BLOCK.finditer(chapter.read_text(encoding="utf-8"))]


def chapter_captions(chapter: Path) -> dict[str, str]:
    """Return {label: caption} of the chapter's ``{exercise}`` blocks.

    A caption reads e.g. "Proof, difficulty 2 of 3"; a block whose title is not such a
    caption is an error.
    """
    out = {}
    for m in EXERCISE_BLOCK.finditer(chapter.read_text(encoding="utf-8")):
        if not CAPTION.match(m.group("caption")):
            raise ValueError(
                f"{chapter.name}: exercise {m.group('label')} has the title "
                f"{m.group('caption')!r}; write its kind ({', '.join(SHOWN_KINDS)}) "
                f"and difficulty, e.g. {{exercise}} Proof, difficulty 2 of 3"
            )
        out[m.group("label")] = m.group("caption")
    return out


def exercise_heading(stem: str, number: int, order: int, label: str) -> str:
    """Return the heading of Exercise ``number.order`` in a sheet, with the book's caption."""
    caption = chapter_captions(ROOT / "book" / f"{stem}.md")[label]
    return f"## Exercise {number}.{order} ({caption})"


def chapter_title(chapter: Path) -> str:
    """Return the chapter's first level-1 heading."""
    for line in chapter.read_text(encoding="utf-8").splitlines():
        if line.startswith("# "):
            return line[2:].strip()
    raise ValueError(f"{chapter} has no '# ' title")


def sheet_path(stem: str, number: int, folder: Path) -> Path:
    """``folder/NN_<stem>.ipynb``."""
    return folder / f"{number:02d}_{stem}.ipynb"


# -- variants ---------------------------------------------------------------------------------


def _number(value: Any) -> str:
    """Write a datum as the sheet shows it: whole floats without ``.0``, tuples element-wise."""
    if isinstance(value, tuple | list):
        return "(" + ", ".join(_number(v) for v in value) + ")"
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    if isinstance(value, float):
        return repr(float(f"{value:.10g}"))
    return str(value)


def render(text: str, stem: str, variant: int) -> str:
    """``text`` with every ``{{name}}`` replaced by the chapter's datum in ``variant``."""
    from dstoolkit.teaching._variants import chapter_of_sheet, data

    chapter = chapter_of_sheet(stem)
    if chapter is None:
        if PLACEHOLDER.search(text):
            raise ValueError(f"{stem}: {{{{…}}}} in a sheet whose chapter has no variant data")
        return text
    values = data(chapter, variant)

    def fill(match: re.Match[str]) -> str:
        name, index = match.group(1), match.group(2)
        if name not in values:
            raise ValueError(f"{stem}: no datum {name!r}; the chapter's are {sorted(values)}")
        value = values[name]
        return _number(value if index is None else value[int(index)])

    return PLACEHOLDER.sub(fill, text)


def varies(stem: str, variant: int) -> bool:
    """Whether the sheet ``stem`` in ``variant`` has other numbers than the book's."""
    from dstoolkit.teaching._variants import chapter_of_sheet

    return variant > 0 and chapter_of_sheet(stem) is not None


def with_variant(setup: str, variant: int, stem: str) -> str:
    """Return the setup cell with ``set_variant`` imported from dstoolkit.teaching.

    The call of ``set_variant`` comes after the last import.
    """
    found = TEACHING_IMPORT.search(setup)
    if found is None:
        raise ValueError(
            f"{stem}: the setup cell imports nothing from dstoolkit.teaching; "
            "cannot set the variant"
        )
    setup = setup[: found.end()] + ", set_variant" + setup[found.end() :]
    lines = setup.splitlines()
    last = max(
        node.end_lineno or 0
        for node in ast.parse(setup).body
        if isinstance(node, ast.Import | ast.ImportFrom)
    )
    call = f"set_variant({variant})  # the checks use this sheet's numbers"
    return "\n".join([*lines[:last], "", call, *lines[last:]])


def in_variant(src: Source, variant: int) -> Source:
    """Return the source with its placeholders filled in for ``variant``.

    In a variant that differs from the book, the setup cell calls ``set_variant`` and the
    intro says so.
    """
    blocks = []
    note = (
        "*(Worked with the book's numbers; this sheet's variant has others. The "
        "method is the same.)*\n\n"
    )
    for block in src.blocks:
        text = render(block.text, src.stem, variant)
        if varies(src.stem, variant) and block.kind == "setup":
            text = with_variant(text, variant, src.stem)
        if varies(src.stem, variant) and block.kind == "solution":
            text = note + text
        blocks.append(Block(block.kind, block.arg, text))
    intro = render(src.intro, src.stem, variant)
    if varies(src.stem, variant):
        intro = (
            f"**Variant {variant}.** The numbers of this sheet differ from the book's; "
            f"its checks know them.\n\n{intro}"
        )
    return Source(src.stem, intro, blocks)


# -- the source -------------------------------------------------------------------------------


@dataclass
class Block:
    kind: str
    arg: str
    text: str


@dataclass
class Source:
    stem: str
    intro: str
    blocks: list[Block] = field(default_factory=list)

    def exercises(self) -> list[tuple[str, str]]:
        """(label, kind) of every exercise, in order."""
        return [tuple(b.arg.split()[:2]) for b in self.blocks if b.kind == "exercise"]


def parse(path: Path) -> Source:
    """Read ``notebooks/source/<stem>.md`` into blocks (see the module docstring)."""
    intro: list[str] = []
    blocks: list[Block] = []
    current = intro
    for line in path.read_text(encoding="utf-8").splitlines():
        found = MARKER.match(line)
        if found:
            blocks.append(Block(found.group(1), found.group(2).strip(), ""))
            current = []
            blocks[-1].text = current  # type: ignore[assignment]
        else:
            current.append(line)
    for block in blocks:
        block.text = "\n".join(block.text).strip("\n")  # type: ignore[arg-type]
        if block.kind == "exercise":
            label, _, kind = block.arg.partition(" ")
            if kind not in KINDS:
                raise ValueError(
                    f"{path.name}: exercise {label} has kind {kind!r}, not one of {KINDS}"
                )
    return Source(path.stem, "\n".join(intro).strip("\n"), blocks)


# -- what the teacher's edition fills in --------------------------------------------------------


def _literal(value: Any) -> str:
    """Python source of a solution value: numbers to 10 significant digits."""
    import numpy as np

    if isinstance(value, bool | np.bool_ | str):
        return repr(bool(value) if isinstance(value, np.bool_) else value)
    if isinstance(value, int | np.integer):
        return str(int(value))
    if isinstance(value, float | np.floating):
        return repr(float(f"{float(value):.10g}"))
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_literal(k)}: {_literal(v)}" for k, v in value.items()) + "}"
    if isinstance(value, set | frozenset):
        return "{" + ", ".join(sorted(_literal(v) for v in value)) + "}"
    if isinstance(value, np.ndarray):
        return _literal(value.tolist())
    if isinstance(value, tuple | list):
        inner = ", ".join(_literal(v) for v in value)
        return (
            f"({inner},)"
            if isinstance(value, tuple) and len(value) == 1
            else (f"({inner})" if isinstance(value, tuple) else f"[{inner}]")
        )
    raise TypeError(f"no literal for a solution of type {type(value).__name__}")


def coding_stub(exercise_id: str) -> str:
    """Return the learner's stub: the reference solution's signature and docstring, no body."""
    from answer_key import plain

    source = textwrap.dedent(inspect.getsource(plain(exercise_id)))
    node = ast.parse(source).body[0]
    lines = source.splitlines()[: node.body[0].end_lineno]
    return "\n".join(lines) + "\n" + STUB_BODY


def coding_answer(exercise_id: str) -> str:
    """Return the reference implementation (and the solutions it calls), as plain source."""
    from answer_key import HELPERS
    from answer_key import plain as plain_solution

    plain = plain_solution(exercise_id)
    module = sys.modules[plain.__module__]
    parts = [getattr(module, name) for name in HELPERS.get(plain.__name__, ())] + [plain]
    needs = sorted(
        {m for fn in parts for m in ("itertools", "math") if f"{m}." in inspect.getsource(fn)}
    )
    head = "".join(f"import {m}\n" for m in needs)
    return (
        head
        + ("\n\n" if head else "")
        + "\n\n\n".join(textwrap.dedent(inspect.getsource(fn)).strip() for fn in parts)
    )


def filled_stub(stub: str, checks: str) -> str:
    """``name = ...`` lines with the value of the exercise their check cell names."""
    from answer_key import solution

    ids = {var: eid for eid, var in CHECK.findall(checks)}

    def fill(match: re.Match[str]) -> str:
        name = match.group(1)
        if name not in ids:
            raise ValueError(f"no check cell uses {name!r}; cannot fill in its answer")
        return f"{name} = {_literal(solution(ids[name]))}"

    return ASSIGN.sub(fill, stub)


def stub_names(block: Block) -> set[str]:
    """Return the names a stub cell defines: its function, or its ``name = ...`` lines."""
    if block.arg:
        from answer_key import plain

        return {plain(block.arg).__name__}
    return set(ASSIGN.findall(block.text))


def imported_names(code: str) -> set[str]:
    """Return the names bound by the import statements of ``code``."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(code)):
        if isinstance(node, ast.Import | ast.ImportFrom):
            names.update((alias.asname or alias.name).split(".")[0] for alias in node.names)
    return names


def unshadowed(src: Source) -> None:
    """Raise ValueError when a stub would rebind a name that the sheet imported.

    The sheet's "confirm with the library" would then call the learner's stub.
    """
    imported: set[str] = set()
    for block in src.blocks:
        if block.kind in ("setup", "code", "explore"):
            imported |= imported_names(block.text)
        if block.kind == "stub":
            clash = stub_names(block) & imported
            if clash:
                raise ValueError(
                    f"{src.stem}: a stub defines {sorted(clash)}, which the sheet "
                    "imports; rename the exercise's function"
                )


# -- notebooks --------------------------------------------------------------------------------


def _cell(kind: str, source: str, index: int, stem: str, meta: dict | None = None) -> dict:
    cell: dict[str, Any] = {
        "cell_type": kind,
        "id": f"{stem.replace('_', '-')[:50]}-{index}",
        "metadata": meta or {},
        "source": source,
    }
    if kind == "code":
        cell.update(execution_count=None, outputs=[])
    return cell


def _checks_of(blocks: list[Block], i: int) -> str:
    """Return the check cells after block ``i``, up to the next exercise."""
    out = []
    for block in blocks[i + 1 :]:
        if block.kind == "exercise":
            break
        if block.kind == "check":
            out.append(block.text)
    return "\n".join(out)


def build(
    src: Source, number: int, title: str, labels: list[str], teacher: bool, variant: int = 0
) -> dict:
    """Build the sheet of chapter ``number`` as a notebook (nbformat 4 JSON).

    It holds the numbers of ``variant`` (0: the book's).
    """
    from dstoolkit.teaching._variants import using_variant

    with using_variant(variant):
        return _build(in_variant(src, variant), number, title, labels, teacher)


def _build(src: Source, number: int, title: str, labels: list[str], teacher: bool) -> dict:
    edition = " (teacher's edition)" if teacher else ""
    head = (
        f"# Exercises of Chapter {number}: {title}{edition}\n\n"
        f"Companion of Chapter {number} of the book (`book/{src.stem}.md`): Exercise "
        f"{number}.k here is Exercise {number}.k there.\n\n{src.intro}"
    ).strip()
    raw: list[tuple[str, str, dict]] = [("markdown", head, {})]
    unshadowed(src)
    order = 0
    for i, block in enumerate(src.blocks):
        text, tags = block.text, []
        if block.kind == "exercise":
            label, kind = block.arg.split()[:2]
            if order >= len(labels) or labels[order] != label:
                raise ValueError(
                    f"{src.stem}: exercise {label} is number {order + 1} in the "
                    f"sheet but the chapter's exercises are {labels}"
                )
            order += 1
            heading = exercise_heading(src.stem, number, order, label)
            raw.append(
                (
                    "markdown",
                    f"{heading}\n\n{text}",
                    {"dstoolkit": {"exercise": label, "kind": kind}},
                )
            )
            continue
        if block.kind in ("answer", "solution") and not teacher:
            continue
        if block.kind == "stub":
            follows = src.blocks[i + 1].kind if i + 1 < len(src.blocks) else ""
            if block.arg:
                text = coding_answer(block.arg) if teacher else coding_stub(block.arg)
            elif teacher and follows != "answer":
                text = filled_stub(text, _checks_of(src.blocks, i))
            elif teacher:
                continue  # the %% answer block below replaces it
            tags = ["answer"] if not teacher else ["solution"]
        if block.kind == "answer":
            tags = ["solution"]
        if block.kind == "solution":
            raw.append(("markdown", f"**Solution.** {text}", {"tags": ["solution"]}))
            continue
        if block.kind in ("check", "explore"):
            tags = ["check" if block.kind == "check" else "explorer"]
        if block.kind == "check":
            text = f"{SETUP_GUARD}\n{text}"
        kind = "markdown" if block.kind == "md" else "code"
        raw.append((kind, text, {"tags": tags} if tags else {}))
    if order != len(labels):
        raise ValueError(
            f"{src.stem}: the sheet has {order} exercises, the chapter {len(labels)} ({labels})"
        )
    cells = [_cell(kind, text, n, src.stem, meta) for n, (kind, text, meta) in enumerate(raw)]
    return {
        "cells": cells,
        "metadata": {
            "kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
            "language_info": {"name": "python"},
        },
        "nbformat": 4,
        "nbformat_minor": 5,
    }


def dump(notebook: dict) -> str:
    """Return the notebook as stored: JSON with one-space indent, as Jupyter writes it."""
    return json.dumps(notebook, indent=1, ensure_ascii=False) + "\n"


def sheets(root: Path = ROOT) -> dict[str, tuple[int, str, Source, list[str]]]:
    """Collect every chapter with a source.

    Return {stem: (chapter number, title, source, the chapter's exercise labels)}.
    """
    numbers = chapter_numbers(root / "_toc.yml")
    out = {}
    for path in sorted((root / "notebooks" / "source").glob("*.md")):
        if path.stem not in numbers:
            raise ValueError(f"{path} has no numbered chapter book/{path.stem}.md in _toc.yml")
        chapter = root / "book" / f"{path.stem}.md"
        out[path.stem] = (
            numbers[path.stem],
            chapter_title(chapter),
            with_exam_solutions(parse(path), root),
            chapter_exercises(chapter),
        )
    return out


def relink(root: Path, stem: str, name: str) -> None:
    """Point every ``notebooks/NN_<stem>.ipynb`` in the chapters and the README at ``name``."""
    pattern = re.compile(rf"notebooks/\d\d_{stem}\.ipynb")
    for path in [*sorted((root / "book").glob("*.md")), root / "README.md"]:
        text = path.read_text(encoding="utf-8")
        new = pattern.sub(f"notebooks/{name}", text)
        if new != text:
            write_output(path, new)


def write_variant(
    variant: int,
    out: Path,
    root: Path = ROOT,
    teacher: Path | None = None,
    *,
    overwrite: bool = True,
) -> list[Path]:
    """Write the student sheets of ``variant`` to ``out`` and return the paths.

    With ``teacher``, its instructor sheets are written there too. An existing sheet is
    replaced only with ``overwrite``.
    """
    from dstoolkit.teaching._variants import valid_variant

    variant = valid_variant(variant)
    written = []
    for stem, (number, title, src, labels) in sheets(root).items():
        for folder, is_teacher in ((out, False), (teacher, True)):
            if folder is None:
                continue
            path = sheet_path(stem, number, folder)
            text = dump(build(src, number, title, labels, is_teacher, variant))
            write_output(path, text, overwrite=overwrite)
            written.append(path)
    return written


def write_sheets(
    root: Path = ROOT, teacher: Path | None = None, *, overwrite: bool = True
) -> list[Path]:
    """Write every student sheet to ``notebooks/`` and return the paths.

    Sheets whose chapter number changed are renamed. With ``teacher``, every instructor
    sheet is written there too; an existing one is replaced only with ``overwrite``.
    """
    written = []
    for stem, (number, title, src, labels) in sheets(root).items():
        target = sheet_path(stem, number, root / "notebooks")
        text = dump(build(src, number, title, labels, False))  # fails before any change
        for old in (root / "notebooks").glob(f"*_{stem}.ipynb"):
            if old != target and re.fullmatch(rf"\d\d_{stem}\.ipynb", old.name):
                old.unlink()  # the chapter moved: its sheet takes the new number
        write_output(target, text)  # the generated sheets are this script's own
        written.append(target)
        relink(root, stem, target.name)
        if teacher is not None:
            path = sheet_path(stem, number, teacher)
            text = dump(build(src, number, title, labels, True))
            write_output(path, text, overwrite=overwrite)
            written.append(path)
    return written


def write_output(path: Path, text: str, *, overwrite: bool = True) -> None:
    """Write one file as the ``dstoolkit`` command writes its outputs.

    The path is checked (a folder, a device, a place that cannot be written is refused; an
    existing file is replaced only with ``overwrite``), and the file is written to a
    temporary file beside it and moved into place when complete. Inside :func:`main`, the
    files of one run are written all or none: a failure or a stop takes the run back.
    """
    check_outputs({"the sheet": path}, overwrite=overwrite)
    atomic_write(path, lambda fh: fh.write(text.encode("utf-8")))


def _outside_student_sheets(option: str, folder: Path | None, root: Path = ROOT) -> None:
    """Refuse the book's student-sheets folder (or a folder in it) as another output."""
    if folder is None:
        return
    sheets_folder = (root / "notebooks").resolve()
    try:
        where = folder.resolve()
    except (OSError, RuntimeError) as exc:
        raise OutputPathError(f"{option}: cannot follow {folder}: {exc}") from None
    if where == sheets_folder or sheets_folder in where.parents:
        raise OutputPathError(
            f"{option}: {folder} is the book's student-sheets folder (notebooks/); "
            "give another folder"
        )


def counts(root: Path = ROOT) -> str:
    """Return a table of the exercises per chapter by kind."""
    rows = [f"{'':>3} {'chapter':22}" + "".join(f"{k:>13}" for k in KINDS) + f"{'total':>7}"]
    total = dict.fromkeys(KINDS, 0)
    for stem, (number, _, src, _) in sorted(sheets(root).items(), key=lambda x: x[1][0]):
        kinds = [kind for _, kind in src.exercises()]
        for k in KINDS:
            total[k] += kinds.count(k)
        rows.append(
            f"{number:>3} {stem:22}"
            + "".join(f"{kinds.count(k):>13}" for k in KINDS)
            + f"{len(kinds):>7}"
        )
    rows.append(
        f"{'':>3} {'all':22}"
        + "".join(f"{total[k]:>13}" for k in KINDS)
        + f"{sum(total.values()):>7}"
    )
    return "\n".join(rows)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--teacher",
        type=Path,
        default=None,
        help="also write the instructor sheets (with solutions) to this folder",
    )
    parser.add_argument(
        "--nbgrader",
        type=Path,
        default=None,
        metavar="DIR",
        help="only write an nbgrader course (config and one assignment per chapter) to this folder",
    )
    parser.add_argument(
        "--chapter",
        action="append",
        default=None,
        metavar="STEM",
        help="with --nbgrader: only this chapter (repeatable)",
    )
    parser.add_argument(
        "--variant",
        type=int,
        default=0,
        metavar="N",
        help="the numbers of variant N (0: the book's) for the chapters with "
        "variant data; needs --out DIR or --nbgrader DIR",
    )
    parser.add_argument(
        "--course-id",
        default=None,
        metavar="ID",
        help="with --nbgrader: nbgrader's course id (default: the folder's name); two "
        "courses on one JupyterHub need two ids",
    )
    parser.add_argument(
        "--per-student",
        action="store_true",
        help="with --nbgrader: every student gets numbers of their own (from their id and "
        "a secret kept in the course folder)",
    )
    parser.add_argument(
        "--students",
        type=Path,
        default=None,
        metavar="FILE",
        help="with --nbgrader, after nbgrader generate_assignment: write each student's "
        "copy (one id a line in FILE) to DIR/students/<id>/",
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        metavar="DIR",
        help="with --variant: write the student sheets to this folder",
    )
    parser.add_argument(
        "--counts", action="store_true", help="only print the exercises per chapter by kind"
    )
    parser.add_argument(
        "--overwrite",
        action="store_true",
        help="replace existing files under --teacher, --out or --nbgrader",
    )
    args = parser.parse_args(argv)
    if args.variant < 0:
        parser.error("--variant takes a whole number ≥ 0 (0 is the book's data)")
    if args.variant > 0 and args.out is None and args.nbgrader is None:
        parser.error("--variant N writes to --out DIR (the sheets under notebooks/ are the book's)")
    return run_command(lambda: _run(args))


def _run(args: argparse.Namespace) -> int:
    if args.counts:
        print(counts(ROOT))
        return 0
    for option in ("teacher", "out", "nbgrader"):
        _outside_student_sheets(f"--{option}", getattr(args, option))
    if args.chapter is not None:
        unknown = sorted(set(args.chapter) - set(sheets(ROOT)))
        if unknown:
            raise InvalidInputError(
                f"--chapter: no chapter with exercises named {', '.join(map(repr, unknown))}; "
                f"the chapters are {', '.join(sorted(sheets(ROOT)))}"
            )
    if args.nbgrader is not None:
        from course import release_for_students, write_course

        if args.students is not None:
            ids = args.students.read_text(encoding="utf-8").split()
            for path in release_for_students(args.nbgrader, ids, ROOT, args.chapter):
                print(path)
            return 0
        for path in write_course(
            args.nbgrader,
            ROOT,
            args.chapter,
            args.variant,
            args.course_id,
            args.per_student,
            overwrite=args.overwrite,
        ):
            print(path)
        return 0
    if args.out is not None:
        for path in write_variant(
            args.variant, args.out, ROOT, args.teacher, overwrite=args.overwrite
        ):
            print(path)
        return 0
    written = write_sheets(ROOT, args.teacher, overwrite=args.overwrite)
    if args.teacher is not None:  # the teacher's edition: the sample exams too
        from exams import build as build_exams

        try:
            written += build_exams(args.teacher / "exams")
        except RuntimeError as err:
            raise InvalidInputError(str(err)) from None
    for path in written:
        print(path.relative_to(ROOT) if path.is_relative_to(ROOT) else path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
