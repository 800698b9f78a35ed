"""Every figure function of dstoolkit.plots draws a figure people can read.

Each public ``plot_*`` function is rendered on small but real inputs and its matplotlib
objects are checked:

- the figure is at most the book's column wide (so it is shown at its own size);
- every text (tick labels, labels, titles, legends, annotations) is at least 9 pt;
- every axis that shows tick labels has a label, with its unit in parentheses unless the
  quantity has none (mass, probability, possibility, a step number ...);
- no legend box covers a data point (a marker or a vertex of a drawn line) of any axes;
- no panel is empty (every axes draws something).
"""

from __future__ import annotations

import io
import re
from collections.abc import Callable

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from conftest import ARTIFACTS  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.collections import PathCollection  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402
from matplotlib.text import Text  # noqa: E402

import dstoolkit.plots as plots  # noqa: E402
from dstoolkit.evidence import IntervalEvidence, MassFunction, triangular_evidence  # noqa: E402
from dstoolkit.filters import BoundedNoise  # noqa: E402
from dstoolkit.gauge import (  # noqa: E402
    PAPER_SWEEP,
    TubeSetup,
    detect_resonances,
    synthesize_recording,
)
from dstoolkit.studies import (  # noqa: E402
    bound_scale_study,
    example_comparison,
    filter_case,
    order_rule_study,
    run_table3,
    tracking_data,
)
from dstoolkit.teaching import GAUGE_CONDITIONS  # noqa: E402

#: Width of the book's text column (inches): a wider figure is shown shrunk.
COLUMN_IN = 6.4
MIN_PT = 9.0
#: Quantities without a unit: their axis labels need no "(unit)".
DIMENSIONLESS = re.compile(
    r"^(cumulated mass|mass|probability|possibility|Bel\(A\)|step k|focal element|"
    r"subset A|ξ|first source|second source|"
    # normalised (estimation and innovation) squared errors: ratios of squared errors to
    # the filter's own covariance, without a unit by definition
    r"average NEES|average NIS)"
)
UNIT = re.compile(r"\([^()]*[^\s()][^()]*\)")

FIGURES: dict[str, Callable[[], Figure]] = {}
SHOTS = ARTIFACTS / "figures"


def figure(name: str) -> Callable[[Callable[[], Figure]], Callable[[], Figure]]:
    def register(function: Callable[[], Figure]) -> Callable[[], Figure]:
        FIGURES[name] = function
        return function

    return register


# -- inputs: small, real --------------------------------------------------------------------

NOISE = triangular_evidence(-10.59, -6.9, -3.21, p=3, epsilon=0.05, theta=(-20.0, 10.0))
FRAME = ("low", "mid", "high")
MF_A = MassFunction({("low",): 0.4, ("low", "mid"): 0.3, ("high",): 0.1, FRAME: 0.2}, FRAME)
MF_B = MassFunction({("mid",): 0.5, ("mid", "high"): 0.3, FRAME: 0.2}, FRAME)


def _filter_run() -> tuple[object, np.ndarray, object]:
    seq, _orders, result = filter_case(9.6, 23.9, record=True, first=12)
    return seq.readings[:12, 0], seq.truth[:12, 0], result


def _detection() -> tuple[object, object, TubeSetup]:
    setup = TubeSetup(4.6, 26.5)
    rec = synthesize_recording(setup, PAPER_SWEEP, GAUGE_CONDITIONS, seed=0)
    return rec, detect_resonances(rec), setup


@figure("plot_focal_intervals")
def _focal() -> Figure:
    return plots.plot_focal_intervals(NOISE, xlim=(-12, -2), xlabel="noise w (Hz)")


@figure("plot_pbox")
def _pbox() -> Figure:
    return plots.plot_pbox(NOISE, xlim=(-12, -2), xlabel="noise w (Hz)")


@figure("plot_possibility")
def _possibility() -> Figure:
    return plots.plot_possibility(-10.59, -6.9, -3.21, 3, evidence=NOISE, xlabel="noise w (Hz)")


