"""The explorers' static-site form.

dstoolkit.teaching.Explorer with static=True, what scripts/build-book.sh builds: every combination
of the live controls' positions is precomputed into a Stack switched in the browser by jslinks from
the sliders; the other controls are disabled with a line pointing at the notebook; no state the page
can show is inconsistent. The browser half is tests/test_explorers_browser.py.
"""

from __future__ import annotations

import html
import re

import ipywidgets as widgets
import matplotlib
import matplotlib.pyplot as plt
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg

from dstoolkit import teaching as w
from dstoolkit.errors import EvidenceError
from dstoolkit.teaching import Explorer, positions, slider

matplotlib.use("Agg")

#: Every explorer factory of the chapters (the lab's station is tested in test_lab_widget).
EXPLORERS = (
    w.mass_function_explorer,
    w.conflict_explorer,
    w.dependent_combination_explorer,
    w.noise_evidence_explorer,
    w.bounded_error_explorer,
    w.extension_explorer,
    w.filter_widget,
    w.filter_step_explorer,
    w.gauge_explorer,
    w.level_estimation_explorer,
    w.noise_bounds_explorer,
    w.consistency_explorer,
    w.copies_explorer,
)
#: The controls live on the site of the explorers of noise bounds, level, temperature, p and
#: ε (the others: see test_every_explorer_is_live_on_the_site).
REQUIRED_LIVE = {
    "noise_evidence_explorer": {"p", "epsilon"},
    "conflict_explorer": {"epsilon"},
    "bounded_error_explorer": {"scale"},
    "filter_widget": {"level", "epsilon"},
    "gauge_explorer": {"level", "temperature"},
    "level_estimation_explorer": {"level", "temperature"},
    "noise_bounds_explorer": {"w_upper", "v_upper"},
    "consistency_explorer": {"scale", "orders"},
    "copies_explorer": {"shared", "copies"},
}


def _toy(static: bool, fail_above: float = 99.0) -> Explorer:
    """Build a toy explorer: two sliders and a dropdown; the figure is a dot at (a, b).

    a + b > fail_above is an invalid setting.
    """
    controls = {
        "a": slider("a", 1.0, 0.0, 4.0, 0.5),
        "b": slider("b", 0.0, 0.0, 2.0, 1.0),
        "kind": widgets.Dropdown(options=["x", "y"], value="x"),
    }

    def render(a: float, b: float, kind: str):
        if a + b > fail_above:
            raise EvidenceError(f"a + b = {a + b} is too much")
        fig, ax = plt.subplots(figsize=(2, 2), layout="constrained")
        ax.plot([a], [b], "o")
        return fig, {"a + b": a + b, "kind": kind}

    live = {"a": positions(controls["a"], 9), "b": positions(controls["b"], 3)}
    return Explorer(controls, render, title="toy", live=live, static=static)


def _stack(ex: Explorer) -> widgets.Stack:
    return next(c for c in ex.children if isinstance(c, widgets.Stack))


def test_positions_are_on_the_step_and_keep_the_start_value():
    s = slider("s", 0.37, 0.0, 1.0, 0.01)
    assert positions(s, 5) == (0.0, 0.25, 0.37, 0.5, 0.75, 1.0)
    assert positions(widgets.IntSlider(value=3, min=1, max=12), 4) == (1, 3, 5, 8, 12)
    assert positions(widgets.Dropdown(options=[("one", 1), ("two", 2)])) == (1, 2)


def test_two_live_controls_give_a_stack_of_stacks_linked_to_the_sliders():
    ex = _toy(static=True)
    outer = _stack(ex)
    a, b = ex.controls["a"], ex.controls["b"]
    assert isinstance(a, widgets.SelectionSlider) and isinstance(b, widgets.SelectionSlider)
    assert len(a.options) == 9 and len(b.options) == 3
    assert len(outer.children) == 9 and all(len(inner.children) == 3 for inner in outer.children)
    # the page opens on the kernel's first state
    assert outer.selected_index == a.index == list(ex.live["a"]).index(1.0)
    assert a.value == 1.0 and b.value == 0.0

    def linked(box: widgets.Stack) -> tuple:
        (source, trait), (target, target_trait) = box.links[0].source, box.links[0].target
        return source, trait, target, target_trait

    assert linked(outer) == (a, "index", outer, "selected_index")
    for inner in outer.children:
        assert linked(inner) == (b, "index", inner, "selected_index")
    # every leaf shows the readout of its own state and a figure whose text alternative
    # gives the controls' values as shown and the readout's numbers
    for i, av in enumerate(a.options):
        for j, bv in enumerate(b.options):
            leaf = outer.children[i].children[j]
            readout, picture = leaf.children
            assert f"{av[1] + bv[1]:.4f}" in readout.value
            assert picture.value.count("<img ") == 1
            assert "src='data:image/png;base64," in picture.value
            alt = html.unescape(re.search(r"alt='([^']*)'", picture.value).group(1))
            assert alt == (
                f"Figure for a = {av[0]}, b = {bv[0]}: a + b {av[1] + bv[1]:.4f}, kind x."
            )
            assert ex.states[(av[1], bv[1])]["a + b"] == pytest.approx(av[1] + bv[1])
    assert "dstoolkit-states" in outer._dom_classes


