"""Exercises of the chapters on random sets ("random.*") and the recursive filter
("filter.*"), their sheets notebooks/05_random_sets.ipynb and 06_recursive_filter.ipynb,
and the two chapters themselves.

Every solution is accepted, a plainly wrong answer is rejected with the exercise's hint,
every listed mistake gets its own hint, and the solutions agree with what the chapters
and the paper say (eq. 16, Prop. 2, eq. 14, eq. 20, (p + 1)^k focal elements, E[w] = −6.9
Hz, K = (1 − ε)^3 from the paper's start, R < 0 with m(D) = m2). The sheets are stored
without outputs, run as shipped ("not answered yet"), and say right with the solutions
filled in. The chapters execute and their prose claims hold for the numbers they glue.
"""

from __future__ import annotations

import re
from pathlib import Path

import jupytext
import nbformat
import numpy as np
import pytest
from nbclient import NotebookClient

from dstoolkit.exercises import REGISTRY, check, exercises, solution

ROOT = Path(__file__).resolve().parents[1]
RANDOM_IDS = ["random.evaluations", "random.expectation", "random.merge", "random.monotone",
              "random.product", "random.square"]
FILTER_IDS = ["filter.conflict-start", "filter.counts", "filter.mass-rule",
              "filter.mean-corrected", "filter.prediction"]
IDS = RANDOM_IDS + FILTER_IDS
SHEETS = {"05_random_sets": RANDOM_IDS, "06_recursive_filter": FILTER_IDS}
CHECK = re.compile(r'check\("([a-z]+\.[a-z0-9-]+)",\s*(\w+)\)')


def _wrong(value: object) -> object:
    """An answer that is plainly wrong: another rule for strings, else every number 10 %
    (and at least 1) off."""
    if isinstance(value, str):
        return "min" if value != "min" else "m2"
    arr = np.asarray(value, dtype=float)
    return arr + np.maximum(0.1 * np.abs(arr), 1.0)


def test_the_exercises_are_registered() -> None:
    assert exercises("random.") == RANDOM_IDS
    assert exercises("filter.") == FILTER_IDS


@pytest.mark.parametrize("exercise_id", IDS)
def test_the_solution_is_accepted(exercise_id: str) -> None:
    assert check(exercise_id, solution(exercise_id)).correct


@pytest.mark.parametrize("exercise_id", IDS)
def test_a_wrong_answer_is_rejected_with_the_hint(exercise_id: str) -> None:
    feedback = check(exercise_id, _wrong(solution(exercise_id)))
    assert not feedback.correct
    assert REGISTRY[exercise_id].hint in feedback.message


@pytest.mark.parametrize(
    ("exercise_id", "index"),
    [(e, i) for e in IDS for i in range(len(REGISTRY[e].mistakes))],
)
def test_each_common_mistake_gets_its_own_hint(exercise_id: str, index: int) -> None:
    wrong, why = REGISTRY[exercise_id].mistakes[index]
    feedback = check(exercise_id, wrong())
    assert not feedback.correct and why in feedback.message


def test_not_answered_yet() -> None:
    assert "not answered yet" in check("filter.counts", ...).message


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
    assert solution("filter.conflict-start") == pytest.approx(0.9 ** 3)
    assert solution("filter.mass-rule") == "m2"


# -- the sheets ---------------------------------------------------------------------------


def _sheet(name: str) -> nbformat.NotebookNode:
    return nbformat.read(ROOT / "notebooks" / f"{name}.ipynb", as_version=4)


def _execute(nb: nbformat.NotebookNode) -> nbformat.NotebookNode:
    NotebookClient(nb, timeout=180, kernel_name="python3",
                   resources={"metadata": {"path": str(ROOT / "notebooks")}}).execute()
    return nb


def _shown(nb: nbformat.NotebookNode) -> dict[str, str]:
    """Exercise id → everything its check cell printed or displayed."""
    out = {}
    for cell in nb.cells:
        match = CHECK.search(cell.source) if cell.cell_type == "code" else None
        if match:
            out[match.group(1)] = "".join(
                o.get("text", "") + str(o.get("data", {}).get("text/plain", ""))
                for o in cell.outputs)
    return out


@pytest.mark.parametrize("name", list(SHEETS))
def test_the_sheet_is_stored_without_outputs_and_checks_its_exercises(name: str) -> None:
    nb = _sheet(name)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert all(not c.outputs and c.execution_count is None for c in code)
    assert all(len(c.source.splitlines()) <= 15 for c in code)
    checked = [m[0] for c in code for m in CHECK.findall(c.source)]
    assert sorted(checked) == SHEETS[name]
    answers = [c for c in code if c.source.lstrip().split("=")[-1].strip().startswith("...")]
    assert len(answers) >= len(SHEETS[name]), "every exercise needs an answer cell with ..."


@pytest.mark.slow
@pytest.mark.parametrize("name", list(SHEETS))
def test_the_sheet_runs_as_shipped_and_says_right_with_the_solutions(name: str) -> None:
    """One execution: each check cell first checks the shipped answer ("not answered
    yet"), then the solution computed by dstoolkit ("right"); the explorers display."""
    nb = _sheet(name)
    for cell in nb.cells:
        match = CHECK.search(cell.source) if cell.cell_type == "code" else None
        if match:
            eid, var = match.groups()
            cell.source = (f"from dstoolkit.exercises import solution\n"
                           f"print('SHIPPED', check({eid!r}, {var}).message)\n"
                           f"{var} = solution({eid!r})\n{cell.source}")
    nb = _execute(nb)
    shown = _shown(nb)
    assert sorted(shown) == SHEETS[name]
    for eid, text in shown.items():
        assert "not answered yet" in text, (eid, text)
        assert f"✔ {eid}: right" in text, (eid, text)
    widgets = [o for c in nb.cells if "explorer(" in c.source or "filter_widget(" in c.source
               for o in c.outputs
               if "application/vnd.jupyter.widget-view+json" in o.get("data", {})]
    assert widgets, "the explorer cells displayed no widget"


# -- the chapters -------------------------------------------------------------------------


def _glued(nb: nbformat.NotebookNode) -> dict[str, object]:
    out = {}
    for cell in nb.cells:
        for o in cell.get("outputs", []):
            name = o.get("metadata", {}).get("scrapbook", {}).get("name")
            if name:
                text = o["data"]["application/papermill.record/text/plain"]
                try:
                    out[name] = float(text)
                except ValueError:
                    out[name] = text.strip("'\"")
    return out


def _run_chapter(name: str) -> dict[str, object]:
    nb = jupytext.read(ROOT / "book" / f"{name}.md")
    NotebookClient(nb, timeout=300, kernel_name="python3",
                   resources={"metadata": {"path": str(ROOT / "book")}}).execute()
    return _glued(nb)


@pytest.mark.slow
def test_the_random_sets_chapter_prose_matches_its_numbers() -> None:
    g = _run_chapter("random_sets")
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
    g = _run_chapter("recursive_filter")
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