@figure("plot_bel_pl")
def _bel_pl() -> Figure:
    return plots.plot_bel_pl(MF_A)


@figure("plot_masses")
def _masses() -> Figure:
    return plots.plot_masses(MF_A)


@figure("plot_products")
def _products() -> Figure:
    return plots.plot_products(MF_A, MF_B)


@figure("plot_enclosure")
def _enclosure() -> Figure:
    readings, truth, result = _filter_run()
    return plots.plot_enclosure(result, truth, readings, ylabel="frequency (Hz)")


@figure("plot_boxes")
def _boxes() -> Figure:
    ev = IntervalEvidence([[0.0, 0.0], [0.5, 0.2]], [[2.0, 1.0], [1.5, 0.8]], [0.4, 0.6])
    return plots.plot_boxes(ev)


@figure("plot_filter_step")
def _filter_step() -> Figure:
    readings, truth, result = _filter_run()
    return plots.plot_filter_step(result.steps[1], truth=truth[1])


@figure("plot_filter_errors")
def _filter_errors() -> Figure:
    readings, truth, result = _filter_run()
    return plots.plot_filter_errors(result, truth, readings)


@figure("plot_table3")
def _table3() -> Figure:
    table = run_table3(
        runs=2,
        methods=("direct", "dependent_evidence"),
        cases=((1.3, 27.0), (4.6, 26.5)),
        progress=False,
    )
    return plots.plot_table3(table)


@figure("plot_estimates")
def _estimates() -> Figure:
    readings, truth, result = _filter_run()
    return plots.plot_estimates(truth, readings, {"dependent_evidence": result.estimates[:, 0]})


@figure("plot_recording")
def _recording() -> Figure:
    rec, det, _ = _detection()
    return plots.plot_recording(rec, det)


@figure("plot_resonances")
def _resonances() -> Figure:
    _, det, setup = _detection()
    return plots.plot_resonances(det, true_frequencies=setup.resonances(PAPER_SWEEP.band)[1])


@figure("plot_step_errors")
def _step_errors() -> Figure:
    rng = np.random.default_rng(0)
    return plots.plot_step_errors(
        {
            "direct": rng.uniform(0.5, 3, (3, 20)),
            "dependent_evidence": rng.uniform(0.05, 1, (3, 20)),
        }
    )


def _image_cases() -> dict[
    str, tuple[Callable[[np.ndarray], np.ndarray], float, float, dict[str, tuple[float, float]]]
]:
    """Return the chapter's two functions on which the vertex method fails, and both images."""
    return {
        "x²": (
            lambda x: x[..., 0] ** 2,
            -1.0,
            2.0,
            {"vertex": (1.0, 4.0), "subdivision": (0.0, 4.0)},
        ),
        "sin x": (
            lambda x: np.sin(x[..., 0]),
            0.0,
            3.0,
            {"vertex": (0.0, float(np.sin(3.0))), "subdivision": (0.0, 1.0)},
        ),
    }


@figure("plot_image_methods")
def _image_methods() -> Figure:
    return plots.plot_image_methods(_image_cases())


def _sweep_inputs() -> tuple[np.ndarray, ...]:
    """Steady-tone and sweep amplitudes of a tube with resonances 17.9 Hz apart."""
    f = np.linspace(1500.0, 1560.0, 1200)
    resonances = np.arange(1503.6, 1560.0, 17.9)
    steady = np.max([1 / (1 + ((f - r) / 0.8) ** 2) for r in resonances], axis=0)
    swept = np.max([0.8 / (1 + ((f - r - 1.9) / 1.2) ** 2) for r in resonances], axis=0)
    return f, steady, swept, resonances


@figure("plot_sweep_peaks")
def _sweep_peaks() -> Figure:
    f, steady, swept, resonances = _sweep_inputs()
    return plots.plot_sweep_peaks(f, steady, swept, resonances, 1.9)