def test_the_other_controls_are_disabled_with_a_line_to_the_run_page():
    ex = _toy(static=True)
    assert ex.controls["kind"].disabled
    notes = [c.value for c in ex.children if isinstance(c, widgets.HTML)]
    assert any(
        "notebook" in n
        and "href='run.html'" in n
        and "dstoolkit-site-note" in n
        and "disabled" in n
        for n in notes
    )
    assert not any(getattr(ex.controls[n], "disabled", False) for n in ("a", "b"))


def test_an_invalid_state_shows_its_warning_and_no_figure():
    ex = _toy(static=True, fail_above=3.0)
    outer = _stack(ex)
    a_values = [v for _, v in ex.controls["a"].options]
    i, j = a_values.index(4.0), 1  # a + b = 5
    (readout,) = outer.children[i].children[j].children  # no picture
    assert "⚠" in readout.value and "too much" in readout.value
    assert "error" in ex.states[(4.0, 1.0)]


def test_in_a_kernel_an_invalid_setting_keeps_the_figure_and_says_so():
    ex = _toy(static=False, fail_above=3.0)
    shown = ex.output.outputs
    assert shown and ex.numbers["a + b"] == 1.0
    ex.controls["a"].value = 3.5
    assert "error" in ex.numbers and ex.output.outputs == shown
    assert "the figure below shows the last valid setting" in ex.readout.value
    ex.controls["a"].value = 2.0
    assert ex.numbers["a + b"] == 2.0 and ex.output.outputs != shown
    assert "⚠" not in ex.readout.value


def test_a_redraw_keeps_the_axes_of_the_first_figure():
    ex = _toy(static=False)
    first = ex.figure.axes[0].get_position().bounds
    ex.controls["a"].value = 3.0
    assert ex.figure.axes[0].get_position().bounds == pytest.approx(first)


@pytest.mark.slow
@pytest.mark.parametrize("make", EXPLORERS, ids=[m.__name__ for m in EXPLORERS])
def test_every_explorer_is_live_on_the_site(make):
    ex = make()
    assert 1 <= len(ex.live) <= 2, ex.live
    main = next(iter(ex.live.values()))
    assert len(main) >= 8, f"the main live control has {len(main)} positions"
    for name, values in ex.live.items():
        assert ex.controls[name].value in values
    assert REQUIRED_LIVE.get(make.__name__, set()) <= set(ex.live)


@pytest.mark.slow
def test_no_mass_function_state_adds_up_to_more_than_one_without_a_warning(monkeypatch):
    monkeypatch.setenv(w.STATIC_SITE_ENV, "1")  # as scripts/build-book.sh sets it
    ex = w.mass_function_explorer()
    assert ex.static
    assert len(ex.states) >= 8
    for (low, high), numbers in ex.states.items():
        total = low + high + 0.0 + 0.3  # mid and m({low, mid}) stay at their start values
        if total > 1 + 1e-9:
            assert "error" in numbers and "> 1" in numbers["error"], (low, high)
        else:
            assert numbers["m(Θ)"] == pytest.approx(1 - total)
            assert sum(numbers[f"BetP({h})"] for h in ("low", "mid", "high")) == (
                pytest.approx(1.0)
            )


def test_wider_labels_get_a_fresh_layout_rather_than_stick_out():
    def render(k: float):
        fig, ax = plt.subplots(figsize=(3, 2), layout="constrained")
        ax.plot([0, 1], [0, -(10.0**k)])
        ax.ticklabel_format(useOffset=False, style="plain")
        return fig, {"k": k}

    ex = Explorer({"k": slider("k", 0.0, 0.0, 9.0, 1.0)}, render, static=False)
    ex.controls["k"].value = 7.0  # labels like −10000000, far wider than the first ones
    renderer = FigureCanvasAgg(ex.figure).get_renderer()  # the figure is closed
    assert ex.figure.get_tightbbox(renderer).x0 >= -0.01, "a tick label sticks out"


