"""A slider's readout cannot show a value the explorer does not show (in a notebook).

A value typed into a float slider's readout reaches the kernel as the slider's new value
(the front end sets ``value``): here it is set the same way. The slider snaps it to the
nearest step within its range, and the explorer draws that value; a value that is no number
is refused and the slider, its readout and the figure keep theirs.
"""

from __future__ import annotations

import math

import ipywidgets as widgets
import pytest
import traitlets

from dstoolkit.teaching import gauge_explorer, mass_function_explorer
from dstoolkit.teaching._explorer import Explorer, StepSlider, slider


def _echo() -> tuple[Explorer, StepSlider]:
    def render(level: float):
        return None, {"level (m)": level}

    level = slider("level L (m)", 4.6, 1.0, 10.6, 0.1, readout_format=".1f")
    return Explorer({"level": level}, render, static=False), level


@pytest.mark.parametrize(
    ("typed", "snapped"),
    [
        (7.6, 7.6),  # on a step
        (7.63, 7.6),  # between two steps: the nearest
        (7.66, 7.7),
        (50.0, 10.6),  # beyond the range: its end
        (-3.0, 1.0),
    ],
)
def test_a_typed_value_snaps_to_the_nearest_step_and_everything_follows(
    typed: float, snapped: float
) -> None:
    ex, level = _echo()
    level.value = typed
    assert level.value == snapped
    # what the readout prints is what the explorer computed
    assert format(level.value, level.readout_format) == format(snapped, ".1f")
    assert ex.numbers == {"level (m)": snapped}


@pytest.mark.parametrize("typed", [math.nan, math.inf, "abc"])
def test_an_impossible_value_is_refused_and_nothing_moves(typed: object) -> None:
    ex, level = _echo()
    computed = ex.computed
    with pytest.raises(traitlets.TraitError):
        level.value = typed
    assert level.value == 4.6 and ex.numbers == {"level (m)": 4.6}
    assert ex.computed == computed  # nothing was drawn for it


def test_every_explorer_float_slider_snaps() -> None:
    for ex in (mass_function_explorer(), gauge_explorer()):
        for control in ex.controls.values():
            if isinstance(control, widgets.FloatSlider):
                assert isinstance(control, StepSlider), control.description


def test_the_gauge_follows_a_typed_level() -> None:
    ex = gauge_explorer()
    ex.controls["level"].value = 7.63  # typed between two steps of 0.1 m
    assert ex.controls["level"].value == 7.6
    # the series fit is within a few mm of the level drawn (tests/test_tube_and_detection.py)
    assert abs(ex.numbers["series-fit L (m)"] - 7.6) < 0.01
    assert "L = 7.6 m" in ex.figure.axes[0].get_title()
