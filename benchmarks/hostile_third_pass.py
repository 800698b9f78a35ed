"""The third pass of ``benchmarks/hostile_probe.py``: cases for each category of its table.

Filesystem, processes and races, WAV inputs, the evidence and filters APIs, array-likes, the
memory budget, the environment, and the teaching layer with ``scripts/sheets.py``. Each case
is ``(category, name, run, expect, time limit)`` as a :class:`hostile_probe.Probe` takes it; ``run``
raises :class:`Lost` when a file was lost or litter left, and :class:`OverBudget` when the
peak memory passed the budget. Every case uses the public API and command lines only, so
that the same cases run on an older dstoolkit (``PYTHONPATH`` pointing at its checkout).
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import io
import os
import signal
import socket
import stat
import struct
import subprocess
import sys
import tracemalloc
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
from hostile_inputs import boxes_evidence, frame_evidence, table3_signalled

import dstoolkit
import dstoolkit.evidence as ev
from dstoolkit import cli
from dstoolkit.audio import analyze, load_recording
from dstoolkit.errors import DstoolkitError
from dstoolkit.filters import (
    BoundedErrorFilter,
    DependentEvidenceFilter,
    KalmanFilter,
    NassreddineFilter,
    ParticleFilter,
    random_walk,
)
from dstoolkit.gauge import gauge_state_space_model, simulate_gauge

#: (category, name, run, expect, time limit in seconds)
Case = tuple[str, str, Callable[[], Any], str, int]
#: The time limit of a case that runs the command in a child process (its imports alone
#: take several seconds on a loaded machine).
CHILD_S = 300
_Case4 = tuple[str, str, Callable[[], Any], str]
QUICK_S = 30
PACKAGE_ROOT = Path(dstoolkit.__file__).resolve().parents[1]
SMALL = ["--runs", "1", "--methods", "direct", "--quiet"]
PRECIOUS = b"precious\n"
MIB = 2**20


class Lost(Exception):
    """A file was lost or replaced unasked, or a command left litter behind."""


class OverBudget(Exception):
    """The peak memory passed the memory budget the work was allowed."""


class TooSlow(Exception):
    """Work in C that no signal can stop was still running past its time limit."""


def _in_fork(work: Callable[[], Any], seconds: float) -> Any:
    """Run ``work()`` in a forked child and give what it returned or raised.

    A child still running after ``seconds`` is killed (:class:`TooSlow`): C code ignores
    the probe's own alarm.
    """
    import multiprocessing

    ctx = multiprocessing.get_context("fork")
    parent, child = ctx.Pipe(duplex=False)

    def target() -> None:
        try:
            child.send(("returned", work()))
        except BaseException as exc:  # noqa: BLE001 - handed back as it is
            child.send(("raised", exc))

    proc = ctx.Process(target=target)
    proc.start()
    try:
        if not parent.poll(seconds):
            raise TooSlow(f"still running after {seconds:g} s")
        kind, value = parent.recv()
    finally:
        if proc.is_alive():
            proc.kill()
        proc.join()
    if kind == "raised":
        raise value
    return value


def _files(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def _in_process(main: Callable[[list[str]], int], argv: list[str], cwd: Path) -> tuple[int, str]:
    """Run a command's ``main(argv)`` here, from ``cwd``; return its status and stderr."""
    err = io.StringIO()
    here = os.getcwd()
    os.chdir(cwd)
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            try:
                status = main(argv)
            except SystemExit as exc:
                status = int(exc.code or 0)
    finally:
        os.chdir(here)
    return status, err.getvalue()


def _cli(argv: list[str], cwd: Path) -> tuple[int, str]:
    return _in_process(cli.main, argv, cwd)


def _verdict(status: int, err: str) -> str:
    """Turn a command's status and stderr into a probe's outcome."""
    if "Traceback" in err or (status != 0 and len(err.strip().splitlines()) != 1):
        raise RuntimeError(err[-600:])
    if status != 0:
        raise DstoolkitError(err.strip())
    return "ran"


