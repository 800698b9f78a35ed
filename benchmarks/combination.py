"""Time Dempster's rule and the dependent combination on interval evidence.

Sizes as in one filter step: 64 × 16 focal elements (step 6 of the paper's filter) and a
larger 1024 × 64. Prints the median of repeated runs. Run: python benchmarks/combination.py
"""

from __future__ import annotations

import timeit

import numpy as np

from dstoolkit import IntervalEvidence, combine_dependent, dempster


def random_evidence(n: int, rng: np.random.Generator, share: IntervalEvidence | None = None):
    lo = rng.uniform(-1.0, 0.5, n)
    hi = lo + rng.uniform(0.5, 2.0, n)
    if share is not None:  # a few focal elements in common, as dependent evidence has
        k = min(4, n, len(share))
        lo[:k], hi[:k] = share.lo_1d[:k], share.hi_1d[:k]
    return IntervalEvidence(lo, hi, rng.dirichlet(np.ones(n)))


def median_ms(fn, repeat: int = 7) -> float:
    number = max(1, int(0.2 / max(timeit.timeit(fn, number=1), 1e-6)))
    times = timeit.repeat(fn, number=number, repeat=repeat)
    return 1e3 * float(np.median(times)) / number


def main() -> None:
    rng = np.random.default_rng(0)
    print(f"{'sizes':>12} {'products':>9} {'dempster ms':>12} {'dependent ms':>13}")
    for n1, n2 in [(64, 16), (1024, 64)]:
        a = random_evidence(n1, rng)
        b = random_evidence(n2, rng, share=a)
        t_d = median_ms(lambda a=a, b=b: dempster(a, b))
        t_c = median_ms(lambda a=a, b=b: combine_dependent(a, b))
        print(f"{n1:>5} x {n2:<4} {n1 * n2:>9} {t_d:>12.3f} {t_c:>13.3f}")


if __name__ == "__main__":
    main()
