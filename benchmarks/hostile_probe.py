"""Probe dstoolkit as a hostile tester would, and print what happened.

Each probe calls the public API, a command line, or ``analyze`` on a crafted file with
hostile input, under a time limit, and is classified:

- clean error: a :class:`dstoolkit.errors.DstoolkitError` (a command: a non-zero exit with
  a one-line ``error:`` message, or argparse's usage error);
- traceback: any other exception (a command: a Python traceback);
- silent wrong answer: a result that is invalid (NaN, an evidence its constructor
  refuses, masses not summing to 1), a result where an error was due, or a file lost
  (an input or an existing file replaced without ``--overwrite``);
- hang: still running after the time limit (or over the memory budget);
- lost/litter: a file lost or replaced unasked, or litter left behind (the third pass).

The categories from "representations" on are the second pass: the merged and unmerged
forms of one evidence, copies (pickle, copy, deepcopy), gauge numbers, ambiguous
recordings, outputs that appear during a run, Ctrl-C and SIGTERM, explorers used from two
threads, and the memory budget. "filters' boundary" probes the models the filters are
given (callbacks returning NaN or complex values, contradictory zero-width readings,
per-run starts, integer options, start arrays changed afterwards).

The third pass (``benchmarks/hostile_third_pass.py``, ``--third`` for it alone) follows the
categories of its audit: filesystem, processes and races, WAV inputs, the evidence and
filters APIs, array-likes, the memory budget, the environment, teaching and sheets.py.

Run: python benchmarks/hostile_probe.py [--audio] [--third]   (--audio adds the sound-server faults,
through the PulseAudio loopback of scripts/audio-loopback.sh)
"""

from __future__ import annotations

import argparse
import contextlib
import copy
import copyreg
import io
import itertools
import math
import os
import pickle
import signal
import struct
import subprocess
import sys
import tempfile
import threading
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
    SPECIAL_OUTPUTS,
    TRUE_LEVEL_M,
    crafted_recordings,
    special_output,
    table3_signalled,
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

sys.path.insert(0, str(ROOT / "benchmarks"))
from hostile_third_pass import CATEGORIES as THIRD_PASS  # noqa: E402
from hostile_third_pass import Lost, OverBudget, TooSlow, third_pass_cases  # noqa: E402

TIME_LIMIT_S = 30
#: How long a signal probe waits for its child to reach the middle of its work.
SIGNAL_WAIT_S = 120
CATEGORIES = (
    "evidence API",
    "filters",
    "crafted files (analyze)",
    "command lines",
    "bounded work",
    "representations",
    "copies",
    "gauge and numbers",
    "recordings",
    "races and files",
    "signals",
    "threads and explorers",
    "memory budget",
    "filters' boundary (lead)",
    "sound-server faults",
    *THIRD_PASS,
)


class Hang(Exception):
    pass


@dataclass
class Probe:
    category: str
    name: str
    run: Callable[[], Any]
    expect: str = "either"  # "error": must be refused; "ok": must succeed; "either"
    check: Callable[[Any], None] | None = None  # extra check of a successful result
    time_limit: int = TIME_LIMIT_S  # seconds before it counts as a hang


def classify(probe: Probe) -> tuple[str, str]:
    """Classify a probe's result as (outcome, detail).

    The outcome is error (clean), ok (a valid result), traceback, wrong or hang.
    """

    def alarm(signum: int, frame: Any) -> None:
        raise Hang()

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(probe.time_limit)
    tracemalloc.start()
    try:
        result = probe.run()
    except Hang:
        return "hang", f"no answer within {probe.time_limit} s"
    except (OverBudget, TooSlow) as exc:
        return "hang", str(exc)
    except Lost as exc:
        return "lost", str(exc)
    except DstoolkitError as exc:
        text = str(exc)
        if not text.strip():
            return "wrong", "an error without a message"
        return (
            ("wrong", f"refused a valid input: {text}") if probe.expect == "ok" else ("error", text)
        )
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
    except Lost as exc:
        return "lost", str(exc)
    except AssertionError as exc:
        return "wrong", f"invalid result: {exc}"
    return "ok", "a valid result"


# -- hostile values ---------------------------------------------------------------------------
NUMBERS = [math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324, 0.0, -1.0]
JUNK = [*NUMBERS, "x", None, 1j, [1, [2, 3]], [], object()]
SHAPES = [np.zeros((2, 2, 2)), np.zeros(0), [[1.0, 2.0], [3.0]], [1.0, "a"], np.array([1 + 1j])]