@contextlib.contextmanager
def _meanwhile(act: Callable[[], None]) -> Iterator[None]:
    real = cli.run_table3

    def hook(**kwargs: Any) -> Any:
        act()
        return real(**kwargs)

    cli.run_table3 = hook  # type: ignore[assignment]
    try:
        yield
    finally:
        cli.run_table3 = real  # type: ignore[assignment]


class _Folders:
    def __init__(self, root: Path) -> None:
        self.root, self.n = root, 0

    def __call__(self) -> Path:
        self.n += 1
        sub = self.root / f"case{self.n}"
        sub.mkdir(parents=True)
        return sub


# -- filesystem ---------------------------------------------------------------------------
def filesystem_cases(fresh: _Folders) -> Iterator[_Case4]:
    c = "filesystem"

    def keeps_mode(mode: int) -> Callable[[], Any]:
        def run() -> Any:
            sub = fresh()
            csv = sub / "t.csv"
            csv.write_bytes(PRECIOUS)
            csv.chmod(mode)
            status, err = _cli(["table3", "--out", str(csv), *SMALL, "--overwrite"], sub)
            if stat.S_IMODE(csv.stat().st_mode) != mode:
                raise Lost(f"mode {oct(mode)} became {oct(stat.S_IMODE(csv.stat().st_mode))}")
            return _verdict(status, err)

        return run

    for mode in (0o600, 0o640, 0o444):
        yield c, f"table3 --overwrite keeps mode {oct(mode)}", keeps_mode(mode), "ok"

    def loop(where: str) -> Callable[[], Any]:
        def run() -> Any:
            sub = fresh()
            (sub / "loop").symlink_to(sub / "loop")
            out = sub / "loop" if where == "file" else sub / "loop" / "t.csv"
            return _verdict(*_cli(["table3", "--out", str(out), *SMALL], sub))

        return run

    yield c, "table3 --out is a symlink loop", loop("file"), "error"
    yield c, "table3 --out lies under a symlink loop", loop("folder"), "error"

    def through_a_file() -> Any:
        sub = fresh()
        (sub / "afile").write_text("x")
        return _verdict(*_cli(["table3", "--out", str(sub / "afile" / "t.csv"), *SMALL], sub))

    yield c, "table3 --out under a regular file", through_a_file, "error"

    def analyze_odd(kind: str) -> Callable[[], Any]:
        def run() -> Any:
            sub = fresh()
            path = sub / "rec.wav"
            if kind == "socket":
                with socket.socket(socket.AF_UNIX) as sock:
                    sock.bind(str(path))
                    return analyze(path)
            path.symlink_to(path)
            return analyze(path)

        return run

    yield c, "analyze a socket", analyze_odd("socket"), "error"
    yield c, "analyze a symlink loop", analyze_odd("loop"), "error"

    def swapped_folder() -> Any:
        sub = fresh()
        out, elsewhere = sub / "out", sub / "elsewhere"
        out.mkdir()
        elsewhere.mkdir()

        def swap() -> None:
            out.rename(sub / "moved")
            out.symlink_to(elsewhere)

        with _meanwhile(swap):
            status, err = _cli(["table3", "--out", str(out / "t.csv"), *SMALL], sub)
        if _files(elsewhere):
            raise Lost(f"wrote into the folder swapped in: {_files(elsewhere)}")
        return _verdict(status, err)

    yield c, "table3: its folder is swapped for a link meanwhile", swapped_folder, "error"


