"""Faults in the sound server surface as errors, through the real audio path.

Each case starts its own PulseAudio loopback (``scripts/audio-loopback.sh``, in a private
folder), runs ``dstoolkit measure`` in a child process and, mid-measurement, stops the
server (SIGSTOP: it stalls) or kills it (SIGKILL: it dies). The command must end within
the stream's deadline with an error that says so, and leave no file behind nor replace
one. Also: the loopback script refuses folders that are not private.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from dstoolkit.audio import STREAM_GRACE_S

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "scripts" / "audio-loopback.sh"
REQUIRED = os.environ.get("DSTOOLKIT_REQUIRE_AUDIO") == "1"
#: Seconds the measurement plays: lead-in, chirp, gap, 5 s sweep, gap, chirp, tail.
PROGRAMME_S = 7.0
#: Seconds allowed beyond the stream's deadline, counted from the moment the stream reaches
#: the server (the child's exit, the error's way to the command's stderr).
SLACK_S = 4.0


def _loopback_env() -> dict[str, str]:
    if shutil.which("pulseaudio") is None or shutil.which("pactl") is None:
        if REQUIRED:
            pytest.fail(
                "audio is required here (DSTOOLKIT_REQUIRE_AUDIO=1) but PulseAudio is not installed"
            )
        pytest.skip(
            "PulseAudio is not installed: apt-get install pulseaudio "
            "pulseaudio-utils libasound2-plugins libportaudio2"
        )
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PULSE_", "DSTOOLKIT_PULSE"))}
    proc = subprocess.run(
        ["bash", str(SCRIPT), "start"], capture_output=True, text=True, timeout=60, env=env
    )
    if proc.returncode != 0:
        if REQUIRED:
            pytest.fail(f"audio-loopback.sh failed: {proc.stderr}")
        pytest.skip(f"audio-loopback.sh failed: {proc.stderr}")
    state = dict(line.split("=", 1) for line in proc.stdout.splitlines() if "=" in line)
    return {**env, **{k: v for k, v in state.items() if k.startswith("PULSE_")}}


@pytest.fixture
def loopback() -> Iterator[dict[str, str]]:
    """Start a loopback of this test's own (it is stopped or killed on purpose)."""
    env = _loopback_env()
    try:
        yield env
    finally:
        pid_file = Path(env["PULSE_RUNTIME_PATH"]) / "pid"
        if pid_file.exists():
            try:
                os.kill(int(pid_file.read_text()), signal.SIGCONT)
            except (ProcessLookupError, ValueError):
                pass
        subprocess.run(["bash", str(SCRIPT), "stop"], capture_output=True, timeout=60, env=env)


def _wait_for_stream(env: dict[str, str], proc: subprocess.Popen[str]) -> None:
    """Wait until the measurement's stream plays into the loopback's sink."""
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and proc.poll() is None:
        inputs = subprocess.run(
            ["pactl", "list", "short", "sink-inputs"],
            capture_output=True,
            text=True,
            env=env,
            timeout=10,
        ).stdout
        if inputs.strip():
            return
        time.sleep(0.1)
    pytest.fail("the measurement's stream never reached the sound server")


def _measure_with_fault(
    env: dict[str, str], folder: Path, fault: signal.Signals
) -> tuple[subprocess.CompletedProcess[str], float]:
    server = int((Path(env["PULSE_RUNTIME_PATH"]) / "pid").read_text())
    cmd = [
        sys.executable,
        "-m",
        "dstoolkit",
        "measure",
        "--temperature",
        "26",
        "--virtual-level",
        "2.6",
        "--input",
        "pulse",
        "--output",
        "pulse",
        "--save",
        str(folder / "rec.wav"),
        "--figure",
        str(folder / "fig.png"),
        "--overwrite",
    ]
    proc = subprocess.Popen(
        cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, cwd=folder
    )
    _wait_for_stream(env, proc)
    start = time.monotonic()  # the stream plays from here
    time.sleep(1.0)  # mid-measurement
    os.kill(server, fault)
    try:
        out, err = proc.communicate(timeout=PROGRAMME_S + STREAM_GRACE_S + 60)
    finally:
        if proc.poll() is None:
            proc.kill()
    elapsed = time.monotonic() - start
    return subprocess.CompletedProcess(cmd, proc.returncode, out, err), elapsed


