"""Probe dstoolkit as a hostile tester would, and print what happened (issue 11).

Each probe calls the public API, a command line, or ``analyze`` on a crafted file with
hostile input, under a time limit, and is classified:

- clean error: a :class:`dstoolkit.errors.DstoolkitError` (a command: a non-zero exit with
  a one-line ``error:`` message, or argparse's usage error);
- traceback: any other exception (a command: a Python traceback);
- silent wrong answer: a result that is invalid (NaN, an evidence its constructor
  refuses, masses not summing to 1), a result where an error was due, or a file lost
  (an input or an existing file replaced without ``--overwrite``);
- hang: still running after the time limit (or over the memory budget).

Run: python benchmarks/hostile_probe.py [--audio]   (--audio adds the sound-server faults,
through the PulseAudio loopback of scripts/audio-loopback.sh)
"""

from __future__ import annotations

import argparse
import contextlib
import io
import itertools
import math
import os
import signal
import subprocess
import sys
import tempfile
import time
import tracemalloc
from collections import Counter
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from hostile_inputs import (  # noqa: E402
    LEVEL_TOLERANCE_M,
    TRUE_LEVEL_M,
    crafted_recordings,
    valid,
)

import dstoolkit.evidence as ev  # noqa: E402
from dstoolkit import cli  # noqa: E402
from dstoolkit.audio import (  # noqa: E402
    STREAM_GRACE_S,
    analyze,
    save_recording,
    simulate_measurement,
)
from dstoolkit.errors import DstoolkitError  # noqa: E402
from dstoolkit.filters import (  # noqa: E402
    BoundedErrorFilter,
    BoundedNoise,
    DependentEvidenceFilter,
    KalmanFilter,
    NassreddineFilter,
    ParticleFilter,
    random_walk,
)
from dstoolkit.gauge import TubeSetup, gauge_state_space_model, simulate_gauge  # noqa: E402

TIME_LIMIT_S = 30
CATEGORIES = ("evidence API", "filters", "crafted files (analyze)", "command lines",
              "bounded work", "sound-server faults")


class Hang(Exception):
    pass


@dataclass
class Probe:
    category: str
    name: str
    run: Callable[[], Any]
    expect: str = "either"  # "error": must be refused; "ok": must succeed; "either"
    check: Callable[[Any], None] | None = None  # extra check of a successful result


def classify(probe: Probe) -> tuple[str, str]:
    """(outcome, detail): outcome is error (clean), ok (a valid result), traceback, wrong or
    hang."""
    def alarm(signum: int, frame: Any) -> None:
        raise Hang()

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(TIME_LIMIT_S)
    tracemalloc.start()
    try:
        result = probe.run()
    except Hang:
        return "hang", f"no answer within {TIME_LIMIT_S} s"
    except DstoolkitError as exc:
        text = str(exc)
        if not text.strip():
            return "wrong", "an error without a message"
        return ("wrong", f"refused a valid input: {text}") if probe.expect == "ok" else (
            "error", text)
    except Exception as exc:  # noqa: BLE001 - counting every other kind is the point
        return "traceback", f"{type(exc).__name__}: {exc}"
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
    if peak > ev.memory_budget():
        return "hang", f"peak memory {peak / 2**30:.2f} GiB over the budget"
    if probe.expect == "error":
        return "wrong", f"returned {result!r:.80} where an error was due"
    try:
        valid(result)
        if probe.check is not None:
            probe.check(result)
    except AssertionError as exc:
        return "wrong", f"invalid result: {exc}"
    return "ok", "a valid result"


# -- hostile values ---------------------------------------------------------------------------
NUMBERS = [math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324, 0.0, -1.0]
JUNK = [*NUMBERS, "x", None, 1j, [1, [2, 3]], [], object()]
SHAPES = [np.zeros((2, 2, 2)), np.zeros(0), [[1.0, 2.0], [3.0]], [1.0, "a"],
          np.array([1 + 1j])]