# -- processes and races -------------------------------------------------------------------
def race_cases(fresh: _Folders) -> Iterator[_Case4]:
    c = "processes & races"

    def stopped(sig: int, overwrite: bool) -> Callable[[], Any]:
        def run() -> Any:
            work = fresh()
            (work / "out").mkdir()
            csv = work / "out" / "t.csv"
            if overwrite:
                csv.write_bytes(PRECIOUS)
            status, err, _ = table3_signalled(work, sig, 120.0, overwrite=overwrite)
            want = ["out", "out/t.csv"] if overwrite else ["out"]
            if overwrite and (not csv.is_file() or csv.read_bytes() != PRECIOUS):
                raise Lost("the original CSV is gone or changed")
            if _files(work) != want:
                raise Lost(f"left {_files(work)}")
            if status != 128 + sig or "Traceback" in err or len(err.splitlines()) != 1:
                raise RuntimeError(f"exit {status}: {err[-400:]}")
            raise DstoolkitError(err.strip())

        return run

    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT):
        for overwrite in (True, False):
            name = f"table3 {'--overwrite ' if overwrite else ''}stopped by {sig.name}"
            yield c, name, stopped(sig, overwrite), "error"

    def other_run_first() -> Any:
        sub = fresh()
        csv = sub / "t.csv"
        csv.write_bytes(PRECIOUS)
        seen: dict[str, Any] = {}
        real = cli.run_table3

        def inner(**kwargs: Any) -> Any:
            cli.run_table3 = real  # type: ignore[assignment]
            seen["status"] = _cli(["table3", "--out", str(csv), *SMALL, "--overwrite"], sub)[0]
            seen["csv"] = csv.read_bytes() if csv.is_file() else None
            return real(**kwargs)

        cli.run_table3 = inner  # type: ignore[assignment]
        try:
            status, err = _cli(["table3", "--out", str(csv), *SMALL, "--overwrite"], sub)
        finally:
            cli.run_table3 = real  # type: ignore[assignment]
        if not csv.is_file() or (status != 0 and csv.read_bytes() != seen["csv"]):
            raise Lost("the other run's complete CSV was removed or spoiled")
        if [n for n in os.listdir(sub) if n.startswith(".")]:
            raise Lost(f"litter {os.listdir(sub)}")
        return _verdict(status, err)

    yield c, "two table3 --overwrite, one inside the other", other_run_first, "either"

    def remade_meanwhile() -> Any:
        sub = fresh()
        csv = sub / "t.csv"
        csv.write_bytes(PRECIOUS)

        def remake() -> None:
            csv.unlink()
            csv.write_bytes(b"theirs\n")

        with _meanwhile(remake):
            status, err = _cli(["table3", "--out", str(csv), *SMALL, "--overwrite"], sub)
        if csv.read_bytes() != b"theirs\n":
            raise Lost("a file made again meanwhile was replaced")
        return _verdict(status, err)

    yield c, "table3 --overwrite: the file is made again meanwhile", remade_meanwhile, "error"

    def link_meanwhile() -> Any:
        sub = fresh()
        victim = sub / "victim.txt"
        victim.write_bytes(PRECIOUS)
        with _meanwhile(lambda: (sub / "t.png").symlink_to(victim)):
            status, err = _cli(["table3", "--out", str(sub / "t.csv"), *SMALL, "--overwrite"], sub)
        if victim.read_bytes() != PRECIOUS or not (sub / "t.png").is_symlink():
            raise Lost("a link made at the figure meanwhile was written through or replaced")
        return _verdict(status, err)

    yield c, "table3 --overwrite: a link appears at the figure", link_meanwhile, "error"

    def disk_full_at_the_figure() -> Any:
        import dstoolkit.plots

        sub = fresh()
        csv, png = sub / "t.csv", sub / "t.png"
        csv.write_bytes(PRECIOUS)
        png.write_bytes(b"old figure")

        class Full:
            def savefig(self, fh: Any, **kwargs: Any) -> None:
                fh.write(b"\x89PNG half")
                raise OSError(28, "No space left on device")

        real = dstoolkit.plots.plot_table3
        dstoolkit.plots.plot_table3 = lambda table: Full()  # type: ignore[assignment]
        try:
            status, err = _cli(["table3", "--out", str(csv), *SMALL, "--overwrite"], sub)
        finally:
            dstoolkit.plots.plot_table3 = real  # type: ignore[assignment]
        if not csv.is_file() or csv.read_bytes() != PRECIOUS:
            raise Lost("the original CSV is gone after the figure failed")
        if png.read_bytes() != b"old figure" or _files(sub) != ["t.csv", "t.png"]:
            raise Lost(f"the old figure changed or litter: {_files(sub)}")
        return _verdict(status, err)

    yield c, "table3 --overwrite: the disk fills at the figure", disk_full_at_the_figure, "error"