@figure("plot_noise_assumption")
def _noise_assumption() -> Figure:
    return plots.plot_noise_assumption(
        BoundedNoise(-10.59, -6.9, -3.21), BoundedNoise(-8.0, -6.9, -5.0)
    )


@figure("plot_rule_curves")
def _rule_curves() -> Figure:
    steps = np.arange(1, 21)
    return plots.plot_rule_curves(
        steps,
        {
            "paper": 30.0 / steps,
            "paper_cells": 20.0 / steps,
            "cautious": 10.0 / steps,
            "dempster": 15.0 / steps,
        },
        xlabel="step k",
        ylabel="|level error| (mm)",
        current=5,
    )


@figure("plot_consistency")
def _consistency() -> Figure:
    from dstoolkit.studies import gauge_consistency

    return plots.plot_consistency(gauge_consistency(runs=5), title="L = 4.6 m, 5 runs")


@figure("plot_scale_study")
def _scale_study() -> Figure:
    data = tracking_data(runs=2)
    return plots.plot_scale_study(
        bound_scale_study(data, [0.5, 1.0, 2.0], methods=("kalman", "bounded_error"))
    )


@figure("plot_order_rule_study")
def _order_rule_study() -> Figure:
    study = order_rule_study(runs=2, cases=((1.3, 27.0), (4.6, 26.5)))
    return plots.plot_order_rule_study([study])


@figure("plot_example")
def _example() -> Figure:
    return plots.plot_example(example_comparison(steps=15, runs=1))


@figure("plot_nassreddine_step")
def _nassreddine_step() -> Figure:
    from dstoolkit.filters import NassreddineFilter, random_walk

    filt = NassreddineFilter(p=2, max_focal=4, theta=((-3.0, 3.0), (-4.0, 4.0)))
    state = filt.initialize(random_walk(0.5, 1.0), 0.2)
    state, record = filt.step(state, 0.6)
    carried = IntervalEvidence.from_boxes(state.carried)
    return plots.plot_nassreddine_step(record, carried, xlim=(-2.5, 2.5), truth=0.4)


# -- checks ---------------------------------------------------------------------------------


def _rendered(name: str) -> Figure:
    """Draw the figure (which lays out every text); save a PNG of it in test-artifacts/figures."""
    fig = FIGURES[name]()
    SHOTS.mkdir(parents=True, exist_ok=True)
    fig.savefig(SHOTS / f"{name}.png", format="png", dpi=96)
    return fig


def _texts(fig: Figure) -> list[Text]:
    return [
        t
        for t in fig.findobj(Text)
        if t.get_visible() and t.get_text().strip() and t.get_figure() is not None
    ]


def _shows_ticklabels(axis: object) -> bool:
    return any(t.get_visible() and t.get_text().strip() for t in axis.get_ticklabels())


def _shares(ax: Axes, which: str) -> list[Axes]:
    group = ax.get_shared_x_axes() if which == "x" else ax.get_shared_y_axes()
    return [other for other in group.get_siblings(ax) if other is not ax]


def _data_points(ax: Axes) -> np.ndarray:
    """Display coordinates of the markers and line vertices drawn inside ``ax``."""
    points = []
    for line in ax.get_lines():
        if not line.get_visible():
            continue
        xy = np.asarray(line.get_xydata(), dtype=float)
        if xy.size and np.isfinite(xy).all(axis=1).any():
            points.append(line.get_transform().transform(xy[np.isfinite(xy).all(axis=1)]))
    for coll in ax.collections:
        if isinstance(coll, PathCollection) and coll.get_visible():
            offsets = np.asarray(coll.get_offsets(), dtype=float)
            if offsets.size:
                points.append(coll.get_offset_transform().transform(offsets))
    for patch in ax.patches:
        if isinstance(patch, Rectangle) and patch.get_visible() and patch.get_height() > 0:
            box = patch.get_window_extent()
            points.append(np.array([[box.x0 + 0.5 * box.width, box.y1]]))  # top of a bar
    if not points:
        return np.zeros((0, 2))
    pts = np.concatenate(points)
    area = ax.get_window_extent()
    inside = (
        (pts[:, 0] > area.x0 + 1)
        & (pts[:, 0] < area.x1 - 1)
        & (pts[:, 1] > area.y0 + 1)
        & (pts[:, 1] < area.y1 - 1)
    )
    return pts[inside]


