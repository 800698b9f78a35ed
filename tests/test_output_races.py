"""Outputs that survive races and interruptions.

A file that appears while a command runs is kept, outputs that are not regular files are
refused even with ``--overwrite``, and a failed, interrupted or terminated command leaves
nothing it made behind.
"""

from __future__ import annotations

import signal
from pathlib import Path

import pytest
from hostile_inputs import SPECIAL_OUTPUTS, special_output, table3_signalled

from dstoolkit import cli
from dstoolkit.audio import save_recording, simulate_measurement
from dstoolkit.errors import InvalidInputError, OutputExistsError, OutputPathError
from dstoolkit.gauge import TubeSetup
from dstoolkit.utils.outputs import atomic_write, check_outputs, output_run

TABLE3_SMALL = ["--runs", "1", "--methods", "direct", "--quiet"]
SOMEONE_ELSES = "made by someone else meanwhile\n"


@pytest.fixture(scope="module")
def recording():
    return simulate_measurement(TubeSetup(level_m=2.6, temperature_c=26.0))


def _files(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


# -- a file that appears while the command runs ------------------------------------------
@pytest.mark.parametrize("which", ["t.csv", "t.png"])
def test_a_file_created_at_out_while_table3_runs_survives(tmp_path, capsys, monkeypatch, which):
    real = cli.run_table3
    target = tmp_path / which

    def meanwhile(**kwargs):
        target.write_text(SOMEONE_ELSES)  # another program, or a second table3
        return real(**kwargs)

    monkeypatch.setattr(cli, "run_table3", meanwhile)
    status = cli.main(["table3", "--out", str(tmp_path / "t.csv"), *TABLE3_SMALL])
    err = capsys.readouterr().err
    assert status == 2
    assert target.read_text() == SOMEONE_ELSES
    assert "appeared" in err and "Traceback" not in err and len(err.splitlines()) == 1
    assert _files(tmp_path) == [which]  # the run's other output was removed too


def test_a_checked_new_path_is_created_without_clobbering(tmp_path):
    path = tmp_path / "out.bin"
    with pytest.raises(OutputExistsError, match="appeared"), output_run():
        check_outputs({"the output": path})
        path.write_bytes(b"theirs")
        atomic_write(path, lambda fh: fh.write(b"ours"))
    assert path.read_bytes() == b"theirs"
    assert _files(tmp_path) == ["out.bin"]  # no temporary file left


def test_a_replaceable_file_is_replaced_only_if_it_is_still_the_same(tmp_path):
    path = tmp_path / "out.bin"
    path.write_bytes(b"old")
    with output_run():
        check_outputs({"the output": path}, overwrite=True)
        atomic_write(path, lambda fh: fh.write(b"new"))
    assert path.read_bytes() == b"new"
    with pytest.raises(OutputExistsError), output_run():
        check_outputs({"the output": path}, overwrite=True)
        path.unlink()
        path.write_bytes(b"another file")  # a new file at the same name
        atomic_write(path, lambda fh: fh.write(b"ours"))
    assert path.read_bytes() == b"another file"


def test_outside_a_command_atomic_write_replaces_as_before(tmp_path):
    path = tmp_path / "out.bin"
    path.write_bytes(b"old")
    atomic_write(path, lambda fh: fh.write(b"new"))
    assert path.read_bytes() == b"new"


# -- outputs that are not regular files --------------------------------------------------
SPECIAL = list(SPECIAL_OUTPUTS)


@pytest.mark.parametrize("kind", SPECIAL)
def test_outputs_that_are_not_regular_files_are_refused_even_with_overwrite(tmp_path, kind):
    link, keep = special_output(kind, tmp_path)
    try:
        with pytest.raises(OutputPathError, match="not a regular file"):
            check_outputs({"the figure": link}, overwrite=True)
        with pytest.raises(OutputPathError, match="not a regular file"):
            atomic_write(link, lambda fh: fh.write(b"png"))
    finally:
        if keep is not None:
            keep.close()  # type: ignore[attr-defined]
    assert link.is_symlink() or not link.is_file()  # nothing was put in its place


@pytest.mark.parametrize("kind", SPECIAL[:3])
def test_analyze_overwrite_never_writes_over_a_special_file(tmp_path, recording, capsys, kind):
    wav = tmp_path / "r.wav"
    save_recording(wav, recording.samples, recording.samplerate, recording.metadata)
    link, keep = special_output(kind, tmp_path)
    try:
        status = cli.main(["analyze", str(wav), "--figure", str(link), "--overwrite"])
    finally:
        if keep is not None:
            keep.close()  # type: ignore[attr-defined]
    err = capsys.readouterr().err
    assert status != 0 and "not a regular file" in err
    assert link.is_symlink() or not link.is_file()


# -- failures and interruptions remove what the run made ----------------------------------
def test_a_failed_run_removes_the_folders_it_made(tmp_path, capsys, monkeypatch):
    def fail(**kwargs):
        raise InvalidInputError("a failure inside the computation")

    monkeypatch.setattr(cli, "run_table3", fail)
    status = cli.main(["table3", "--out", str(tmp_path / "new" / "deep" / "t.csv"), "--quiet"])
    assert status == 2 and "a failure inside" in capsys.readouterr().err
    assert _files(tmp_path) == []


def test_ctrl_c_removes_what_the_command_had_written(tmp_path, capsys, monkeypatch):
    import dstoolkit.plots

    def interrupted(table):  # the CSV is written; Ctrl-C while the figure is drawn
        assert (tmp_path / "out" / "t.csv").is_file()
        raise KeyboardInterrupt

    monkeypatch.setattr(dstoolkit.plots, "plot_table3", interrupted)
    status = cli.main(["table3", "--out", str(tmp_path / "out" / "t.csv"), *TABLE3_SMALL])
    err = capsys.readouterr().err
    assert status == 130
    assert err.startswith("interrupted") and len(err.splitlines()) == 1
    assert _files(tmp_path) == []


def test_the_signal_handlers_are_given_back(tmp_path, capsys):
    before = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    cli.main(["table3", "--runs", "0", "--out", str(tmp_path / "t.csv"), "--quiet"])
    assert (signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)) == before


@pytest.mark.slow
@pytest.mark.parametrize(
    ("sig", "status", "word"),
    [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated")],
)
def test_a_signal_halfway_leaves_no_traceback_and_no_file(tmp_path, sig, status, word):
    """table3 in a child process, stopped once its CSV is written (its figure being drawn)."""
    work = tmp_path / "work"
    work.mkdir()
    returncode, err, written = table3_signalled(work, sig)
    assert written  # halfway: the CSV was there when the signal came
    assert returncode == status
    assert "Traceback" not in err and err.startswith(word) and len(err.splitlines()) == 1
    assert _files(work) == []