# -- WAV inputs -----------------------------------------------------------------------------
def _wav(*chunks: bytes) -> bytes:
    body = b"WAVE" + b"".join(chunks)
    return b"RIFF" + struct.pack("<I", len(body)) + body


def _chunk(tag: bytes, payload: bytes) -> bytes:
    return tag + struct.pack("<I", len(payload)) + payload + b"\0" * (len(payload) % 2)


def _fmt(rate: int) -> bytes:
    return _chunk(b"fmt ", struct.pack("<HHIIHH", 3, 1, rate, rate * 4, 4, 32))


def wav_cases(fresh: _Folders) -> Iterator[_Case4]:
    c = "WAV inputs"
    data = _chunk(b"data", np.zeros(4410, "<f4").tobytes())
    layouts = {
        "two fmt chunks, rates differ": (_fmt(44100), _fmt(48000), data),
        "two equal fmt chunks": (_fmt(44100), _fmt(44100), data),
        "a second fmt chunk after data": (_fmt(44100), data, _fmt(22050)),
    }
    for name, chunks in layouts.items():

        def run(chunks: tuple[bytes, ...] = chunks) -> Any:
            path = fresh() / "r.wav"
            path.write_bytes(_wav(*chunks))
            return load_recording(path)

        yield c, name, run, "error"

    def data_before_fmt() -> Any:
        path = fresh() / "r.wav"
        path.write_bytes(_wav(data, _fmt(44100)))
        return load_recording(path).samplerate

    yield c, "data before fmt (legal RIFF order)", data_before_fmt, "either"


# -- evidence API ---------------------------------------------------------------------------
def evidence_cases() -> Iterator[_Case4]:
    c = "evidence API"
    e1, e2 = ev.appendix_pair()
    joint = ev.cartesian_product([e1, e2])
    for axes in ([5], [0, 0], [], [-1], [0.5], "0", 3):
        yield c, f"projection(e, {axes!r})", lambda a=axes: ev.projection(joint, a), "error"
    yield c, "projection(e, np.array([1]))", lambda: ev.projection(joint, np.array([1])), "ok"
    yield c, "dempster(e, 5)", lambda: ev.dempster(e1, 5), "error"  # type: ignore[arg-type]
    yield c, "projection(5, [0])", lambda: ev.projection(5, [0]), "error"  # type: ignore[arg-type]


# -- filters API ----------------------------------------------------------------------------
GAUGE = gauge_state_space_model()
SEQ = simulate_gauge(level_m=2.6, temperature_c=26.0, seed=0)


def _filters() -> list[Any]:
    return [
        DependentEvidenceFilter(p=2),
        NassreddineFilter(p=2, max_focal=8),
        BoundedErrorFilter(),
        KalmanFilter(),
        ParticleFilter(n_particles=200),
    ]


