"""Figures of the paper's results.

Fig. 10 (frequency estimates and errors per step), Fig. 11 (level estimates and errors per
step) and Table 3 as a picture.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.text import Text

from dstoolkit.errors import InvalidInputError
from dstoolkit.filters import registered_filters
from dstoolkit.studies import TABLE3_MEAN_ABS_ERROR_M, Table3

from ._kept import animate, set_limits, snapped_limits
from ._style import (
    END_LABEL_GID,
    OKABE_ITO,
    label_line_ends,
    log_ticks,
    new_figure,
    place_line_end_labels,
    styled,
)

#: The style of the readings' direct estimate (eq. 32), which is not a filter.
DIRECT_STYLE: dict[str, Any] = {
    "color": OKABE_ITO["bluish green"],
    "ls": ":",
    "marker": "^",
    "label": "direct (eq. 32)",
}


class _Styles(Mapping[str, dict[str, Any]]):
    """Each method's colour, line style, marker and label, read from the filters' registry.

    The registered filters (:func:`dstoolkit.filters.registered_filters`, read at each
    look-up, so a filter registered later is styled too), and ``"direct"``.
    """

    def _all(self) -> dict[str, dict[str, Any]]:
        styles = {
            entry.name: {
                "color": OKABE_ITO.get(entry.colour, entry.colour),
                "ls": entry.line_style,
                "marker": entry.marker,
                "label": entry.label,
            }
            for entry in registered_filters()
        }
        return {**styles, "direct": dict(DIRECT_STYLE)}

    def __getitem__(self, name: str) -> dict[str, Any]:
        return self._all()[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._all())

    def __len__(self) -> int:
        return len(self._all())


#: Colour (Okabe–Ito), line style, marker and label of each method in every figure: the
#: methods differ in line style and marker as well as in colour, so they can be told apart
#: without colour (in grey print, or with a colour-vision deficiency). The filters' come
#: from their registry (:func:`dstoolkit.filters.register_filter`).
STYLE: Mapping[str, dict[str, Any]] = _Styles()
#: Styles of curves that are not one of STYLE's methods (variants of a method), in order.
EXTRA_STYLES: tuple[dict[str, Any], ...] = (
    {"color": OKABE_ITO["black"], "ls": (0, (1, 1)), "marker": "x"},
    {"color": OKABE_ITO["blue"], "ls": (0, (6, 2, 1, 2)), "marker": "*"},
    {"color": OKABE_ITO["vermillion"], "ls": (0, (2, 2)), "marker": "h"},
    {"color": OKABE_ITO["bluish green"], "ls": (0, (8, 2)), "marker": "<"},
)
#: Markers on a line at about this fraction of the axes' diagonal apart (``markevery``).
MARK_EVERY = 0.1


def _style(name: str) -> dict[str, Any]:
    return STYLE.get(name, {"color": "k", "ls": "-", "marker": "", "label": name})


def line_style(st: Mapping[str, Any]) -> dict[str, Any]:
    """Return the keyword arguments of ``Axes.plot`` that draw a method of :data:`STYLE`.

    Or of :data:`EXTRA_STYLES`: colour, line style, and markers spaced along the line.
    """
    return {
        "color": st["color"],
        "ls": st.get("ls", "-"),
        "marker": st.get("marker", ""),
        "markevery": MARK_EVERY,
        "ms": 4,
    }


def plot_table3(table: Table3) -> Figure:
    """Plot the mean absolute level error against the level, ours and the paper's.

    Ours solid with filled markers, the paper's dashed with open markers; each method has
    its own marker and colour.

    Parameters
    ----------
    table : dstoolkit.studies.Table3
        The result of :func:`dstoolkit.studies.run_table3`.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (not attached to pyplot).

    References
    ----------
    The paper's Table 3.

    Examples
    --------
    >>> from dstoolkit.studies import run_table3
    >>> table = run_table3(runs=1, methods=("direct",), cases=((1.3, 27.0),), progress=False)
    >>> plot_table3(table).axes[0].get_xlabel()
    'true level L (m)'
    """
    fig = new_figure(6.4, 4.4)
    ax = fig.add_subplot()
    methods = list(dict.fromkeys(r.method for r in table.rows))
    for m in methods:
        rows = [r for r in table.rows if r.method == m]
        st = _style(m)
        ax.plot(
            [r.level_m for r in rows],
            [r.mean_abs_error_m for r in rows],
            ls="-",
            marker=st["marker"] or "o",
            color=st["color"],
            label=f"{st['label']}, ours",
        )
        paper = [(lv, v[m]) for lv, v in TABLE3_MEAN_ABS_ERROR_M.items() if m in v]
        if paper:
            ax.plot(
                *zip(*paper, strict=True),
                ls="--",
                marker=st["marker"] or "s",
                color=st["color"],
                alpha=0.6,
                mfc="none",
                label=f"{st['label']}, paper",
            )
    ax.set_yscale("log")
    log_ticks(ax.yaxis)
    ax.set_xlabel("true level L (m)")
    ax.set_ylabel("mean |L̂ − L| (m)")
    ax.set_title(
        f"Table 3: {table.simulation}-level simulation, n_k by {table.order_rule}",
        pad=4,
        loc="left",
    )
    ax.grid(True, which="both", alpha=0.3)
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncols=2)
    label_line_ends(ax, short=True)
    return fig


@styled
def plot_estimates(
    truth: np.ndarray,
    readings: np.ndarray,
    estimates: Mapping[str, np.ndarray],
    *,
    quantity: str = "frequency",
    unit: str = "Hz",
    note: str = "",
    kept: bool = False,
) -> Figure:
    """Fig. 10 / Fig. 11: (a) estimates, truth and readings per step; (b) absolute errors.

    ``truth`` and ``readings`` have one value per step (or a scalar truth for a level);
    ``estimates`` maps method names to one value per step. When the truth changes from
    step to step (the resonances of Fig. 10 climb by f_F each), panel (a) shows every
    curve minus the truth: on the raw scale they would all lie on one diagonal. A ``note``
    follows panel (a)'s title (in a smaller font). ``update_estimates`` draws other values
    on the figure; a figure that an explorer keeps (``kept``) has its data and title
    animated and its limits snapped to round numbers (``snapped_limits``), so that most
    changes redraw only those (blitting).

    Parameters
    ----------
    truth : numpy.ndarray or float
        Shape (K,), or a scalar: the true value per step (unit ``unit``).
    readings : numpy.ndarray
        Shape (K,): the readings z_k.
    estimates : collections.abc.Mapping
        Method name (a key of ``STYLE`` or any name) to its estimates, shape (K,).
    quantity : str, optional
        What is estimated, for the titles and labels.
    unit : str, optional
        Its unit.
    note : str, optional
        Written after panel (a)'s title.
    kept : bool, optional
        Whether an explorer keeps the figure and redraws it (animated data).

    Returns
    -------
    matplotlib.figure.Figure
        Two panels, (a) and (b) (not attached to pyplot).

    References
    ----------
    The paper's Figs. 10 and 11.

    Examples
    --------
    >>> import numpy as np
    >>> truth = np.full(5, 4.6)
    >>> fig = plot_estimates(truth, truth + 0.1, {"direct": truth - 0.05}, quantity="level",
    ...                      unit="m")
    >>> len(fig.axes)
    2
    """
    fig = new_figure(6.4, 5.6)
    ax_a, ax_b = fig.subplots(2, 1, sharex=True)
    ax_a.plot([], [], "k-", lw=1.5, label="true")
    for ax in (ax_a, ax_b):
        ax.plot([], [], ".", color="0.5", ms=4, label="readings / direct")
    for name in estimates:
        st = _style(name)
        for ax in (ax_a, ax_b):
            ax.plot([], [], lw=1, label=st["label"], **line_style(st))
    ax_b.set_yscale("log")
    log_ticks(ax_b.yaxis)
    ax_b.set_xlabel("step k")
    # y = 1 where matplotlib would put the titles (nothing is drawn above the panels), so
    # that a draw skips the search for it (a tight box of each panel's y axis)
    ax_a.set_title("", y=1.0)
    ax_b.set_title("(b) absolute errors", loc="left", y=1.0)
    for ax in (ax_a, ax_b):
        ax.grid(True, alpha=0.3)
    fig.legend(*ax_a.get_legend_handles_labels(), loc="outside lower center", ncols=3)
    for ax in (ax_a, ax_b):  # each series named at its end; update_estimates moves them
        label_line_ends(ax, short=True)
    if kept:  # set_title re-places all three titles: none may mark the figure stale
        animate(*ax_a.lines, *ax_b.lines, *ax_a.texts, *ax_b.texts, ax_a.title, *_side_titles(ax_a))
    update_estimates(fig, truth, readings, estimates, quantity=quantity, unit=unit, note=note)
    return fig


def _side_titles(ax: Axes) -> list[Text]:
    """Return the left and right titles of ``ax`` (set_title returns them; it sets them too)."""
    return [ax.set_title(ax.get_title(loc), loc=loc) for loc in ("left", "right")]


@styled
def update_estimates(
    fig: Figure,
    truth: np.ndarray,
    readings: np.ndarray,
    estimates: Mapping[str, np.ndarray],
    *,
    quantity: str = "frequency",
    unit: str = "Hz",
    note: str = "",
) -> None:
    """Draw other values on a figure of :func:`plot_estimates` made for the same methods.

    ``estimates`` with the same names, in the same order: data, limits, labels.
    """
    ax_a, ax_b = fig.axes[:2]
    true_line, reading_a, *est_a = ax_a.lines
    reading_b, *est_b = ax_b.lines
    if len(est_a) != len(estimates):
        raise InvalidInputError(
            f"this figure draws {len(est_a)} methods, not "
            f"{len(estimates)}: make a new one with plot_estimates"
        )
    steps = np.arange(1, np.size(readings) + 1)
    truth = (
        np.broadcast_to(np.asarray(truth, dtype=float).reshape(-1), steps.shape)
        if np.size(truth) in (1, steps.size)
        else np.asarray(truth)
    )
    moving = bool(np.ptp(truth) > 0)
    ref = truth if moving else np.zeros_like(truth)
    true_line.set_data(steps, truth - ref)
    reading_a.set_data(steps, np.asarray(readings) - ref)
    reading_b.set_data(steps, np.abs(np.asarray(readings) - truth))
    for line_a, line_b, est in zip(est_a, est_b, estimates.values(), strict=True):
        est = np.asarray(est, dtype=float).reshape(-1)
        line_a.set_data(steps[: est.size], est - ref[: est.size])
        line_b.set_data(steps[: est.size], np.abs(est - truth[: est.size]))
    title = (
        f"(a) estimated {quantity}"
        + (", minus the truth" if moving else "")
        + (f": {note}" if note else "")
    )
    for ax, label in (
        (ax_a, f"{quantity} − true ({unit})" if moving else f"{quantity} ({unit})"),
        (ax_b, f"|error| ({unit})"),
    ):
        if ax.get_ylabel() != label:  # an unchanged label would mark the figure stale
            ax.set_ylabel(label)
    if ax_a.get_title(loc="left") != title:
        smaller: dict[str, Any] = {"fontsize": 9} if note else {}
        ax_a.set_title(title, loc="left", **smaller)
    if not true_line.get_animated():
        for ax in (ax_a, ax_b):
            ax.relim()
            ax.autoscale_view()
        _place_end_labels(ax_a, ax_b)
        return
    a = np.concatenate([line.get_ydata() for line in ax_a.lines])
    b = np.concatenate([line.get_ydata() for line in ax_b.lines])
    b = b[b > 0]
    set_limits(
        ax_a,
        x=snapped_limits(1.0, float(steps[-1])),
        y=snapped_limits(float(np.nanmin(a)), float(np.nanmax(a))),
    )
    if b.size:
        set_limits(ax_b, y=snapped_limits(float(np.nanmin(b)), float(np.nanmax(b)), log=True))
    _place_end_labels(ax_a, ax_b)


def _place_end_labels(*axes: Axes) -> None:
    """Move each axes' end labels level with the new ends of their lines."""
    for ax in axes:
        texts = [t for t in ax.texts if t.get_gid() == END_LABEL_GID]
        lines = [line for line in ax.lines if not str(line.get_label()).startswith("_")]
        place_line_end_labels(ax, lines, texts)
