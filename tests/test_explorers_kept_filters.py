"""The filter explorers keep their figure and redraw it in place.

After any number of changes a kept figure holds what a figure drawn afresh for the same setting
holds (the artists' data, colours, texts, limits), the static site (which renders every state
through the same kept figure) shows no leftover of an earlier state, and an invalid setting keeps
the last figure and says so. Speed is measured in benchmarks/widget_latency.py.
"""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from matplotlib.collections import Collection  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from dstoolkit import plots, studies  # noqa: E402
from dstoolkit import teaching as w  # noqa: E402
from dstoolkit.errors import EvidenceError  # noqa: E402
from dstoolkit.filters import BoundedErrorFilter, random_walk  # noqa: E402


def _visible(artists: list) -> list:
    return [a for a in artists if a.get_visible()]


def _state(fig: Figure) -> dict:
    """Return what a figure shows, artist by artist.

    Limits, titles, labels, the data and colours of every visible line and collection, every
    visible text and the legends. (Not the ticks: they follow the limits and the size of the
    axes, which the layout sets.)
    """
    out: dict = {
        "suptitle": fig._suptitle.get_text() if fig._suptitle else "",
        "size": tuple(fig.get_size_inches()),
        "axes": [],
    }
    for ax in fig.axes:
        out["axes"].append(
            {
                "limits": (ax.get_xlim(), ax.get_ylim()),
                "scales": (ax.get_xscale(), ax.get_yscale()),
                "titles": tuple(ax.get_title(loc) for loc in ("left", "center", "right")),
                "labels": (ax.get_xlabel(), ax.get_ylabel()),
                "lines": [
                    (
                        line.get_xydata().tolist(),
                        line.get_color(),
                        line.get_linestyle(),
                        line.get_marker(),
                        line.get_linewidth(),
                    )
                    for line in _visible(ax.lines)
                ],
                "collections": [
                    (
                        [p.vertices.tolist() for p in c.get_paths()],
                        c.get_facecolor().tolist(),
                        c.get_edgecolor().tolist(),
                    )
                    for c in _visible(ax.collections)
                    if isinstance(c, Collection)
                ],
                "patches": [
                    (p.get_x(), p.get_y(), p.get_width(), p.get_height())
                    for p in _visible(ax.patches)
                ],
                "texts": [
                    (t.get_text(), tuple(t.get_position()), t.get_fontsize())
                    for t in _visible(ax.texts)
                    if t.get_text()
                ],
                "legend": (
                    [t.get_text() for t in ax.get_legend().get_texts()] if ax.get_legend() else None
                ),
            }
        )
    return out


def assert_same_picture(kept: Figure, fresh: Figure) -> None:
    a, b = _state(kept), _state(fresh)
    assert a["suptitle"] == b["suptitle"] and a["size"] == pytest.approx(b["size"])
    assert len(a["axes"]) == len(b["axes"])
    for i, (x, y) in enumerate(zip(a["axes"], b["axes"], strict=True)):
        for key in x:
            if key == "limits":
                for mine, theirs in zip(x[key], y[key], strict=True):
                    assert mine == pytest.approx(theirs, rel=1e-12, abs=1e-9), (i, key)
            else:
                assert x[key] == y[key], (i, key)


# -- the filter widget (the paper's Fig. 10 of one run) ----------------------------------------

#: Changes that visit other runs, another number of resonances (level 3 m: 26) and back.
WIDGET_CHANGES = (
    ("epsilon", 0.1),
    ("level", 3.0),
    ("w_mode", -6.5),
    ("p", 5),
    ("start", "mean_corrected"),
    ("orders", "eq43"),
    ("level", 9.6),
)


def test_the_filter_widget_keeps_one_figure_that_matches_a_fresh_one_after_each_change():
    ex = w.filter_widget()
    kept = ex.figure
    for name, value in WIDGET_CHANGES:
        ex.controls[name].value = value
        assert ex.figure is kept, f"a new figure after changing {name}"
        fresh, numbers = w.render_filter(**ex.values())  # drawn afresh (through pyplot)
        assert numbers == pytest.approx(ex.numbers)
        assert_same_picture(kept, fresh)
        matplotlib.pyplot.close(fresh)


def test_an_invalid_setting_keeps_the_last_figure_and_says_so():
    ex = w.filter_widget()
    ex.controls["epsilon"].value = 0.2
    shown, last = ex.output.outputs, ex.values()
    ex.controls["v_mode"].value = 0.9  # above the upper bound 0.3
    assert "lower <= mode <= upper" in ex.numbers["error"]
    assert "⚠" in ex.readout.value and "last valid setting" in ex.readout.value
    assert ex.output.outputs == shown
    fresh, _ = w.render_filter(**last)
    assert_same_picture(ex.figure, fresh)  # the kept figure still shows ε = 0.2
    ex.controls["v_mode"].value = 0.1
    assert "error" not in ex.numbers and ex.output.outputs != shown
    fresh, _ = w.render_filter(**ex.values())
    assert_same_picture(ex.figure, fresh)


