"""What students install holds no answer: the answer key is the repository's ``answer_key/``.

* The package ``dstoolkit`` offers no ``solution``, no ``solution_in``, no ``plain``: neither
  ``dstoolkit.teaching`` nor any registered exercise hands out an answer or a teacher's function.
* No function of the package is a teacher's plain solution: not in its source files (compared
  statement by statement), not among the objects reachable from its exercises (compared by
  their compiled code).
* The wheel and the sdist, built for real by ``python -m build`` in an isolated build
  environment (the build backend pyproject requires, from the package index), hold
  ``dstoolkit`` and no ``answer_key``: no module of it, no teacher's plain function, no
  ``solution`` API. The sdist leaves out the tests and the teacher's exam bank too.
* ``scripts/sheets.py`` writes student sheets holding none of the answers of their variant and
  no body of a plain solution, while the teacher's edition it writes beside them holds them.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import json
import os
import pkgutil
import shutil
import subprocess
import sys
import tarfile
import textwrap
import zipfile
from pathlib import Path
from types import FunctionType

import pytest
from conftest import ROOT

import dstoolkit
import dstoolkit.teaching as teaching
from answer_key import PLAIN, plain_solutions, solution
from dstoolkit.teaching import REGISTRY, CodingExercise, Exercise

sys.path.insert(0, str(ROOT / "scripts"))
import sheets  # noqa: E402

PLAIN_FUNCTIONS = [
    f
    for _, f in inspect.getmembers(plain_solutions, inspect.isfunction)
    if f.__module__ == plain_solutions.__name__
]


def _body(node: ast.FunctionDef) -> list[str]:
    """Return the statements of a function after its docstring, each as an AST dump."""
    body = node.body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        body = body[1:]
    return [ast.dump(stmt) for stmt in body]


def _plain_bodies() -> dict[str, list[str]]:
    tree = ast.parse(inspect.getsource(plain_solutions))
    return {n.name: _body(n) for n in tree.body if isinstance(n, ast.FunctionDef)}


def test_the_package_offers_no_solution_and_no_plain_function() -> None:
    for name in ("solution", "solution_in", "plain"):
        assert not hasattr(teaching, name), name
        assert name not in teaching.__all__, name
    for cls in (Exercise, CodingExercise):
        for name in ("solution", "solution_in", "plain"):
            assert not hasattr(cls, name), (cls.__name__, name)
    for exercise_id, item in REGISTRY.items():
        for name in ("solution", "solution_in", "plain"):
            assert not hasattr(item, name), (exercise_id, name)


def test_no_source_file_of_the_package_holds_a_plain_solution() -> None:
    bodies = _plain_bodies()
    assert len(bodies) == len(PLAIN_FUNCTIONS) >= len(PLAIN)
    package = Path(dstoolkit.__file__).parent
    found = []
    for path in sorted(package.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
                body = _body(node) if not isinstance(node, ast.Lambda) else []
                for name, plain in bodies.items():
                    if body and body == plain:
                        found.append(f"{path.relative_to(package)}:{node.lineno} is {name}")
        assert "plain_solutions" not in path.read_text(encoding="utf-8"), path
    assert not found, found


def _code_key(code) -> tuple:
    return code.co_code, code.co_consts[1:], code.co_names


def _reachable_functions() -> list[FunctionType]:
    """Return every function of every module of dstoolkit, and those its exercises hold."""
    for info in pkgutil.walk_packages(dstoolkit.__path__, "dstoolkit."):
        if info.name.endswith("__main__"):
            continue  # running it would run the command line
        try:
            importlib.import_module(info.name)
        except ImportError:  # a layer whose optional extra is not installed here
            continue
    seen: dict[int, FunctionType] = {}
    todo: list[object] = [
        m for name, m in sys.modules.items() if name.startswith("dstoolkit") and m is not None
    ]
    for item in REGISTRY.values():
        todo.extend(v for v in vars(item).values())
        todo.extend(f for pair in item.mistakes for f in pair)
    while todo:
        obj = todo.pop()
        if id(obj) in seen:
            continue
        if isinstance(obj, FunctionType):
            seen[id(obj)] = obj
            todo.extend(c.cell_contents for c in obj.__closure__ or () if _filled(c))
            todo.extend(obj.__defaults__ or ())
        elif inspect.ismodule(obj):
            seen[id(obj)] = obj  # type: ignore[assignment]
            todo.extend(vars(obj).values())
        elif inspect.isclass(obj) and obj.__module__.startswith("dstoolkit"):
            seen[id(obj)] = obj  # type: ignore[assignment]
            todo.extend(vars(obj).values())
        elif isinstance(obj, tuple | list):
            todo.extend(obj)
    return [f for f in seen.values() if isinstance(f, FunctionType)]


def _filled(cell) -> bool:
    try:
        cell.cell_contents  # noqa: B018 - an empty cell raises
    except ValueError:
        return False
    return True


def test_no_function_reachable_in_the_package_is_a_teachers() -> None:
    teachers = {_code_key(f.__code__): f.__name__ for f in PLAIN_FUNCTIONS}
    functions = _reachable_functions()
    assert len(functions) > 500  # the walk reached the package, not just a corner of it
    found = [
        f"{f.__module__}.{f.__qualname__} is {teachers[_code_key(f.__code__)]}"
        for f in functions
        if _code_key(f.__code__) in teachers
    ]
    assert not found, found
    assert all(f.__module__ != plain_solutions.__name__ for f in functions)


def _source_copy(into: Path) -> Path:
    """Copy the checkout's files (tracked and new, not ignored) to ``into``; return it.

    The build writes ``build/`` and ``*.egg-info`` into its source folder: a copy keeps the
    checkout clean.
    """
    listed = subprocess.run(
        ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
        cwd=ROOT, check=True, capture_output=True,
    ).stdout.decode().split("\0")  # fmt: skip
    for name in filter(None, listed):
        source = ROOT / name
        if source.is_file():
            (into / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, into / name)
    return into


def _defines_a_plain_solution(text: str, bodies: dict[str, list[str]]) -> list[str]:
    """Return the names of the plain solutions whose body a module's source repeats."""
    found = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            found += [name for name, plain in bodies.items() if _body(node) == plain]
    return found


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> tuple[Path, Path]:
    """Return the sdist and the wheel of the checkout, built by ``python -m build`` (isolated)."""
    work = tmp_path_factory.mktemp("build")
    src = _source_copy(work / "src")
    assert (src / "answer_key" / "plain_solutions.py").is_file()  # there to be left out
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    proc = subprocess.run(
        [sys.executable, "-m", "build", "--outdir", str(work / "dist"), str(src)],
        cwd=work, env=env, capture_output=True, text=True, timeout=900, check=False,
    )  # fmt: skip
    assert proc.returncode == 0, f"python -m build failed:\n{proc.stdout}\n{proc.stderr}"
    (sdist,) = (work / "dist").glob("dstoolkit-*.tar.gz")
    (wheel,) = (work / "dist").glob("dstoolkit-*-py3-none-any.whl")
    return sdist, wheel