def evidence_probes() -> Iterator[Probe]:
    c = "evidence API"
    a = ev.IntervalEvidence([-0.3, 0.3], [2.6, 1.9], [0.3, 0.7])
    b = ev.IntervalEvidence([0.0, 1.0], [1.0, 3.0], [0.5, 0.5])
    m = ev.MassFunction({"a": 0.5, "ab": 0.3, "abc": 0.2})
    for v in [*JUNK, *SHAPES]:
        yield Probe(
            c, f"IntervalEvidence(lo={v!r:.20})", lambda v=v: ev.IntervalEvidence(v, [1.0], [1.0])
        )
        yield Probe(
            c, f"IntervalEvidence(mass={v!r:.20})", lambda v=v: ev.IntervalEvidence([0.0], [1.0], v)
        )
        yield Probe(c, f"discount(rate={v!r:.20})", lambda v=v: ev.discount(a, v))
        yield Probe(c, f"discount(theta={v!r:.20})", lambda v=v: ev.discount(a, 0.1, v))
        yield Probe(c, f"shift({v!r:.20})", lambda v=v: a.shift(v))
        yield Probe(c, f"dependence(energy1={v!r:.20})", lambda v=v: ev.dependence(a, b, energy1=v))
        yield Probe(
            c, f"MassFunction(mass={v!r:.20})", lambda v=v: ev.MassFunction({"a": v, "b": 0.5})
        )
        yield Probe(c, f"belief({v!r:.20})", lambda v=v: m.belief(v))
        yield Probe(
            c,
            f"triangular_evidence(epsilon={v!r:.20})",
            lambda v=v: ev.triangular_evidence(-1, 0, 1, 3, v),
        )
    yield Probe(c, "discount(theta=[5, -5])", lambda: ev.discount(a, 0.5, [5.0, -5.0]), "error")
    yield Probe(
        c,
        "bounds ±inf, energy",
        lambda: ev.energy(ev.IntervalEvidence([-math.inf, 0.0], [math.inf, 1.0], [0.5, 0.5])),
    )
    yield Probe(c, "widths ±1e308", lambda: ev.IntervalEvidence([-1e308], [1e308], [1.0]), "error")
    yield Probe(c, "Θ mass 1.7", lambda: ev.MassFunction({"a": -0.7, "abc": 1.7}), "error")
    yield Probe(c, "energy1=0 with shared energy", lambda: ev.dependence(a, a, energy1=0), "error")
    for k in range(1, 16):  # 1 − K = 10^-k: the masses must still sum to 1
        eps = math.sqrt(10.0**-k)
        x = ev.IntervalEvidence([0.0, 10.0], [1.0, 10.1], [1 - eps, eps])
        y = ev.IntervalEvidence([20.0, 10.0], [21.0, 11.0], [1 - eps, eps])
        yield Probe(
            c,
            f"dempster at 1 − K = 1e-{k}",
            lambda x=x, y=y: ev.dempster(x, y),
            "ok",
            lambda r: _sums_to_one(r),
        )
        yield Probe(
            c,
            f"combine_dependent at 1 − K = 1e-{k}",
            lambda x=x, y=y: ev.combine_dependent(x, y),
            "either",
            lambda r: _sums_to_one(r),
        )
    for rule in ("min", "m1", "m2", "max", None):
        yield Probe(
            c,
            f"decorrelate(mass_rule={rule})",
            lambda rule=rule: ev.decorrelate(a, b, mass_rule=rule),
        )
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
    filters = [
        DependentEvidenceFilter(),
        NassreddineFilter(),
        NassreddineFilter(restart=True),
        BoundedErrorFilter(),
        KalmanFilter(),
        ParticleFilter(n_particles=200),
    ]
    for flt in filters:
        n = flt.name
        yield Probe(c, f"{n}: clean run", lambda f=flt: f.run(gauge, z[0], u[0]), "ok")
        for v in NUMBERS:
            bad_u = u.copy()
            bad_u[0, 3] = v
            yield Probe(c, f"{n}: order {v}", lambda f=flt, b=bad_u: f.run(gauge, z[0], b[0]))
            yield Probe(c, f"{n}: batch order {v}", lambda f=flt, b=bad_u: f.run_batch(gauge, z, b))
            bad_z = z.copy()
            bad_z[0, 5] = v
            yield Probe(c, f"{n}: reading {v}", lambda f=flt, b=bad_z: f.run(gauge, b[0], u[0]))
        for shape in [u[0, :3], u[0][:, None].repeat(2, 1), u, u[0].astype(str), "orders"]:
            yield Probe(
                c,
                f"{n}: orders of shape {np.shape(shape)}",
                lambda f=flt, s=shape: f.run(gauge, z[0], s),
            )
        for readings in SHAPES:
            yield Probe(
                c,
                f"{n}: readings {np.shape(np.asarray(readings, dtype=object))}",
                lambda f=flt, r=readings: f.run(walk, r),
            )
        yield Probe(c, f"{n}: not a model", lambda f=flt: f.run("model", z[0], u[0]), "error")
    for v in JUNK:
        yield Probe(
            c,
            f"DependentEvidenceFilter(p={v!r:.12})",
            lambda v=v: DependentEvidenceFilter(p=v).run(walk, [0.0, 0.1]),
        )
        yield Probe(
            c,
            f"NassreddineFilter(epsilon={v!r:.12})",
            lambda v=v: NassreddineFilter(epsilon=v).run(walk, [0.0, 0.1]),
        )
        yield Probe(
            c,
            f"KalmanFilter(initial_box=({v!r:.12}, 1))",
            lambda v=v: KalmanFilter(initial_box=(v, 1.0)).run(walk, [0.0, 0.1]),
        )
        yield Probe(
            c,
            f"ParticleFilter(n_particles={v!r:.12})",
            lambda v=v: ParticleFilter(n_particles=v).run(walk, [0.0, 0.1]),
        )
        yield Probe(c, f"BoundedNoise({v!r:.12}, 0, 1)", lambda v=v: BoundedNoise(v, 0.0, 1.0))
        yield Probe(
            c,
            f"DependentEvidenceFilter(theta=({v!r:.12}, None))",
            lambda v=v: DependentEvidenceFilter(theta=(v, None)).run(walk, [0.0, 0.1]),
        )
    for policy in ("raise", "predict", "reset", "explode", None):
        yield Probe(
            c,
            f"on_conflict={policy}",
            lambda p=policy: DependentEvidenceFilter(on_conflict=p).run(walk, [0, 50.0]),
        )


def file_probes(folder: Path) -> Iterator[Probe]:
    c = "crafted files (analyze)"
    for case in crafted_recordings(folder):
        check = None
        if case.expect == "level":

            def check(result: Any) -> None:
                err = abs(result.level.level_m - TRUE_LEVEL_M)
                assert err <= LEVEL_TOLERANCE_M, f"level off by {err:.3f} m"

        yield Probe(
            c,
            case.name,
            lambda p=case.path: analyze(p, methods=()),
            "ok" if case.expect == "level" else "error",
            check,
        )


