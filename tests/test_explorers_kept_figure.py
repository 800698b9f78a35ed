"""The evidence explorers keep their figure and update its artists on every change.

After any path of changes the kept figure shows what a freshly built explorer shows at the same
values (the static site precomputes its states on one kept figure), and an invalid setting leaves
the last figure alone.
"""

from __future__ import annotations

import io

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.collections import Collection, LineCollection
from matplotlib.figure import Figure
from matplotlib.legend import Legend
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.text import Text

from dstoolkit import teaching as w

matplotlib.use("Agg")

#: explorer → (changes made one after the other, start values of a fresh explorer that
#: shows the state they end in). The paths pass through states with more focal elements,
#: bars, cuts or labels than the start and the end (and end with fewer than the start where
#: they can), and through a method that refuses.
PATHS = {
    "mass_function_explorer": (
        [
            ("mid", 0.2),
            ("low", 0.0),
            ("low_mid", 0.0),
            ("high", 0.0),
            ("mid", 0.0),
            ("low", 0.5),
            ("low_mid", 0.3),
        ],
        {"low": 0.5, "mid": 0.0, "high": 0.0, "low_mid": 0.3},
    ),
    "conflict_explorer": (
        [("epsilon", 0.2), ("rule", "Yager"), ("y", 0.7), ("x", 1.0), ("epsilon", 0.0)],
        {"x": 1.0, "y": 0.7, "epsilon": 0.0, "rule": "Yager"},
    ),
    "dependent_combination_explorer": (
        [("a2", 0.0), ("mass_rule", "m1"), ("b2", 0.0), ("a3", 0.4), ("b2", 0.15), ("a2", 0.45)],
        {"a2": 0.45, "a3": 0.4, "b2": 0.15, "b3": 0.6, "mass_rule": "m1"},
    ),
    "noise_evidence_explorer": (
        [
            ("p", 9),
            ("upper", 0.45),
            ("mode", 0.1),
            ("p", 2),
            ("epsilon", 0.2),
            ("p", 5),
            ("upper", 0.3),
        ],
        {"mode": 0.1, "p": 5, "epsilon": 0.2},
    ),
    "extension_explorer": (
        [
            ("function", "x²"),
            ("lo", -1.0),
            ("sign", -1),
            ("function", "exp(−x)"),
            ("hi", 3.5),
            ("function", "x³ − 3x"),
            ("sign", 1),
        ],
        {"function": "x³ − 3x", "lo": -1.0, "hi": 3.5, "sign": 1},
    ),
}

#: explorer → a valid change, then one that makes the setting invalid, and words of the
#: message.
INVALID = {
    "mass_function_explorer": (("low", 0.2), ("mid", 0.9), "> 1"),
    "conflict_explorer": (("x", 0.95), ("y", 1.0), "total conflict"),
    "dependent_combination_explorer": (("b2", 0.1), ("a3", 0.9), "> 1"),
    "noise_evidence_explorer": (("p", 5), ("mode", 0.5), "lower <= mode <= upper"),
    "extension_explorer": (("function", "x²"), ("lo", 3.5), "lo > hi"),
}


def _data(artist: object) -> tuple:
    """Return what an artist shows: its geometry in data coordinates, colours, text, visibility."""
    if isinstance(artist, Line2D):
        x, y = artist.get_data()
        return (
            "line",
            np.asarray(x, float),
            np.asarray(y, float),
            artist.get_color(),
            artist.get_linewidth(),
            artist.get_linestyle(),
        )
    if isinstance(artist, Text):
        return (
            "text",
            artist.get_text(),
            tuple(np.asarray(artist.get_position(), float)),
            artist.get_fontsize(),
            artist.get_color(),
        )
    if isinstance(artist, LineCollection):
        return (
            "lines",
            [np.asarray(s) for s in artist.get_segments()],
            np.asarray(artist.get_color()),
        )
    if isinstance(artist, Collection):
        return (
            "collection",
            [p.vertices for p in artist.get_paths()],
            np.asarray(artist.get_offsets()),
            np.asarray(artist.get_facecolor()),
        )
    if isinstance(artist, Patch):
        corners = artist.get_patch_transform().transform(artist.get_path().vertices)
        return ("patch", corners, tuple(artist.get_facecolor()), tuple(artist.get_edgecolor()))
    if isinstance(artist, Legend):
        return ("legend", [t.get_text() for t in artist.get_texts()])
    return (type(artist).__name__,)