@pytest.mark.slow
def test_the_built_wheel_holds_dstoolkit_and_no_answer(built) -> None:
    _, wheel = built
    with zipfile.ZipFile(wheel) as archive:
        names = archive.namelist()
        sources = {n: archive.read(n).decode("utf-8") for n in names if n.endswith(".py")}
    tops = {n.split("/")[0] for n in names}
    assert tops == {"dstoolkit", wheel.name.split("-py3")[0] + ".dist-info"}, tops
    assert "dstoolkit/teaching/_variants.py" in names and "dstoolkit/py.typed" in names
    # every module of the package is in the wheel, and nothing else is
    package = Path(dstoolkit.__file__).parent
    expected = {
        "dstoolkit/" + p.relative_to(package).as_posix()
        for p in package.rglob("*.py")
        if "__pycache__" not in p.parts
    }
    assert set(sources) == expected
    assert not [n for n in names if "answer_key" in n or "plain_solutions" in n]
    bodies = _plain_bodies()
    teachers = {n: _defines_a_plain_solution(t, bodies) for n, t in sources.items()}
    assert not {n: f for n, f in teachers.items() if f}, teachers
    for name, text in sources.items():  # no module imports the answer key
        imported = [
            node.module if isinstance(node, ast.ImportFrom) else alias.name
            for node in ast.walk(ast.parse(text))
            if isinstance(node, ast.ImportFrom | ast.Import)
            for alias in node.names
        ]
        assert not [m for m in imported if m and m.split(".")[0] == "answer_key"], name
        assert "plain_solutions" not in text, name
    # no solution API in the student's teaching layer
    tree = ast.parse(sources["dstoolkit/teaching/__init__.py"])
    defined = {
        alias.asname or alias.name
        for node in ast.walk(tree)
        if isinstance(node, ast.ImportFrom | ast.Import)
        for alias in node.names
    } | {n.name for n in ast.walk(tree) if isinstance(n, ast.FunctionDef | ast.ClassDef)}
    assert "check" in defined  # the walk saw the module's names
    assert not defined & {"solution", "solution_in", "plain", "PLAIN"}, defined