def command_probes(folder: Path) -> Iterator[Probe]:
    c = "command lines"
    rec = simulate_measurement(TubeSetup(level_m=2.6, temperature_c=26.0))

    def wav(name: str) -> Path:
        path = folder / name
        save_recording(path, rec.samples, rec.samplerate, rec.metadata)
        return path

    def command(argv: list[str], protect: list[Path], expect: str) -> Callable[[], Any]:
        """Run the command line in this process and check its outcome.

        Expected: a one-line error, and protected files unchanged, or the exit status 0 when
        it must succeed.
        """

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
        (
            "analyze --figure = its input",
            ["analyze", str(keep), "--figure", str(keep)],
            [keep],
            "error",
        ),
        (
            "analyze keep.wav beside keep.png",
            ["analyze", str(keep)],
            [folder / "keep.png"],
            "error",
        ),
        ("analyze a FIFO", ["analyze", str(folder / "fifo")], [], "error"),
        ("analyze /dev/zero", ["analyze", "/dev/zero"], [], "error"),
        ("analyze a folder", ["analyze", str(folder)], [], "error"),
        ("analyze a missing file", ["analyze", str(folder / "none.wav")], [], "error"),
        (
            "analyze --temperature nan",
            ["analyze", str(existing), "--temperature", "nan", "--figure", str(folder / "n.png")],
            [],
            "error",
        ),
        (
            "analyze --temperature 1e400",
            ["analyze", str(existing), "--temperature", "1e400", "--figure", str(folder / "n.png")],
            [],
            "error",
        ),
        (
            "analyze --figure /proc/x.png",
            ["analyze", str(existing), "--figure", "/proc/x.png"],
            [],
            "error",
        ),
        (
            "analyze --figure into a folder",
            ["analyze", str(existing), "--figure", str(folder)],
            [],
            "error",
        ),
        (
            "table3 --out t.png (CSV and figure)",
            [
                "table3",
                "--out",
                str(folder / "t.png"),
                "--runs",
                "1",
                "--methods",
                "direct",
                "--quiet",
            ],
            [],
            "ok",
        ),
        ("table3 --out .", ["table3", "--out", ".", "--quiet"], [], "error"),
        ("table3 --out /proc/x", ["table3", "--out", "/proc/x", "--quiet"], [], "error"),
        ("table3 --out /dev/null", ["table3", "--out", "/dev/null", "--quiet"], [], "error"),
        (
            "table3 --out an existing CSV",
            ["table3", "--out", str(folder / "t.csv"), "--quiet"],
            [folder / "t.csv"],
            "error",
        ),
        ("table3 --out dir/", ["table3", "--out", str(folder) + "/", "--quiet"], [], "error"),
        (
            "table3 --runs 0",
            ["table3", "--runs", "0", "--out", str(folder / "r.csv"), "--quiet"],
            [],
            "error",
        ),
        (
            "table3 --runs -5",
            ["table3", "--runs", "-5", "--out", str(folder / "r.csv"), "--quiet"],
            [],
            "error",
        ),
        ("table3 --runs x", ["table3", "--runs", "x"], [], "error"),
        (
            "table3 --methods nope",
            ["table3", "--methods", "nope", "--out", str(folder / "r.csv"), "--quiet"],
            [],
            "error",
        ),
        ("table3 --simulation nope", ["table3", "--simulation", "nope"], [], "error"),
        (
            "measure --save x --figure x",
            [
                "measure",
                "--temperature",
                "20",
                "--save",
                str(folder / "same.png"),
                "--figure",
                str(folder / "same.png"),
            ],
            [],
            "error",
        ),
        (
            "measure --save an existing file",
            [
                "measure",
                "--temperature",
                "20",
                "--save",
                str(existing),
                "--figure",
                str(folder / "m.png"),
            ],
            [existing],
            "error",
        ),
        (
            "measure --save over its figure default",
            ["measure", "--temperature", "20", "--save", "measurement.png"],
            [],
            "error",
        ),
        ("measure without --temperature", ["measure"], [], "error"),
        (
            "measure --temperature nan",
            [
                "measure",
                "--temperature",
                "nan",
                "--virtual-level",
                "2",
                "--figure",
                str(folder / "m2.png"),
            ],
            [],
            "error",
        ),
        (
            "measure --virtual-level -1",
            [
                "measure",
                "--temperature",
                "20",
                "--virtual-level",
                "-1",
                "--figure",
                str(folder / "m3.png"),
            ],
            [],
            "error",
        ),
        (
            "measure --latency -1",
            [
                "measure",
                "--temperature",
                "20",
                "--latency",
                "-1",
                "--figure",
                str(folder / "m4.png"),
                "--input",
                "nodev",
            ],
            [],
            "error",
        ),
        (
            "measure --input no-such-device",
            [
                "measure",
                "--temperature",
                "20",
                "--input",
                "no-such-device",
                "--figure",
                str(folder / "m5.png"),
            ],
            [],
            "error",
        ),
        ("an unknown command", ["frobnicate"], [], "error"),
        ("no command", [], [], "error"),
    ]
    os.mkfifo(folder / "fifo")
    cwd = os.getcwd()
    for name, argv, protect, expect in cases:

        def run(argv: list[str] = argv, protect: list[Path] = protect, expect: str = expect) -> Any:
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
    yield Probe(
        c,
        "particle filter, 1e5 steps",
        lambda: ParticleFilter(n_particles=1000).run(walk, np.zeros(100_000)),
        "error",
    )
    yield Probe(
        c,
        "particle filter batch 100 x 300 steps",
        lambda: ParticleFilter(n_particles=1000).run_batch(walk, np.zeros((100, 300))),
        "ok",
    )
    yield Probe(
        c,
        "paper's filter p = 40",
        lambda: DependentEvidenceFilter(p=40).run(walk, [0.0, 0.1]),
        "error",
    )
    yield Probe(
        c,
        "paper's filter p = 20, one step",
        lambda: DependentEvidenceFilter(p=20).run(walk, [0.0, 0.1]),
        "ok",
    )
    yield Probe(
        c,
        "Nassreddine, NaN order, 83 steps",
        lambda: NassreddineFilter().run(gauge, seq.readings, nan_u),
        "error",
    )
    yield Probe(
        c,
        "Nassreddine max_focal 1e9",
        lambda: NassreddineFilter(max_focal=10**9).run(walk, [0.0, 0.1]),
        "error",
    )
    yield Probe(
        c,
        "Nassreddine p = 1000",
        lambda: NassreddineFilter(p=1000).run(walk, [0.0, 0.1, 0.2]),
        "error",
    )
    yield Probe(
        c,
        "fit_resonance_series [1e-300, 1e308]",
        lambda: __import__("dstoolkit.gauge", fromlist=["x"]).fit_resonance_series([1e-300, 1e308]),
        "error",
    )
    yield Probe(
        c, "triangular_evidence p = 10**9", lambda: ev.triangular_evidence(-1, 0, 1, 10**9), "error"
    )


# -- second pass ----------------------------------------------------------------------------
def _same(a: Any, b: Any, what: str) -> None:
    if isinstance(a, float | np.floating) and isinstance(b, float | np.floating):
        assert math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12), f"{what}: {a!r} vs {b!r}"
    else:
        assert a == b, f"{what}: {a!r} vs {b!r}"


def _dict_close(a: dict, b: dict) -> None:
    assert a.keys() == b.keys(), f"focal elements differ: {list(a)} vs {list(b)}"
    for k in a:
        _same(a[k], b[k], f"mass of {k}")