def _kept_figure_explorer(moving_limit: bool = False) -> tuple[Explorer, list[int]]:
    """Build an explorer whose render keeps one figure.

    Three animated bars follow slider a; with ``moving_limit`` the y limit (not animated)
    follows it too. Also returns the list that counts the explorer's whole-figure draws.
    """
    from matplotlib.figure import Figure

    kept: dict[str, object] = {}

    def render(a: float):
        if not kept:
            fig = Figure(figsize=(4.0, 2.5), layout="constrained")
            ax = fig.subplots()
            kept["bars"] = ax.bar(["low", "mid", "high"], [a, 0.2, 0.3], animated=True)
            ax.set_title("masses")
            ax.set_ylim(0, 1.0)
            kept["fig"], kept["ax"] = fig, ax
        for bar, height in zip(kept["bars"], [a, 0.2, 0.3], strict=True):
            bar.set_height(height)
        if moving_limit:  # set_ylim marks the figure stale even when nothing changes
            kept["ax"].set_ylim(0, 1.0 + a)
        return kept["fig"], {"a": a}

    ex = Explorer({"a": slider("a", 0.5, 0.0, 1.0, 0.05)}, render, static=False)
    draws: list[int] = []  # after the first picture
    whole = ex._draw
    ex._draw = lambda fig: (draws.append(1), whole(fig))[1]  # type: ignore[method-assign]
    return ex, draws


def _pixels(png: bytes):
    import io

    import numpy as np
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))


@pytest.mark.parametrize("moving_limit", [False, True])
def test_a_kept_figure_shows_the_same_picture_as_a_fresh_one(moving_limit):
    ex, draws = _kept_figure_explorer(moving_limit)
    for a in (0.1, 0.7, 0.35, 0.9):
        ex.controls["a"].value = a
    fresh, _ = _kept_figure_explorer(moving_limit)
    fresh.controls["a"].value = 0.9
    assert (_pixels(ex.png(ex.figure)) == _pixels(fresh.png(fresh.figure))).all()
    # only animated bars moved: they are blitted onto the kept background; a moved limit
    # redraws the whole figure on each of the 4 changes (the last png changed nothing)
    assert len(draws) == (4 if moving_limit else 0)


def test_a_kept_figure_is_laid_out_afresh_whenever_labels_would_stick_out():
    from matplotlib.figure import Figure

    fig = Figure(figsize=(3, 2), layout="constrained")
    ax = fig.subplots()
    (line,) = ax.plot([0, 1], [0, -1.0])
    ax.ticklabel_format(useOffset=False, style="plain")

    def render(k: float):
        line.set_ydata([0, -(10.0**k)])
        ax.relim()
        ax.autoscale_view()
        return fig, {"k": k}

    ex = Explorer({"k": slider("k", 0.0, 0.0, 9.0, 1.0)}, render, static=False)
    for k in (7.0, 1.0, 8.0):  # wide, narrow, wide again: the layout engine is found again
        ex.controls["k"].value = k
        renderer = fig.canvas.get_renderer()
        assert fig.get_tightbbox(renderer).x0 >= -0.01, f"a tick label sticks out at k={k}"


def test_bad_live_declarations_are_refused_with_a_reason():
    from dstoolkit.errors import InvalidInputError

    def render(a: float):
        return None, {"a": a}

    a = slider("a", 1.0, 0.0, 4.0, 0.5)
    with pytest.raises(InvalidInputError, match="one or two of"):
        Explorer({"a": a}, render, live={"nope": (1.0,)}, static=True)
    with pytest.raises(InvalidInputError, match="must include its value 1.0"):
        Explorer({"a": a}, render, live={"a": (0.0, 2.0)}, static=True)


def test_the_print_picture_is_the_shown_png_and_leaves_a_kept_figure_alone():
    from dstoolkit.teaching._print_edition import first_figure_png

    ex, draws = _kept_figure_explorer()
    assert first_figure_png(ex) == ex.picture == _png_of(ex)
    ex.controls["a"].value = 0.2  # still blitted: the print picture did not redraw the figure
    assert draws == []
    assert first_figure_png(ex) == ex.picture != _png_of(_kept_figure_explorer()[0])


def _png_of(ex: Explorer) -> bytes:
    import base64

    return base64.b64decode(ex.output.outputs[0]["data"]["image/png"])


def test_the_site_keeps_no_picture_outside_its_states():
    """The kernel's output and readout are not shown on the site.

    The output is emptied and both are closed, so that the page's widget state holds pictures
    only in the precomputed states.
    """
    ex = _toy(static=True)
    assert ex.output.outputs == () and ex.output.comm is None and ex.readout.comm is None
    assert ex.output not in ex.children and ex.picture is not None  # print keeps its still
