"""What an explorer's state says: one short sentence per change, a figure described in words.

On the static site each precomputed state carries the sentence the page announces when the
state is shown (the control's value and the one or two results that moved) and a text
alternative saying what its figure shows. Both are checked here for every explorer's
start state.
"""

from __future__ import annotations

import re

import matplotlib
import pytest

from dstoolkit import teaching
from dstoolkit.teaching._explorer import shown_value

matplotlib.use("Agg")

#: At most this many words per announced change: a sentence a screen reader says in
#: about five seconds (the audit heard about 45 words per arrow press before).
MAX_WORDS = 25

EXPLORERS = sorted(
    name
    for name in teaching.__all__
    if name.endswith(("_explorer", "_widget")) and name != "lab_widget"
)


@pytest.fixture(scope="module", params=EXPLORERS)
def explorer(request: pytest.FixtureRequest):
    return getattr(teaching, request.param)()


def _settings(ex) -> dict[str, str]:
    return {
        ex.controls[name].description: shown_value(ex.controls[name], ex.controls[name].value)
        for name in ex.live
    }


@pytest.mark.slow
def test_a_change_is_said_in_one_short_sentence(explorer) -> None:
    settings, numbers = _settings(explorer), explorer.numbers
    sentence = explorer.change_sentence(settings, numbers)
    assert len(sentence.split()) <= MAX_WORDS, sentence
    assert sentence.endswith(".") and "\n" not in sentence, sentence
    # the live controls' values come first, then at least one result of the state
    for label, shown in settings.items():
        assert shown in sentence, (label, sentence)
    said = explorer._said or tuple(numbers)[:2]
    assert all(name in numbers for name in said), (said, list(numbers))


@pytest.mark.slow
def test_the_figure_is_described_in_words_not_every_number(explorer) -> None:
    (alt, *_) = explorer.figure_alts(_settings(explorer), explorer.numbers)
    names = [name for name in explorer.numbers if name != "error"]
    listed = [name for name in names if name in alt]
    # the numbers' names, listed one after the other, are what the old alt texts were
    assert len(listed) < len(names), alt
    words = re.findall(r"[A-Za-z]{3,}", alt)
    assert len(words) >= 12, alt  # a sentence about the figure, not a label
    assert len(alt.split()) <= 70, alt  # and still short enough to hear at once