def representation_probes() -> Iterator[Probe]:
    """Each reader of an evidence gives one answer for its merged and unmerged forms."""
    c = "representations"
    m1 = ev.MassFunction({"a": 0.5, "ab": 0.5})
    m2 = ev.MassFunction({"a": 0.5, "ab": 0.5}, frame=m1.frame)
    mf_split = ev.dempster(m1, m2, merge=False)
    mf_merged = ev.dempster(m1, m2)
    iv_split = ev.IntervalEvidence([0.0, 0.0, 1.0], [1.0, 1.0, 2.0], [0.25, 0.25, 0.5], merge=False)
    iv_merged = ev.IntervalEvidence([0.0, 1.0], [1.0, 2.0], [0.5, 0.5])
    other_iv = ev.IntervalEvidence([0.0, 0.5], [1.0, 3.0], [0.6, 0.4])
    other_mf = ev.MassFunction({"a": 0.3, "ab": 0.7}, frame=m1.frame)
    pairs = (
        ("mass function", mf_split, mf_merged, other_mf),
        ("intervals", iv_split, iv_merged, other_iv),
    )
    for kind, split, merged, other in pairs:

        def both(fn: Callable[[Any], Any], s: Any = split, m: Any = merged) -> Any:
            return fn(s), fn(m)

        def agree(r: Any) -> None:
            a, b = r
            if isinstance(a, dict):
                _dict_close(a, b)
            elif isinstance(a, ev.Dependence):
                for name in ("energy1", "energy2", "joint_energy", "degree", "r12", "r21"):
                    _same(getattr(a, name), getattr(b, name), name)
            elif isinstance(a, ev.Evidence):
                _dict_close(_as_dict(a), _as_dict(b))
            else:
                _same(a, b, "value")

        readers: list[tuple[str, Callable[[Any], Any]]] = [
            ("repr", repr),
            ("energy", ev.energy),
            ("dependence with itself", lambda e: ev.dependence(e, e)),
            ("dependence with another", lambda e, o=other: ev.dependence(e, o)),
            ("joint_energy", lambda e, o=other: ev.joint_energy(e, o)),
            ("conflict", lambda e, o=other: ev.conflict(e, o)),
            ("dempster", lambda e, o=other: ev.dempster(e, o)),
            ("combine_dependent", lambda e, o=other: ev.combine_dependent(e, o)),
            ("yager", lambda e, o=other: ev.yager(e, o)),
            ("discount", lambda e: ev.discount(e, 0.2)),
        ]
        if kind == "mass function":
            readers += [
                ("as_dict", lambda e: e.as_dict()),
                ("sum of as_dict", lambda e: sum(e.as_dict().values())),
                ("mass_of('a')", lambda e: e.mass_of("a")),
                ("belief('a')", lambda e: e.belief("a")),
                ("pignistic", lambda e: e.pignistic()),
            ]
        else:
            readers += [
                ("belief", lambda e: e.belief(0.0, 1.0)),
                ("pignistic_expectation", lambda e: e.pignistic_expectation()),
            ]
        for name, fn in readers:
            yield Probe(
                c,
                f"{kind}: {name}, merged vs unmerged",
                lambda fn=fn, both=both: both(fn),
                "ok",
                agree,
            )

    def tuple_hypothesis() -> Any:
        m = ev.MassFunction({(0, 1): 0.5, 0: 0.5}, frame=[0, 1, (0, 1)])
        return m

    def is_hypothesis(m: Any) -> None:
        assert frozenset({(0, 1)}) in m.as_dict(), f"(0, 1) read as a set: {m.as_dict()}"

    yield Probe(
        c, "frame [0, 1, (0, 1)]: key (0, 1) is a hypothesis", tuple_hypothesis, "ok", is_hypothesis
    )


def _as_dict(e: Any) -> dict:
    if isinstance(e, ev.MassFunction):
        return e.as_dict()
    out: dict = {}
    for lo, hi, m in zip(e.boxes_lo.tolist(), e.boxes_hi.tolist(), e.mass.tolist(), strict=True):
        key = (tuple(lo), tuple(hi))
        out[key] = out.get(key, 0.0) + m
    return out


class _Crafted:
    """Pickle as an object of another class with a chosen state (no constructor).

    This is what the default pickle of a plain object holds.
    """

    def __init__(self, cls: type, state: dict) -> None:
        self.cls, self.state = cls, state

    def __reduce__(self) -> tuple[Any, ...]:
        return (copyreg._reconstructor, (self.cls, object, None), self.state)


def copy_probes() -> Iterator[Probe]:
    c = "copies"
    objects = {
        "IntervalEvidence": (
            ev.IntervalEvidence([0.0, 1.0], [1.0, 2.0], [0.5, 0.5]),
            lambda o: o.mass,
        ),
        "unmerged dempster": (
            ev.dempster(
                ev.MassFunction({"a": 0.5, "ab": 0.5}),
                ev.MassFunction({"a": 0.5, "ab": 0.5}),
                merge=False,
            ),
            lambda o: o.mass,
        ),
        "interval ends": (ev.IntervalEvidence([0.0, 1.0], [1.0, 2.0], [0.5, 0.5]), lambda o: o.lo),
        "BoundedNoise upper": (BoundedNoise(-1.0, 0.0, 1.0), lambda o: o.upper),
    }
    copiers = {
        "pickle": lambda o: pickle.loads(pickle.dumps(o)),
        "copy": copy.copy,
        "deepcopy": copy.deepcopy,
    }

    def read_only(arr: Any) -> None:
        assert isinstance(arr, np.ndarray) and not arr.flags.writeable, "writable again"

    for (oname, (obj, view)), (cname, copier) in itertools.product(
        objects.items(), copiers.items()
    ):
        yield Probe(
            c,
            f"{cname} of {oname}: read-only",
            lambda o=obj, v=view, cp=copier: v(cp(o)),
            "ok",
            read_only,
        )
        yield Probe(
            c,
            f"{cname} of {oname}: equal",
            lambda o=obj, cp=copier: repr(cp(o)),
            "ok",
            lambda r, o=obj: _same(r, repr(o), "repr"),
        )
    crafted = {
        "BoundedNoise upper < lower": _Crafted(
            BoundedNoise,
            {"lower": np.array([1.0]), "mode": np.array([0.0]), "upper": np.array([-1.0])},
        ),
        "IntervalEvidence masses 1.4": _Crafted(
            ev.IntervalEvidence,
            {"_focal": np.array([[0.0, 1.0], [1.0, 2.0]]), "_mass": np.array([0.7, 0.7])},
        ),
        "MassFunction masses 1.4": _Crafted(
            ev.MassFunction,
            {
                "frame": ("a", "b"),
                "_index": {"a": 0, "b": 1},
                "_focal": np.array([1, 3], dtype=np.uint64),
                "_mass": np.array([0.7, 0.7]),
            },
        ),
    }
    for name, bad in crafted.items():
        yield Probe(
            c, f"unpickle a crafted {name}", lambda b=bad: pickle.loads(pickle.dumps(b)), "error"
        )


