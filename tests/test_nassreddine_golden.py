"""Nassreddine's filter gives the stored numbers, on every CPU.

``tests/data/nassreddine_golden.npz`` holds, for settings that make the focal-element cap
(Denœux's clustering, :func:`dstoolkit.filters.NassreddineFilter` with ``max_focal``) work
hard, the inputs and the estimates, bounds and merged mass of

- the two-dimensional Lotka–Volterra example (the clustering's sort dimension alternates),
  three runs, each filtered alone (``run``);
- a batch of five gauge runs at 4.6 m (``run_batch``: runs of a batch need different
  numbers of clustering rounds, so finished runs ride along while others still merge).

The filter runs on the stored inputs, so the comparison does not depend on how this CPU
rounds the simulations; the simulations are compared with the stored inputs on their own.
The gauge cases with default settings are in ``tests/test_filter_golden.py``.

Written by this module, run as a script: ``python tests/test_nassreddine_golden.py
--force`` (regenerate only on purpose, with the code that lands).
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest
from golden_inputs import ULPS, nudged

from dstoolkit.filters import NassreddineFilter, lotka_volterra, simulate_lotka_volterra
from dstoolkit.gauge import gauge_state_space_model, simulate_gauge

TARGET = Path(__file__).resolve().parent / "data" / "nassreddine_golden.npz"

#: Settings stored, by key: the default cap and two tighter ones (more rounds per step).
SETTINGS: dict[str, NassreddineFilter] = {
    "default": NassreddineFilter(on_conflict="reset"),
    "cap8": NassreddineFilter(max_focal=8, on_conflict="reset"),
    "p2_cap5": NassreddineFilter(p=2, max_focal=5, on_conflict="reset"),
}

#: Tolerance of the filter's outputs against the stored ones (absolute; the states are of
#: order 1–10). Moving every input by ±4 ulp moves them by at most about 3e-12 (measured
#: by ``test_inputs_moved_by_a_few_ulps_give_the_stored_numbers``, the stand-in for
#: another CPU), so 1e-9 leaves a margin of 300 and still catches any change of method.
ATOL = 1e-9

#: Tolerance of today's simulations against the stored inputs (relative): they go through
#: ``exp`` and ``sin``, whose last bits differ between CPUs' SIMD code; 1e-12 is a few
#: thousand ulps, far below any change of the simulation itself.
INPUT_RTOL = 1e-12


def simulated() -> dict[str, np.ndarray]:
    """Simulate the inputs of the stored cases today."""
    _, _, lv_z = simulate_lotka_volterra(steps=30, runs=3, seed=11)
    gauge = simulate_gauge(4.6, 26.5, runs=5, seed=2)
    return {
        "inputs/lotka_volterra/readings": lv_z,
        "inputs/gauge/readings": gauge.readings,
        "inputs/gauge/orders": gauge.inputs,
    }


def computed(inputs: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Run the filter on ``inputs``; arrays by name ``<setting>/<case>/<field>``."""
    lv_model = lotka_volterra()
    lv_z = inputs["inputs/lotka_volterra/readings"]
    out: dict[str, np.ndarray] = {}
    for name, flt in SETTINGS.items():
        for r in range(lv_z.shape[0]):
            result = flt.run(lv_model, lv_z[r])
            out[f"{name}/lotka_volterra_{r}/estimates"] = result.estimates
            out[f"{name}/lotka_volterra_{r}/lower"] = result.lower
            out[f"{name}/lotka_volterra_{r}/upper"] = result.upper
            out[f"{name}/lotka_volterra_{r}/merged_mass"] = result.diagnostics["merged_mass"]
        out[f"{name}/gauge_batch/estimates"] = flt.run_batch(
            gauge_state_space_model(),
            inputs["inputs/gauge/readings"],
            inputs["inputs/gauge/orders"],
        ).estimates
    return out


STORED = dict(np.load(TARGET)) if TARGET.exists() else {}
INPUTS = {key: value for key, value in STORED.items() if key.startswith("inputs/")}


@pytest.fixture(scope="module")
def today() -> dict[str, np.ndarray]:
    return computed(INPUTS)


def assert_like_stored(arrays: dict[str, np.ndarray], name: str) -> None:
    keys = [key for key in STORED if key.startswith(f"{name}/")]
    assert keys
    for key in keys:
        np.testing.assert_allclose(arrays[key], STORED[key], rtol=0, atol=ATOL, err_msg=key)