@pytest.fixture(scope="module", params=sorted(FIGURES))
def rendered(request: pytest.FixtureRequest) -> tuple[str, Figure]:
    return request.param, _rendered(request.param)


def test_every_figure_function_is_checked() -> None:
    public = {name for name in plots.__all__ if name.startswith("plot_")}
    assert public == set(FIGURES), f"figure functions without a check: {public - set(FIGURES)}"


def test_figure_fits_the_column(rendered: tuple[str, Figure]) -> None:
    name, fig = rendered
    width = fig.get_size_inches()[0]
    assert width <= COLUMN_IN + 0.01, f"{name}: {width:.2f} in wide, the column is {COLUMN_IN}"


def test_text_is_at_least_9_pt(rendered: tuple[str, Figure]) -> None:
    name, fig = rendered
    small = sorted(
        {
            (round(t.get_fontsize(), 1), t.get_text()[:30])
            for t in _texts(fig)
            if t.get_fontsize() < MIN_PT - 0.01
        }
    )
    assert not small, f"{name}: text below {MIN_PT} pt: {small[:8]}"


def test_axes_are_labelled_with_units(rendered: tuple[str, Figure]) -> None:
    name, fig = rendered
    problems = []
    for index, ax in enumerate(fig.axes):
        if not ax.axison:
            continue
        assert ax.has_data(), f"{name}: panel {index} is empty"
        for which, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            if not _shows_ticklabels(axis) or axis.get_scale() == "function":
                continue
            label = axis.get_label_text().strip()
            if not label:
                labelled = [
                    o
                    for o in _shares(ax, which)
                    if (o.xaxis if which == "x" else o.yaxis).get_label_text().strip()
                ]
                if labelled:
                    continue
                if (
                    which == "x"
                    and all(t.get_text() for t in axis.get_ticklabels())
                    and axis.get_major_formatter().__class__.__name__ == "FixedFormatter"
                ):
                    continue  # named categories (subsets, focal elements) label themselves
                problems.append(f"panel {index}: no {which} label")
            elif not (UNIT.search(label) or DIMENSIONLESS.match(label)):
                problems.append(f"panel {index}: {which} label {label!r} has no unit")
    assert not problems, f"{name}: {problems}"


def test_legends_do_not_hide_data(rendered: tuple[str, Figure]) -> None:
    name, fig = rendered
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    legends += list(fig.legends)
    problems = []
    for legend in legends:
        box = legend.get_window_extent().shrunk(0.98, 0.96)
        for index, ax in enumerate(fig.axes):
            pts = _data_points(ax)
            covered = (
                (pts[:, 0] > box.x0)
                & (pts[:, 0] < box.x1)
                & (pts[:, 1] > box.y0)
                & (pts[:, 1] < box.y1)
            )
            if covered.any():
                problems.append(
                    f"legend {[t.get_text() for t in legend.get_texts()][:3]} "
                    f"covers {int(covered.sum())} data points of panel {index}"
                )
            for loc in ("left", "center", "right"):
                title = ax.get_title(loc)
                texts = [t for t in _texts(fig) if t.get_text() == title] if title else []
                if any(box.overlaps(t.get_window_extent()) for t in texts):
                    problems.append(f"legend overlaps the title {title!r} of panel {index}")
    assert not problems, f"{name}: {problems}"