def gauge_probes() -> Iterator[Probe]:
    c = "gauge and numbers"
    from dstoolkit.gauge import (
        LinearSweep,
        level_from_fundamental,
        level_from_resonance,
    )

    def near(value: float) -> Callable[[Any], None]:
        def check(r: Any) -> None:
            assert abs(float(np.asarray(r).reshape(-1)[0]) - value) < 1e-9, f"{r!r}"

        return check

    cases: list[tuple[str, Callable[[], Any], str, Callable[[Any], None] | None]] = [
        (
            "LinearSweep(sample_rate=nan, duration=inf)",
            lambda: LinearSweep(sample_rate=math.nan, duration=math.inf),
            "error",
            None,
        ),
        ("LinearSweep(duration=nan)", lambda: LinearSweep(duration=math.nan), "error", None),
        ("LinearSweep(f_start='1000')", lambda: LinearSweep(f_start="1000"), "error", None),
        ("LinearSweep(taper=nan)", lambda: LinearSweep(taper=math.nan), "error", None),
        (
            "level_from_fundamental(1e308, 1e308)",
            lambda: level_from_fundamental(1e308, 1e308),
            "ok",
            near(0.5),
        ),
        (
            "level_from_resonance(1e308, 1, 1e308)",
            lambda: level_from_resonance(1e308, 1, 1e308),
            "ok",
            near(0.5),
        ),
        (
            "level_from_fundamental(1e308, 1e-308)",
            lambda: level_from_fundamental(1e308, 1e-308),
            "error",
            None,
        ),
        (
            "triangular_from_samples k = -3",
            lambda: ev.triangular_from_samples([0.1, -0.2, 0.3], k=-3),
            "error",
            None,
        ),
        (
            "triangular_from_samples k = nan",
            lambda: ev.triangular_from_samples([0.1, -0.2, 0.3], k=math.nan),
            "error",
            None,
        ),
        (
            "triangular_from_samples k = 'x'",
            lambda: ev.triangular_from_samples([0.1, -0.2, 0.3], k="x"),
            "error",
            None,
        ),
        (
            "triangular_from_samples of 1e308s",
            lambda: ev.triangular_from_samples([1e308, -1e308, 1e308]),
            "error",
            None,
        ),
        ("simulate_gauge(runs=0)", lambda: simulate_gauge(runs=0), "error", None),
        ("simulate_gauge(runs=2.5)", lambda: simulate_gauge(runs=2.5), "error", None),
        ("simulate_gauge(runs='3')", lambda: simulate_gauge(runs="3"), "error", None),
        ("TubeSetup(level_m='2')", lambda: TubeSetup(level_m="2"), "error", None),
        (
            "TubeSetup(temperature_c='20')",
            lambda: TubeSetup(level_m=2.0, temperature_c="20"),
            "error",
            None,
        ),
        (
            "TubeSetup(diameter_m=nan)",
            lambda: TubeSetup(level_m=2.0, diameter_m=math.nan),
            "error",
            None,
        ),
        (
            "IntervalEvidence with (2, 0) boxes",
            lambda: ev.IntervalEvidence(np.zeros((2, 0)), np.zeros((2, 0)), [0.5, 0.5]),
            "error",
            None,
        ),
        (
            "image((lo, hi), sqrt(x - 5))",
            lambda: ev.image(
                (np.array([[0.0], [1.0]]), np.array([[1.0], [2.0]])), lambda x: np.sqrt(x - 5)
            ),
            "error",
            None,
        ),
        (
            "image(evidence, complex f)",
            lambda: ev.image(ev.IntervalEvidence([0.0], [1.0], [1.0]), lambda x: x + 1j),
            "error",
            None,
        ),
        (
            "image((nan, 1), f)",
            lambda: ev.image((np.array([[math.nan]]), np.array([[1.0]])), lambda x: x),
            "error",
            None,
        ),
    ]
    for name, run, expect, check in cases:
        yield Probe(c, name, run, expect, check)


def _wav_bytes(metadata_chunks: list[bytes], rate: int = 44100) -> bytes:
    from scipy.io import wavfile

    rec = simulate_measurement(TubeSetup(level_m=2.6, temperature_c=26.0))
    buffer = io.BytesIO()
    wavfile.write(buffer, rate, rec.samples.astype(np.float32))
    riff = bytearray(buffer.getvalue())
    for chunk in metadata_chunks:
        riff += chunk
    riff[4:8] = struct.pack("<I", len(riff) - 8)
    return bytes(riff)


def _rchunk(tag: bytes, payload: bytes) -> bytes:
    return tag + struct.pack("<I", len(payload)) + payload + b"\0" * (len(payload) % 2)


def _info(*fields: tuple[bytes, str]) -> bytes:
    body = b"".join(_rchunk(t, text.encode() + b"\0") for t, text in fields)
    return _rchunk(b"LIST", b"INFO" + body)


