"""The explorers of the chapters *Estimating the level* and *Beyond the paper*.

They are driven through a Jupyter kernel (nbclient).

Each explorer is built in a real kernel, a control is changed there, and the numbers it
prints and the figure it draws must follow:

* level_estimation_explorer (the paper's Figs. 10–11): moving the level from 4.6 m to 9.6 m
  changes the number of steps (37 → 82 orders n_k) and the figure's title; switching from
  eq. 43 to the true orders makes every order right and brings the direct level error
  from the ~0.2 m of wrong orders down to centimetres (the chapter's main finding).
* noise_bounds_explorer: shrinking the assumed bounds of w to a quarter about the mode
  makes the strict bounded-error filter fail in some runs (it never fails with the true
  bounds) and changes every evidential filter's error, while the Kalman filter, which
  sees only means and variances, changes too (its R is 16 times smaller).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import output_widget_mimes, printed_json

pytestmark = pytest.mark.slow
ROOT = Path(__file__).resolve().parents[1]

# The kernel keeps ipykernel's inline backend, as in JupyterLab and in the book build, so
# that the test sees what a reader sees: the figure must arrive as a PNG.
SETUP = """
import json
from dstoolkit.teaching import level_estimation_explorer, noise_bounds_explorer


def state(ex):
    numbers = dict(ex.numbers)
    fig = ex.figure
    numbers["title"] = fig.axes[0].get_title(loc='left') if fig is not None else None
    numbers["lines"] = sum(len(ax.lines) for ax in fig.axes) if fig is not None else 0
    numbers["xmax"] = max(ax.get_xlim()[1] for ax in fig.axes) if fig is not None else 0
    numbers["continuous_update"] = [getattr(c, "continuous_update", False)
                                    for c in ex.controls.values()]
    return json.dumps(numbers)
"""


@pytest.fixture(scope="module")
def states() -> dict[str, list]:
    level, noise = (
        "ex = level_estimation_explorer()\nprint(state(ex))",
        "nb = noise_bounds_explorer()\nprint(state(nb))",
    )
    got, nb = printed_json(
        [
            SETUP,
            level,
            'ex.controls["level"].value = 9.6\nex.controls["temperature"].value = 23.9\n'
            "print(state(ex))",
            'ex.controls["order_rule"].value = "true"\nprint(state(ex))',
            noise,
            'nb.controls["w_lower"].value = -7.8225\nnb.controls["w_upper"].value = -5.9775\n'
            "print(state(nb))",
        ]
    )
    got = got[1:]  # SETUP prints nothing
    return {"level": got[:3], "noise": got[3:], "shown": output_widget_mimes(nb)}


def test_the_figures_are_embedded_as_images(states) -> None:
    """Both explorers' Output widgets hold a PNG in the stored widget state.

    The page shows the figure without a kernel (and not as the text repr of a Figure).
    """
    shown = [mimes for mimes in states["shown"] if mimes]
    assert len(shown) == 2, states["shown"]
    assert all("image/png" in mimes for mimes in shown), shown


DIRECT = "direct"
PAPER = "paper's filter"


def mm(readout: str) -> float:
    """Return the mean level error of a readout entry "12.3 mm / 0.0456 Hz"."""
    level, _, _ = readout.partition(" mm / ")
    return float(level)


def test_level_explorer_first_state_is_the_papers_fig11_case(states) -> None:
    first = states["level"][0]
    assert "error" not in first, first
    assert "L = 4.6 m" in first["title"] and "eq43" in first["title"]
    assert first["wrong n_k"].endswith("/39")
    # i.i.d. triangular w: eq. 43 is wrong at most steps, each miss costs ~L/n ≈ 0.1 m
    wrong, total = map(int, first["wrong n_k"].split("/"))
    assert wrong > total // 2 and mm(first[DIRECT]) > 100
    sliders = [v for v in first["continuous_update"] if v is not False]
    # sliders follow the drag (the worker drops what it cannot keep up with)
    assert sliders and all(sliders), "sliders must follow the drag"


def test_moving_the_level_changes_the_figure_and_the_numbers(states) -> None:
    before, after = states["level"][0], states["level"][1]
    assert "error" not in after, after
    assert "L = 9.6 m" in after["title"] and after["title"] != before["title"]
    assert after["wrong n_k"].endswith("/82") and after["xmax"] > before["xmax"]
    assert after[DIRECT] != before[DIRECT] and after[PAPER] != before[PAPER]


def test_true_orders_bring_the_level_error_down_to_centimetres(states) -> None:
    eq43, true = states["level"][1], states["level"][2]
    assert true["wrong n_k"].startswith("0/")
    assert mm(true[DIRECT]) < 100 < mm(eq43[DIRECT])
    assert mm(true[PAPER]) < mm(true[DIRECT])


def test_tight_bounds_break_the_bounded_error_filter_only(states) -> None:
    true_bounds, tight = states["noise"]
    assert "error" not in tight, tight
    assert true_bounds["bounded error: inconsistent runs"] == "0%"
    assert tight["bounded error: inconsistent runs"] != "0%"
    for key in ("dependent evidence (paper) (Hz)", "Nassreddine (Hz)", "Kalman (Hz)"):
        assert tight[key] != true_bounds[key], key
    # the evidential filters keep going: finite errors, no exception shown in the readout
    assert all(isinstance(tight[k], float) for k in tight if k.endswith("(Hz)"))
