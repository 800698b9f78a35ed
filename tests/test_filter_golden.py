"""The filters' estimates on the gauge cases are those stored before the speed work.

``tests/data/filter_golden.npz`` holds, for every Table 3 case (level, temperature) at
seed 0, with the true orders and with eq. 43's orders, the estimates, lower and upper
bounds of

- the paper's filter (p = 3 with the default Θ; p = 2 with the Θ of Tables 1–2 and
  m(D) = m1), both keeping the prediction at total conflict;
- the Kalman filter;
- Nassreddine's filter (default settings and the restart variant);

and the paper's filter (p = 1) on the Lotka–Volterra example (two states, vertex method).
The filters run on the inputs stored beside the results (readings and orders), so the
comparison does not depend on how this CPU rounds the simulation; the simulation is
compared with the stored inputs on its own, and the same comparison runs on inputs moved
by a few ulps (the stand-in for another CPU). The tests check that today's code still
gives these numbers to 1e-9 Hz, so that speed work cannot change a result unnoticed.
Written by this module, run as a script; regenerate it only on purpose, with the code
that lands: ``python tests/test_filter_golden.py --force``.
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
from golden_inputs import nudged

from dstoolkit.filters import (
    DependentEvidenceFilter,
    KalmanFilter,
    NassreddineFilter,
    lotka_volterra,
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


#: Tolerance of the filters' outputs against the stored ones, in Hz (the states are
#: 20–200 Hz). Moving every reading by ±4 ulp moves them by at most about 1e-11 Hz
#: (``test_readings_moved_by_a_few_ulps_give_the_stored_numbers``, the stand-in for
#: another CPU), so 1e-9 Hz leaves a margin of 100 and still catches any change of method.
ATOL = 1e-9

#: Tolerance of today's simulation against the stored inputs (relative): it goes through
#: ``exp`` and ``sin``, whose last bits differ between CPUs' SIMD code; 1e-12 is a few
#: thousand ulps, far below any change of the simulation itself.
INPUT_RTOL = 1e-12


def simulated() -> dict[str, np.ndarray]:
    """Simulate the stored cases' inputs today, by name ``inputs/<case>/<field>``."""
    out: dict[str, np.ndarray] = {}
    for level, temperature in TABLE3_CASES:
        seq = simulate_gauge(level, temperature, seed=0)
        case = f"{level}m_{temperature}C"
        out[f"inputs/{case}/readings"] = seq.readings
        out[f"inputs/{case}/true"] = seq.true_inputs
        out[f"inputs/{case}/eq43"] = seq.inputs
    out["inputs/lotka_volterra/readings"] = simulate_lotka_volterra(steps=25, runs=3, seed=4)[2]
    return out


def cases(inputs: dict[str, np.ndarray]) -> Iterator[tuple[str, np.ndarray, np.ndarray]]:
    """(key prefix, readings, orders) of every stored gauge case."""
    for level, temperature in TABLE3_CASES:
        case = f"{level}m_{temperature}C"
        for source in ORDERS:
            yield (
                f"{case}_{source}",
                inputs[f"inputs/{case}/readings"],
                inputs[f"inputs/{case}/{source}"],
            )


def golden(
    inputs: dict[str, np.ndarray], names: Iterator[str] | None = None
) -> dict[str, np.ndarray]:
    """Run the filters on ``inputs``; every array by name ``<filter>/<case>/<field>``."""
    model = gauge_state_space_model()
    out: dict[str, np.ndarray] = {}
    wanted = set(FILTERS) | {"dependent_p1"} if names is None else set(names)
    for name, make in FILTERS.items():
        if name not in wanted:
            continue
        flt = make()
        for case, readings, orders in cases(inputs):
            result = flt.run(model, readings, orders)
            for field in ("estimates", "lower", "upper"):
                out[f"{name}/{case}/{field}"] = getattr(result, field)
    if "dependent_p1" in wanted:
        lv = DependentEvidenceFilter(p=1).run_batch(
            lotka_volterra(), inputs["inputs/lotka_volterra/readings"]
        )
        for field in ("estimates", "lower", "upper"):
            out[f"dependent_p1/lotka_volterra/{field}"] = getattr(lv, field)
    return out


STORED = dict(np.load(TARGET)) if TARGET.exists() else {}
INPUTS = {key: value for key, value in STORED.items() if key.startswith("inputs/")}
NOW: dict[str, np.ndarray] = {}


def now(name: str) -> dict[str, np.ndarray]:
    """Today's arrays of one filter on the stored inputs (computed once per session)."""
    if not NOW:
        NOW.update(golden(INPUTS))
    return {key: value for key, value in NOW.items() if key.startswith(f"{name}/")}


def assert_like_stored(arrays: dict[str, np.ndarray], name: str) -> None:
    assert arrays and set(arrays) == {key for key in STORED if key.startswith(f"{name}/")}
    for key, value in arrays.items():
        np.testing.assert_allclose(value, STORED[key], rtol=0, atol=ATOL, err_msg=key)


def test_every_case_is_stored():
    outputs = 3 * (len(FILTERS) * len(TABLE3_CASES) * len(ORDERS) + 1)
    assert len(STORED) == outputs + 3 * len(TABLE3_CASES) + 1


def test_the_simulation_gives_the_stored_inputs():
    for key, value in simulated().items():
        np.testing.assert_allclose(value, STORED[key], rtol=INPUT_RTOL, atol=0, err_msg=key)


@pytest.mark.parametrize("name", [*FILTERS, "dependent_p1"])
def test_estimates_and_bounds_are_unchanged(name):
    assert_like_stored(now(name), name)


@pytest.mark.slow
@pytest.mark.parametrize("name", [*FILTERS, "dependent_p1"])
def test_readings_moved_by_a_few_ulps_give_the_stored_numbers(name):
    """Readings moved by ±4 ulp (another CPU's rounding) give the stored numbers."""
    moved = {
        key: nudged(value, seed=len(key)) if key.endswith("readings") else value
        for key, value in INPUTS.items()
    }
    assert_like_stored(golden(moved, iter([name])), name)


@pytest.mark.parametrize("name", ["dependent_p3", "dependent_p2_paper_theta"])
@pytest.mark.extras  # numba, the extra "speed"
def test_the_compiled_kernel_gives_the_stored_estimates(name):
    """kernel="numba" (extra "speed") gives the stored estimates of the paper's filter."""
    flt = dataclasses.replace(FILTERS[name](), kernel="numba")
    model = gauge_state_space_model()
    for case, readings, orders in cases(INPUTS):
        result = flt.run(model, readings, orders)
        np.testing.assert_allclose(
            result.estimates, STORED[f"{name}/{case}/estimates"], rtol=0, atol=ATOL, err_msg=case
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--force", action="store_true", help="overwrite the stored file")
    args = parser.parse_args(argv)
    if TARGET.exists() and not args.force:
        print(f"{TARGET} exists; pass --force to overwrite the reference data", file=sys.stderr)
        return 1
    inputs = simulated()
    data = {**inputs, **golden(inputs)}
    TARGET.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(TARGET, **data)
    print(f"wrote {len(data)} arrays to {TARGET} ({TARGET.stat().st_size:,} bytes)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