@pytest.mark.slow
def test_the_built_sdist_leaves_out_the_answer_key_the_tests_and_the_exams(built) -> None:
    sdist, _ = built
    with tarfile.open(sdist) as archive:
        names = [n.split("/", 1)[1] for n in archive.getnames() if "/" in n]
    tops = {n.split("/")[0] for n in names}
    assert {"dstoolkit", "pyproject.toml", "README.md", "LICENSE"} <= tops, tops
    assert not tops & {"answer_key", "tests", "instructor", "notebooks", "book"}, tops
    assert "dstoolkit/teaching/_checking.py" in names


def _body_lines(function: FunctionType) -> list[str]:
    """Return the source lines of a function after its signature and docstring."""
    source = textwrap.dedent(inspect.getsource(function))
    node = ast.parse(source).body[0]
    assert isinstance(node, ast.FunctionDef)
    return source.splitlines()[node.body[0].end_lineno :]


def _sheet_texts(folder: Path) -> dict[str, str]:
    return {p.name: p.read_text(encoding="utf-8") for p in sorted(folder.glob("*.ipynb"))}


def _cells(text: str, tag: str) -> list[str]:
    return [
        "".join(c["source"])
        for c in json.loads(text)["cells"]
        if tag in c.get("metadata", {}).get("tags", [])
    ]


@pytest.fixture(scope="module")
def written(tmp_path_factory) -> tuple[dict[str, str], dict[str, str]]:
    """Student and teacher sheets of variant 1, written by the command line into a temp dir."""
    out = tmp_path_factory.mktemp("sheets")
    subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "sheets.py"), "--variant", "1",
         "--out", str(out / "students"), "--teacher", str(out / "teacher")],
        cwd=ROOT, check=True, capture_output=True, env=os.environ.copy(),
    )  # fmt: skip
    return _sheet_texts(out / "students"), _sheet_texts(out / "teacher")


def test_student_sheets_hold_no_answer_and_the_teachers_hold_them(written) -> None:
    students, teachers = written
    assert students.keys() == teachers.keys() and len(students) >= 10
    values = bodies = 0
    for name, teacher in teachers.items():
        student = students[name]
        checks = "\n".join(_cells(teacher, "check"))
        ids = {var: eid for eid, var in sheets.CHECK.findall(checks)}
        for var, eid in ids.items():
            if isinstance(REGISTRY[eid], CodingExercise):
                body = [ln.strip() for ln in _body_lines(PLAIN[eid]) if len(ln.strip()) > 25]
                assert body, eid
                teacher_has = all(
                    json.dumps(ln, ensure_ascii=False)[1:-1] in teacher for ln in body
                )
                assert teacher_has, (name, eid)
                assert not any(
                    json.dumps(ln, ensure_ascii=False)[1:-1] in student for ln in body
                ), (name, eid)
                bodies += 1
                continue
            line = f"{var} = {sheets._literal(solution(eid, variant=1))}"
            assert json.dumps(line, ensure_ascii=False)[1:-1] in teacher, (name, line)
            assert json.dumps(line, ensure_ascii=False)[1:-1] not in student, (name, line)
            assert f"{var} = ..." in student, (name, var)
            values += 1
        assert not _cells(student, "solution"), name
    assert values >= 40 and bodies >= 15, (values, bodies)