def recording_probes(folder: Path) -> Iterator[Probe]:
    c = "recordings"
    rec = simulate_measurement(TubeSetup(level_m=2.6, temperature_c=26.0))
    meta = rec.metadata.to_json()
    hot = meta.replace('"temperature_c": 26.0', '"temperature_c": 40.0')
    assert hot != meta
    dup = meta.replace('"temperature_c": 26.0', '"temperature_c": 26.0, "temperature_c": 40.0')
    crafted = {
        "a JSON key given twice": [_info((b"ICMT", dup))],
        "two LIST/INFO chunks": [_info((b"ICMT", meta)), _info((b"ICMT", hot))],
        "two ICMT fields in one LIST": [_info((b"ICMT", meta), (b"ICMT", hot))],
    }
    for name, chunks in crafted.items():
        path = folder / (name.replace(" ", "_").replace("/", "_") + ".wav")
        path.write_bytes(_wav_bytes(chunks))
        yield Probe(c, f"analyze: {name}", lambda p=path: analyze(p, methods=()), "error")
    from dstoolkit.audio import RecordingMetadata

    x = rec.samples
    counter = itertools.count()

    def save(samples: Any, rate: Any = rec.samplerate, metadata: Any = rec.metadata) -> Any:
        path = folder / f"saved{next(counter)}.wav"
        save_recording(path, samples, rate, metadata)
        return path

    saves: dict[str, Callable[[], Any]] = {
        "a sample of 1e39": lambda: save(np.concatenate([x, [1e39]])),
        "complex samples": lambda: save(x + 0.5j),
        "a 500 Hz rate": lambda: save(x, 500),
        "a rate of nan": lambda: save(x, math.nan),
        "metadata over 64 KiB": lambda: save(
            x, metadata=RecordingMetadata(temperature_c=20.0, extra={"note": "x" * 70_000})
        ),
        "metadata nested 40 deep": lambda: save(
            x, metadata=RecordingMetadata(temperature_c=20.0, extra={"deep": _nested(40)})
        ),
    }
    for name, run in saves.items():
        yield Probe(c, f"save_recording with {name}", run, "error")


def _nested(depth: int) -> Any:
    value: Any = 0
    for _ in range(depth):
        value = [value]
    return value


def _run_cli(argv: list[str], folder: Path) -> tuple[int, str]:
    """Run cli.main in this process, from ``folder``, and return (status, stderr).

    A KeyboardInterrupt that escapes becomes a RuntimeError (a traceback at the terminal).
    """
    err = io.StringIO()
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            try:
                status = cli.main(argv)
            except SystemExit as exc:
                status = int(exc.code or 0)
            except KeyboardInterrupt:
                raise RuntimeError("KeyboardInterrupt escaped the command") from None
    finally:
        os.chdir(cwd)
    return status, err.getvalue()


@contextlib.contextmanager
def _patched(obj: Any, name: str, value: Any) -> Iterator[None]:
    old = getattr(obj, name)
    setattr(obj, name, value)
    try:
        yield
    finally:
        setattr(obj, name, old)


def race_probes(folder: Path) -> Iterator[Probe]:
    c = "races and files"
    real = cli.run_table3
    counter = itertools.count()

    def fresh() -> Path:
        sub = folder / f"case{next(counter)}"
        sub.mkdir()
        return sub

    def appears(which: str) -> Callable[[], Any]:
        """Make a file appear at the CSV (or the figure) while table3 computes.

        The file must survive, and the command must say so.
        """

        def run() -> Any:
            sub = fresh()
            target = sub / ("t.csv" if which == "csv" else "t.png")

            def slow(**kw: Any) -> Any:
                target.write_text("made by someone else meanwhile\n")
                return real(**kw)

            with _patched(cli, "run_table3", slow):
                status, err = _run_cli(
                    [
                        "table3",
                        "--out",
                        str(sub / "t.csv"),
                        "--runs",
                        "1",
                        "--methods",
                        "direct",
                        "--quiet",
                    ],
                    sub,
                )
            if target.read_bytes() != b"made by someone else meanwhile\n":
                return "file lost"
            if "Traceback" in err:
                raise RuntimeError(err)
            if status == 0:
                return f"exit 0, leftovers {sorted(os.listdir(sub))}"
            raise DstoolkitError(err.strip())

        return run

    yield Probe(c, "table3: a file appears at --out meanwhile", appears("csv"), "error")
    yield Probe(c, "table3: a file appears at the figure meanwhile", appears("png"), "error")

    def failed_run_folders() -> Any:
        sub = fresh()

        def fail(**kw: Any) -> Any:
            from dstoolkit.errors import InvalidInputError

            raise InvalidInputError("a failure inside the computation")

        with _patched(cli, "run_table3", fail):
            status, err = _run_cli(
                ["table3", "--out", str(sub / "new" / "deep" / "t.csv"), "--quiet"], sub
            )
        if (sub / "new").exists():
            return "the failed run left its output folder behind"
        raise DstoolkitError(err.strip())

    yield Probe(c, "table3 fails: its new output folders go", failed_run_folders, "error")

    def interrupted_in_process() -> Any:
        sub = fresh()

        def interrupt(**kw: Any) -> Any:
            raise KeyboardInterrupt

        with _patched(cli, "run_table3", interrupt):
            status, err = _run_cli(["table3", "--out", str(sub / "new" / "t.csv"), "--quiet"], sub)
        if status != 130 or "Traceback" in err or len(err.strip().splitlines()) != 1:
            return f"exit {status}, said {err!r}"
        if (sub / "new").exists():
            return "left its output folder behind"
        raise DstoolkitError(err.strip())

    yield Probe(c, "table3: Ctrl-C (in process)", interrupted_in_process, "error")

    def special(kind: str) -> Callable[[], Any]:
        """--figure --overwrite on a link to a non-regular file or into /proc."""

        def run() -> Any:
            sub = fresh()
            wav = sub / "r.wav"
            rec = simulate_measurement(TubeSetup(level_m=2.6, temperature_c=26.0))
            save_recording(wav, rec.samples, rec.samplerate, rec.metadata)
            link, keep = special_output(kind, sub)
            try:
                status, err = _run_cli(
                    ["analyze", str(wav), "--figure", str(link), "--overwrite"], sub
                )
            finally:
                if keep is not None:
                    keep.close()
            if status == 0:
                state = "a link" if link.is_symlink() else "a file"
                return f"wrote over {kind}: {link} is now {state}"
            if "Traceback" in err:
                raise RuntimeError(err)
            raise DstoolkitError(err.strip())

        return run

    for kind in SPECIAL_OUTPUTS:
        yield Probe(c, f"analyze --figure {kind} --overwrite", special(kind), "error")


