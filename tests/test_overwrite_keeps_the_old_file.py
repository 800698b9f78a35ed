"""``--overwrite`` as ``mv`` does it: the old file stays until the new one is complete.

A command only ever removes what it made itself: its temporary files, and on a failure or a
stop signal the files it had put in place, the files they replaced being put back (a
command's outputs are written all or none). A file replaced keeps its permissions and
owner; a file or a symbolic link that appears at an output, or a folder swapped, while the
command runs is never written over; concurrent runs never remove each other's files. A
closed standard output, an ASCII-only locale, a broken ``MPLBACKEND`` and a symbolic link
loop end in one line.
"""

from __future__ import annotations

import errno
import os
import signal
import stat
import subprocess
import sys
from pathlib import Path

import pytest
from hostile_inputs import table3_signalled

import dstoolkit
import dstoolkit.plots
from dstoolkit import _startup, cli
from dstoolkit.errors import BrokenExtraError, OutputExistsError, OutputPathError, require_extra
from dstoolkit.utils.console import command_console
from dstoolkit.utils.outputs import atomic_write, check_outputs, output_run

TABLE3_SMALL = ["--runs", "1", "--methods", "direct", "--quiet"]
PRECIOUS = "precious\n"
THEIRS = "another run's file\n"
ROOT = Path(dstoolkit.__file__).resolve().parents[1]