def evidence_probes() -> Iterator[Probe]:
    c = "evidence API"
    a = ev.IntervalEvidence([-0.3, 0.3], [2.6, 1.9], [0.3, 0.7])
    b = ev.IntervalEvidence([0.0, 1.0], [1.0, 3.0], [0.5, 0.5])
    m = ev.MassFunction({"a": 0.5, "ab": 0.3, "abc": 0.2})
    for v in [*JUNK, *SHAPES]:
        yield Probe(c, f"IntervalEvidence(lo={v!r:.20})", lambda v=v: ev.IntervalEvidence(
            v, [1.0], [1.0]))
        yield Probe(c, f"IntervalEvidence(mass={v!r:.20})", lambda v=v: ev.IntervalEvidence(
            [0.0], [1.0], v))
        yield Probe(c, f"discount(rate={v!r:.20})", lambda v=v: ev.discount(a, v))
        yield Probe(c, f"discount(theta={v!r:.20})", lambda v=v: ev.discount(a, 0.1, v))
        yield Probe(c, f"shift({v!r:.20})", lambda v=v: a.shift(v))
        yield Probe(c, f"dependence(energy1={v!r:.20})", lambda v=v: ev.dependence(
            a, b, energy1=v))
        yield Probe(c, f"MassFunction(mass={v!r:.20})", lambda v=v: ev.MassFunction(
            {"a": v, "b": 0.5}))
        yield Probe(c, f"belief({v!r:.20})", lambda v=v: m.belief(v))
        yield Probe(c, f"triangular_evidence(epsilon={v!r:.20})",
                    lambda v=v: ev.triangular_evidence(-1, 0, 1, 3, v))
    yield Probe(c, "discount(theta=[5, -5])", lambda: ev.discount(a, 0.5, [5.0, -5.0]),
                "error")
    yield Probe(c, "bounds ±inf, energy", lambda: ev.energy(ev.IntervalEvidence(
        [-math.inf, 0.0], [math.inf, 1.0], [0.5, 0.5])))
    yield Probe(c, "widths ±1e308", lambda: ev.IntervalEvidence([-1e308], [1e308], [1.0]),
                "error")
    yield Probe(c, "Θ mass 1.7", lambda: ev.MassFunction({"a": -0.7, "abc": 1.7}), "error")
    yield Probe(c, "energy1=0 with shared energy", lambda: ev.dependence(a, a, energy1=0),
                "error")
    for k in range(1, 16):  # 1 − K = 10^-k: the masses must still sum to 1
        eps = math.sqrt(10.0 ** -k)
        x = ev.IntervalEvidence([0.0, 10.0], [1.0, 10.1], [1 - eps, eps])
        y = ev.IntervalEvidence([20.0, 10.0], [21.0, 11.0], [1 - eps, eps])
        yield Probe(c, f"dempster at 1 − K = 1e-{k}", lambda x=x, y=y: ev.dempster(x, y), "ok",
                    lambda r: _sums_to_one(r))
        yield Probe(c, f"combine_dependent at 1 − K = 1e-{k}",
                    lambda x=x, y=y: ev.combine_dependent(x, y), "either",
                    lambda r: _sums_to_one(r))
    for rule in ("min", "m1", "m2", "max", None):
        yield Probe(c, f"decorrelate(mass_rule={rule})",
                    lambda rule=rule: ev.decorrelate(a, b, mass_rule=rule))
    yield Probe(c, "dempster(evidence, str)", lambda: ev.dempster(a, "x"), "error")
    yield Probe(c, "dempster(interval, mass function)", lambda: ev.dempster(a, m), "error")


def _sums_to_one(e: Any) -> None:
    assert abs(float(np.sum(e.mass)) - 1.0) <= 1e-12, f"masses sum to {np.sum(e.mass)!r}"


