"""scripts/sheets.py writes its files as the command line does.

No existing file is replaced without ``--overwrite``; each file is written atomically and a
failed or stopped run leaves nothing of its own (the files it replaced put back); the
book's student-sheets folder is refused as the teacher's, a variant's or a course's folder;
an output that cannot be written and a misspelled ``--chapter`` are one ``error:`` line.
"""

from __future__ import annotations

import errno
import hashlib
import os
import sys
from pathlib import Path

import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "scripts"))
import course  # noqa: E402
import sheets  # noqa: E402

from dstoolkit.utils import outputs as _outputs  # noqa: E402

CHAPTER = ["--chapter", "mass_functions"]  # one chapter keeps a course quick to write
EDITED = "# my edited nbgrader_config.py\n"


def _files(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def _fingerprint(folder: Path) -> dict[str, str]:
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def _main(argv: list[str], capsys) -> tuple[int, str]:
    status = sheets.main(argv)
    return status, capsys.readouterr().err


@pytest.mark.parametrize(
    "argv",
    [
        ["--teacher", "notebooks"],
        ["--variant", "2", "--out", "notebooks"],
        ["--variant", "2", "--out", "notebooks/v2"],
        ["--nbgrader", "notebooks", *CHAPTER],
    ],
    ids=["teacher", "variant", "variant-inside", "nbgrader"],
)
def test_the_student_sheets_folder_is_refused_as_another_output(argv, capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    before = _fingerprint(ROOT / "notebooks")
    status, err = _main([*argv, "--overwrite"], capsys)
    assert status == 2 and "student-sheets folder" in err and len(err.splitlines()) == 1
    assert _fingerprint(ROOT / "notebooks") == before


def test_an_existing_course_is_kept_without_overwrite(tmp_path, capsys):
    home = tmp_path / "course"
    home.mkdir()
    (home / "nbgrader_config.py").write_text(EDITED)
    status, err = _main(["--nbgrader", str(home), *CHAPTER], capsys)
    assert status == 2 and "exists" in err and "--overwrite" in err
    assert _files(home) == ["nbgrader_config.py"]
    assert (home / "nbgrader_config.py").read_text() == EDITED
    assert _main(["--nbgrader", str(home), *CHAPTER, "--overwrite"], capsys)[0] == 0
    assert "course_id" in (home / "nbgrader_config.py").read_text()


def test_existing_variant_sheets_are_kept_without_overwrite(tmp_path, capsys):
    out = tmp_path / "v"
    out.mkdir()
    mine = out / "02_mass_functions.ipynb"
    mine.write_text("my annotated copy")
    status, err = _main(["--variant", "2", "--out", str(out)], capsys)
    assert status == 2 and "exists" in err
    assert _files(out) == ["02_mass_functions.ipynb"]  # the sheets written before it: gone
    assert mine.read_text() == "my annotated copy"


def test_a_full_disk_half_way_leaves_the_course_as_it_was(tmp_path, capsys, monkeypatch):
    home = tmp_path / "course"
    home.mkdir()
    (home / "nbgrader_config.py").write_text(EDITED)
    real = sheets.dump
    calls = []

    def disk_full(notebook):
        calls.append(1)
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(sheets, "dump", disk_full)
    status, err = _main(["--nbgrader", str(home), *CHAPTER, "--overwrite"], capsys)
    assert calls and status == 2 and "No space left" in err and len(err.splitlines()) == 1
    assert _files(home) == ["nbgrader_config.py"]  # its template and folders: gone
    assert (home / "nbgrader_config.py").read_text() == EDITED  # put back
    monkeypatch.setattr(sheets, "dump", real)


def test_a_stop_half_way_removes_the_variant_it_had_written(tmp_path, capsys, monkeypatch):
    real = sheets.build
    made = []

    def stopped_after_two(*args, **kwargs):
        made.append(1)
        if len(made) == 3:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(sheets, "build", stopped_after_two)
    status, err = _main(["--variant", "1", "--out", str(tmp_path / "v")], capsys)
    assert status == 130 and err.startswith("interrupted") and len(err.splitlines()) == 1
    assert _files(tmp_path) == []


@pytest.mark.parametrize("kind", ["file", "read-only", "proc"])
def test_an_output_that_cannot_be_a_folder_of_sheets_is_one_line(
    tmp_path, capsys, monkeypatch, kind
):
    if kind == "file":
        out = tmp_path / "a-file"
        out.write_text("x")
    elif kind == "read-only":
        tmp_path.chmod(0o500)
        out = tmp_path / "v"
        if os.geteuid() == 0:  # root writes into read-only folders: the kernel's answer then

            def denied(*args, **kwargs):
                raise PermissionError(errno.EACCES, "Permission denied")

            monkeypatch.setattr(_outputs.tempfile, "mkstemp", denied)
            monkeypatch.setattr(Path, "mkdir", denied)
    else:
        out = Path("/proc/dstoolkit-sheets")
    try:
        status, err = _main(["--variant", "1", "--out", str(out)], capsys)
    finally:
        tmp_path.chmod(0o700)
    assert status == 2 and err.startswith("error:") and len(err.splitlines()) == 1, err
    assert "Traceback" not in err
    if kind == "file":
        assert _files(tmp_path) == ["a-file"]


def test_a_misspelled_chapter_is_an_error(tmp_path, capsys):
    status, err = _main(["--nbgrader", str(tmp_path / "c"), "--chapter", "mass_function"], capsys)
    assert status == 2 and "no chapter" in err and "'mass_function'" in err
    assert _files(tmp_path) == []


def test_write_course_called_directly_still_replaces_its_own_course(tmp_path):
    first = course.write_course(tmp_path, ROOT, ["mass_functions"])
    again = course.write_course(tmp_path, ROOT, ["mass_functions"])
    assert first == again and all(p.is_file() for p in again)


def test_a_matrix_reads_row_by_row_in_plain_text() -> None:
    """The course's markdown writes a pmatrix as [a b; c d], and a formula it cannot read fails.

    A student's notebook without MathJax must not show raw TeX.
    """
    text = r"$P = \begin{pmatrix} 2 & 1 \\ 1 & 2 \end{pmatrix}$, $x_k$"
    assert course.plain_maths(text) == "P = [2 1; 1 2], xₖ"
    assert course.plain_maths(r"$e^\top P^{-1} e = \tfrac13$") == "eᵀ P⁻¹ e = 1/3"
    assert course.plain_maths(r"$\sqrt{(n + \lambda_{\mathrm{UT}}) P}$") == "√((n + λ_(UT)) P)"
    with pytest.raises(ValueError, match="no plain form"):
        course.plain_maths(r"$\unknowncommand x$")
