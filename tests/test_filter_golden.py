"""The filters' estimates on the gauge cases are those stored before the speed work.

``tests/data/filter_golden.npz`` holds, for every Table 3 case (level, temperature) at
seed 0, with the true orders and with eq. 43's orders, the estimates, lower and upper
bounds of

- the paper's filter (p = 3 with the default Θ; p = 2 with the Θ of Tables 1–2 and
  m(D) = m1), both keeping the prediction at total conflict;
- the Kalman filter;
- Nassreddine's filter (default settings and the restart variant);

and the paper's filter (p = 1) on the Lotka–Volterra example (two states, vertex method).
The tests check that today's code still gives these numbers to 1e-9 Hz, so that speed
work cannot change a result unnoticed. The file was written by this module (run as a
script) before the speed work on the filters; regenerate it only on purpose:
``python tests/test_filter_golden.py --force``.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from dstoolkit.filters import (
    DependentEvidenceFilter,
    KalmanFilter,
    NassreddineFilter,
    simulate_lotka_volterra,
)
from dstoolkit.gauge import PAPER_THETA, gauge_state_space_model, simulate_gauge
from dstoolkit.studies import TABLE3_CASES

TARGET = Path(__file__).resolve().parent / "data" / "filter_golden.npz"

#: Filters stored, by key: a factory each.
FILTERS: dict[str, Callable[[], Any]] = {
    "dependent_p3": lambda: DependentEvidenceFilter(p=3, on_conflict="predict"),
    "dependent_p2_paper_theta": lambda: DependentEvidenceFilter(
        p=2, theta=PAPER_THETA, mass_rule="m1", on_conflict="predict"
    ),
    "kalman": KalmanFilter,
    "nassreddine": lambda: NassreddineFilter(on_conflict="reset"),
    "nassreddine_restart": lambda: NassreddineFilter(restart=True, on_conflict="reset"),
}
ORDERS = ("true", "eq43")


def cases() -> Iterator[tuple[str, Any, np.ndarray]]:
    """(key prefix, gauge sequence, orders) of every stored gauge case."""
    for level, temperature in TABLE3_CASES:
        seq = simulate_gauge(level, temperature, seed=0)
        for source in ORDERS:
            orders = seq.true_inputs if source == "true" else seq.inputs
            yield f"{level}m_{temperature}C_{source}", seq, orders


def golden() -> dict[str, np.ndarray]:
    """Every stored array, by name ``<filter>/<case>/<field>``."""
    model = gauge_state_space_model()
    out: dict[str, np.ndarray] = {}
    for name, make in FILTERS.items():
        flt = make()
        for case, seq, orders in cases():
            result = flt.run(model, seq.readings, orders)
            for field in ("estimates", "lower", "upper"):
                out[f"{name}/{case}/{field}"] = getattr(result, field)
    lv_model, _, z = simulate_lotka_volterra(steps=25, runs=3, seed=4)
    lv = DependentEvidenceFilter(p=1).run_batch(lv_model, z)
    for field in ("estimates", "lower", "upper"):
        out[f"dependent_p1/lotka_volterra/{field}"] = getattr(lv, field)
    return out


STORED = dict(np.load(TARGET)) if TARGET.exists() else {}
NOW: dict[str, np.ndarray] = {}


def now(name: str) -> dict[str, np.ndarray]:
    """Today's arrays of one filter (computed once per session)."""
    if not NOW:
        NOW.update(golden())
    return {key: value for key, value in NOW.items() if key.startswith(f"{name}/")}


def test_every_case_is_stored():
    assert len(STORED) == 3 * (len(FILTERS) * len(TABLE3_CASES) * len(ORDERS) + 1)


@pytest.mark.parametrize("name", [*FILTERS, "dependent_p1"])
def test_estimates_and_bounds_are_unchanged(name):
    arrays = now(name)
    assert arrays and set(arrays) == {key for key in STORED if key.startswith(f"{name}/")}
    for key, value in arrays.items():
        np.testing.assert_allclose(value, STORED[key], rtol=0, atol=1e-9, err_msg=key)


@pytest.mark.parametrize("name", ["dependent_p3", "dependent_p2_paper_theta"])
@pytest.mark.extras  # numba, the extra "speed"
def test_the_compiled_kernel_gives_the_stored_estimates(name):
    """kernel="numba" (extra "speed") gives the stored estimates of the paper's filter."""
    flt = dataclasses.replace(FILTERS[name](), kernel="numba")
    model = gauge_state_space_model()
    for case, seq, orders in cases():
        result = flt.run(model, seq.readings, orders)
        np.testing.assert_allclose(
            result.estimates, STORED[f"{name}/{case}/estimates"], rtol=0, atol=1e-9, err_msg=case
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--force", action="store_true", help="overwrite the stored file")
    args = parser.parse_args(argv)
    if TARGET.exists() and not args.force:
        print(f"{TARGET} exists; pass --force to overwrite the reference data", file=sys.stderr)
        return 1
    data = golden()
    TARGET.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(TARGET, **data)
    print(f"wrote {len(data)} arrays to {TARGET} ({TARGET.stat().st_size:,} bytes)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
