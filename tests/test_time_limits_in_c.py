"""A check's time limit stops C-level work too: the check runs in a child process.

A coding answer that computes in C (``sum(range(10**11))``) and a value answer whose
``__float__`` never returns are stopped at the limit (the child is killed a grace period
after it) with a "stopped" verdict; plain answers are compared in the calling process.
"""

from __future__ import annotations

import os
import time

import pytest

from answer_key import solution
from dstoolkit.teaching import check
from dstoolkit.teaching._child_checks import GRACE_S, plain_data, run_isolated

CODING = "beyond.sigma-code"
#: Slack over limit + grace for starting the child and reading its verdict on a loaded
#: machine (2 cores shared by several jobs).
SLACK_S = 8.0


def _c_level(*args, **kwargs):
    return float(sum(range(10**11)))  # one C call: no trace function, no signal handler


class _Endless:
    def __float__(self):
        while True:
            pass


class _EndlessInC:
    def __float__(self):
        return float(sum(range(10**11)))


@pytest.mark.slow
def test_a_coding_answer_computing_in_c_is_stopped_at_the_limit():
    start = time.monotonic()
    verdict = check(CODING, _c_level, time_limit=1)
    took = time.monotonic() - start
    assert not verdict and verdict.details.get("timeout") and "stopped after 1 s" in str(verdict)
    assert took < 1 + GRACE_S + SLACK_S


@pytest.mark.slow
@pytest.mark.parametrize("answer", [_Endless(), _EndlessInC()], ids=["python", "c"])
def test_a_value_answer_whose_float_never_returns_is_stopped(answer):
    start = time.monotonic()
    verdict = check("mass.bel", answer, time_limit=1)
    took = time.monotonic() - start
    assert not verdict and verdict.details.get("timeout")
    assert took < 1 + GRACE_S + SLACK_S


def test_a_coding_answer_still_gets_its_verdict_through_the_child():
    assert check(CODING, solution(CODING))
    verdict = check(CODING, lambda *a, **k: 0.0)
    assert not verdict and "case" in verdict.details


def test_plain_answers_are_compared_here(monkeypatch):
    def no_fork():
        raise AssertionError("a plain answer must not need a child process")

    monkeypatch.setattr(os, "fork", no_fork)
    assert check("mass.bel", solution("mass.bel"))
    assert not check("mass.bel", [0.3])


@pytest.mark.parametrize(
    ("value", "plain"),
    [
        (0.8, True),
        ({"a": [1, 2.5], "b": (None, "x")}, True),
        (_Endless(), False),
        ([0.1, _Endless()], False),
        (type("Float", (float,), {})(0.8), False),  # a float subclass may override anything
    ],
)
def test_what_counts_as_plain_data(value, plain):
    assert plain_data(value) is plain


def test_the_learners_side_effects_stay_in_the_child():
    seen: list[int] = []
    assert run_isolated(lambda: seen.append(1) or len(seen), 5.0, lambda: -1) == 1
    assert seen == []


def test_an_exception_in_the_child_is_raised_here():
    def fails():
        raise ValueError("from the child")

    with pytest.raises(ValueError, match="from the child"):
        run_isolated(fails, 5.0, lambda: None)