@pytest.mark.slow
@pytest.mark.audio
def test_a_stalled_server_ends_the_measurement_with_a_stall_error(loopback, tmp_path):
    (tmp_path / "rec.wav").write_bytes(b"an earlier recording")
    result, elapsed = _measure_with_fault(loopback, tmp_path, signal.SIGSTOP)
    print(f"stalled: exit {result.returncode} after {elapsed:.1f} s: {result.stderr.strip()}")
    assert result.returncode == 1
    assert "the audio stream stalled" in result.stderr
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr
    # the deadline: the stream's length plus STREAM_GRACE_S
    assert elapsed < PROGRAMME_S + STREAM_GRACE_S + SLACK_S
    assert (tmp_path / "rec.wav").read_bytes() == b"an earlier recording"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rec.wav"]


@pytest.mark.slow
@pytest.mark.audio
def test_a_dead_server_is_named_in_the_error(loopback, tmp_path):
    result, elapsed = _measure_with_fault(loopback, tmp_path, signal.SIGKILL)
    print(f"killed: exit {result.returncode} after {elapsed:.1f} s: {result.stderr.strip()}")
    assert result.returncode == 1
    assert "sound server died" in result.stderr
    assert f"PulseAudio sound server at {loopback['PULSE_SERVER']}" in result.stderr
    assert "wiring" not in result.stderr and "Traceback" not in result.stderr
    assert elapsed < PROGRAMME_S + STREAM_GRACE_S + SLACK_S
    assert list(tmp_path.iterdir()) == []


# -- the loopback script's folder --------------------------------------------------------------
def _script(*args: str, **env: str) -> subprocess.CompletedProcess[str]:
    base = {k: v for k, v in os.environ.items() if not k.startswith(("PULSE_", "DSTOOLKIT_P"))}
    return subprocess.run(
        ["bash", str(SCRIPT), *args],
        capture_output=True,
        text=True,
        timeout=60,
        env={**base, **env},
    )


def test_loopback_script_refuses_a_symlinked_folder(tmp_path):
    target = tmp_path / "elsewhere"
    target.mkdir(mode=0o700)
    (tmp_path / "link").symlink_to(target)
    for command in ("start", "stop", "status"):
        proc = _script(command, DSTOOLKIT_PULSE_DIR=str(tmp_path / "link"))
        assert proc.returncode == 4, (command, proc.stderr)
        assert "refusing" in proc.stderr
    assert list(target.iterdir()) == []


def test_loopback_script_refuses_a_folder_others_can_enter(tmp_path):
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o755)
    proc = _script("start", DSTOOLKIT_PULSE_DIR=str(shared))
    assert proc.returncode == 4 and "mode 0700" in proc.stderr
    assert list(shared.iterdir()) == []


@pytest.mark.skipif(os.geteuid() != 0, reason="needs root to give a folder to another user")
def test_loopback_script_refuses_a_folder_of_another_user(tmp_path):
    planted = tmp_path / "planted"
    planted.mkdir(mode=0o700)
    os.chown(planted, 65534, 65534)
    proc = _script("start", DSTOOLKIT_PULSE_DIR=str(planted))
    assert proc.returncode == 4 and "refusing" in proc.stderr


def test_loopback_script_never_uses_the_old_predictable_folder():
    text = SCRIPT.read_text()
    assert "dstoolkit-pulse-$(id -u)" not in text and "mktemp -d" in text


@pytest.mark.audio
def test_loopback_script_makes_a_private_folder_of_its_own(tmp_path):
    env = _loopback_env()
    folder = Path(env["PULSE_RUNTIME_PATH"])
    try:
        st = folder.stat()
        assert not folder.is_symlink() and st.st_uid == os.geteuid()
        assert st.st_mode & 0o777 == 0o700
        assert folder.name.startswith("dstoolkit-pulse.")
    finally:
        subprocess.run(["bash", str(SCRIPT), "stop"], capture_output=True, timeout=60, env=env)
    assert not folder.exists()
