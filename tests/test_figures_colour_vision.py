"""The noise-bounds explorer's figure and the bounds-scaling chart without colour vision.

Both are drawn, then every colour of their series is seen as with protanopia and with
deuteranopia (tests/colour_vision.py: Machado et al. 2009, ΔE2000). Series that come
close in colour must differ in line style or marker, and every line is named at its end
(a direct label): no series is told apart by colour or by a legend only. The bounds-scaling
chart's mark of a failed bounded-error filter must stand out from every line.
"""

from __future__ import annotations

import itertools

import numpy as np
from colour_vision import DEFICIENCIES, seen_difference
from matplotlib.colors import to_hex

from dstoolkit.filters import BoundedNoise, registered_filters
from dstoolkit.plots import STYLE, plot_scale_study
from dstoolkit.plots._style import END_LABEL_GID
from dstoolkit.plots.artists import noise_bounds_figure, update_noise_bounds_figure
from dstoolkit.studies import MismatchResult

#: ΔE2000 of about 20 or more: two colours a viewer tells apart at a glance on a thin line
#: (10 is a noticeable difference between patches; a plot's strokes need more).
DISTINCT_DE = 20.0

METHODS = [entry.name for entry in registered_filters()]


def _errors(scale: float = 1.0) -> dict[str, np.ndarray]:
    steps = np.arange(1, 41)
    return {
        name: scale * (1.0 + i) * (1.0 + 1.0 / steps) * np.ones((2, steps.size))
        for i, name in enumerate(METHODS)
    }


def _looks(line) -> tuple[str, str, str]:
    return to_hex(line.get_color()), str(line.get_linestyle()), str(line.get_marker())


def _check_told_apart(lines, where: str) -> None:
    for a, b in itertools.combinations(lines, 2):
        (colour_a, ls_a, mk_a), (colour_b, ls_b, mk_b) = _looks(a), _looks(b)
        styled_apart = ls_a != ls_b or mk_a != mk_b
        for deficiency in DEFICIENCIES:
            de = seen_difference(colour_a, colour_b, deficiency)
            assert de >= DISTINCT_DE or styled_apart, (
                f"{where}: {a.get_label()!r} and {b.get_label()!r} look alike with "
                f"{deficiency} (ΔE2000 {de:.1f}) and share line style and marker"
            )
        assert styled_apart, f"{where}: {a.get_label()!r}, {b.get_label()!r}: same style"


def _end_labels(ax) -> list[str]:
    return [t.get_text() for t in ax.texts if t.get_gid() == END_LABEL_GID and t.get_visible()]


def test_the_noise_bounds_figure_names_every_filter_at_its_line() -> None:
    noise_v, noise_w = BoundedNoise(-0.3, 0.0, 0.3), BoundedNoise(-10.59, -6.9, -3.21)
    fig = noise_bounds_figure(
        noise_v,
        noise_w,
        noise_v,
        BoundedNoise(-10.0, -6.9, -4.0),
        _errors(),
        title="test",
        v_range=(-1.0, 1.0),
        w_range=(-20.0, 5.0),
    )
    ax = fig.axes[2]
    lines = list(ax.lines)
    assert len(lines) == len(METHODS) >= 5
    _check_told_apart(lines, "noise-bounds explorer")
    named = _end_labels(ax)
    for line in lines:
        label = str(line.get_label())
        assert any(label.startswith(text) or text.startswith(label) for text in named), (
            label,
            named,
        )


def test_the_noise_bounds_labels_follow_the_lines() -> None:
    """A new assumption moves the lines; their names move with them."""
    noise_v, noise_w = BoundedNoise(-0.3, 0.0, 0.3), BoundedNoise(-10.59, -6.9, -3.21)
    args = (noise_v, noise_w, noise_v, noise_w)
    fig = noise_bounds_figure(
        *args, _errors(), title="t", v_range=(-1.0, 1.0), w_range=(-20.0, 5.0)
    )
    ax = fig.axes[2]
    before = [t.get_position() for t in ax.texts if t.get_gid() == END_LABEL_GID]
    errors = _errors()
    errors[METHODS[0]] = errors[METHODS[0]] * 50.0  # the first line moves far up
    update_noise_bounds_figure(fig, *args, errors)
    after = [t.get_position() for t in ax.texts if t.get_gid() == END_LABEL_GID]
    assert after[0] != before[0]


def test_the_bounds_scaling_chart_marks_failures_apart_from_every_line() -> None:
    scales = (0.5, 1.0, 2.0)
    study = {
        s: MismatchResult(
            errors=_errors(s), seconds=dict.fromkeys(METHODS, 0.0),
            inconsistent_runs=0.5 if s < 1 else 0.0,
        )
        for s in scales
    }  # fmt: skip
    fig = plot_scale_study(study)
    ax = fig.axes[0]
    methods = [
        line for line in ax.lines if line.get_label() in {STYLE[m]["label"] for m in METHODS}
    ]
    assert len(methods) == len(METHODS)
    _check_told_apart(methods, "bounds-scaling chart")
    assert len(_end_labels(ax)) == len(METHODS)
    (failed,) = [line for line in ax.lines if "failed" in str(line.get_label())]
    mark = to_hex(failed.get_markerfacecolor())
    for line in methods:
        for deficiency in DEFICIENCIES:
            de = seen_difference(mark, line.get_color(), deficiency)
            assert de >= DISTINCT_DE, (
                f"the failure mark looks like {line.get_label()!r} with {deficiency} "
                f"(ΔE2000 {de:.1f})"
            )
    assert failed.get_marker() not in {line.get_marker() for line in methods}


def test_the_check_fails_on_the_old_red_cross() -> None:
    """Red on the Kalman line's vermillion, as the chart drew it, is what the audit found."""
    assert seen_difference("red", STYLE["kalman"]["color"], "deuteranopia") < DISTINCT_DE
