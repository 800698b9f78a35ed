"""Every command of the grading guide (book/grading.md) works, in the page's order.

The test runs each line of the page's ``bash`` blocks with a fresh home folder. Between
two commands it plays the parts the page leaves to people: the exchange folder of a
JupyterHub (set in ``nbgrader_config.py`` as the page says), a student who fetches the
assignment and submits it from the hub, and Alice, who returns her notebook as a file.
The install line runs with ``--dry-run`` (it must resolve, but the test environment is
not reinstalled) and the kernel spec goes to the fresh home (``--user``, not the test
environment's own: the rest of the run then uses it); ``release_feedback`` gets
``--student`` for the hub's student, as the page says for a course that also received
files. At the end the exported CSV holds both
students with their scores.
"""

from __future__ import annotations

import csv
import json
import os
import pwd
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "scripts"))
import course  # noqa: E402

pytestmark = pytest.mark.slow

PAGE = ROOT / "book" / "grading.md"
NAME = "03_combining_evidence"
BIN = Path(sys.executable).parent


def commands() -> list[str]:
    """Return the lines of the page's ``bash`` blocks, in order."""
    blocks = re.findall(r"^```bash\n(.*?)^```", PAGE.read_text("utf-8"), re.MULTILINE | re.DOTALL)
    return [line.strip() for block in blocks for line in block.splitlines() if line.strip()]


def test_the_page_is_in_the_back_matter_and_says_the_limits():
    toc = (ROOT / "_toc.yml").read_text("utf-8")
    assert "- file: book/grading" in toc.split("Back matter", 1)[1]
    text = PAGE.read_text("utf-8")
    assert f"may run {course.CELL_TIMEOUT} seconds" in text
    from dstoolkit.teaching._limits import DEFAULT_TIME_LIMIT

    assert f"after {DEFAULT_TIME_LIMIT:g} seconds on each case" in text
    from dstoolkit.teaching._sandbox import MEMORY

    assert f"memory is limited to {MEMORY / 1024**3:g} GiB" in text
    steps = [c.split()[1] for c in commands() if c.startswith("nbgrader ")]
    assert steps == [
        "generate_assignment",
        "release_assignment",
        "collect",
        "autograde",
        "generate_feedback",
        "release_feedback",
        "export",
    ]


def test_the_page_installs_the_class_kernel_with_its_environment():
    """The kernel spec's ``env`` of the page is the one the memory benchmark measures with."""
    install = [c for c in commands() if c.startswith("python -m ipykernel install")]
    assert len(install) == 1
    words = shlex.split(install[0])
    assert words[words.index("--name") + 1] == "python3"  # the kernel the notebooks ask for
    pairs = {words[i + 1]: words[i + 2] for i, word in enumerate(words) if word == "--env"}
    assert pairs == course.KERNEL_ENV


def _run(command: str, cwd: Path, env: dict[str, str]) -> None:
    done = subprocess.run(
        ["bash", "-c", command], cwd=cwd, env=env, capture_output=True, text=True, timeout=1800
    )
    assert done.returncode == 0, f"{command}\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"


def _answered(release: Path, source: Path) -> str:
    """Return the released notebook with the teacher's answers in its answer cells."""
    nb = json.loads(release.read_text("utf-8"))
    teacher = {
        c["metadata"]["nbgrader"]["grade_id"]: c["source"]
        for c in json.loads(source.read_text("utf-8"))["cells"]
    }
    for cell in nb["cells"]:
        meta = cell["metadata"].get("nbgrader", {})
        if meta.get("solution") and cell["cell_type"] == "code":
            cell["source"] = teacher[meta["grade_id"]]
    return json.dumps(nb)


def test_every_command_of_the_page_runs(tmp_path: Path):
    home = tmp_path / "home"
    home.mkdir()
    env = {**os.environ, "HOME": str(home), "PATH": f"{BIN}:{os.environ['PATH']}"}
    hub_student = pwd.getpwuid(os.getuid()).pw_name  # the hub's login, as nbgrader reads it
    exchange = tmp_path / "exchange"
    exchange.mkdir(mode=0o777)
    exchange.chmod(0o777)
    cwd = ROOT
    folder = home / "dstoolkit-course"
    ran = []
    for line in commands():
        command = line
        words = shlex.split(command, comments=True)
        if words[0] == "cd":
            cwd = home / words[1][2:] if words[1].startswith("~/") else cwd / words[1]
            assert cwd.is_dir(), command
            ran.append(line)
            continue
        if words[:2] == ["pip", "install"]:
            command = command.replace("pip install", "pip install --dry-run --quiet", 1)
        if words[:4] == ["python", "-m", "ipykernel", "install"]:
            command = command.replace("--sys-prefix", "--user", 1)
        if words[:2] == ["nbgrader", "release_feedback"]:
            # this course mixes both ways: return feedback to the hub's student only, as
            # the page says for such a course
            command += f" --student {hub_student}"
        if words[:2] == ["nbgrader", "release_assignment"]:
            with (folder / "nbgrader_config.py").open("a", encoding="utf-8") as f:
                f.write(f'c.Exchange.root = "{exchange}"\n')
        if words[:2] == ["nbgrader", "collect"]:
            student = tmp_path / "student"
            student.mkdir()
            # the course's id is its folder's name
            where = f'--course {course.course_id_of(folder)} --Exchange.root="{exchange}"'
            _run(
                f"nbgrader fetch_assignment {NAME} {where}",
                student,
                env,
            )
            _run(
                f"nbgrader submit {NAME} {where}",
                student,
                env,
            )
        if words[0] == "install":
            downloads = home / "Downloads"
            downloads.mkdir()
            (downloads / "alice.ipynb").write_text(
                _answered(
                    folder / "release" / NAME / f"{NAME}.ipynb",
                    folder / "source" / NAME / f"{NAME}.ipynb",
                ),
                encoding="utf-8",
            )
        _run(command, cwd, env)
        ran.append(line)
        if words[:4] == ["python", "-m", "ipykernel", "install"]:
            spec = home / ".local" / "share" / "jupyter" / "kernels" / "python3" / "kernel.json"
            assert json.loads(spec.read_text("utf-8"))["env"] == course.KERNEL_ENV
    assert ran == commands()
    with (folder / "grades.csv").open(encoding="utf-8") as f:
        rows = {row["student_id"]: row for row in csv.DictReader(f)}
    autograded = 5 * course.VALUE_POINTS + 2 * course.CODING_POINTS
    assert float(rows["alice"]["score"]) == autograded
    assert float(rows[hub_student]["score"]) == 0.0
    assert (folder / "feedback" / "alice" / NAME / f"{NAME}.html").exists()
    returned = exchange / course.course_id_of(folder) / "feedback"
    assert any(returned.rglob("*.html")), "release_feedback returned nothing"