def filter_probes() -> Iterator[Probe]:
    c = "filters"
    gauge = gauge_state_space_model()
    walk = random_walk(0.1, 0.5)
    seq = simulate_gauge(level_m=4.6, temperature_c=26.5, runs=2, seed=3)
    z, u = seq.readings[:, :12].astype(float), seq.inputs[:, :11].astype(float)
    filters = [DependentEvidenceFilter(), NassreddineFilter(),
               NassreddineFilter(restart=True), BoundedErrorFilter(), KalmanFilter(),
               ParticleFilter(n_particles=200)]
    for flt in filters:
        n = flt.name
        yield Probe(c, f"{n}: clean run", lambda f=flt: f.run(gauge, z[0], u[0]), "ok")
        for v in NUMBERS:
            bad_u = u.copy()
            bad_u[0, 3] = v
            yield Probe(c, f"{n}: order {v}", lambda f=flt, b=bad_u: f.run(gauge, z[0], b[0]))
            yield Probe(c, f"{n}: batch order {v}",
                        lambda f=flt, b=bad_u: f.run_batch(gauge, z, b))
            bad_z = z.copy()
            bad_z[0, 5] = v
            yield Probe(c, f"{n}: reading {v}", lambda f=flt, b=bad_z: f.run(gauge, b[0], u[0]))
        for shape in [u[0, :3], u[0][:, None].repeat(2, 1), u, u[0].astype(str), "orders"]:
            yield Probe(c, f"{n}: orders of shape {np.shape(shape)}",
                        lambda f=flt, s=shape: f.run(gauge, z[0], s))
        for readings in SHAPES:
            yield Probe(c, f"{n}: readings {np.shape(np.asarray(readings, dtype=object))}",
                        lambda f=flt, r=readings: f.run(walk, r))
        yield Probe(c, f"{n}: not a model", lambda f=flt: f.run("model", z[0], u[0]), "error")
    for v in JUNK:
        yield Probe(c, f"DependentEvidenceFilter(p={v!r:.12})",
                    lambda v=v: DependentEvidenceFilter(p=v).run(walk, [0.0, 0.1]))
        yield Probe(c, f"NassreddineFilter(epsilon={v!r:.12})",
                    lambda v=v: NassreddineFilter(epsilon=v).run(walk, [0.0, 0.1]))
        yield Probe(c, f"KalmanFilter(initial_box=({v!r:.12}, 1))",
                    lambda v=v: KalmanFilter(initial_box=(v, 1.0)).run(walk, [0.0, 0.1]))
        yield Probe(c, f"ParticleFilter(n_particles={v!r:.12})",
                    lambda v=v: ParticleFilter(n_particles=v).run(walk, [0.0, 0.1]))
        yield Probe(c, f"BoundedNoise({v!r:.12}, 0, 1)", lambda v=v: BoundedNoise(v, 0.0, 1.0))
        yield Probe(c, f"DependentEvidenceFilter(theta=({v!r:.12}, None))",
                    lambda v=v: DependentEvidenceFilter(theta=(v, None)).run(walk, [0.0, 0.1]))
    for policy in ("raise", "predict", "reset", "explode", None):
        yield Probe(c, f"on_conflict={policy}",
                    lambda p=policy: DependentEvidenceFilter(on_conflict=p).run(walk, [0, 50.0]))


def file_probes(folder: Path) -> Iterator[Probe]:
    c = "crafted files (analyze)"
    for case in crafted_recordings(folder):
        check = None
        if case.expect == "level":
            def check(result: Any) -> None:
                err = abs(result.level.level_m - TRUE_LEVEL_M)
                assert err <= LEVEL_TOLERANCE_M, f"level off by {err:.3f} m"
        yield Probe(c, case.name, lambda p=case.path: analyze(p, methods=()),
                    "ok" if case.expect == "level" else "error", check)


