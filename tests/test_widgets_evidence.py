"""The evidence explorers of dstoolkit.teaching.

Built in a kernel, a control changed in a later cell, and the figure and the printed numbers change
(through nbclient, as the book's build executes them); plus quick in-process checks of what they
show.
"""

from __future__ import annotations

import json

import matplotlib
import pytest
from conftest import ExplorerRun, drive_explorers

from dstoolkit import combine_dependent, dempster, dependence
from dstoolkit import teaching as w
from dstoolkit.evidence import appendix_pair

matplotlib.use("Agg")

#: explorer factory → (control to change, new value)
CHANGES = {
    "mass_function_explorer": ("low", 0.1),
    "conflict_explorer": ("epsilon", 0.2),
    "dependent_combination_explorer": ("b3", 0.2),
    "noise_evidence_explorer": ("p", 6),
    "bounded_error_explorer": ("scale", 0.5),
}


@pytest.fixture(scope="module")
def executed() -> ExplorerRun:
    return drive_explorers(
        {f"{name}()": change for name, change in CHANGES.items()},
        ("ex0.controls['mid'].value = 0.9\nprint('INVALID', json.dumps(ex0.numbers))",),
    )


@pytest.mark.slow
@pytest.mark.parametrize("index", range(len(CHANGES)), ids=list(CHANGES))
def test_changing_a_control_in_the_kernel_redraws(executed, index):
    before = json.loads(executed.printed[f"BEFORE {index}"])
    after = json.loads(executed.printed[f"AFTER {index}"])
    assert before["numbers"] != after["numbers"], "the printed numbers did not change"
    assert before["figure"] != after["figure"], "the figure did not change"


@pytest.mark.slow
def test_invalid_setting_is_explained_in_the_readout(executed):
    numbers = json.loads(executed.printed["INVALID"])
    assert "error" in numbers and "> 1" in numbers["error"]


@pytest.mark.slow
def test_first_figure_is_embedded_in_the_widget_state(executed):
    """As in the built book: each explorer's Output holds a PNG before any interaction."""
    assert executed.outputs_with_png >= len(CHANGES)


# -- in-process checks of what the explorers compute ------------------------------------------


def test_dependent_explorer_starts_at_the_papers_example():
    ex = w.dependent_combination_explorer()
    e1, e2 = appendix_pair()
    dep = dependence(e1, e2)
    assert ex.numbers["D"] == pytest.approx(dep.degree)
    assert ex.numbers["R12"] == pytest.approx(dep.r12)
    assert ex.numbers["E[dependent]"] == pytest.approx(
        combine_dependent(e1, e2).pignistic_expectation_1d()
    )
    assert ex.numbers["E[Dempster]"] == pytest.approx(dempster(e1, e2).pignistic_expectation_1d())


def test_conflict_explorer_shows_zadeh_and_total_conflict():
    ex = w.conflict_explorer()
    assert ex.numbers["conflict K"] == pytest.approx(0.9999)
    assert ex.numbers["m(tumour)"] == pytest.approx(1.0)
    ex.controls["x"].value = 1.0
    ex.controls["y"].value = 1.0
    assert "total conflict" in ex.numbers["error"]
    ex.controls["rule"].value = "Yager"  # Yager's rule survives total conflict
    assert ex.numbers["m(Θ)"] == pytest.approx(1.0)


def test_noise_explorer_reproduces_table_1_and_rejects_a_bad_mode():
    ex = w.noise_evidence_explorer()
    assert ex.numbers["mass per cut"] == pytest.approx(0.95 / 3)
    assert ex.numbers["Θ"] == "[-10, 10]"
    ex.controls["mode"].value = 0.5  # above the upper bound
    assert "lower <= mode <= upper" in ex.numbers["error"]


@pytest.mark.slow
def test_every_slider_follows_the_drag():
    # the figure follows the drag: in a kernel the explorer's worker drops the values it
    # cannot keep up with (tests/test_explorer_background.py)
    for make in (
        w.mass_function_explorer,
        w.conflict_explorer,
        w.dependent_combination_explorer,
        w.noise_evidence_explorer,
        w.bounded_error_explorer,
    ):
        for control in make().controls.values():
            if hasattr(control, "continuous_update"):
                assert control.continuous_update is True, (make.__name__, control.description)
