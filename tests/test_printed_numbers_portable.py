"""The book's key numbers print the same digits from inputs moved by a few ulps.

A number the book prints is computed when the book is built, on whatever CPU builds it.
Another CPU rounds the simulated readings differently in their last bits; these tests
rebuild the key numbers of chapters 7, 10 and 11 from readings moved by ±4 ulp
(:func:`golden_inputs.nudged`, the stand-in for that CPU) and check that they print the
same digits, at the precision the chapters print them (and one digit more).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from golden_inputs import nudged

from dstoolkit.filters import DependentEvidenceFilter
from dstoolkit.gauge import gauge_state_space_model, simulate_gauge
from dstoolkit.studies import TABLE3_CASES, noise_mismatch, run_table3, tracking_data
from dstoolkit.studies import _experiments as experiments

pytestmark = pytest.mark.slow


def test_table3_rows_print_the_same_digits(monkeypatch):
    """Chapter 10's Table 3 (frequency simulation, 30 runs): every row's mean error."""

    def printed(table) -> list[str]:
        return [f"{r.level_m} {r.method} {r.mean_abs_error_m:.5f}" for r in table.rows]

    here = printed(run_table3(runs=30, seed=0, simulation="frequency", progress=False))
    draw = experiments.frequency_readings
    calls = iter(range(100))

    def moved(*args, **kwargs):
        return [
            dataclasses.replace(b, readings=nudged(b.readings, seed=next(calls)))
            for b in draw(*args, **kwargs)
        ]

    monkeypatch.setattr(experiments, "frequency_readings", moved)
    there = printed(run_table3(runs=30, seed=0, simulation="frequency", progress=False))
    assert next(calls) == len(TABLE3_CASES)  # every case's readings were moved
    assert there == here


def test_the_filters_mean_errors_print_the_same_digits():
    """Chapter 11's test bench: every filter's mean error on 40 runs at 4.6 m."""
    data = tracking_data(level_m=4.6, temperature_c=26.5, runs=40, seed=0)
    moved = dataclasses.replace(data, readings=nudged(data.readings, seed=3))

    def printed(d) -> dict[str, str]:
        errors = noise_mismatch(d, d.state_noise, d.obs_noise).mean_errors()
        return {m: f"{e:.4f}" for m, e in errors.items()}

    assert printed(moved) == printed(data)


def test_the_recursive_filter_chapter_s_mean_errors_print_the_same_digits():
    """Chapter 7: the paper's filter on 50 sequences at 9.6 m, mean error at each step."""
    many = simulate_gauge(9.6, 23.9, runs=50, seed=1)
    true_orders = np.broadcast_to(many.true_inputs, (50, many.orders.size - 1))
    flt, model = DependentEvidenceFilter(on_conflict="predict"), gauge_state_space_model()

    def printed(readings: np.ndarray) -> list[str]:
        est = flt.run_batch(model, readings, true_orders).estimates[..., 0]
        return [f"{e:.3f}" for e in np.abs(est - many.truth[..., 0]).mean(axis=0)]

    assert printed(nudged(many.readings, seed=4)) == printed(many.readings)
