"""No file is lost.

Outputs never replace inputs or existing files unasked, never collide, are checked before
any computing, and are written atomically.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from dstoolkit import cli
from dstoolkit.audio import _measurement, save_recording, simulate_measurement
from dstoolkit.errors import OutputExistsError, OutputPathError
from dstoolkit.gauge import TubeSetup
from dstoolkit.utils import outputs as _output
from dstoolkit.utils.outputs import atomic_write, check_outputs, figure_tag, made_by


@pytest.fixture(scope="module")
def recording():
    return simulate_measurement(TubeSetup(level_m=2.6, temperature_c=26.0))


def _save(path: Path, rec) -> bytes:
    save_recording(path, rec.samples, rec.samplerate, rec.metadata)
    return path.read_bytes()


def _run(argv: list[str], capsys) -> tuple[int, str, str]:
    status = cli.main(argv)
    out = capsys.readouterr()
    return status, out.out, out.err


def _no_computing(monkeypatch):
    """Make every computation fail loudly: the command must stop before it."""

    def boom(*args, **kwargs):
        raise AssertionError("computing started before the outputs were checked")

    monkeypatch.setattr(cli, "run_table3", boom)
    monkeypatch.setattr(_measurement, "analyze", boom)
    monkeypatch.setattr(_measurement, "measure", boom)


# -- analyze ---------------------------------------------------------------------------------
def test_analyze_never_writes_its_figure_over_the_recording(tmp_path, recording, capsys):
    victim = tmp_path / "victim.png"  # a WAV file named .png
    original = _save(victim, recording)
    status, out, err = _run(["analyze", str(victim)], capsys)
    assert status == 0, err
    assert victim.read_bytes() == original
    assert made_by(tmp_path / "victim.png.png", "analyze")
    assert "victim.png.png" in out


def test_analyze_refuses_an_explicit_figure_that_is_its_input(
    tmp_path, recording, capsys, monkeypatch
):
    victim = tmp_path / "victim.wav"
    original = _save(victim, recording)
    _no_computing(monkeypatch)
    status, _, err = _run(["analyze", str(victim), "--figure", str(victim)], capsys)
    assert status == 1 and "would overwrite the input" in err and err.count("\n") == 1
    assert victim.read_bytes() == original


def test_analyze_keeps_an_existing_figure_unless_overwrite(
    tmp_path, recording, capsys, monkeypatch
):
    rec = tmp_path / "keep.wav"
    _save(rec, recording)
    mine = tmp_path / "keep.png"
    mine.write_bytes(b"my own picture")
    with monkeypatch.context() as patch:
        _no_computing(patch)
        status, _, err = _run(["analyze", str(rec)], capsys)
    assert status == 1 and "exists" in err and "--overwrite" in err
    assert mine.read_bytes() == b"my own picture"
    status, _, err = _run(["analyze", str(rec), "--overwrite"], capsys)
    assert status == 0, err
    assert made_by(mine, "analyze")
    # a figure that analyze made itself may be replaced without --overwrite
    status, _, err = _run(["analyze", str(rec)], capsys)
    assert status == 0, err


# -- table3 ----------------------------------------------------------------------------------
def test_table3_csv_and_figure_never_collide(tmp_path):
    for name in ("t.csv", "t.png", "t", "t.PNG", "t.tar.csv"):
        csv_path, figure = cli.table3_outputs(tmp_path / name)
        assert csv_path != figure and figure.suffix == ".png"
    assert cli.table3_outputs("t.png") == (Path("t.png"), Path("t.figure.png"))


@pytest.mark.parametrize("out", [".", "/proc/x/t.csv", "/dev/null", "{tmp}", "{tmp}/sub/"])
def test_table3_checks_its_outputs_before_computing(tmp_path, out, capsys, monkeypatch):
    _no_computing(monkeypatch)
    status, _, err = _run(["table3", "--out", out.format(tmp=tmp_path), "--quiet"], capsys)
    assert status == 2 and err.startswith("error: ") and err.count("\n") == 1


def test_table3_keeps_an_existing_csv_unless_overwrite(tmp_path, capsys, monkeypatch):
    out = tmp_path / "t.csv"
    out.write_text("precious\n")
    with monkeypatch.context() as patch:
        _no_computing(patch)
        status, _, err = _run(["table3", "--out", str(out), "--quiet"], capsys)
    assert status == 2 and "exists" in err
    assert out.read_text() == "precious\n"


def test_table3_out_png_writes_both_files(tmp_path, capsys):
    out = tmp_path / "t.png"
    status, stdout, err = _run(
        ["table3", "--out", str(out), "--runs", "1", "--methods", "direct", "--quiet"], capsys
    )
    assert status == 0, err
    assert out.read_text().startswith("level_m,")
    assert made_by(tmp_path / "t.figure.png", "table3")
    assert f"wrote {out} and {tmp_path / 't.figure.png'}" in stdout


# -- measure ---------------------------------------------------------------------------------
def test_measure_refuses_one_file_for_recording_and_figure(tmp_path, capsys, monkeypatch):
    _no_computing(monkeypatch)
    same = tmp_path / "same.png"
    status, _, err = _run(
        ["measure", "--temperature", "20", "--save", str(same), "--figure", str(same)], capsys
    )
    assert status == 1 and "would both be written" in err
    assert not same.exists()


def test_measure_keeps_an_existing_recording_unless_overwrite(
    tmp_path, recording, capsys, monkeypatch
):
    existing = tmp_path / "existing.wav"
    original = _save(existing, recording)
    _no_computing(monkeypatch)
    status, _, err = _run(
        [
            "measure",
            "--temperature",
            "20",
            "--save",
            str(existing),
            "--figure",
            str(tmp_path / "f.png"),
        ],
        capsys,
    )
    assert status == 1 and "exists" in err and "--overwrite" in err
    assert existing.read_bytes() == original
    with pytest.raises(OutputExistsError):
        save_recording(existing, recording.samples, recording.samplerate, overwrite=False)
    assert existing.read_bytes() == original


# -- the building blocks ---------------------------------------------------------------------
def test_atomic_write_leaves_the_old_file_or_nothing(tmp_path):
    target = tmp_path / "data.bin"

    def fail_half_way(fh):
        fh.write(b"partial")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError):
        atomic_write(target, fail_half_way)
    assert not target.exists() and os.listdir(tmp_path) == []
    target.write_bytes(b"old")
    with pytest.raises(RuntimeError):
        atomic_write(target, fail_half_way)
    assert target.read_bytes() == b"old" and os.listdir(tmp_path) == ["data.bin"]
    atomic_write(target, lambda fh: fh.write(b"new"))
    assert target.read_bytes() == b"new" and os.listdir(tmp_path) == ["data.bin"]


def test_a_failed_recording_save_keeps_the_previous_file(tmp_path, recording, monkeypatch):
    path = tmp_path / "rec.wav"
    original = _save(path, recording)

    def broken_replace(src, dst, **dir_fds):
        raise OSError("no space left on device")

    monkeypatch.setattr(_output.os, "replace", broken_replace)
    with pytest.raises(OSError, match="no space"):
        save_recording(path, np.zeros(100), 8000, overwrite=True)
    assert path.read_bytes() == original and os.listdir(tmp_path) == ["rec.wav"]


def test_check_outputs_refuses_inputs_collisions_folders_and_devices(tmp_path):
    source = tmp_path / "in.wav"
    source.write_bytes(b"x")
    link = tmp_path / "link.png"
    link.symlink_to(source)
    with pytest.raises(OutputPathError, match="overwrite the input"):
        check_outputs({"the figure": link}, inputs=[source], overwrite=True)
    with pytest.raises(OutputPathError, match="would both be written"):
        check_outputs({"a": tmp_path / "x.png", "b": tmp_path / "." / "x.png"})
    with pytest.raises(OutputPathError, match="folder"):
        check_outputs({"a": tmp_path})
    with pytest.raises(OutputPathError, match="not a regular file"):
        check_outputs({"a": "/dev/null"}, overwrite=True)
    assert check_outputs({"a": tmp_path / "new" / "x.png"})["a"] == tmp_path / "new" / "x.png"


def test_made_by_reads_the_png_text_chunk(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    fig = Figure()
    fig.subplots().plot([0, 1])
    path = tmp_path / "f.png"
    atomic_write(path, lambda fh: fig.savefig(fh, format="png", metadata=figure_tag("analyze")))
    assert made_by(path, "analyze") and not made_by(path, "table3")
    (tmp_path / "g.png").write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 20)
    assert not made_by(tmp_path / "g.png", "analyze")


def test_the_python_api_keeps_an_existing_recording_unless_asked(tmp_path, recording):
    path = tmp_path / "keep.wav"
    original = _save(path, recording)
    with pytest.raises(OutputExistsError, match="overwrite=True"):
        save_recording(path, np.zeros(100), 8000)
    assert path.read_bytes() == original
    save_recording(path, np.zeros(100), 8000, overwrite=True)
    assert path.read_bytes() != original


def test_measure_refuses_an_existing_recording_before_playing(tmp_path, recording, monkeypatch):
    path = tmp_path / "rec.wav"
    original = _save(path, recording)

    def must_not_play(*args, **kwargs):
        raise AssertionError("played although the output exists")

    monkeypatch.setattr(_measurement.audio, "play_record", must_not_play)
    setup = TubeSetup(level_m=2.5, temperature_c=21.0)
    with pytest.raises(OutputExistsError, match="exists"):
        _measurement.measure(virtual_tube=setup, save=path)
    assert path.read_bytes() == original