def signature(fig: Figure) -> list:
    """Every axes' titles, ranges, ticks, labels and visible artists (by kind, in order)."""
    out = []
    for ax in fig.axes:
        shown = [
            a
            for a in ax.get_children()
            if a.get_visible()
            and a
            not in (
                ax.patch,
                ax.xaxis,
                ax.yaxis,
                ax.title,
                ax._left_title,
                ax._right_title,
                *ax.spines.values(),
            )
        ]
        kinds = sorted({type(a).__name__ for a in shown})
        out.append(
            {
                "titles": [ax.get_title(loc) for loc in ("left", "center", "right")],
                "limits": (ax.get_xlim(), ax.get_ylim()),
                "labels": (ax.get_xlabel(), ax.get_ylabel()),
                "ticks": [
                    (list(axis.get_ticklocs()), [t.get_text() for t in axis.get_ticklabels()])
                    for axis in (ax.xaxis, ax.yaxis)
                ],
                **{kind: [_data(a) for a in shown if type(a).__name__ == kind] for kind in kinds},
            }
        )
    return out


def assert_same(a: object, b: object, where: str = "") -> None:
    """Equal nested structures, floats and arrays to 1e-12."""
    if isinstance(a, dict):
        assert a.keys() == b.keys(), where
        for key in a:
            assert_same(a[key], b[key], f"{where}.{key}")
    elif isinstance(a, list | tuple):
        assert len(a) == len(b), f"{where}: {len(a)} != {len(b)}"
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            assert_same(x, y, f"{where}[{i}]")
    elif isinstance(a, np.ndarray | float | np.floating):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12, err_msg=where)
    else:
        assert a == b, f"{where}: {a!r} != {b!r}"


def whole(fig: Figure, like: Figure | None = None) -> np.ndarray:
    """Draw ``fig`` whole, its animated artists in order of zorder among the others.

    As saved; with the axes where ``like`` has them (no layout pass) if given.
    """
    if like is not None:
        fig.set_layout_engine("none")
        for ax, other in zip(fig.axes, like.axes, strict=True):
            ax.set_position(other.get_position())
    buffer = io.BytesIO()
    fig.savefig(buffer, format="rgba", dpi=fig.dpi)
    width, height = fig.canvas.get_width_height()
    return np.frombuffer(buffer.getvalue(), np.uint8).reshape(height, width, 4)


@pytest.mark.parametrize("name", list(PATHS))
def test_kept_figure_after_changes_equals_a_fresh_one(name):
    changes, start = PATHS[name]
    ex = getattr(w, name)()
    kept = ex.figure
    pyplot_figures = plt.get_fignums()
    for control, value in changes:
        ex.controls[control].value = value
        assert "error" not in ex.numbers, (control, value, ex.numbers)
        assert ex.figure is kept, "the explorer made a new figure instead of updating"
    assert plt.get_fignums() == pyplot_figures, "a pyplot figure was left open"
    fresh = getattr(w, name)(**start)
    assert fresh.values() == ex.values()
    assert fresh.numbers == ex.numbers
    assert_same(signature(kept), signature(fresh.figure), name)
    ex.png(kept)  # as shown: the animated artists drawn on the rest as last drawn
    shown = np.asarray(kept.canvas.buffer_rgba()).copy()
    assert kept.findobj(lambda artist: artist.get_animated()), "nothing is animated"
    assert np.array_equal(shown, whole(kept)), "blitting changed the picture"
    fresh.png(fresh.figure)
    assert np.array_equal(whole(kept), whole(fresh.figure, like=kept))


@pytest.mark.parametrize("name", list(INVALID))
def test_invalid_setting_warns_and_keeps_the_last_figure(name):
    (valid, first), (control, value), words = INVALID[name]
    ex = getattr(w, name)()
    ex.controls[valid].value = first
    assert "error" not in ex.numbers
    before, shown = signature(ex.figure), ex.output.outputs
    kept, previous = ex.figure, ex.controls[control].value
    ex.controls[control].value = value
    assert words in ex.numbers["error"]
    assert "⚠" in ex.readout.value and "last valid setting" in ex.readout.value
    assert ex.figure is kept and ex.output.outputs == shown
    assert_same(signature(kept), before, name)
    ex.controls[control].value = previous  # valid again: redrawn, the same picture
    assert "error" not in ex.numbers and ex.output.outputs is not shown
    assert ex.figure is kept and ex.output.outputs == shown
    assert_same(signature(kept), before, name)