def test_the_log_ticks_of_a_short_range_are_readable() -> None:
    """A log axis over about a decade shows several plain labelled ticks (Fig. 7.2).

    Matplotlib's default labels only the decade, "1".
    """
    fig = Figure(figsize=(6, 3))
    ax = fig.add_subplot()
    ax.semilogy([1, 2, 3], [0.3, 1.0, 2.5])
    plots.log_ticks(ax.yaxis)
    fig.savefig(io.BytesIO(), format="png")
    low, high = ax.get_ylim()
    locs = [v for v in ax.yaxis.get_majorticklocs() if low <= v <= high]
    labels = [ax.yaxis.get_major_formatter()(v) for v in locs]
    assert labels == ["0.5", "1", "2"], labels


def test_the_style_is_undone_but_nothing_else() -> None:
    """figure_style restores its own settings only.

    IPython's inline backend switches the interactive mode on when a session's first figure
    is made, maybe inside the style, and undoing that would stop every later figure of a
    notebook from showing.
    """
    import matplotlib as mpl

    before_size, before_interactive = mpl.rcParams["font.size"], mpl.is_interactive()
    try:
        with plots.figure_style():
            assert mpl.rcParams["font.size"] == 10
            mpl.interactive(True)  # what matplotlib-inline does on first use
        assert mpl.rcParams["font.size"] == before_size
        assert mpl.is_interactive()
    finally:
        mpl.interactive(before_interactive)


# -- methods told apart without colour ------------------------------------------------------

_SIX = ("dependent_evidence", "nassreddine", "direct", "kalman", "particle", "bounded_error")


def _line_keys(ax: Axes, labels: set[str]) -> dict[str, tuple[str, str, str]]:
    """For each line of ``ax`` labelled one of ``labels``: (dash pattern, marker, colour)."""
    from matplotlib.colors import to_hex

    return {
        line.get_label(): (
            str(line.get_linestyle()) + str(line._dash_pattern),
            str(line.get_marker()),
            to_hex(line.get_color()),
        )
        for line in ax.lines
        if line.get_label() in labels
    }


def _assert_told_apart(keys: dict[str, tuple[str, str, str]], want: int) -> None:
    assert len(keys) == want, keys
    patterns = [(dashes, marker) for dashes, marker, _ in keys.values()]
    assert len(set(patterns)) == len(patterns), f"two series differ in colour only: {keys}"
    assert all(marker not in ("None", "", " ") for _, marker in patterns), keys


def test_the_methods_have_okabe_ito_colours_and_their_own_lines_and_markers() -> None:
    palette = {c.lower() for c in plots.OKABE_ITO.values()}
    styles = [plots.STYLE[m] for m in _SIX]
    assert {st["color"].lower() for st in styles} <= palette
    assert len({(str(st["ls"]), st["marker"]) for st in styles}) == len(_SIX)
    assert len({st["marker"] for st in styles}) == len(_SIX)


def test_fig_11_tells_the_methods_apart_without_colour() -> None:
    """plot_estimates (Figs. 10 and 11) with all six methods tells them apart without colour.

    In both panels every method is drawn with its own dash pattern and marker.
    """
    rng = np.random.default_rng(1)
    steps = 30
    estimates = {m: 4.6 + rng.normal(0, 0.1, steps) for m in _SIX}
    fig = plots.plot_estimates(
        4.6, 4.6 + rng.normal(0, 0.3, steps), estimates, quantity="level", unit="m"
    )
    labels = {plots.STYLE[m]["label"] for m in _SIX}
    for ax in fig.axes[:2]:
        _assert_told_apart(_line_keys(ax, labels), len(_SIX))
    fig.savefig(io.BytesIO(), format="png")


def test_step_errors_tell_methods_and_variants_apart_without_colour() -> None:
    rng = np.random.default_rng(2)
    errors = {
        "paper's filter, start z_1": rng.uniform(0.1, 1, (2, 20)),
        "paper's filter, start z_1 + E[w]": rng.uniform(0.1, 1, (2, 20)),
    }
    errors.update({m: rng.uniform(0.1, 1, (2, 20)) for m in _SIX})
    fig = plots.plot_step_errors(errors)
    labels = {plots.STYLE.get(m, {"label": m})["label"] for m in errors}
    _assert_told_apart(_line_keys(fig.axes[0], labels), len(errors))