def filter_cases() -> Iterator[_Case4]:
    c = "filters API"
    bad_models = {
        "f returns inf": dataclasses.replace(GAUGE, f=lambda x, u: np.full_like(x, np.inf)),
        "f is 0": dataclasses.replace(GAUGE, f=lambda x, u: np.zeros_like(x)),
        "g gives 2 columns": dataclasses.replace(
            GAUGE, g=lambda x: np.concatenate([GAUGE.g(x), x], axis=-1)
        ),
        "g_inverse returns one array": dataclasses.replace(
            GAUGE, g_inverse=lambda lo, hi, x_lo, x_hi: x_lo
        ),
        "g_inverse takes 2 arguments": dataclasses.replace(
            GAUGE, g_inverse=lambda lo, hi: (lo, hi)
        ),
    }
    for flt in _filters():
        for what, model in bad_models.items():
            if what == "f is 0" and flt.name == "kalman":
                continue  # a Kalman filter follows any linear model: no contradiction to see
            yield (
                c,
                f"{flt.name}: {what}",
                lambda f=flt, m=model: f.run(m, SEQ.readings, SEQ.inputs),
                "error",
            )
        walk = random_walk(0.1, 0.5)
        other = KalmanFilter() if flt.name == "particle" else ParticleFilter(n_particles=50)
        yield (
            c,
            f"{flt.name}: step() given another filter's state",
            lambda f=flt, o=other, w=walk: f.step(o.initialize(w, 1.0), 1.1),
            "error",
        )


# -- array-likes ----------------------------------------------------------------------------
def array_cases() -> Iterator[_Case4]:
    c = "array-likes"
    masked = np.ma.masked_array(SEQ.readings.copy(), mask=False)
    masked[3] = -999.0
    masked[3] = np.ma.masked
    for flt in _filters():
        yield (
            c,
            f"{flt.name}: a masked reading",
            lambda f=flt: f.run(GAUGE, masked, SEQ.inputs),
            "error",
        )
    yield (
        c,
        "kalman: a masked array with nothing masked",
        lambda: KalmanFilter().run(GAUGE, np.ma.masked_array(SEQ.readings), SEQ.inputs),
        "ok",
    )
    for which in ("lo", "hi", "mass"):
        args = {"lo": [0.0, 1.0], "hi": [1.0, 2.0], "mass": [0.5, 0.5]}
        args[which] = np.ma.masked_array(args[which], mask=[False, True])
        yield (
            c,
            f"IntervalEvidence: masked {which}",
            lambda a=args: ev.IntervalEvidence(**a),
            "error",
        )

    def masked_answer() -> Any:
        from answer_key import solution
        from dstoolkit.teaching import check

        verdict = check("mass.bel", np.ma.masked_array([solution("mass.bel")], mask=[True]))
        if verdict:
            return "right"  # a silent wrong verdict: the mask was ignored
        raise DstoolkitError(str(verdict))

    yield c, "check: a masked answer", masked_answer, "error"


# -- memory budget ------------------------------------------------------------------------
def _within(budget: int, work: Callable[[], Any]) -> Callable[[], Any]:
    def run() -> Any:
        ev.set_memory_budget(budget)
        started = not tracemalloc.is_tracing()
        if started:
            tracemalloc.start()
        tracemalloc.reset_peak()
        try:
            result = work()
            _, peak = tracemalloc.get_traced_memory()
        finally:
            if started:
                tracemalloc.stop()
            ev.set_memory_budget(None)
        if peak > budget:
            raise OverBudget(f"peak {peak / MIB:.0f} MiB under a {budget // MIB} MiB budget")
        return len(result)

    return run


def budget_cases() -> Iterator[_Case4]:
    c = "memory budget"
    for mib, n in ((32, 600), (128, 1200)):
        a, b = frame_evidence(n, 24, 1), frame_evidence(n, 24, 2)
        work = _within(mib * MIB, lambda a=a, b=b: ev.dempster(a, b))
        yield c, f"dempster, 24 hypotheses, {n} focal sets, {mib} MiB", work, "either"
    for mib, k in ((32, 50), (128, 80)):
        parts = [boxes_evidence(k, 1, i) for i in range(3)]
        work = _within(mib * MIB, lambda p=parts: ev.cartesian_product(p))
        yield c, f"cartesian_product of 3 x {k}, {mib} MiB", work, "either"


