"""The filter widgets of dstoolkit.teaching and the extension-principle explorer.

filter_widget, filter_step_explorer and the extension explorer: built in a kernel, a control changed
in a later cell, and the printed estimates (the widget's numbers) and the figure change — through
nbclient, as the book's build executes them; plus in-process checks of their structure and of what
they compute.
"""

from __future__ import annotations

import json

import ipywidgets
import matplotlib
import numpy as np
import pytest
from conftest import ExplorerRun, drive_explorers

from dstoolkit import filters, studies
from dstoolkit import teaching as w
from dstoolkit.plots import plot_filter_step
from dstoolkit.teaching._readouts import filter_summary

matplotlib.use("Agg")

#: explorer call → (control to change, new value)
CHANGES = {
    "filter_widget()": ("epsilon", 0.1),
    "filter_widget(level_m=4.6, temperature_c=26.5)": ("w_mode", -5.0),
    "filter_step_explorer()": ("step", 4),
    "extension_explorer()": ("hi", 1.5),
}


@pytest.fixture(scope="module")
def executed() -> ExplorerRun:
    return drive_explorers(
        CHANGES, ("ex0.controls['mass_rule'].value = 'm2'\nprint('M2', json.dumps(ex0.numbers))",)
    )


@pytest.mark.slow
@pytest.mark.parametrize("index", range(len(CHANGES)), ids=list(CHANGES))
def test_changing_a_control_in_the_kernel_changes_the_estimates_and_figure(executed, index):
    before = json.loads(executed.printed[f"BEFORE {index}"])
    after = json.loads(executed.printed[f"AFTER {index}"])
    assert before["numbers"] != after["numbers"], "the printed numbers did not change"
    assert before["figure"] != after["figure"], "the figure did not change"


@pytest.mark.slow
def test_the_filter_widgets_printed_estimates_follow_epsilon(executed):
    """ε = 0.05 → 0.1 from the paper's start: the filter recovers sooner (paper §3.2)."""
    before = json.loads(executed.printed["BEFORE 0"])["numbers"]
    after = json.loads(executed.printed["AFTER 0"])["numbers"]
    assert before["x̂_2 (Hz)"] != after["x̂_2 (Hz)"]
    assert int(after["below 1 Hz from step"]) < int(before["below 1 Hz from step"])


@pytest.mark.slow
def test_an_invalid_rule_is_explained_in_the_readout(executed):
    numbers = json.loads(executed.printed["M2"])
    assert "R12" in numbers["error"] and "mass_rule='min'" in numbers["error"]


@pytest.mark.slow
def test_first_figures_are_embedded_in_the_widget_state(executed):
    """As in the built book: each explorer's Output holds a PNG before any interaction."""
    assert executed.outputs_with_png >= len(CHANGES)


# -- in-process checks of structure and content ------------------------------------------------

FILTER_CONTROLS = {
    "v_lower",
    "v_mode",
    "v_upper",
    "w_lower",
    "w_mode",
    "w_upper",
    "p",
    "epsilon",
    "level",
    "temperature",
    "start",
    "orders",
    "mass_rule",
}


def test_filter_widget_structure_controls_and_output():
    ex = w.filter_widget()
    assert set(ex.controls) == FILTER_CONTROLS
    assert isinstance(ex.output, ipywidgets.Output) and ex.output in ex.children
    for control in ex.controls.values():
        assert control in ex.children[1].children
        if hasattr(control, "continuous_update"):
            # follows the drag; the worker drops what it cannot keep up with
            assert control.continuous_update is True, control.description
    assert ex.controls["level"].value == 9.6 and ex.controls["temperature"].value == 23.9


def test_filter_widget_prints_what_the_filter_computes():
    ex = w.filter_widget()
    seq, orders, result = studies.filter_case(9.6, 23.9)
    expected = filter_summary(seq, orders, result)
    assert ex.numbers == pytest.approx(expected)
    x = seq.truth[:, 0]
    assert ex.numbers["mean |x̂ − x| (Hz)"] == pytest.approx(
        np.mean(np.abs(result.estimates[:, 0] - x))
    )
    assert ex.numbers["mean |x̂ − x| (Hz)"] < ex.numbers["mean |z − x| (Hz)"]
    assert ex.numbers["total-conflict steps"] == 0


def test_filter_widget_recompute_function_matches_the_widget():
    ex = w.filter_widget()
    ex.controls["start"].value = "mean_corrected"
    values = {name: control.value for name, control in ex.controls.items()}
    fig, numbers = w.render_filter(**values)
    assert numbers == pytest.approx(ex.numbers)
    assert len(fig.axes) == 2


def test_filter_widget_explains_bad_bounds_and_counts_total_conflict():
    ex = w.filter_widget()
    ex.controls["v_mode"].value = 0.9  # above the upper bound 0.3
    assert "lower <= mode <= upper" in ex.numbers["error"]
    ex.controls["v_mode"].value = 0.0
    ex.controls["epsilon"].value = 0.0  # no Θ: the paper's start is in total conflict
    assert ex.numbers["total-conflict steps"] > 0


