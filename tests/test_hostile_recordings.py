"""Crafted recordings through ``analyze``: a one-line error or the right level, in bounds.

The corpus (``tests/hostile_inputs.py``) is generated here from one simulated recording:
truncated files, chunk sizes that lie, impossible fmt fields, hostile metadata (wrong
types, huge, nested 200,000 deep, not UTF-8, numbers that overflow), and things that are
not regular files (a FIFO, /dev/zero, a folder, a sparse 2 GiB file).
"""

from __future__ import annotations

import os
import signal
import time
import tracemalloc

import pytest
from hostile_inputs import (
    ANALYSIS_ALLOWANCE_BYTES,
    LEVEL_TOLERANCE_M,
    TRUE_LEVEL_M,
    crafted_recordings,
)

from dstoolkit.audio import analyze
from dstoolkit.errors import DstoolkitError

#: Seconds one analysis may take (a good one takes well under one).
TIME_LIMIT_S = 10.0


class Hang(Exception):
    pass


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    return crafted_recordings(tmp_path_factory.mktemp("corpus"))


def _alarm(signum, frame):
    raise Hang("analyze did not return within the time limit")


def test_the_corpus_is_varied(corpus):
    assert len(corpus) >= 60
    assert sum(case.expect == "level" for case in corpus) >= 6


def test_every_crafted_recording_gives_a_one_line_error_or_the_level(corpus):
    failures = []
    previous = signal.signal(signal.SIGALRM, _alarm)
    try:
        for case in corpus:
            size = os.stat(case.path).st_size if case.path.is_file() else 0
            tracemalloc.start()
            start = time.perf_counter()
            signal.alarm(int(TIME_LIMIT_S) + 5)
            try:
                result = analyze(case.path)
                outcome = f"level {result.level.level_m:.4f} m"
            except DstoolkitError as exc:
                result, outcome = None, f"error: {exc}"
                if "\n" in str(exc) or not str(exc).strip():
                    failures.append(f"{case.name}: error not on one line: {exc!r}")
            except Exception as exc:  # noqa: BLE001 - the point is to catch every other kind
                result, outcome = None, f"TRACEBACK {type(exc).__name__}: {exc}"
                failures.append(f"{case.name}: {outcome}")
            finally:
                signal.alarm(0)
                elapsed = time.perf_counter() - start
                _, peak = tracemalloc.get_traced_memory()
                tracemalloc.stop()
            if case.expect == "level" and (
                result is None or abs(result.level.level_m - TRUE_LEVEL_M) > LEVEL_TOLERANCE_M
            ):
                failures.append(f"{case.name}: expected the level {TRUE_LEVEL_M} m, got {outcome}")
            if case.expect == "error" and result is not None:
                failures.append(f"{case.name}: expected an error, got {outcome}")
            if elapsed > TIME_LIMIT_S:
                failures.append(f"{case.name}: took {elapsed:.1f} s")
            if peak > max(4 * size, ANALYSIS_ALLOWANCE_BYTES):
                failures.append(
                    f"{case.name}: peak memory {peak / 2**20:.0f} MiB for a file "
                    f"of {size / 2**20:.1f} MiB"
                )
    finally:
        signal.signal(signal.SIGALRM, previous)
    assert not failures, "\n".join(failures)