def command_probes(folder: Path) -> Iterator[Probe]:
    c = "command lines"
    rec = simulate_measurement(TubeSetup(level_m=2.6, temperature_c=26.0))

    def wav(name: str) -> Path:
        path = folder / name
        save_recording(path, rec.samples, rec.samplerate, rec.metadata)
        return path

    def command(argv: list[str], protect: list[Path], expect: str) -> Callable[[], Any]:
        """Run the command line in this process; a one-line error, and protected files
        unchanged, or the exit status 0 when it must succeed."""
        def run() -> int:
            before = {p: p.read_bytes() for p in protect if p.is_file()}
            err = io.StringIO()
            with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
                try:
                    status = cli.main(argv)
                except SystemExit as exc:  # argparse: usage error
                    status = int(exc.code or 0)
            for path, data in before.items():
                if not path.is_file() or path.read_bytes() != data:
                    return -1  # a file lost
            if status == 0:
                return 0
            text = err.getvalue().strip()
            if "Traceback" in text:
                raise RuntimeError(text)
            if text.startswith("error:") or "error:" in text:  # ours, or argparse's usage
                raise DstoolkitError(text)
            raise RuntimeError(f"exit {status} without a message")
        return run

    def check_status(status: Any) -> None:
        assert status == 0, "a file was lost" if status == -1 else f"exit {status}"

    victim = wav("victim.png")
    keep = wav("keep.wav")
    (folder / "keep.png").write_bytes(b"precious figure")
    existing = wav("existing.wav")
    (folder / "t.csv").write_text("precious table\n")
    cases: list[tuple[str, list[str], list[Path], str]] = [
        ("analyze victim.png (a WAV named .png)", ["analyze", str(victim)], [victim], "ok"),
        ("analyze --figure = its input", ["analyze", str(keep), "--figure", str(keep)],
         [keep], "error"),
        ("analyze keep.wav beside keep.png", ["analyze", str(keep)], [folder / "keep.png"],
         "error"),
        ("analyze a FIFO", ["analyze", str(folder / "fifo")], [], "error"),
        ("analyze /dev/zero", ["analyze", "/dev/zero"], [], "error"),
        ("analyze a folder", ["analyze", str(folder)], [], "error"),
        ("analyze a missing file", ["analyze", str(folder / "none.wav")], [], "error"),
        ("analyze --temperature nan", ["analyze", str(existing), "--temperature", "nan",
                                       "--figure", str(folder / "n.png")], [], "error"),
        ("analyze --temperature 1e400", ["analyze", str(existing), "--temperature", "1e400",
                                         "--figure", str(folder / "n.png")], [], "error"),
        ("analyze --figure /proc/x.png", ["analyze", str(existing), "--figure",
                                          "/proc/x.png"], [], "error"),
        ("analyze --figure into a folder", ["analyze", str(existing), "--figure",
                                            str(folder)], [], "error"),
        ("table3 --out t.png (CSV and figure)", ["table3", "--out", str(folder / "t.png"),
                                                 "--runs", "1", "--methods", "direct",
                                                 "--quiet"], [], "ok"),
        ("table3 --out .", ["table3", "--out", ".", "--quiet"], [], "error"),
        ("table3 --out /proc/x", ["table3", "--out", "/proc/x", "--quiet"], [], "error"),
        ("table3 --out /dev/null", ["table3", "--out", "/dev/null", "--quiet"], [], "error"),
        ("table3 --out an existing CSV", ["table3", "--out", str(folder / "t.csv"),
                                          "--quiet"], [folder / "t.csv"], "error"),
        ("table3 --out dir/", ["table3", "--out", str(folder) + "/", "--quiet"], [], "error"),
        ("table3 --runs 0", ["table3", "--runs", "0", "--out", str(folder / "r.csv"),
                             "--quiet"], [], "error"),
        ("table3 --runs -5", ["table3", "--runs", "-5", "--out", str(folder / "r.csv"),
                              "--quiet"], [], "error"),
        ("table3 --runs x", ["table3", "--runs", "x"], [], "error"),
        ("table3 --methods nope", ["table3", "--methods", "nope", "--out",
                                   str(folder / "r.csv"), "--quiet"], [], "error"),
        ("table3 --simulation nope", ["table3", "--simulation", "nope"], [], "error"),
        ("measure --save x --figure x", ["measure", "--temperature", "20", "--save",
                                         str(folder / "same.png"), "--figure",
                                         str(folder / "same.png")], [], "error"),
        ("measure --save an existing file", ["measure", "--temperature", "20", "--save",
                                             str(existing), "--figure",
                                             str(folder / "m.png")], [existing], "error"),
        ("measure --save over its figure default", ["measure", "--temperature", "20",
                                                    "--save", "measurement.png"], [], "error"),
        ("measure without --temperature", ["measure"], [], "error"),
        ("measure --temperature nan", ["measure", "--temperature", "nan", "--virtual-level",
                                       "2", "--figure", str(folder / "m2.png")], [], "error"),
        ("measure --virtual-level -1", ["measure", "--temperature", "20", "--virtual-level",
                                        "-1", "--figure", str(folder / "m3.png")], [],
         "error"),
        ("measure --latency -1", ["measure", "--temperature", "20", "--latency", "-1",
                                  "--figure", str(folder / "m4.png"), "--input", "nodev"], [],
         "error"),
        ("measure --input no-such-device", ["measure", "--temperature", "20", "--input",
                                            "no-such-device", "--figure",
                                            str(folder / "m5.png")], [], "error"),
        ("an unknown command", ["frobnicate"], [], "error"),
        ("no command", [], [], "error"),
    ]
    os.mkfifo(folder / "fifo")
    cwd = os.getcwd()
    for name, argv, protect, expect in cases:
        def run(argv: list[str] = argv, protect: list[Path] = protect, expect: str = expect
                ) -> Any:
            os.chdir(folder)
            try:
                return command(argv, protect, expect)()
            finally:
                os.chdir(cwd)
        yield Probe(c, name, run, expect, check_status)


