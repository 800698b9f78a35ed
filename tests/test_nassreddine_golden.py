"""Nassreddine's filter gives the numbers it gave before its clustering was sped up.

``tests/data/nassreddine_golden.npz`` holds, for settings that make the focal-element cap
(Denœux's clustering, :func:`dstoolkit.filters.NassreddineFilter` with ``max_focal``) work
hard, the estimates, bounds and merged mass of

- the two-dimensional Lotka–Volterra example (the clustering's sort dimension alternates),
  three runs, each filtered alone (``run``);
- a batch of five gauge runs at 4.6 m (``run_batch``: runs of a batch need different
  numbers of clustering rounds, so finished runs ride along while others still merge).

The gauge cases with default settings are in ``tests/test_filter_golden.py``. The file was
written by this module, run as a script, with the code from before the speed work; the
tests check today's code against it to 1e-9. Regenerate it only on purpose:
``python tests/test_nassreddine_golden.py --force``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from dstoolkit.filters import NassreddineFilter, simulate_lotka_volterra
from dstoolkit.gauge import gauge_state_space_model, simulate_gauge

TARGET = Path(__file__).resolve().parent / "data" / "nassreddine_golden.npz"

#: Settings stored, by key: the default cap and two tighter ones (more rounds per step).
SETTINGS: dict[str, NassreddineFilter] = {
    "default": NassreddineFilter(on_conflict="reset"),
    "cap8": NassreddineFilter(max_focal=8, on_conflict="reset"),
    "p2_cap5": NassreddineFilter(p=2, max_focal=5, on_conflict="reset"),
}


def computed() -> dict[str, np.ndarray]:
    """Today's arrays, by name ``<setting>/<case>/<field>``."""
    lv_model, _, lv_z = simulate_lotka_volterra(steps=30, runs=3, seed=11)
    gauge = simulate_gauge(4.6, 26.5, runs=5, seed=2)
    out: dict[str, np.ndarray] = {}
    for name, flt in SETTINGS.items():
        for r in range(lv_z.shape[0]):
            result = flt.run(lv_model, lv_z[r])
            out[f"{name}/lotka_volterra_{r}/estimates"] = result.estimates
            out[f"{name}/lotka_volterra_{r}/lower"] = result.lower
            out[f"{name}/lotka_volterra_{r}/upper"] = result.upper
            out[f"{name}/lotka_volterra_{r}/merged_mass"] = result.diagnostics["merged_mass"]
        out[f"{name}/gauge_batch/estimates"] = flt.run_batch(
            gauge_state_space_model(), gauge.readings, gauge.inputs
        ).estimates
    return out


STORED = dict(np.load(TARGET)) if TARGET.exists() else {}


@pytest.fixture(scope="module")
def today() -> dict[str, np.ndarray]:
    return computed()


def test_every_case_is_stored(today):
    assert len(STORED) == len(SETTINGS) * (3 * 4 + 1)
    assert set(today) == set(STORED)


@pytest.mark.parametrize("name", SETTINGS)
def test_estimates_bounds_and_merged_mass_are_unchanged(name, today):
    keys = [key for key in STORED if key.startswith(f"{name}/")]
    assert keys
    for key in keys:
        np.testing.assert_allclose(today[key], STORED[key], rtol=0, atol=1e-9, err_msg=key)


def test_the_cap_merged_mass_in_the_stored_cases():
    """The stored cases exercise the clustering: some steps carry merged mass."""
    for name in SETTINGS:
        assert STORED[f"{name}/lotka_volterra_0/merged_mass"].max() > 0, name


if __name__ == "__main__":
    if TARGET.exists() and "--force" not in sys.argv[1:]:
        sys.exit(f"{TARGET} exists; pass --force to overwrite the reference data")
    data = computed()
    np.savez_compressed(TARGET, **data)
    print(f"wrote {len(data)} arrays to {TARGET} ({TARGET.stat().st_size:,} bytes)")


@pytest.mark.extras  # numba, the extra "speed"
@pytest.mark.parametrize("name", SETTINGS)
def test_the_compiled_kernels_give_the_same_numbers_bit_for_bit(name, today):
    """kernel="numba" gives exactly the numpy path's numbers.

    The compiled kernel merges equal boxes and clusters; single runs (2-D, the sort
    dimension alternating) and a batch alike.
    """
    import dataclasses

    from dstoolkit.filters import _nassreddine

    flt = dataclasses.replace(SETTINGS[name], kernel="numba")
    assert flt._kernels()[0] is not _nassreddine.contracted_posterior  # the compiled ones
    lv_model, _, lv_z = simulate_lotka_volterra(steps=30, runs=3, seed=11)
    for r in range(lv_z.shape[0]):
        result = flt.run(lv_model, lv_z[r])
        for field in ("estimates", "lower", "upper"):
            np.testing.assert_array_equal(
                getattr(result, field), today[f"{name}/lotka_volterra_{r}/{field}"]
            )
        np.testing.assert_array_equal(
            result.diagnostics["merged_mass"], today[f"{name}/lotka_volterra_{r}/merged_mass"]
        )
    gauge = simulate_gauge(4.6, 26.5, runs=5, seed=2)
    np.testing.assert_array_equal(
        flt.run_batch(gauge_state_space_model(), gauge.readings, gauge.inputs).estimates,
        today[f"{name}/gauge_batch/estimates"],
    )
