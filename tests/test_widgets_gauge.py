"""The gauge explorer (dstoolkit.teaching.gauge_explorer) driven through a Jupyter kernel.

The explorer is built in a real kernel (nbclient), a slider is moved there, and the numbers
it prints and the figure it draws must follow: moving the level from 4.6 m to 9.6 m must
move the series-fit level by the same 5 m (within 1 cm: the fit is within a few mm of the
truth at both levels, see tests/test_tube_and_detection.py), change the number of
resonances in the 1000–2400 Hz sweep (37 → about 75) and the figure's title.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import printed_json

pytestmark = pytest.mark.slow
ROOT = Path(__file__).resolve().parents[1]


BUILD = """
import json
import matplotlib
matplotlib.use("Agg")
from dstoolkit.teaching import gauge_explorer

ex = gauge_explorer()


def state():
    numbers = dict(ex.numbers)
    numbers["title"] = ex.figure.axes[0].get_title() if ex.figure is not None else None
    numbers["continuous_update"] = [c.continuous_update for c in ex.controls.values()]
    return json.dumps(numbers)


print(state())
"""


@pytest.fixture(scope="module")
def states() -> list[dict]:
    return printed_json(
        [
            BUILD,
            'ex.controls["level"].value = 9.6\nex.controls["temperature"].value = 23.9\n'
            "print(state())",
            'ex.controls["background"].value = 100.0\nprint(state())',
        ]
    )[0]


def test_first_state_is_the_papers_fig6_case(states: list[dict]) -> None:
    first = states[0]
    assert "error" not in first, first
    assert abs(first["series-fit L (m)"] - 4.6) < 0.01
    assert first["resonances"] == 37 and first["missed"] == 0 and first["spurious"] == 0
    assert "L = 4.6 m" in first["title"]
    # every slider follows the drag (the worker drops what it cannot keep up with)
    assert first["continuous_update"] == [True, True, True, True]


def test_moving_the_level_slider_changes_the_estimate_and_the_figure(states: list[dict]) -> None:
    before, after = states[0], states[1]
    assert "error" not in after, after
    moved = after["series-fit L (m)"] - before["series-fit L (m)"]
    assert abs(moved - 5.0) < 0.01, (before, after)
    assert after["resonances"] > 70 > before["resonances"]
    assert after["title"] != before["title"] and "L = 9.6 m" in after["title"]
    # eq. 43 goes wrong on the long tube (chapter: about a third of the orders)
    wrong, total = map(int, after["eq. 43 orders wrong"].split("/"))
    assert total == after["resonances"] - 1 and wrong >= 5


def test_a_loud_background_brings_spurious_peaks(states: list[dict]) -> None:
    quiet, loud = states[1], states[2]
    assert quiet["spurious"] == 0 and loud["spurious"] > 0
    assert abs(loud["series-fit L (m)"] - 9.6) < 0.02