def work_probes() -> Iterator[Probe]:
    c = "bounded work"
    n = 4500
    lo = np.arange(n, dtype=float)
    big = ev.IntervalEvidence(lo, lo + 0.5, np.full(n, 1.0 / n))
    walk = random_walk(0.1, 0.5)
    gauge = gauge_state_space_model()
    seq = simulate_gauge(level_m=4.6, temperature_c=26.5, seed=1)
    nan_u = seq.inputs.astype(float)
    nan_u[2] = np.nan
    yield Probe(c, "dempster 4500 x 4500", lambda: ev.dempster(big, big), "error")
    yield Probe(c, "conflict 4500 x 4500", lambda: ev.conflict(big, big), "error")
    yield Probe(c, "particle filter, 1e5 steps", lambda: ParticleFilter(n_particles=1000).run(
        walk, np.zeros(100_000)), "error")
    yield Probe(c, "particle filter batch 100 x 300 steps", lambda: ParticleFilter(
        n_particles=1000).run_batch(walk, np.zeros((100, 300))), "ok")
    yield Probe(c, "paper's filter p = 40", lambda: DependentEvidenceFilter(p=40).run(
        walk, [0.0, 0.1]), "error")
    yield Probe(c, "paper's filter p = 20, one step", lambda: DependentEvidenceFilter(
        p=20).run(walk, [0.0, 0.1]), "ok")
    yield Probe(c, "Nassreddine, NaN order, 83 steps", lambda: NassreddineFilter().run(
        gauge, seq.readings, nan_u), "error")
    yield Probe(c, "Nassreddine max_focal 1e9", lambda: NassreddineFilter(
        max_focal=10**9).run(walk, [0.0, 0.1]), "error")
    yield Probe(c, "Nassreddine p = 1000", lambda: NassreddineFilter(p=1000).run(
        walk, [0.0, 0.1, 0.2]), "error")
    yield Probe(c, "fit_resonance_series [1e-300, 1e308]", lambda: __import__(
        "dstoolkit.gauge", fromlist=["x"]).fit_resonance_series([1e-300, 1e308]), "error")
    yield Probe(c, "triangular_evidence p = 10**9", lambda: ev.triangular_evidence(
        -1, 0, 1, 10**9), "error")