# -- series told apart by line style or marker, and named next to them ---------------------


def _direct_labels(ax: Axes) -> set[str]:
    """Texts written right of the data area of ``ax`` (labels at the series' ends)."""
    return {
        t.get_text()
        for t in ax.texts
        if t.get_transform() == ax.transAxes and t.get_position()[0] > 1.0
    }


def test_step_errors_with_end_labels_name_each_line_at_its_end() -> None:
    """The start figure of the recursive filter's chapter names each series at its end.

    It shows two runs of the filter and the readings, raw and corrected, in four styles.
    """
    rng = np.random.default_rng(3)
    errors = {
        "filter, x̂_1 = z_1 (paper)": 7 * np.exp(-np.arange(40) / 12) + 0.3,
        "filter, x̂_1 = z_1 + E[w]": 2 * np.exp(-np.arange(40) / 8) + 0.25,
        "|z_k − x_k|": rng.uniform(5, 9, (6, 40)),
        "|z_k + E[w] − x_k|": rng.uniform(0.5, 2.5, (6, 40)),
    }
    fig = plots.plot_step_errors(errors, end_labels=True)
    ax = fig.axes[0]
    _assert_told_apart(_line_keys(ax, set(errors)), len(errors))
    assert _direct_labels(ax) == set(errors)
    fig.savefig(io.BytesIO(), format="png")
    boxes = [t.get_window_extent() for t in ax.texts]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :]), (
        "two end labels overlap"
    )
    assert not plots.plot_step_errors(errors).axes[0].texts, "end labels only when asked"


def test_the_sweep_figure_tells_curves_and_lattices_apart_without_colour() -> None:
    fig = _sweep_peaks()
    ax = fig.axes[0]
    curves = {"steady tones, eq. (29)", "sweep, read as f(u)"}
    keys = _line_keys(ax, curves)
    assert len(keys) == 2 and len({dashes for dashes, _, _ in keys.values()}) == 2, keys
    assert _direct_labels(ax) == curves
    styles = {str(c.get_linestyle()) for c in ax.collections}
    assert len(ax.collections) == 2 and len(styles) == 2, styles


def test_the_image_bands_differ_in_hatch_and_are_named_beside_them() -> None:
    fig = _image_methods()
    for ax in fig.axes:
        hatches = [patch.get_hatch() for patch in ax.patches]
        assert len(hatches) == 2 and len(set(hatches)) == 2 and None not in hatches, hatches
        assert {text.split(":")[0] for text in _direct_labels(ax)} == {"vertex", "subdivision"}
    fig.savefig(io.BytesIO(), format="png")


def test_the_resonance_kinds_differ_in_line_style_or_marker() -> None:
    """Each legend entry of the resonances has its own (dash pattern, marker).

    The entries are detected, missed and spurious resonances and the lattice n c/(2L).
    """
    from dataclasses import replace

    _, det, setup = _detection()
    det = replace(det, missed=det.frequencies[:2] + 3.0, spurious=det.frequencies[:2] + 7.0)
    fig = plots.plot_resonances(det, true_frequencies=setup.resonances(PAPER_SWEEP.band)[1])
    legend = fig.axes[0].get_legend()
    keys = {
        text.get_text().split(" (")[0]: (str(handle.get_linestyle()), str(handle.get_marker()))
        for text, handle in zip(legend.get_texts(), legend.legend_handles, strict=True)
    }
    assert set(keys) == {"n c/(2L)", "detected z_k", "missed", "spurious"}, keys
    assert len(set(keys.values())) == 4, f"two kinds differ in colour only: {keys}"
    # the two kinds drawn as vertical lines: not both solid, and the spurious stems marked
    assert keys["n c/(2L)"][0] not in ("-", "solid"), keys
    assert keys["spurious"][1] not in ("None", "", " "), keys


