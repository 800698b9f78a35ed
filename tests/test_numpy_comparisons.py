"""The chapters' comparisons on the numpy kernels never load numba.

Chapters 9–13 and their sheets call ``set_comparison_kernel("numpy")``: numba's compiler
would about double a notebook kernel's memory (benchmarks/chapter_memory.py measures it).
This checks, in a fresh interpreter, that a comparison of Table 3's filters and the lab's
analysis of a simulated recording then run without importing numba.
"""

from __future__ import annotations

import os
import subprocess
import sys

from conftest import ROOT

SCRIPT = """
import sys
from dstoolkit.filters import set_comparison_kernel
set_comparison_kernel("numpy")
from dstoolkit.studies import gauge_run
from dstoolkit.audio import analyze, simulate_measurement
from dstoolkit.gauge import TubeSetup
run = gauge_run(4.6, 26.5, simulation="frequency", order_rule="eq43", seed=0)
assert run.readings.size > 0
analyze(simulate_measurement(TubeSetup(level_m=2.5, temperature_c=21.0), latency_s=0.137))
print("numba" in sys.modules)
"""


def test_the_numpy_kernels_leave_numba_unloaded():
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=os.environ.copy(),
        timeout=300,  # a guard against a hang, not a speed requirement
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.strip().splitlines()[-1] == "False"