def fault_probes() -> Iterator[Probe]:
    """SIGSTOP / SIGKILL of the loopback's PulseAudio mid-measurement (needs PulseAudio)."""
    c = "sound-server faults"
    script = ROOT / "scripts" / "audio-loopback.sh"

    def fault(sig: signal.Signals, want: str) -> Callable[[], Any]:
        def run() -> Any:
            env = {k: v for k, v in os.environ.items() if not k.startswith("PULSE_")}
            state = subprocess.run(["bash", str(script), "start"], capture_output=True,
                                   text=True, check=True, env=env).stdout
            env.update(line.split("=", 1) for line in state.splitlines() if "=" in line)
            pid = int((Path(env["PULSE_RUNTIME_PATH"]) / "pid").read_text())
            with tempfile.TemporaryDirectory() as tmp:
                start = time.monotonic()
                proc = subprocess.Popen(
                    [sys.executable, "-m", "dstoolkit", "measure", "--temperature", "26",
                     "--virtual-level", "2.6", "--input", "pulse", "--output", "pulse",
                     "--save", "rec.wav", "--figure", "fig.png"], cwd=tmp, env=env,
                    stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                while proc.poll() is None and time.monotonic() - start < 60 and not \
                        subprocess.run(["pactl", "list", "short", "sink-inputs"], env=env,
                                       capture_output=True, text=True).stdout.strip():
                    time.sleep(0.1)  # until the measurement's stream reaches the server
                start = time.monotonic()
                time.sleep(1.0)
                os.kill(pid, sig)
                try:
                    _, err = proc.communicate(timeout=25)
                finally:
                    with contextlib.suppress(ProcessLookupError):
                        os.kill(pid, signal.SIGCONT)
                    subprocess.run(["bash", str(script), "stop"], capture_output=True, env=env)
                elapsed = time.monotonic() - start
                left = os.listdir(tmp)
            if "Traceback" in err:
                raise RuntimeError(err)
            if left or elapsed > 7.1 + STREAM_GRACE_S + 4 or want not in err:
                return f"{elapsed:.1f} s, files {left}, said {err.strip()!r}"
            raise DstoolkitError(err.strip())
        return run

    yield Probe(c, "SIGSTOP the server mid-measurement",
                fault(signal.SIGSTOP, "the audio stream stalled"), "error")
    yield Probe(c, "SIGKILL the server mid-measurement",
                fault(signal.SIGKILL, "sound server died"), "error")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--audio", action="store_true", help="also the sound-server faults")
    parser.add_argument("--verbose", action="store_true", help="print every probe")
    args = parser.parse_args()
    import matplotlib

    matplotlib.use("Agg")
    counts: dict[str, Counter[str]] = {c: Counter() for c in CATEGORIES}
    problems = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "corpus").mkdir()
        (folder / "cli").mkdir()
        groups = [evidence_probes(), filter_probes(), file_probes(folder / "corpus"),
                  command_probes(folder / "cli"), work_probes()]
        if args.audio:
            groups.append(fault_probes())
        for probe in itertools.chain(*groups):
            outcome, detail = classify(probe)
            counts[probe.category][outcome] += 1
            if outcome not in ("error", "ok"):
                problems.append(f"[{outcome}] {probe.category} / {probe.name}: {detail:.300}")
            if args.verbose:
                print(f"{outcome:9} {probe.category:24} {probe.name:45} {detail:.100}")
    head = (f"{'category':26} {'inputs tried':>12} {'clean errors':>13} {'valid results':>14} "
            f"{'tracebacks':>11} {'silent wrong':>13} {'hangs':>6}")
    print(head)
    print("-" * len(head))
    for category, c in counts.items():
        total = sum(c.values())
        if total:
            print(f"{category:26} {total:>12} {c['error']:>13} {c['ok']:>14} "
                  f"{c['traceback']:>11} {c['wrong']:>13} {c['hang']:>6}")
    all_ = sum(counts.values(), Counter())
    print(f"{'total':26} {sum(all_.values()):>12} {all_['error']:>13} {all_['ok']:>14} "
          f"{all_['traceback']:>11} {all_['wrong']:>13} {all_['hang']:>6}")
    for line in problems:
        print(line)


if __name__ == "__main__":
    main()
