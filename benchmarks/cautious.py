"""Time the cautious rule and the canonical weights against Dempster's rule, by frame size.

The cautious rule works on all 2^|Θ| subsets (commonalities, their logarithms, two Möbius
transforms), Dempster's rule on the products of focal elements: this prints how each grows
with the frame. Prints the median of repeated runs. Run: python benchmarks/cautious.py
"""

from __future__ import annotations

import timeit

import numpy as np

from dstoolkit.evidence import MassFunction, canonical_weights, cautious, dempster


def random_nondogmatic(n_frame: int, n_focal: int, rng: np.random.Generator) -> MassFunction:
    frame = tuple(range(n_frame))
    full = 2**n_frame - 1
    # focal elements that all hold hypothesis 0 (odd masks), so that two bodies of evidence
    # do not contradict each other
    masks = rng.choice(np.arange(1, full, 2), size=min(n_focal, full // 2), replace=False)
    w = rng.dirichlet(np.ones(len(masks) + 1))
    masses = {
        frozenset(h for h in frame if (int(m) >> h) & 1): float(x)
        for m, x in zip(masks, w, strict=False)
    }
    masses[frozenset(frame)] = float(w[-1])
    return MassFunction(masses, frame)


def median_ms(fn, repeat: int = 5) -> float:
    number = max(1, int(0.2 / max(timeit.timeit(fn, number=1), 1e-6)))
    return 1e3 * float(np.median(timeit.repeat(fn, number=number, repeat=repeat))) / number


def main() -> None:
    rng = np.random.default_rng(0)
    print(f"{'|Θ|':>4} {'subsets':>9} {'weights ms':>11} {'cautious ms':>12} {'dempster ms':>12}")
    for n in (4, 8, 12, 16, 20):
        a, b = random_nondogmatic(n, 16, rng), random_nondogmatic(n, 16, rng)
        t_w = median_ms(lambda a=a: canonical_weights(a))
        t_c = median_ms(lambda a=a, b=b: cautious(a, b))
        t_d = median_ms(lambda a=a, b=b: dempster(a, b))
        print(f"{n:>4} {2**n:>9} {t_w:>11.3f} {t_c:>12.3f} {t_d:>12.3f}")


if __name__ == "__main__":
    main()
