"""Bounded work: a memory budget set in one place, limits on loops, one filter contract."""

from __future__ import annotations

import inspect
import time

import numpy as np
import pytest

from dstoolkit.errors import (
    EvidenceError,
    InvalidInputError,
    MemoryBudgetError,
    WorkLimitError,
)
from dstoolkit.evidence import (
    DEFAULT_MEMORY_BUDGET,
    Boxes,
    IntervalEvidence,
    _clustering,
    dempster,
    memory_budget,
    set_memory_budget,
)
from dstoolkit.evidence.boxes import cluster_boxes
from dstoolkit.filters import (
    BatchResult,
    BoundedErrorFilter,
    BoundedNoise,
    DependentEvidenceFilter,
    Filter,
    FilterResult,
    KalmanFilter,
    NassreddineFilter,
    ParticleFilter,
    random_walk,
)
from dstoolkit.gauge import gauge_state_space_model, simulate_gauge

FILTERS = [
    DependentEvidenceFilter(),
    NassreddineFilter(),
    NassreddineFilter(restart=True),
    BoundedErrorFilter(),
    KalmanFilter(),
    ParticleFilter(n_particles=100),
]
IDS = [f.name for f in FILTERS]


@pytest.fixture
def budget():
    yield
    set_memory_budget(None)


# -- the Filter interface and the shared base ---------------------------------------------
@pytest.mark.parametrize("flt", FILTERS, ids=IDS)
def test_every_filter_has_the_interface_with_its_signatures(flt):
    assert isinstance(flt, Filter)
    assert isinstance(flt.name, str) and flt.name.isidentifier()
    for method in ("initialize", "step", "run", "run_batch"):
        want = list(inspect.signature(getattr(Filter, method)).parameters.values())[1:]
        have = list(inspect.signature(getattr(flt, method)).parameters.values())
        assert [(p.name, p.default) for p in have] == [(p.name, p.default) for p in want], method
    assert type(flt).run is Filter.run and type(flt).run_batch is Filter.run_batch


@pytest.mark.parametrize("flt", FILTERS, ids=IDS)
def test_run_and_run_batch_return_what_the_protocol_says(flt):
    model = gauge_state_space_model()
    seq = simulate_gauge(level_m=4.6, temperature_c=26.5, runs=2, seed=1)
    result = flt.run(model, seq.readings[0], seq.inputs[0])
    batch = flt.run_batch(model, seq.readings, seq.inputs)
    assert result.estimates.shape == (seq.readings.shape[1], 1)
    assert isinstance(result, FilterResult) and isinstance(batch, BatchResult)
    assert batch.estimates.shape == (2, seq.readings.shape[1], 1)
    assert np.all(np.isfinite(batch.estimates))


# -- the memory budget ----------------------------------------------------------------------
def test_the_budget_is_set_in_one_place(budget, monkeypatch):
    assert memory_budget() == DEFAULT_MEMORY_BUDGET == 2**30
    monkeypatch.setenv("DSTOOLKIT_MEMORY_BUDGET", "512M")
    assert memory_budget() == 2**29
    set_memory_budget(2**25)
    assert memory_budget() == 2**25
    monkeypatch.setenv("DSTOOLKIT_MEMORY_BUDGET", "lots")
    set_memory_budget(None)
    with pytest.raises(InvalidInputError, match="not a size"):
        memory_budget()
    with pytest.raises(InvalidInputError, match="at least 1 MiB"):
        set_memory_budget(10)


def test_dempster_of_huge_products_is_refused_with_the_size():
    n = 4500
    lo = np.arange(n, dtype=float)
    e = IntervalEvidence(lo, lo + 0.5, np.full(n, 1.0 / n))
    start = time.perf_counter()
    with pytest.raises(MemoryBudgetError, match=r"4500 by 4500 .* needs about 3\.\d+ GiB"):
        dempster(e, e)
    assert time.perf_counter() - start < 2.0


def test_the_papers_filter_cuts_a_large_batch_into_chunks_that_fit(monkeypatch):
    flt = DependentEvidenceFilter(p=20)
    model = gauge_state_space_model()
    per_run = flt._bytes_per_run(model, 0)
    assert 64 * per_run > 2**30  # the old fixed batch of 64 runs would not fit
    seen = []

    def fake_run_arrays(self, maps, noise, z, inputs, run_ids=None, bounds=True):
        seen.append(z.shape[0])
        est = np.ones((z.shape[0], z.shape[1], 1))
        return est, est, est, {}

    monkeypatch.setattr(DependentEvidenceFilter, "_run_arrays", fake_run_arrays)
    seq = simulate_gauge(level_m=4.6, temperature_c=26.5, runs=64, seed=1)
    flt.run_batch(model, seq.readings, seq.inputs)
    assert sum(seen) == 64 and max(seen) * per_run <= memory_budget() / 4


def test_a_run_that_cannot_fit_is_refused_before_it_allocates(budget):
    model = random_walk(0.1, 0.5)
    z = np.zeros(100_000)
    start = time.perf_counter()
    with pytest.raises(MemoryBudgetError, match="particle filter.*GiB"):
        ParticleFilter(n_particles=1000).run(model, z)
    set_memory_budget(2**20)
    with pytest.raises(MemoryBudgetError, match="dependent-evidence"):
        DependentEvidenceFilter(p=20).run(model, z[:3])
    assert time.perf_counter() - start < 5.0


# -- loops that could run away --------------------------------------------------------------
def test_nan_in_the_inputs_never_reaches_the_clustering():
    model = gauge_state_space_model()
    seq = simulate_gauge(level_m=4.6, temperature_c=26.5, seed=1)
    inputs = seq.inputs.astype(float)
    inputs[3] = np.nan
    start = time.perf_counter()
    with pytest.raises(EvidenceError, match="transition 3 is not a finite number"):
        NassreddineFilter().run(model, seq.readings, inputs)
    assert time.perf_counter() - start < 2.0


def test_cluster_boxes_refuses_nan_and_stops_at_its_round_limit(monkeypatch):
    lo = np.arange(40.0).reshape(1, 40, 1)
    boxes = Boxes(lo, lo + 1.0, np.full((1, 40), 1 / 40))
    with pytest.raises(EvidenceError, match="finite"):
        cluster_boxes(Boxes(lo * np.nan, lo, boxes.mass), 4)
    monkeypatch.setattr(_clustering, "MAX_CLUSTER_ROUNDS", 1)
    with pytest.raises(WorkLimitError, match="in 1 rounds"):
        cluster_boxes(boxes, 2)


def test_noise_bounds_that_overflow_are_refused():
    with pytest.raises(EvidenceError, match="overflows"):
        BoundedNoise(-1e308, 0.0, 1e308)