def test_every_case_is_stored():
    assert len(STORED) == len(SETTINGS) * (3 * 4 + 1) + 3
    assert set(computed(INPUTS)) | set(INPUTS) == set(STORED)


def test_the_simulations_give_the_stored_inputs():
    for key, value in simulated().items():
        np.testing.assert_allclose(value, STORED[key], rtol=INPUT_RTOL, atol=0, err_msg=key)


@pytest.mark.parametrize("name", SETTINGS)
def test_estimates_bounds_and_merged_mass_are_unchanged(name, today):
    assert_like_stored(today, name)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2])
def test_inputs_moved_by_a_few_ulps_give_the_stored_numbers(seed):
    """Readings moved by ±4 ulp (another CPU's rounding) give the stored numbers.

    Without the clustering's tie rule (:data:`dstoolkit.evidence.boxes.TIE_RTOL` = 0) the
    estimates move by up to 0.4 here: merges are picked by comparing values that tie in
    exact arithmetic.
    """
    moved = {
        key: nudged(value, seed) if "readings" in key else value for key, value in INPUTS.items()
    }
    assert ULPS == 4
    arrays = computed(moved)
    for name in SETTINGS:
        assert_like_stored(arrays, name)


def test_a_batch_gives_each_run_what_it_gives_alone_in_any_order(today):
    """The gauge batch in reverse order and run by run gives the same estimates."""
    model, flt = gauge_state_space_model(), SETTINGS["cap8"]
    z, u = INPUTS["inputs/gauge/readings"], INPUTS["inputs/gauge/orders"]
    reverse = flt.run_batch(model, z[::-1], u[::-1]).estimates[::-1]
    # bit-identical by construction: the same code on the same runs in the same process
    np.testing.assert_array_equal(reverse, today["cap8/gauge_batch/estimates"])
    for r in range(z.shape[0]):
        np.testing.assert_array_equal(
            flt.run(model, z[r], u[r]).estimates, today["cap8/gauge_batch/estimates"][r]
        )


def test_the_cap_merged_mass_in_the_stored_cases():
    """The stored cases exercise the clustering: some steps carry merged mass."""
    for name in SETTINGS:
        assert STORED[f"{name}/lotka_volterra_0/merged_mass"].max() > 0, name


@pytest.mark.extras  # numba, the extra "speed"
@pytest.mark.parametrize("name", SETTINGS)
def test_the_compiled_kernels_give_the_same_numbers_bit_for_bit(name, today):
    """kernel="numba" gives exactly the numpy path's numbers (the same tie rule).

    The compiled kernel merges equal boxes and clusters; single runs (2-D, the sort
    dimension alternating) and a batch alike.
    """
    from dstoolkit.filters import _nassreddine

    flt = dataclasses.replace(SETTINGS[name], kernel="numba")
    assert flt._kernels()[0] is not _nassreddine.contracted_posterior  # the compiled ones
    lv_model = lotka_volterra()
    lv_z = INPUTS["inputs/lotka_volterra/readings"]
    for r in range(lv_z.shape[0]):
        result = flt.run(lv_model, lv_z[r])
        for field in ("estimates", "lower", "upper"):
            np.testing.assert_array_equal(
                getattr(result, field), today[f"{name}/lotka_volterra_{r}/{field}"]
            )
        np.testing.assert_array_equal(
            result.diagnostics["merged_mass"], today[f"{name}/lotka_volterra_{r}/merged_mass"]
        )
    np.testing.assert_array_equal(
        flt.run_batch(
            gauge_state_space_model(),
            INPUTS["inputs/gauge/readings"],
            INPUTS["inputs/gauge/orders"],
        ).estimates,
        today[f"{name}/gauge_batch/estimates"],
    )


if __name__ == "__main__":
    if TARGET.exists() and "--force" not in sys.argv[1:]:
        sys.exit(f"{TARGET} exists; pass --force to overwrite the reference data")
    inputs = simulated()
    data = {**inputs, **computed(inputs)}
    np.savez_compressed(TARGET, **data)
    print(f"wrote {len(data)} arrays to {TARGET} ({TARGET.stat().st_size:,} bytes)")
