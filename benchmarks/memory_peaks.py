"""The memory budget against the real peak: what tracemalloc measures, what the checks count.

For Dempster's rule (eq. 1) on mass functions and interval evidence, and for the Cartesian
product of marginals (eq. 16), prints the peak per product (per box) that tracemalloc sees
and the bytes per product the budget check counts (``PRODUCT_BYTES``,
``product_row_bytes``), then the peak at the largest size a 32 MiB budget allows. The
check's count must stay above the measured peak.

Run: python benchmarks/memory_peaks.py
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from hostile_inputs import boxes_evidence, frame_evidence, traced_peak  # noqa: E402

import dstoolkit.evidence as ev  # noqa: E402
from dstoolkit.evidence._combination import PRODUCT_BYTES  # noqa: E402
from dstoolkit.evidence._extension import product_row_bytes  # noqa: E402

MIB = 2**20


def dempster_rows() -> None:
    print("Dempster's rule, bytes per product: measured peak / counted by the budget check")
    for name, make, row in (
        ("mass functions, 24 hypotheses", lambda n, s: frame_evidence(n, 24, s), 8),
        ("mass functions, 64 hypotheses", lambda n, s: frame_evidence(n, 64, s), 8),
        ("interval evidence, d = 1", lambda n, s: boxes_evidence(n, 1, s), 16),
        ("interval evidence, d = 3", lambda n, s: boxes_evidence(n, 3, s), 48),
    ):
        for n in (300, 900):
            a, b = make(n, 1), make(n, 2)
            for merge in (True, False):
                _, peak = traced_peak(lambda a=a, b=b, merge=merge: ev.dempster(a, b, merge=merge))
                print(
                    f"  {name:32} n = {n:4}  merge={merge!s:5}  "
                    f"{peak / n**2:7.1f} / {2 * row + PRODUCT_BYTES}"
                )


def product_rows() -> None:
    print("Cartesian product, bytes per box: measured peak / counted by the budget check")
    for marginals, dim, k in ((2, 1, 600), (3, 1, 60), (3, 2, 50), (4, 1, 25), (2, 3, 500)):
        parts = [boxes_evidence(k, dim, i) for i in range(marginals)]
        for merge in (True, False):
            _, peak = traced_peak(lambda p=parts, m=merge: ev.cartesian_product(p, merge=m))
            print(
                f"  {marginals} marginals of {k} boxes in {dim} dimension(s)  merge={merge!s:5}  "
                f"{peak / k**marginals:7.1f} / {product_row_bytes(marginals * dim, marginals):.0f}"
            )


def at_the_budget(budget: int = 32 * MIB) -> None:
    ev.set_memory_budget(budget)
    try:
        n = int((budget / (2 * 8 + PRODUCT_BYTES)) ** 0.5)
        a, b = frame_evidence(n, 24, 1), frame_evidence(n, 24, 2)
        _, peak = traced_peak(lambda: ev.dempster(a, b))
        print(f"dempster, 24 hypotheses, n = {n} (the most a {budget // MIB} MiB budget allows):")
        print(f"  peak {peak / MIB:.1f} MiB")
        k = int((budget / product_row_bytes(3, 3)) ** (1 / 3))
        parts = [boxes_evidence(k, 1, i) for i in range(3)]
        _, peak = traced_peak(lambda: ev.cartesian_product(parts))
        print(f"cartesian_product of 3 marginals of {k} boxes (the most the budget allows):")
        print(f"  peak {peak / MIB:.1f} MiB")
    finally:
        ev.set_memory_budget(None)


if __name__ == "__main__":
    dempster_rows()
    product_rows()
    at_the_budget()