# -- the examples of the docstrings ---------------------------------------------------------


@pytest.mark.parametrize(
    "name",
    [f"dstoolkit.plots.{info.name}" for info in __import__("pkgutil").iter_modules(plots.__path__)],
)
def test_docstring_examples_run(name: str) -> None:
    """Every example in the docstrings of dstoolkit.plots runs (Agg) and shows what it says.

    The examples run as doctests.
    """
    import doctest
    import importlib

    import matplotlib.pyplot as plt

    module = importlib.import_module(name)
    try:
        result = doctest.testmod(module, optionflags=doctest.ELLIPSIS, report=False)
    finally:
        plt.close("all")
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed"


#: The figures that name each series beside its data (direct labels), besides any legend.
_DIRECTLY_LABELLED = (
    "plot_estimates",
    "plot_table3",
    "plot_filter_errors",
    "plot_scale_study",
    "plot_order_rule_study",
    "plot_example",
    "plot_noise_assumption",
)


def _series(ax: Axes) -> list[tuple[str, np.ndarray]]:
    """Each labelled line or filled area of ``ax``: its label and its points (display)."""
    found = []
    for line in ax.get_lines():
        xy = np.asarray(line.get_xydata(), dtype=float)
        xy = xy[np.isfinite(xy).all(axis=1)]
        if not str(line.get_label()).startswith("_") and xy.size:
            found.append((str(line.get_label()), line.get_transform().transform(xy)))
    for coll in ax.collections:
        if not str(coll.get_label()).startswith("_") and coll.get_paths():
            xy = np.concatenate([p.vertices for p in coll.get_paths()])
            found.append((str(coll.get_label()), coll.get_transform().transform(xy)))
    return found


def _matches(text: str, label: str) -> bool:
    """Whether ``text`` names ``label``.

    The same, without its parenthesised notes, or its first words (a short name:
    "estimate" for "estimate x̂_k − x_k").
    """
    return (
        text == label or text == re.sub(r"\s+\([^)]*\)", "", label) or label.startswith(text + " ")
    )


def _beside(box: object, points: np.ndarray, area: object, spread: float) -> bool:
    """Whether a label's box is beside its series (display coordinates).

    Right of the data area level with the series' last point (within ``spread`` px), or
    within 30 px of one of its points.
    """
    at_end = box.x0 >= area.x1 and abs(0.5 * (box.y0 + box.y1) - points[-1, 1]) <= spread
    dx = np.maximum(0.0, np.maximum(box.x0 - points[:, 0], points[:, 0] - box.x1))
    dy = np.maximum(0.0, np.maximum(box.y0 - points[:, 1], points[:, 1] - box.y1))
    return bool(at_end or np.hypot(dx, dy).min() <= 30.0)


@pytest.mark.parametrize("name", _DIRECTLY_LABELLED)
def test_each_series_is_named_beside_its_data(name: str) -> None:
    """Every series of these figures has a visible text of its name near its data.

    Either right of the data area, level with the series' last point (within the spread
    the labels need to stay apart), or within 30 px of one of its points; no two overlap.
    """
    fig = FIGURES[name]()
    fig.savefig(io.BytesIO(), format="png")  # lays the texts out
    for ax in fig.axes:
        series = _series(ax)
        texts = [t for t in ax.texts if t.get_visible() and t.get_text().strip()]
        for label, points in series:
            boxes = [t.get_window_extent() for t in texts if _matches(t.get_text(), label)]
            assert boxes, f"{name}: no direct label for {label!r}"
            spread = len(series) * max(b.height for b in boxes)
            assert any(_beside(b, points, ax.get_window_extent(), spread) for b in boxes), (
                f"{name}: the label {label!r} is far from its data"
            )
        direct = [t.get_window_extent() for t in texts]
        assert not any(a.overlaps(b) for i, a in enumerate(direct) for b in direct[i + 1 :]), (
            f"{name}: two labels overlap"
        )
