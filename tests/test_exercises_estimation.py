"""Exercises, sheets and prose claims of the chapters *Estimating the level* and *Beyond the paper*.

The exercises are "estimating.*" and "beyond.*", their sheets
notebooks/NN_estimating_level.ipynb and notebooks/NN_beyond_the_paper.ipynb; the claims
are those the two chapters' prose makes.

Every solution is accepted, every listed mistake is rejected with its own hint, a plainly
wrong answer gets the generic hint, and the solutions agree with the paper's numbers where
the paper gives them. Each sheet runs as stored, and with the solutions filled into its
answer cells every check says right. The chapters execute, and the statements their prose
makes in words (not in glued numbers) hold for the numbers they glue.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import executed_chapter, glued

from answer_key import solution
from dstoolkit.teaching import exercises

ROOT = Path(__file__).resolve().parents[1]
IDS = {
    "estimating.": [
        "estimating.bias",
        "estimating.eq43-code",
        "estimating.first-level",
        "estimating.improvement",
        "estimating.improvement-choice",
        "estimating.outlier-orders",
    ],
    "beyond.": [
        "beyond.failures",
        "beyond.failures-choice",
        "beyond.kalman-sigma",
        "beyond.nassreddine-correction",
        "beyond.offset-ratio",
        "beyond.products",
        "beyond.sigma-code",
        "beyond.start-error",
    ],
}
ALL_IDS = IDS["estimating."] + IDS["beyond."]


@pytest.mark.parametrize("prefix", list(IDS))
def test_the_exercises_are_registered(prefix: str) -> None:
    assert exercises(prefix) == IDS[prefix]


def test_solutions_agree_with_the_papers_numbers() -> None:
    # eq. 32 with the paper's z_1 = 1023.3 Hz, n_1 = 27, c = 347.359 m/s
    assert solution("estimating.first-level") == pytest.approx(27 * 347.359 / 2046.6, abs=1e-6)
    # a reading 6.9 Hz high makes the level short by L·6.9/(f_27 + 6.9)
    f27 = 27 * 347.359 / 9.2
    assert solution("estimating.bias") == pytest.approx(-4.6 * 6.9 / (f27 + 6.9), rel=1e-6)
    # orders 8..18 at 1.3 m, 27 °C: 0.238 m is more than two orders at every step
    assert 2.0 < solution("estimating.outlier-orders") < 2.5
    # the paper's filter improves on the direct measurement when the orders are right
    assert solution("estimating.improvement") > 1.5
    assert solution("beyond.start-error") == pytest.approx(6.9, abs=1e-9)
    assert solution("beyond.kalman-sigma") == pytest.approx(np.sqrt(1.5) * 1.23, rel=1e-3)
    assert solution("beyond.products") == 4**10
    assert 0.0 < solution("beyond.failures") < 1.0
    assert solution("beyond.offset-ratio") > 0.5  # the fit's n_1 comes out one too high


# -- the chapters: they execute, and the claims their prose makes hold for their numbers --


@pytest.fixture(scope="module")
def estimating() -> dict[str, object]:
    return glued(executed_chapter("estimating_level"))


@pytest.fixture(scope="module")
def beyond() -> dict[str, object]:
    return glued(executed_chapter("beyond_the_paper"))


METHODS = ("dependent_evidence", "nassreddine", "direct", "kalman", "particle")


@pytest.mark.slow
def test_estimating_level_prose_matches_its_numbers(estimating) -> None:
    g = estimating
    # Fig. 10: the paper's filter starts |E[w]| off and walks a fraction of a hertz a step
    assert g["el_dep_first"] > 3 and 0 < g["el_dep_walk"] < 1
    assert g["el_nas_first"] < g["el_dep_first"] and g["el_dep_last"] < g["el_dep_first"]
    # Fig. 11: eq. 43 wrong most of the time with i.i.d. w; the waveform run far better
    assert g["el_wrong"] > 0.5 and g["el_l_direct"] > 0.1
    assert g["el_w_scatter"] < 0.25 * g["el_w_bias"] and g["el_w_wrong"] < 0.2
    assert g["el_wl_direct"] < 0.2 * g["el_l_direct"]
    for m, paper in (("direct", "el_paper46_direct"), ("dependent_evidence", "el_paper46_dep")):
        assert 1 / 3 < g[f"el_wl_{m}"] / g[paper] < 3, m  # "the size of the paper's numbers"
    # 1.: the wrong-order fraction and every method's error grow to ~1 m at 9.6 m
    wrong = [
        g[f"el_wrong_{k}"] for k in ("13", "21", "26", "36", "46", "56", "66", "76", "86", "96")
    ]
    assert wrong == sorted(wrong) and wrong[-1] > 0.9 and wrong[0] < 0.1
    assert g["el_freq96_min"] > 0.5 > g["el_paper_96_direct"]
    # 2.: waveform level: the paper's magnitudes (within a factor 3), our direct smaller
    for lv in ("46", "96"):
        for m in ("dependent_evidence", "direct"):
            assert 1 / 3 < g[f"el_wave_{lv}_{m}"] / g[f"el_paper_{lv}_{m}"] < 3, (lv, m)
        assert g[f"el_wave_{lv}_direct"] < g[f"el_paper_{lv}_direct"]
    # 3.: true orders: the paper's filter beats direct, every rival beats it
    assert g["el_ratio_46"] > 1.5 and g["el_ratio_96"] > 1.5
    for m in ("nassreddine", "kalman", "particle"):
        assert g[f"el_true_46_{m}"] < g["el_true_46_dependent_evidence"], m
    assert g["el_var_46_mean_start"] < 0.5 * g["el_var_46_paper"]
    assert g["el_var_96_mean_start"] < 0.5 * g["el_var_96_paper"]
    assert g["el_var_46_nas_restart"] <= g["el_var_46_nas"]  # "restarting is not the handicap"
    # 4.: the 1.3 m outlier: more than two orders off at every step; ours millimetres
    assert g["el_units_13"] > 2 and g["el_freq_13_direct"] < 0.02 > g["el_wave_13_direct"]
    # 5.: run times: milliseconds against the paper's seconds
    assert g["el_ms_dep"] < 1e3 * g["el_paper_s_hi"] / 100


@pytest.mark.slow
def test_beyond_the_paper_prose_matches_its_numbers(beyond) -> None:
    g = beyond
    # the start: z_1 costs ~|E[w]| at step 1, corrected start much better on average
    assert g["bp_z1_first"] > 3 * g["bp_mean_first"] and g["bp_mean_mean"] < g["bp_z1_mean"]
    assert 0 < g["bp_walk"] < g["bp_pred_half"]
    # too tight: the bounded-error filter fails, the evidential filters do not degrade much
    assert g["bp_fail_05"] > 0.5 and g["bp_fail_075"] > 0 and g["bp_fail_1"] == 0
    for m in ("dependent_evidence", "nassreddine"):
        assert g[f"bp_s05_{m}"] < 2 * g[f"bp_s1_{m}"], m
    assert g["bp_s05_particle"] > g["bp_s1_particle"]
    # too wide: pessimistic; the Kalman filter does not care about a common scale
    for m in ("dependent_evidence", "nassreddine", "bounded_error"):
        assert g[f"bp_s3_{m}"] > g[f"bp_s1_{m}"], m
    assert g["bp_width_ratio"] > 2 and g["bp_kalman_spread"] < 1e-9
    # a wrong mode: every method about δ off
    assert 2 < g["bp_shift3_min"] and g["bp_shift3_max"] < 5
    # n_k: the fit right at the frequency level; at the waveform level b > f_F/2 at 9.6 m
    assert g["bp_f_fit_wrong_max"] == 0 and g["bp_f_wrong_eq43_96"] > 0.9
    assert g["bp_offset_96"] > g["bp_half_ff_96"] and g["bp_w_wrong_fit_96"] == 1
    assert g["bp_w_fit_dependent_evidence_96"] > g["bp_w_true_dependent_evidence_96"]
    assert max(g["bp_w_slope_max_mm"], g["bp_f_slope_max_mm"]) < 10
    # Kalman and particle: better than both evidential filters, Kalman by far the cheapest
    for m in ("kalman", "particle"):
        for e in ("dependent_evidence", "nassreddine"):
            assert g[f"bp_t3_46_{m}"] < g[f"bp_t3_46_{e}"], (m, e)
    assert g["bp_ms_kalman"] < min(
        g[f"bp_ms_{m}"] for m in ("particle", "dependent_evidence", "nassreddine")
    )
    # the Kalman filter's cost and accuracy are said as glued ratios
    assert g["bp_kalman_cheaper"] == pytest.approx(
        g["bp_ms_dependent_evidence"] / g["bp_ms_kalman"], rel=1e-12
    )
    assert g["bp_kalman_cheaper"] > 1 and g["bp_kalman_better_96"] > 1
    # Nassreddine's filter: one step grows its evidence, the cap cuts it back; it beats
    # the paper's filter as the paper starts it but not with the corrected start
    assert g["bp_nas_pred"] > g["bp_nas_start"] and g["bp_nas_post"] > g["bp_nas_cap"]
    assert 0 < g["bp_nas_k"] < 1 and 0 < g["bp_nas_merged"] <= 1
    assert g["bp_nv_paper_mean"] < g["bp_nv_nas"] < g["bp_nv_paper"]
    assert g["bp_nv_nas_cap128"] < g["bp_nv_nas"] < g["bp_nv_nas_cap8"]
    # the solution's hand arithmetic (default rel 1e-6: the glue is the same sums in floats)
    assert g["bp_ex_nas_k"] == pytest.approx(0.18) and g["bp_ex_nas_est"] == pytest.approx(
        1.715 / 0.82
    )
    # the 2-D example: (p+1)^(5n) products; p = 3 far slower per step than p = 2
    assert g["bp_products_3"] == 4**10 and g["bp_products_gauge"] == 4**5
    assert g["bp_step_s_p3"] > 10 * g["bp_step_ms_p2"] / 1e3
    assert g["bp_lv_best"] in ("Kalman", "particle")
    assert (
        max(
            g[f"bp_lv_rms_{m}"]
            for m in ("dependent_evidence", "nassreddine", "bounded_error", "kalman", "particle")
        )
        < 0.1
    )