# -- environment ----------------------------------------------------------------------------
def _child(argv: list[str], cwd: Path, **env: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, *argv],
        cwd=cwd,
        env={**os.environ, "PYTHONPATH": str(PACKAGE_ROOT), **env},
        capture_output=True,
        encoding="utf-8",
        errors="replace",  # a child on another locale prints in its own encoding
        timeout=300,
        check=False,
    )


def environment_cases(fresh: _Folders) -> Iterator[_Case4]:
    c = "environment"
    table3 = ["-m", "dstoolkit", "table3", "--out", "t.csv", *SMALL]

    def locale(env: dict[str, str]) -> Callable[[], Any]:
        def run() -> Any:
            sub = fresh()
            done = _child(table3, sub, **env)
            if done.returncode == 0 and _files(sub) != ["t.csv", "t.png"]:
                raise Lost(f"exit 0 but {_files(sub)}")
            if done.returncode != 0 and _files(sub):
                raise Lost(f"failed and left {_files(sub)}")
            return _verdict(done.returncode, done.stderr)

        return run

    for name, env in (
        ("PYTHONIOENCODING=ascii", {"PYTHONIOENCODING": "ascii"}),
        ("LC_ALL=C without UTF-8 mode", {"LC_ALL": "C", "LANG": "C", "PYTHONUTF8": "0"}),
        ("PYTHONIOENCODING=latin-1", {"PYTHONIOENCODING": "latin-1"}),
    ):
        yield c, f"table3 under {name}", locale(env), "ok"
    yield c, "table3 with MPLBACKEND=nonsense", locale({"MPLBACKEND": "nonsense"}), "error"

    def closed_stdout() -> Any:
        sub = fresh()
        read, write = os.pipe()
        os.close(read)
        try:
            done = subprocess.run(
                [sys.executable, *table3],
                cwd=sub,
                env={**os.environ, "PYTHONPATH": str(PACKAGE_ROOT)},
                stdout=write,
                stderr=subprocess.PIPE,
                text=True,
                timeout=300,
                check=False,
            )
        finally:
            os.close(write)
        if _files(sub) != ["t.csv", "t.png"]:
            raise Lost(f"the finished outputs were not kept: {_files(sub)}")
        return _verdict(done.returncode, done.stderr)

    yield c, "table3 | head (standard output closed)", closed_stdout, "either"

    def stop_while_importing(sig: int) -> Callable[[], Any]:
        code = (
            "import signal, sys\n"
            "sys.orig_argv[1:] = ['-m', 'dstoolkit']\n"
            "import dstoolkit\n"
            f"signal.raise_signal({int(sig)})\n"
            "import numpy\n"
        )

        def run() -> Any:
            done = _child(["-c", code], fresh())
            return _verdict(done.returncode, done.stderr)

        return run

    for sig in (signal.SIGINT, signal.SIGTERM):
        yield c, f"{sig.name} while the command imports", stop_while_importing(sig), "error"


# -- teaching and sheets.py ---------------------------------------------------------------
def _fingerprint(folder: Path) -> str:
    digest = hashlib.sha256()
    for path in sorted(folder.glob("*.ipynb")):
        digest.update(path.name.encode() + path.read_bytes())
    return digest.hexdigest()


def _sheets(argv: list[str], cwd: Path) -> tuple[int, str]:
    """Run scripts/sheets.py's main in this process (its folder on the path, as a script's)."""
    scripts = str(PACKAGE_ROOT / "scripts")
    sys.path.insert(0, scripts)
    try:
        import sheets

        return _in_process(sheets.main, argv, cwd)
    finally:
        sys.path.remove(scripts)