def test_a_kept_filter_errors_figure_redraws_runs_of_other_lengths():
    seq, _, long_run = studies.filter_case(9.6, 23.9)
    short_seq, _, short_run = studies.filter_case(1.6, 23.9)
    kept = plots.FilterErrorsFigure(long_run, seq.truth, seq.readings, title="long", pyplot=False)
    kept.update(short_run, short_seq.truth, short_seq.readings, title="short")
    assert_same_picture(
        kept.figure,
        plots.plot_filter_errors(short_run, short_seq.truth, short_seq.readings, title="short"),
    )
    assert kept.axes[0].get_xlim()[1] < 20  # 14 resonances at 1.6 m, not 83


# -- the step explorer (every evidence of one step, Fig. 3) -----------------------------------

#: Steps and settings, with a total conflict (ε = 0: two panels fewer) and back.
STEP_CHANGES = (
    ("step", 5),
    ("epsilon", 0.1),
    ("start", "observation"),
    ("step", 20),
    ("epsilon", 0.0),
    ("step", 2),
    ("epsilon", 0.5),
    ("step", 11),
    ("epsilon", 0.05),
)  # Θ (m = ε) labelled at ε > 0.05 only: a label goes


@pytest.mark.slow
def test_the_step_explorer_redraws_in_place_and_matches_a_fresh_figure():
    ex = w.filter_step_explorer()
    kept = {len(ex.figure.axes): ex.figure}
    for name, value in STEP_CHANGES:
        ex.controls[name].value = value
        v = ex.values()
        assert kept.setdefault(len(ex.figure.axes), ex.figure) is ex.figure, (
            "a new figure for panels already drawn"
        )
        fresh = w.filter_step_explorer(step=v["step"], start=v["start"], epsilon=v["epsilon"])
        assert fresh.numbers == pytest.approx(ex.numbers, nan_ok=True)
        assert_same_picture(ex.figure, fresh.figure)
    assert set(kept) == {7, 5}, "the total conflict (ε = 0) fills two panels fewer"


def test_a_kept_step_figure_refuses_a_step_with_other_panels():
    _, _, run = studies.filter_case(record=True, first=4)
    _, _, stopped = studies.filter_case(start="observation", epsilon=0.0, record=True, first=4)
    kept = plots.FilterStepFigure(run.steps[1], pyplot=False)
    assert plots.FilterStepFigure.panels_of(stopped.steps[1]) != kept.panels
    with pytest.raises(EvidenceError, match="build a new FilterStepFigure"):
        kept.update(stopped.steps[1])
    kept.update(run.steps[3])
    assert_same_picture(kept.figure, plots.plot_filter_step(run.steps[3]))


@pytest.mark.slow
def test_the_static_step_explorer_shows_each_state_as_drawn_afresh():
    # The static site renders every state through one Explorer: its kept figure must not
    # carry anything of the state before. Render the states in the site's order, compare.
    ex = w.filter_step_explorer()
    for step in (20, 3, 11, 2):
        ex.refresh(step=step)
        fresh = w.filter_step_explorer(step=step)
        assert ex.numbers == pytest.approx(fresh.numbers)
        assert_same_picture(ex.figure, fresh.figure)


# -- the bounded-error explorer -------------------------------------------------------------


def test_the_bounded_error_explorer_keeps_its_figure_and_its_legend():
    ex = w.bounded_error_explorer(v_half=0.1, w_half=1.0, steps=60, seed=7)
    x, z = random_walk(0.1, 1.0).simulate([0.0], 60, np.random.default_rng(7))
    kept = ex.figure
    for scale in (0.3, 2.5, 0.5, 1.0):  # empty boxes (red lines) come and go
        ex.controls["scale"].value = scale
        assert ex.figure is kept
        res = BoundedErrorFilter(on_inconsistent="reset").run(
            random_walk(0.1 * scale, 1.0 * scale), z
        )
        fresh = plots.plot_enclosure(res, x, z, title=f"bounds × {scale:g}")
        fresh.axes[0].legend(fontsize=8, loc="upper left")
        assert_same_picture(kept, fresh)
        # the reset lines: one collection, a vertical segment per reset step
        (lines,) = [c for c in kept.axes[0].collections if type(c).__name__ == "LineCollection"]
        assert len(lines.get_segments()) == int(np.sum(res.diagnostics["resets"]))
        # the title stays as high above the panel as legend_above put it
        pad_pt = [f.axes[0].titleOffsetTrans.get_matrix()[1, 2] * 72 / f.dpi for f in (kept, fresh)]
        assert pad_pt[0] == pytest.approx(pad_pt[1]) and pad_pt[0] > 20


def test_the_zero_line_widens_the_view_only_when_zero_lies_outside_it():
    """Keep the view that an axhline drawn after the data would give.

    At 1.6 m and ε = 0.25 every deviation is > 0, and the view is the data's with 5 % margins
    (0 lies within them), in a kept figure too.
    """
    ex = w.filter_widget()
    for level in (1.6, 9.6, 1.6):
        ex.controls["epsilon"].value = 0.25
        ex.controls["level"].value = level
    data = np.concatenate([line.get_ydata() for line in ex.figure.axes[0].lines[:2]])
    low, high = float(data.min()), float(data.max())
    assert low > 0
    margin = 0.05 * (high - low)
    assert ex.figure.axes[0].get_ylim() == pytest.approx((low - margin, high + margin))