def _files(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def _table3(out: Path, *extra: str) -> list[str]:
    return ["table3", "--out", str(out), *TABLE3_SMALL, *extra]


def _child(argv: list[str], cwd: Path, **env: str) -> subprocess.CompletedProcess[str]:
    """Run ``python -m dstoolkit argv`` with this worktree's package."""
    return subprocess.run(
        [sys.executable, "-m", "dstoolkit", *argv],
        cwd=cwd,
        env={**os.environ, "PYTHONPATH": str(ROOT), **env},
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )


# -- stop signals, with and without --overwrite ----------------------------------------------
SIGNALS = [signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT]


@pytest.mark.slow
@pytest.mark.parametrize("overwrite", [True, False], ids=["overwrite", "new"])
@pytest.mark.parametrize("sig", SIGNALS, ids=lambda s: signal.Signals(s).name)
def test_a_stop_signal_keeps_the_original_and_leaves_no_litter(tmp_path, sig, overwrite):
    """The signal comes once the new CSV is in place (the figure being drawn)."""
    work = tmp_path / "work"
    (work / "out").mkdir(parents=True)
    csv = work / "out" / "t.csv"
    if overwrite:
        csv.write_text(PRECIOUS)
        csv.chmod(0o600)
    returncode, err, written = table3_signalled(work, sig, overwrite=overwrite)
    assert written  # the new CSV had replaced the old one when the signal came
    assert returncode == 128 + sig
    assert "Traceback" not in err and len(err.splitlines()) == 1, err
    if overwrite:
        assert csv.read_text() == PRECIOUS
        assert stat.S_IMODE(csv.stat().st_mode) == 0o600
        assert _files(work) == ["out", "out/t.csv"]  # no .part, no kept-aside copy
    else:
        assert _files(work) == ["out"]  # the folder was there before; nothing in it


# -- failures after the first output was put in place -----------------------------------
class _DiskFull:
    """A figure whose saving writes half a file and then finds the disk full."""

    def savefig(self, fh, **kwargs):
        fh.write(b"\x89PNG half")
        raise OSError(errno.ENOSPC, "No space left on device")


def test_a_full_disk_while_the_figure_is_written_puts_the_old_files_back(
    tmp_path, capsys, monkeypatch
):
    csv, png = tmp_path / "t.csv", tmp_path / "t.png"
    csv.write_text(PRECIOUS)
    png.write_bytes(b"old figure")
    monkeypatch.setattr(dstoolkit.plots, "plot_table3", lambda table: _DiskFull())
    status = cli.main(_table3(csv, "--overwrite"))
    err = capsys.readouterr().err
    assert status == 2 and "No space left" in err and len(err.splitlines()) == 1
    assert csv.read_text() == PRECIOUS and png.read_bytes() == b"old figure"
    assert _files(tmp_path) == ["t.csv", "t.png"]


def test_a_failed_run_never_removes_a_file_another_run_put_at_its_name(
    tmp_path, capsys, monkeypatch
):
    csv = tmp_path / "t.csv"
    csv.write_text(PRECIOUS)

    def meanwhile(table):  # our CSV is in place; another run replaces it, then we fail
        assert csv.read_text() != PRECIOUS
        tmp = tmp_path / "theirs.tmp"
        tmp.write_text(THEIRS)
        os.replace(tmp, csv)
        raise OSError(errno.EIO, "Input/output error")

    monkeypatch.setattr(dstoolkit.plots, "plot_table3", meanwhile)
    status = cli.main(_table3(csv, "--overwrite"))
    assert status == 2 and "Input/output" in capsys.readouterr().err
    assert csv.read_text() == THEIRS
    assert _files(tmp_path) == ["t.csv"]  # our kept-aside copy of PRECIOUS is gone too


def test_a_successful_overwrite_leaves_only_its_outputs(tmp_path, capsys):
    csv, png = tmp_path / "t.csv", tmp_path / "t.png"
    csv.write_text(PRECIOUS)
    png.write_bytes(b"old figure")
    assert cli.main(_table3(csv, "--overwrite")) == 0
    assert csv.read_text() != PRECIOUS and csv.read_text().count("\n") >= 2
    assert png.read_bytes().startswith(b"\x89PNG")
    assert _files(tmp_path) == ["t.csv", "t.png"]
    capsys.readouterr()


# -- concurrent runs ----------------------------------------------------------------------
def test_a_run_that_finishes_first_wins_and_the_other_stops_cleanly(tmp_path, capsys, monkeypatch):
    """Run B starts and finishes inside run A; A then finds t.csv changed and keeps it."""
    csv = tmp_path / "t.csv"
    csv.write_text(PRECIOUS)
    real = cli.run_table3
    results = {}

    def a_inside(**kwargs):
        monkeypatch.setattr(cli, "run_table3", real)
        results["b"] = cli.main(_table3(csv, "--overwrite", "--seed", "7"))
        results["b_csv"] = csv.read_bytes()
        return real(**kwargs)

    monkeypatch.setattr(cli, "run_table3", a_inside)
    status = cli.main(_table3(csv, "--overwrite"))
    err = capsys.readouterr().err
    assert results["b"] == 0
    assert status == 2 and "appeared or changed" in err
    assert csv.read_bytes() == results["b_csv"]  # B's complete file, not removed by A
    assert _files(tmp_path) == ["t.csv", "t.png"]


@pytest.mark.slow
def test_three_concurrent_overwrite_runs_leave_a_complete_file(tmp_path):
    (tmp_path / "t.csv").write_text(PRECIOUS)
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    argv = [sys.executable, "-m", "dstoolkit", *_table3(tmp_path / "t.csv", "--overwrite")]
    procs = [
        subprocess.Popen(
            argv, cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE
        )
        for _ in range(3)
    ]
    statuses = [p.wait(timeout=600) for p in procs]
    for p in procs:
        p.stdout.close()  # type: ignore[union-attr]
        p.stderr.close()  # type: ignore[union-attr]
    assert 0 in statuses and set(statuses) <= {0, 2}
    text = (tmp_path / "t.csv").read_text()
    assert text != PRECIOUS and text.endswith("\n") and len(text.splitlines()) >= 2
    assert (tmp_path / "t.png").read_bytes().startswith(b"\x89PNG")
    assert _files(tmp_path) == ["t.csv", "t.png"]


# -- a path swapped while the command runs -----------------------------------------------
def _meanwhile(monkeypatch, act):
    real = cli.run_table3

    def hook(**kwargs):
        act()
        return real(**kwargs)

    monkeypatch.setattr(cli, "run_table3", hook)


def test_a_file_deleted_and_made_again_meanwhile_is_not_replaced(tmp_path, capsys, monkeypatch):
    csv = tmp_path / "t.csv"
    csv.write_text(PRECIOUS)

    def recreate():
        csv.unlink()
        csv.write_text(THEIRS)  # the file system may give it the same inode

    _meanwhile(monkeypatch, recreate)
    status = cli.main(_table3(csv, "--overwrite"))
    assert status == 2 and "appeared or changed" in capsys.readouterr().err
    assert csv.read_text() == THEIRS
    assert _files(tmp_path) == ["t.csv"]


def test_a_symlink_made_at_the_figure_path_meanwhile_is_not_followed(tmp_path, capsys, monkeypatch):
    csv, png, victim = tmp_path / "t.csv", tmp_path / "t.png", tmp_path / "victim.txt"
    victim.write_text(PRECIOUS)
    _meanwhile(monkeypatch, lambda: png.symlink_to(victim))
    status = cli.main(_table3(csv, "--overwrite"))
    assert status == 2 and "appeared or changed" in capsys.readouterr().err
    assert png.is_symlink() and victim.read_text() == PRECIOUS
    assert _files(tmp_path) == ["t.png", "victim.txt"]


def test_a_folder_swapped_meanwhile_is_refused(tmp_path, capsys, monkeypatch):
    out = tmp_path / "out"
    out.mkdir()
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()

    def swap():
        out.rename(tmp_path / "moved")
        out.symlink_to(elsewhere)

    _meanwhile(monkeypatch, swap)
    status = cli.main(_table3(out / "t.csv", "--overwrite"))
    assert status == 2 and "moved or replaced" in capsys.readouterr().err
    assert _files(elsewhere) == [] and _files(tmp_path / "moved") == []


def test_a_checked_file_removed_meanwhile_is_not_made_again():
    """With overwrite, a file that vanished is not the file that was checked either."""
    import tempfile

    folder = Path(tempfile.mkdtemp())
    path = folder / "a.txt"
    path.write_text(PRECIOUS)
    with pytest.raises(OutputExistsError), output_run():
        check_outputs({"the text": path}, overwrite=True)
        path.unlink()
        atomic_write(path, lambda fh: fh.write(b"new"))
    assert _files(folder) == []


# -- permissions and owner -------------------------------------------------------------
def test_overwrite_keeps_the_permissions_of_the_file_it_replaces(tmp_path, capsys):
    csv, png = tmp_path / "t.csv", tmp_path / "t.png"
    csv.write_text(PRECIOUS)
    csv.chmod(0o600)
    png.write_bytes(b"old")
    png.chmod(0o640)
    assert cli.main(_table3(csv, "--overwrite")) == 0
    assert stat.S_IMODE(csv.stat().st_mode) == 0o600
    assert stat.S_IMODE(png.stat().st_mode) == 0o640
    capsys.readouterr()


def test_a_new_file_gets_the_usual_permissions(tmp_path):
    mask = os.umask(0o022)
    try:
        path = atomic_write(tmp_path / "new.bin", lambda fh: fh.write(b"x"))
    finally:
        os.umask(mask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644


@pytest.mark.skipif(os.geteuid() != 0, reason="only root can give a file to another owner")
def test_as_root_overwrite_keeps_the_owner(tmp_path):
    path = tmp_path / "a.csv"
    path.write_text(PRECIOUS)
    os.chown(path, 65534, 65534)
    with output_run():
        check_outputs({"the CSV": path}, overwrite=True)
        atomic_write(path, lambda fh: fh.write(b"new"))
    info = path.stat()
    assert (info.st_uid, info.st_gid) == (65534, 65534) and path.read_bytes() == b"new"


# -- symbolic link loops ---------------------------------------------------------------
@pytest.mark.parametrize("where", ["file", "folder"])
def test_a_symlink_loop_in_an_output_path_is_one_line(tmp_path, capsys, where):
    loop = tmp_path / "loop"
    loop.symlink_to(loop)
    out = loop if where == "file" else loop / "t.csv"
    status = cli.main(_table3(out, "--overwrite"))
    err = capsys.readouterr().err
    assert status == 2 and err.startswith("error:") and len(err.splitlines()) == 1, err
    assert _files(tmp_path) == ["loop"]


def test_a_symlink_loop_as_the_recording_is_one_line(tmp_path, capsys):
    loop = tmp_path / "loop.wav"
    loop.symlink_to(loop)
    status = cli.main(["analyze", str(loop), "--figure", str(tmp_path / "f.png")])
    err = capsys.readouterr().err
    assert status != 0 and err.startswith("error:") and len(err.splitlines()) == 1, err
    assert "Traceback" not in err


# -- the console: encodings, closed pipes, a broken matplotlib, Ctrl-C while importing ----
def test_text_the_output_cannot_encode_is_written_in_ascii(tmp_path):
    with open(tmp_path / "out.txt", "w", encoding="ascii") as fh:
        before = sys.stdout
        sys.stdout = fh
        try:
            with command_console():
                print("T (°C) 2.60 ± 0.01 m, ü")
        finally:
            sys.stdout = before
    assert (tmp_path / "out.txt").read_text() == "T (degC) 2.60 +/- 0.01 m, \\xfc\n"


@pytest.mark.slow
@pytest.mark.parametrize(
    "env",
    [{"PYTHONIOENCODING": "ascii"}, {"LC_ALL": "C", "LANG": "C", "PYTHONUTF8": "0"}],
    ids=["PYTHONIOENCODING", "LC_ALL"],
)
def test_table3_prints_on_an_ascii_only_locale_and_keeps_its_outputs(tmp_path, env):
    done = _child(_table3(tmp_path / "t.csv"), tmp_path, **env)
    assert done.returncode == 0, done.stderr
    assert "degC" in done.stdout and "Traceback" not in done.stderr
    assert _files(tmp_path) == ["t.csv", "t.png"]


@pytest.mark.slow
def test_a_closed_pipe_keeps_the_finished_outputs(tmp_path):
    """``table3 | head -0``: the reader is gone before the table is printed."""
    read, write = os.pipe()
    os.close(read)
    try:
        done = subprocess.run(
            [sys.executable, "-m", "dstoolkit", *_table3(tmp_path / "t.csv")],
            cwd=tmp_path,
            env={**os.environ, "PYTHONPATH": str(ROOT)},
            stdout=write,
            stderr=subprocess.PIPE,
            text=True,
            timeout=600,
            check=False,
        )
    finally:
        os.close(write)
    assert done.returncode == 2
    assert done.stderr.startswith("error: the standard output was closed")
    assert len(done.stderr.splitlines()) == 1, done.stderr
    assert _files(tmp_path) == ["t.csv", "t.png"]


@pytest.mark.slow
def test_a_nonsense_mplbackend_is_one_line_and_leaves_nothing(tmp_path):
    done = _child(_table3(tmp_path / "t.csv"), tmp_path, MPLBACKEND="nonsense")
    assert done.returncode == 2
    assert done.stderr.startswith("error:") and "MPLBACKEND" in done.stderr
    assert len(done.stderr.splitlines()) == 1, done.stderr
    assert _files(tmp_path) == []


def test_require_extra_names_a_module_that_fails_to_import(monkeypatch):
    import importlib

    def broken(name):
        raise ValueError("Key backend: 'nonsense' is not a valid value for backend")

    monkeypatch.setattr(importlib, "import_module", broken)
    with pytest.raises(BrokenExtraError, match="failed to import.*MPLBACKEND"):
        require_extra("matplotlib", "plots", "dstoolkit.plots")


@pytest.mark.parametrize(
    ("argv", "command"),
    [
        (["/venv/bin/python", "/venv/bin/dstoolkit", "table3"], True),
        (["python", "-m", "dstoolkit", "table3"], True),
        (["python", "-mdstoolkit"], True),
        (["python", "-m", "pytest", "dstoolkit"], False),
        (["python", "script.py", "-m"], False),
        (["python"], False),
    ],
)
def test_the_quiet_start_is_only_for_the_command(argv, command):
    assert _startup._is_the_command(argv) is command


@pytest.mark.slow
@pytest.mark.parametrize("sig", SIGNALS, ids=lambda s: signal.Signals(s).name)
def test_a_stop_while_the_command_imports_is_one_line(tmp_path, sig):
    """The signal comes while numpy is being imported, in a process that is the command."""
    code = (
        "import signal, sys\n"
        "sys.orig_argv[1:] = ['-m', 'dstoolkit']\n"
        "import dstoolkit._startup as s\n"
        "s.install_if_command()\n"
        f"signal.raise_signal({int(sig)})\n"
        "import numpy\n"
        "print('not stopped')\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code],
        env={**os.environ, "PYTHONPATH": str(ROOT)},
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
        # a run under nohup ignores SIGHUP, and an ignored signal is left ignored (as a
        # shell would): the child starts with the signal's default, as in a terminal
        preexec_fn=lambda: signal.signal(sig, signal.SIG_DFL),
    )
    assert done.returncode == 128 + sig
    assert done.stdout == "" and len(done.stderr.splitlines()) == 1, done.stderr
    assert "no file was being written" in done.stderr


def test_an_output_given_as_a_path_through_a_loop_is_refused_by_the_checks(tmp_path):
    loop = tmp_path / "loop"
    loop.symlink_to(loop)
    with pytest.raises(OutputPathError):
        check_outputs({"the CSV": loop / "t.csv"})
