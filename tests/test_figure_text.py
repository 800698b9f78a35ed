"""Text in the figures reads right: inside the canvas, and tick labels apart.

For every figure of the package's plotting functions used in the book and for every state
that an explorer precomputes for the static site, the window extent of every visible text
artist (titles, labels, tick labels, annotations, legend entries) must lie inside the
figure's canvas, and neighbouring tick labels of one axis must not overlap. The extents
come from the artists after a draw, as the saved picture shows them.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator

import matplotlib
import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.text import Text
from matplotlib.transforms import Bbox

matplotlib.use("Agg")

#: Pixels a text may poke out of the canvas or into its neighbour (antialiasing).
SLACK = 1.0


def _renderer(fig: Figure):
    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    fig.canvas.draw()
    return fig.canvas.get_renderer()


def _shown(text: Text) -> bool:
    if not text.get_visible() or not text.get_text().strip():
        return False
    parent = text.axes
    return parent is None or parent.get_visible()


def text_problems(fig: Figure) -> list[str]:
    """Texts outside the canvas and overlapping tick labels of ``fig``."""
    renderer = _renderer(fig)
    canvas = fig.bbox
    problems = []
    # tick labels count only for the ticks drawn (those in the view limits)
    all_ticks = {
        id(label)
        for ax in fig.axes
        for axis in (ax.xaxis, ax.yaxis)
        for tick in (*axis.majorTicks, *axis.minorTicks)
        for label in (tick.label1, tick.label2)
    }
    drawn_ticks = [
        label
        for ax in fig.axes
        if ax.get_visible()
        for axis in (ax.xaxis, ax.yaxis)
        for label in _drawn_tick_labels(axis)
    ]
    texts = [t for t in fig.findobj(Text) if id(t) not in all_ticks] + drawn_ticks
    for text in texts:
        if not _shown(text):
            continue
        box = text.get_window_extent(renderer)
        if (
            box.x0 < canvas.x0 - SLACK
            or box.y0 < canvas.y0 - SLACK
            or box.x1 > canvas.x1 + SLACK
            or box.y1 > canvas.y1 + SLACK
        ):
            problems.append(
                f"{text.get_text()!r} at {np.round(box.extents, 1)} leaves the "
                f"canvas {np.round(canvas.extents, 1)}"
            )
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        for axis in (ax.xaxis, ax.yaxis):
            labels = [t for t in _drawn_tick_labels(axis) if _shown(t)]
            boxes = [t.get_window_extent(renderer) for t in labels]
            pairs = itertools.combinations(zip(labels, boxes, strict=True), 2)
            for (a, box_a), (b, box_b) in pairs:
                if _overlap(box_a, box_b) and _glyphs_collide(a, box_a, b, box_b, fig.dpi):
                    problems.append(f"tick labels {a.get_text()!r} and {b.get_text()!r} overlap")
    return problems


def _drawn_tick_labels(axis) -> list[Text]:
    """Return the tick labels a draw shows: those of the ticks inside the view limits.

    Matplotlib keeps label artists for ticks outside them, which it skips when drawing.
    """
    if not axis.axes.axison or not axis.get_visible():
        return []
    ticks = axis._update_ticks()  # the ticks Axis.draw draws
    return [
        label
        for tick in ticks
        for label, on in (
            (tick.label1, tick.label1.get_visible()),
            (tick.label2, tick.label2.get_visible()),
        )
        if on
    ]


def _glyphs_collide(a: Text, box_a: Bbox, b: Text, box_b: Bbox, dpi: float) -> bool:
    """Whether two labels whose upright boxes overlap really collide.

    Level labels: yes. Labels turned by the same angle are parallel strips centred on their
    boxes' centres; they collide when the centres are less than a line height apart across
    the strips.
    """
    angle = np.deg2rad(a.get_rotation())
    if np.isclose(np.sin(angle), 0.0) or not np.isclose(a.get_rotation(), b.get_rotation()):
        return True
    normal = np.array([-np.sin(angle), np.cos(angle)])
    gap = abs(float(np.dot(np.subtract(box_b.p0 + box_b.p1, box_a.p0 + box_a.p1) / 2, normal)))
    return gap < 0.9 * max(a.get_fontsize(), b.get_fontsize()) * dpi / 72.0


def _overlap(a: Bbox, b: Bbox) -> bool:
    return min(a.x1, b.x1) - max(a.x0, b.x0) > SLACK and min(a.y1, b.y1) - max(a.y0, b.y0) > SLACK


# -- the checker catches what it must ------------------------------------------------------


def test_a_cut_label_is_caught() -> None:
    fig = Figure(figsize=(3, 2))
    ax = fig.add_axes((0.0, 0.2, 1.0, 0.7))  # no room for the y tick labels
    ax.set_ylim(-0.75, 0.25)
    assert any("leaves the canvas" in p for p in text_problems(fig))


def test_overlapping_categories_are_caught() -> None:
    fig = Figure(figsize=(2, 2), layout="constrained")
    ax = fig.add_subplot()
    ax.set_xticks(range(3), ["{meningitis}", "{tumour}", "{concussion}"])
    assert any("overlap" in p for p in text_problems(fig))


def test_a_tidy_figure_passes() -> None:
    fig = Figure(figsize=(4, 3), layout="constrained")
    ax = fig.add_subplot()
    ax.plot([0, 1], [-0.75, 0.25])
    ax.set_title("tidy")
    assert text_problems(fig) == []


# -- the explorers: every precomputed state --------------------------------------------------


def explorer_states(name: str) -> Iterator[tuple[str, Figure]]:
    """Yield every precomputed state of an explorer, drawn as the static site draws it.

    The explorer is built for the site (which renders every state, the start one last, and
    keeps the layout of the first), then each state is rendered again in the same order
    with the same kept figure and layouts.
    """
    from dstoolkit import teaching

    explorer = getattr(teaching, name)()
    assert explorer.static, "the explorer was not built for the static site"
    names = list(explorer.live)
    start = tuple(explorer.controls[n].value for n in names)
    yield f"{name} as built (start state)", explorer.figure
    combos = sorted(
        itertools.product(*(explorer.live[n] for n in names)), key=lambda combo: combo == start
    )
    for combo in combos:
        explorer.refresh(**dict(zip(names, combo, strict=True)))
        figure = getattr(explorer, "figure", None)
        if figure is not None:
            yield f"{name}{dict(zip(names, combo, strict=True))}", figure


EXPLORERS = [
    "mass_function_explorer",
    "conflict_explorer",
    "dependent_combination_explorer",
    "noise_evidence_explorer",
    "extension_explorer",
    "filter_step_explorer",
    "bounded_error_explorer",
    "consistency_explorer",
    "copies_explorer",
]


@pytest.mark.slow
@pytest.mark.parametrize("name", EXPLORERS)
def test_explorer_text_reads_right(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    from dstoolkit.plots import use_style
    from dstoolkit.teaching import STATIC_SITE_ENV

    monkeypatch.setenv(STATIC_SITE_ENV, "1")

    found, states = [], 0
    with matplotlib.rc_context():  # drawn as the book draws them: in the book's style
        use_style()
        for state, figure in explorer_states(name):
            states += 1
            found += [f"{state}: {p}" for p in text_problems(figure)]
    assert states > 0
    assert not found, "\n".join(found[:20])


# -- the figures of the package's plotting functions ----------------------------------------


def test_filter_step_figure_reads_right() -> None:
    from dstoolkit.plots import plot_filter_step
    from dstoolkit.studies import filter_case, gauge_case

    seq = gauge_case(9.6, 23.9, seed=0)
    _, _, result = filter_case(9.6, 23.9, start="mean_corrected", record=True, first=4)
    fig = plot_filter_step(result.steps[1], truth=seq.truth[1, 0])
    titles = [ax.get_title(loc="left") for ax in fig.axes]
    assert not any("_{" in t and "$" not in t for t in titles), titles  # no raw TeX
    assert text_problems(fig) == []


def test_estimates_figure_reads_right() -> None:
    from dstoolkit.plots import plot_estimates

    steps = np.arange(1, 41)
    truth = 1000.0 + 37.8 * steps
    fig = plot_estimates(
        truth, truth + 3.0, {"dependent_evidence": truth + 0.5, "nassreddine": truth - 0.4}
    )
    assert text_problems(fig) == []


# -- labels inside the axes clear of the marks ---------------------------------------------


def texts_over_marks(fig: Figure) -> list[str]:
    """Texts inside an axes (``ax.texts``) that lie over a line or a filled patch of it.

    Lines are sampled every pixel along their drawn path; a patch counts by its extent
    clipped to the axes (a band across the axes is a patch).
    """
    renderer = _renderer(fig)
    problems = []
    for ax in fig.axes:
        texts = [t for t in ax.texts if _shown(t)]
        if not texts:
            continue
        points = []
        for line in ax.get_lines():
            if not line.get_visible() or len(line.get_xdata()) < 1:
                continue
            xy = line.get_transform().transform(np.column_stack(line.get_data()))
            xy = xy[np.all(np.isfinite(xy), axis=1)]
            for a, b in itertools.pairwise(xy):
                steps = max(2, int(np.hypot(*(b - a))))
                points.append(a + np.linspace(0, 1, steps)[:, None] * (b - a))
            points.append(xy)
        sampled = np.concatenate(points) if points else np.empty((0, 2))
        patches = [
            Bbox.intersection(p.get_window_extent(renderer), ax.bbox)
            for p in ax.patches
            if p.get_visible() and p.get_fill()
        ]
        for text in texts:
            box = text.get_window_extent(renderer)
            inside = (
                (sampled[:, 0] > box.x0)
                & (sampled[:, 0] < box.x1)
                & (sampled[:, 1] > box.y0)
                & (sampled[:, 1] < box.y1)
            )
            if inside.any():
                problems.append(f"{text.get_text()!r} lies over a line")
            if any(p is not None and _overlap(box, p) for p in patches):
                problems.append(f"{text.get_text()!r} lies over a filled band")
    return problems


def test_a_label_over_a_line_is_caught() -> None:
    fig = Figure(figsize=(4, 3))
    ax = fig.subplots()
    ax.plot([0, 1], [0, 1])
    ax.text(0.5, 0.5, "98 %", ha="center", va="center")
    assert texts_over_marks(fig) == ["'98 %' lies over a line"]
    ax.texts[0].set_position((0.9, 0.1))
    assert texts_over_marks(fig) == []


def test_image_methods_labels_clear_the_bands_and_curves() -> None:
    from dstoolkit.plots import plot_image_methods
    from dstoolkit.teaching import compare_image_methods

    cases = {
        "x²": (lambda x: x[..., 0] ** 2, -1.0, 2.0),
        "sin x": (lambda x: np.sin(x[..., 0]), 0.0, 3.0),
    }
    images = {
        name: {
            m: compare_image_methods(f, lo, hi, +1)[m]["image"] for m in ("subdivision", "vertex")
        }
        for name, (f, lo, hi) in cases.items()
    }
    fig = plot_image_methods({n: (f, lo, hi, images[n]) for n, (f, lo, hi) in cases.items()})
    assert texts_over_marks(fig) == [] and text_problems(fig) == []
    # the box is named (in the title), and each band by its method at the right
    titles = [ax.get_title(loc="left") for ax in fig.axes]
    assert titles == [
        "f(x) = x², thick on the box [-1, 2]",
        "f(x) = sin x, thick on the box [0, 3]",
    ]


def test_scale_study_writes_the_failures_clear_of_the_lines() -> None:
    from dstoolkit.plots import plot_scale_study
    from dstoolkit.studies import bound_scale_study, tracking_data

    study = bound_scale_study(
        tracking_data(runs=4), [0.3, 1.0, 2.0], methods=("kalman", "bounded_error", "particle")
    )
    assert study[0.3].inconsistent_runs > 0  # a scale whose failures are written
    fig = plot_scale_study(study)
    assert texts_over_marks(fig) == [] and text_problems(fig) == []
    ax = fig.axes[0]
    _renderer(fig)
    labels = [t.get_text() for t in _drawn_tick_labels(ax.xaxis)]
    assert labels[0] == f"0.3\n{study[0.3].inconsistent_runs:.0%} failed", labels
    assert labels[1:] == ["1", "2"]


def test_a_table_names_every_column():
    """A blank header cell leaves a screen reader nothing to say: markdown_table refuses it."""
    from dstoolkit.errors import InvalidInputError
    from dstoolkit.plots import markdown_table

    with pytest.raises(InvalidInputError, match="column 2 is blank"):
        markdown_table(["evidence", " ", "Bel"], [("E1", 0.1, 0.2)])
    assert markdown_table(["evidence", "Bel"], [("E1", 0.25)]).data.startswith("| evidence | Bel |")