def test_the_mean_corrected_start_converges_sooner():
    _, _, paper = studies.filter_case(start="observation")
    _, _, corrected = studies.filter_case(start="mean_corrected")
    seq = studies.gauge_case()
    first = {
        name: filters.converged_at(r.estimates - seq.truth)
        for name, r in (("paper", paper), ("corrected", corrected))
    }
    assert first["corrected"] < first["paper"]
    assert abs(paper.estimates[0, 0] - seq.truth[0, 0]) > 3.0  # off by about −E[w]


def test_converged_at():
    assert filters.converged_at([5.0, 2.0, 0.5, 0.2]) == 3
    assert filters.converged_at([0.5, 2.0, 0.5]) == 3
    assert filters.converged_at([0.1, 0.2]) == 1
    assert filters.converged_at([0.1, 2.0]) is None


def test_step_explorer_shows_the_papers_first_update_in_conflict():
    ex = w.filter_step_explorer(start="observation", step=2)
    assert ex.numbers["K (Step 4)"] == pytest.approx(0.95**3)
    assert 0.0 <= ex.numbers["D"] and 0.0 < ex.numbers["R12"] <= 1.0
    assert len(ex.figure.axes) == 7


def test_plot_filter_step_refuses_the_start():
    _, _, result = studies.filter_case(record=True, first=3)
    with pytest.raises(ValueError, match="step k >= 2"):
        plot_filter_step(result.steps[0])


def test_extension_explorer_shows_the_vertex_method_failing_on_sin():
    ex = w.extension_explorer(function="sin x", lo=0.0, hi=3.0)

    def image(method: str) -> str:  # the readout is "[a, b]", maybe with a warning
        return ex.numbers[method].split(" ⚠")[0]

    assert image("vertex") == "[0, 0.1411]" and "⚠" in ex.numbers["vertex"]
    assert ex.numbers["monotone"] == "NotMonotoneError"
    assert image("subdivision") == "[0, 1]"
    calls = [int(n) for n in ex.numbers["f calls"].split(" / ")]
    assert len(calls) == 4 and calls[1] > 0 and calls[2] > calls[0]  # subdivision costs most
    lo, hi = (float(v) for v in image("mean-value").strip("[]").split(", "))
    assert lo <= 0.0 and hi >= 1.0 and hi - lo < 1.2  # outer, and not by much
    ex.controls["function"].value = "2x + 1"
    assert image("vertex") == image("monotone") == image("subdivision") == "[1, 7]"
    assert image("mean-value") == "[1, 7]"  # exact on a linear function
    ex.controls["lo"].value = 3.5
    assert "lo > hi" in ex.numbers["error"]


def test_extension_explorer_images_have_their_own_range():
    # x² on [0, 0.5]: the images are [0, 0.25] while f runs to 16 on [−4, 4]; on f's range
    # the four bars would be dots
    ex = w.extension_explorer(function="x²", lo=-1.0, hi=2.0)
    ex.controls["lo"].value = 0.0
    ex.controls["hi"].value = 0.5
    f_panel, bars = ex.figure.axes
    low, high = bars.get_ylim()
    shown = [line for line in bars.get_lines() if line.get_visible()]
    assert len(shown) == 4
    for line in shown:
        a, b = sorted(line.get_ydata())
        assert low <= a and b <= high  # every bar inside the panel
        assert b - a >= 0.5 * (high - low)  # and at least half of its height
    assert f_panel.get_ylim()[1] > 10 * high  # f's panel keeps f's own range


def test_compare_image_methods_counts_and_flags():
    out = w.compare_image_methods(lambda x: x[..., 0] ** 2, -1.0, 2.0, 1)
    assert out["vertex"]["image"] == (1.0, 4.0)
    assert out["vertex"]["message"].startswith("VertexMethodWarning")
    assert out["monotone"]["image"] is None
    assert out["monotone"]["message"].startswith("NotMonotoneError")
    assert out["subdivision"]["image"] == pytest.approx((0.0, 4.0), abs=1e-12)
    # checks included: 2 vertices + 3 interior samples; 2 corners + the centre
    assert out["vertex"]["evaluations"] == 5 and out["monotone"]["evaluations"] == 3
    assert "mean_value" not in out  # it needs a slope bound
    outer = w.compare_image_methods(
        lambda x: x[..., 0] ** 2, -1.0, 2.0, 1, slope=lambda lo, hi: (2 * lo, 2 * hi), pieces=1
    )
    assert outer["mean_value"]["image"] == pytest.approx((-5.75, 6.25))  # f(c) ± 4 · 1.5
    assert outer["mean_value"]["evaluations"] == 1
