"""The speed scripts print the figures they promise.

Their figures are not checked here: speed is measured by the scripts, never asserted in tests.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"


def load(name: str) -> ModuleType:
    """Import ``benchmarks/<name>.py`` as a module."""
    spec = importlib.util.spec_from_file_location(f"benchmark_{name}", BENCHMARKS / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def test_the_latency_benchmark_times_every_explorer():
    """Every explorer of dstoolkit.teaching has its value changes in widget_latency.py.

    The lab's measuring station aside: it measures on a button press.
    """
    from dstoolkit import teaching

    timed = {call.split("(")[0] for call in load("widget_latency").CHANGES}
    explorers = {name for name in teaching.__all__ if name.endswith(("_explorer", "_widget"))}
    assert timed == explorers - {"lab_widget"}


def test_the_filter_benchmark_prints_the_floor_beside_the_steps(capsys):
    """filters.py prints the load average before and after, and the floor above the filters.

    Its table's first row is the floor (one numpy call per step, × floor = 1), above each
    filter's per-step time.
    """
    assert load("filters").main(["--runs", "3", "--repeat", "2", "--filters", "kalman"]) == 0
    lines = capsys.readouterr().out.splitlines()
    header = next(i for i, line in enumerate(lines) if line.startswith("filter "))
    assert "per step" in lines[header] and "× floor" in lines[header]
    floor, kalman = lines[header + 1].split(), lines[header + 2].split()
    assert floor[:4] == ["floor", floor[1], "µs", "1"] and float(floor[1]) > 0
    assert kalman[0] == "kalman" and "µs" in kalman
    assert sum("load average" in line for line in lines) == 2


@pytest.mark.slow
def test_the_filter_profile_shows_every_block_of_a_step(capsys):
    """filter_profile.py prints, for the numpy path, a row per block of Steps 2–6.

    Each row holds its time and numpy calls per step (counted, not guessed); then come the
    rest, and the load average.
    """
    profile = load("filter_profile")
    assert profile.main(["--repeat", "2", "--runs", "8"]) == 0
    out = capsys.readouterr().out
    numpy_part = out.split("compiled Step 6")[0]
    for label, name in profile.BLOCKS:
        if name != "_fuse_compiled":
            row = next(line for line in numpy_part.splitlines() if line.strip().startswith(label))
            us, calls = (float(x) for x in row[len(label) + 2 :].split()[:2])
            assert us > 0 and calls >= 1, row
    total = float(numpy_part.split(" numpy calls per step")[0].rsplit(" ", 1)[1])
    assert 20 < total < 200  # the whole step, model callbacks included
    assert "rest:" in numpy_part and out.count("load average") == 2