def signal_probes(folder: Path) -> Iterator[Probe]:
    """Run table3 in a child process, stopped by a signal once its CSV is written.

    Its figure is being drawn then. Expected: one line, the shell's exit status, no file
    left.
    """
    c = "signals"
    counter = itertools.count()

    def stop(sig: signal.Signals, status: int) -> Callable[[], Any]:
        def run() -> Any:
            sub = folder / f"sig{next(counter)}"
            sub.mkdir()
            returncode, err, _ = table3_signalled(sub, sig, wait_s=SIGNAL_WAIT_S)
            left = sorted(str(p.relative_to(sub)) for p in sub.rglob("*"))
            if "Traceback" in err:
                raise RuntimeError(err.strip().splitlines()[-1])
            if returncode != status or left or len(err.strip().splitlines()) != 1:
                return f"exit {returncode}, left {left}, said {err.strip()!r}"
            raise DstoolkitError(err.strip())

        return run

    limit = SIGNAL_WAIT_S + 150  # the child's start, its table, and its stop
    yield Probe(c, "table3: SIGINT halfway", stop(signal.SIGINT, 130), "error", time_limit=limit)
    yield Probe(c, "table3: SIGTERM halfway", stop(signal.SIGTERM, 143), "error", time_limit=limit)


def thread_probes() -> Iterator[Probe]:
    c = "threads and explorers"
    try:
        import ipywidgets as widgets

        from dstoolkit.teaching import Explorer
    except ImportError:
        return

    def overlap() -> Any:
        busy = {"now": 0, "most": 0}
        guard = threading.Lock()

        def render(x: float) -> tuple[None, dict[str, Any]]:
            with guard:
                busy["now"] += 1
                busy["most"] = max(busy["most"], busy["now"])
            time.sleep(0.002)
            with guard:
                busy["now"] -= 1
            return None, {"x": x}

        explorer = Explorer({"x": widgets.FloatSlider(value=0.0)}, render, static=False)

        def work(offset: int) -> None:
            for i in range(40):
                explorer.refresh(x=float(offset + i))

        threads = [threading.Thread(target=work, args=(k * 100,)) for k in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        return busy["most"]

    yield Probe(
        c,
        "two threads refresh one explorer",
        overlap,
        "ok",
        lambda most: _same(most, 1, "renders at once"),
    )

    def budget_in_refresh() -> Any:
        from dstoolkit.errors import MemoryBudgetError

        def render(x: float) -> Any:
            if x > 1:
                raise MemoryBudgetError("too big for the budget")
            return None, {"x": x}

        explorer = Explorer({"x": widgets.FloatSlider(value=0.0, max=5)}, render, static=False)
        explorer.refresh(x=3.0)
        return explorer.numbers

    yield Probe(
        c,
        "a MemoryBudgetError in Explorer.refresh",
        budget_in_refresh,
        "ok",
        lambda n: _same(sorted(n), ["error"], "readout"),
    )


def budget_probes(folder: Path) -> Iterator[Probe]:
    c = "memory budget"
    twelve = ev.IntervalEvidence(np.arange(12.0), np.arange(12.0) + 0.5, np.full(12, 1 / 12))
    yield Probe(
        c,
        "cartesian_product of 6 marginals x 12",
        lambda: ev.cartesian_product([twelve] * 6),
        "error",
    )
    from dstoolkit.gauge import LinearSweep, fit_resonance_series, synthesize_recording

    z = 1000.0 + 18.0 * np.arange(400_000)
    yield Probe(
        c, "fit_resonance_series on 400k frequencies", lambda: fit_resonance_series(z), "error"
    )
    yield Probe(c, "simulate_gauge(runs=10**9)", lambda: simulate_gauge(runs=10**9), "error")
    yield Probe(
        c,
        "synthesize a 10^6 s sweep",
        lambda: synthesize_recording(TubeSetup(level_m=2.0), LinearSweep(duration=1e6)),
        "error",
    )

    def table3(runs: str) -> Callable[[], Any]:
        def run() -> Any:
            status, err = _run_cli(
                ["table3", "--runs", runs, "--out", str(folder / f"r{runs}.csv"), "--quiet"], folder
            )
            if "Traceback" in err:
                raise RuntimeError(err)
            if status == 0:
                return "ran"
            raise DstoolkitError(err.strip())

        return run

    for runs in ("1000000000", "1e9"):
        yield Probe(c, f"table3 --runs {runs}", table3(runs), "error")
    for value in ("inf", "nan", "-1", "1e400", "0", "12", "lots", "1e30"):

        def env_budget(v: str = value) -> Any:
            old = os.environ.get("DSTOOLKIT_MEMORY_BUDGET")
            os.environ["DSTOOLKIT_MEMORY_BUDGET"] = v
            try:
                return ev.memory_budget()
            finally:
                if old is None:
                    del os.environ["DSTOOLKIT_MEMORY_BUDGET"]
                else:
                    os.environ["DSTOOLKIT_MEMORY_BUDGET"] = old

        yield Probe(c, f"DSTOOLKIT_MEMORY_BUDGET={value}", env_budget, "error")


def boundary_probes() -> Iterator[Probe]:
    """Probe what the filters are given (the lead's part of the second pass)."""
    c = "filters' boundary (lead)"
    from dstoolkit.filters import StateSpaceModel

    def model(f: Callable[..., Any], w: float = 0.5, v: float = 0.1) -> Any:
        return StateSpaceModel(
            f=f,
            g=lambda x: x,
            g_inverse=lambda lo, hi, x_lo, x_hi: (np.maximum(lo, x_lo), np.minimum(hi, x_hi)),
            state_noise=BoundedNoise.symmetric(v),
            obs_noise=BoundedNoise.symmetric(w),
        )

    nan_f = model(lambda x, u: x * np.nan)
    complex_f = model(lambda x, u: x + 1e-3j)
    readings = [0.0, 0.1, 0.2, 0.3]
    for flt in (
        DependentEvidenceFilter(),
        NassreddineFilter(),
        BoundedErrorFilter(),
        KalmanFilter(),
        ParticleFilter(n_particles=200),
    ):
        yield Probe(c, f"{flt.name}: f is NaN", lambda f=flt: f.run(nan_f, readings), "error")
        yield Probe(
            c, f"{flt.name}: f is complex", lambda f=flt: f.run(complex_f, readings), "error"
        )
    zero = StateSpaceModel(
        f=lambda x, u: x,
        g=lambda x: x,
        g_inverse=lambda lo, hi, a, b: (np.maximum(lo, a), np.minimum(hi, b)),
        state_noise=BoundedNoise(0.0, 0.0, 0.0),
        obs_noise=BoundedNoise(0.0, 0.0, 0.0),
    )
    yield Probe(
        c,
        "Kalman, zero-width noises, readings 2.0, 2.1, 2.2",
        lambda: KalmanFilter().run(zero, [2.0, 2.1, 2.2]),
        "error",
    )
    walk = random_walk(0.1, 0.5)
    yield Probe(
        c,
        "run_batch: a (2, 1) start for 4 runs",
        lambda: DependentEvidenceFilter(start=np.zeros((2, 1))).run_batch(walk, np.zeros((4, 3))),
        "error",
    )
    yield Probe(
        c,
        "ParticleFilter(n_particles=100.0)",
        lambda: ParticleFilter(n_particles=100.0).run(walk, [0.0, 0.1]),
    )
    yield Probe(
        c, "ParticleFilter(seed=5.0)", lambda: ParticleFilter(seed=5.0).run(walk, [0.0, 0.1])
    )
    yield Probe(
        c,
        "NassreddineFilter(max_focal=32.0)",
        lambda: NassreddineFilter(max_focal=32.0).run(walk, [0.0, 0.1]),
    )

    def start_kept() -> Any:
        arr = np.array([0.0])
        flt = DependentEvidenceFilter(start=arr)
        before = flt.run(walk, [0.0, 0.1]).estimates.copy()
        arr[0] = 0.05
        after = flt.run(walk, [0.0, 0.1]).estimates
        return bool(np.array_equal(before, after))

    yield Probe(
        c,
        "DependentEvidenceFilter(start=arr), arr changed afterwards",
        start_kept,
        "ok",
        lambda same: _same(same, True, "results unchanged"),
    )


def fault_probes() -> Iterator[Probe]:
    """SIGSTOP / SIGKILL of the loopback's PulseAudio mid-measurement (needs PulseAudio)."""
    c = "sound-server faults"
    script = ROOT / "scripts" / "audio-loopback.sh"

    def fault(sig: signal.Signals, want: str) -> Callable[[], Any]:
        def run() -> Any:
            env = {k: v for k, v in os.environ.items() if not k.startswith("PULSE_")}
            state = subprocess.run(
                ["bash", str(script), "start"], capture_output=True, text=True, check=True, env=env
            ).stdout
            env.update(line.split("=", 1) for line in state.splitlines() if "=" in line)
            pid = int((Path(env["PULSE_RUNTIME_PATH"]) / "pid").read_text())
            with tempfile.TemporaryDirectory() as tmp:
                start = time.monotonic()
                proc = subprocess.Popen(
                    [
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
                        "rec.wav",
                        "--figure",
                        "fig.png",
                    ],
                    cwd=tmp,
                    env=env,
                    stdout=subprocess.PIPE,
                    stderr=subprocess.PIPE,
                    text=True,
                )
                while (
                    proc.poll() is None
                    and time.monotonic() - start < 60
                    and not subprocess.run(
                        ["pactl", "list", "short", "sink-inputs"],
                        env=env,
                        capture_output=True,
                        text=True,
                    ).stdout.strip()
                ):
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

    yield Probe(
        c,
        "SIGSTOP the server mid-measurement",
        fault(signal.SIGSTOP, "the audio stream stalled"),
        "error",
    )
    yield Probe(
        c, "SIGKILL the server mid-measurement", fault(signal.SIGKILL, "sound server died"), "error"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--audio", action="store_true", help="also the sound-server faults")
    parser.add_argument("--verbose", action="store_true", help="print every probe")
    parser.add_argument(
        "--only-new",
        action="store_true",
        help="only the second pass's categories (representations onwards)",
    )
    parser.add_argument(
        "--third",
        action="store_true",
        help="only the third pass's categories (filesystem to teaching + sheets.py)",
    )
    args = parser.parse_args()
    import matplotlib

    matplotlib.use("Agg")
    # imported once before any probe: an import cut short by a probe's time limit would
    # leave a module half made for every later probe
    import matplotlib.pyplot  # noqa: F401

    with contextlib.suppress(ImportError):
        import dstoolkit.plots  # noqa: F401
        import dstoolkit.teaching  # noqa: F401
    counts: dict[str, Counter[str]] = {c: Counter() for c in CATEGORIES}
    problems = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "corpus").mkdir()
        (folder / "cli").mkdir()
        for name in ("recordings", "races", "signals", "budget"):
            (folder / name).mkdir()
        groups = [
            evidence_probes(),
            filter_probes(),
            file_probes(folder / "corpus"),
            command_probes(folder / "cli"),
            work_probes(),
        ]
        if args.only_new:
            groups = []
        groups += [
            representation_probes(),
            copy_probes(),
            gauge_probes(),
            recording_probes(folder / "recordings"),
            race_probes(folder / "races"),
            signal_probes(folder / "signals"),
            thread_probes(),
            budget_probes(folder / "budget"),
            boundary_probes(),
        ]
        if args.audio:
            groups.append(fault_probes())
        if args.third:
            groups = []
        (folder / "third").mkdir()
        groups.append(
            Probe(category, name, run, expect, time_limit=limit)
            for category, name, run, expect, limit in third_pass_cases(folder / "third")
        )
        for probe in itertools.chain(*groups):
            outcome, detail = classify(probe)
            counts[probe.category][outcome] += 1
            if outcome not in ("error", "ok"):
                problems.append(f"[{outcome}] {probe.category} / {probe.name}: {detail:.300}")
            if args.verbose:
                print(f"{outcome:9} {probe.category:24} {probe.name:45} {detail:.100}")
    head = (
        f"{'category':26} {'inputs tried':>12} {'clean errors':>13} {'valid results':>14} "
        f"{'tracebacks':>11} {'silent wrong':>13} {'hangs':>6} {'lost/litter':>12}"
    )
    print(head)
    print("-" * len(head))
    all_ = sum(counts.values(), Counter())
    for category, c in [*counts.items(), ("total", all_)]:
        total = sum(c.values())
        if total:
            print(
                f"{category:26} {total:>12} {c['error']:>13} {c['ok']:>14} "
                f"{c['traceback']:>11} {c['wrong']:>13} {c['hang']:>6} {c['lost']:>12}"
            )
    for line in problems:
        print(line)


if __name__ == "__main__":
    main()