def teaching_cases(fresh: _Folders) -> Iterator[_Case4]:
    c = "teaching + sheets.py"
    notebooks = PACKAGE_ROOT / "notebooks"

    def into_the_book(argv: list[str]) -> Callable[[], Any]:
        def run() -> Any:
            before = _fingerprint(notebooks)
            status, err = _sheets([a.replace("NB", str(notebooks)) for a in argv], fresh())
            if _fingerprint(notebooks) != before:
                raise Lost("the book's student sheets were written over")
            return _verdict(status, err)

        return run

    for argv in (
        ["--teacher", "NB"],
        ["--variant", "2", "--out", "NB"],
        ["--nbgrader", "NB", "--chapter", "mass_functions"],
    ):
        yield c, f"sheets.py {' '.join(argv)}", into_the_book(argv), "error"

    def existing_course() -> Any:
        home = fresh()
        config = home / "nbgrader_config.py"
        config.write_bytes(PRECIOUS)
        status, err = _sheets(["--nbgrader", str(home), "--chapter", "mass_functions"], home)
        if config.read_bytes() != PRECIOUS:
            raise Lost("an edited nbgrader_config.py was replaced without --overwrite")
        return _verdict(status, err)

    yield c, "sheets.py --nbgrader into an existing course", existing_course, "error"

    def misspelled() -> Any:
        home = fresh()
        return _verdict(*_sheets(["--nbgrader", str(home / "c"), "--chapter", "mass_fn"], home))

    yield c, "sheets.py --chapter misspelled", misspelled, "error"

    def out_is(kind: str) -> Callable[[], Any]:
        def run() -> Any:
            home = fresh()
            out = home / "afile" if kind == "a file" else Path("/proc/dstoolkit-sheets")
            if kind == "a file":
                out.write_text("x")
            return _verdict(*_sheets(["--variant", "1", "--out", str(out)], home))

        return run

    for kind in ("a file", "under /proc"):
        yield c, f"sheets.py --out {kind}", out_is(kind), "error"

    from dstoolkit.teaching import check, set_time_limit

    yield c, "check(5, 1.0)", lambda: check(5, 1.0), "error"  # type: ignore[arg-type]
    yield c, "set_time_limit(10**400)", lambda: set_time_limit(10**400), "error"

    def huge_answer() -> Any:
        verdict = check("mass.bel", 10**400)
        if verdict:
            return "right"
        raise DstoolkitError(str(verdict))

    yield c, "check('mass.bel', 10**400)", huge_answer, "error"

    class EndlessInC:
        def __float__(self) -> float:
            return float(sum(range(10**11)))

    def c_level(answer: Any, exercise: str) -> Callable[[], Any]:
        def judged() -> Any:
            verdict = check(exercise, answer, time_limit=1)
            if verdict:
                return "right"
            raise DstoolkitError(str(verdict))

        return lambda: _in_fork(judged, 25.0)

    yield (
        c,
        "check a value whose __float__ computes in C",
        c_level(EndlessInC(), "mass.bel"),
        "error",
    )
    yield (
        c,
        "check a coding answer computing in C, time_limit=1",
        c_level(lambda *a, **k: float(sum(range(10**11))), "beyond.sigma-code"),
        "error",
    )


CATEGORIES = (
    "filesystem",
    "processes & races",
    "WAV inputs",
    "evidence API",
    "filters API",
    "array-likes",
    "memory budget",
    "environment",
    "teaching + sheets.py",
)


def third_pass_cases(folder: Path) -> Iterator[Case]:
    """Every case of the third pass, in the order of :data:`CATEGORIES`."""
    fresh = _Folders(folder)
    for group, limit in (
        (filesystem_cases(fresh), QUICK_S),
        (race_cases(fresh), CHILD_S),
        (wav_cases(fresh), QUICK_S),
        (evidence_cases(), QUICK_S),
        (filter_cases(), QUICK_S),
        (array_cases(), QUICK_S),
        (budget_cases(), QUICK_S),
        (environment_cases(fresh), CHILD_S),
        (teaching_cases(fresh), CHILD_S),
    ):
        for category, name, run, expect in group:
            yield category, name, run, expect, limit
