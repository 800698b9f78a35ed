"""An explorer in a kernel never lags: the latest value wins, and it says when it is working.

The explorer's worker thread (``Explorer(..., background=True)``, the default in a Jupyter
kernel) is driven here in-process with a render that takes a known time, so that a burst
of value changes (as a slider sends them while it is dragged) arrives faster than it is
computed.
"""

from __future__ import annotations

import re
import time

import pytest
from matplotlib.figure import Figure

from dstoolkit.errors import InvalidInputError
from dstoolkit.teaching._explorer import STALE_CLASS, WORKING, Explorer, announce_html, slider

#: What one render costs here: longer than the gap between two changes of the burst, as the
#: gauge's computation is longer than the gap between two messages of a drag.
RENDER_S = 0.02


def _explorer(fail_at: float | None = None, invalid_at: float | None = None):
    seen: list[float] = []

    def render(level: float):
        seen.append(level)
        time.sleep(RENDER_S)
        if fail_at is not None and level == fail_at:
            raise ZeroDivisionError("a bug in the render")
        if invalid_at is not None and level == invalid_at:
            raise InvalidInputError("this level is not possible")
        fig = Figure(figsize=(2, 1.5))
        fig.add_subplot().plot([0, 1], [0, level])
        return fig, {"level (m)": level}

    level = slider("level L (m)", 1.0, 1.0, 10.0, 0.1, readout_format=".1f")
    ex = Explorer({"level": level}, render, static=False, background=True)
    return ex, level, seen


def test_a_burst_of_changes_computes_few_states_and_ends_on_the_last() -> None:
    ex, level, seen = _explorer()
    statuses: list[str] = []
    ex.status.observe(lambda change: statuses.append(change["new"]), "value")
    burst = [round(1.0 + 0.1 * i, 1) for i in range(1, 51)]
    start = time.perf_counter()
    for value in burst:
        level.value = value
    returned = time.perf_counter() - start
    # the callback only notes the value: 50 assignments return long before 50 renders
    # (half of that time would be a backlog of 25 renders)
    assert returned < 25 * RENDER_S, returned
    ex.wait(timeout=30)  # a generous bound: the machine is shared, nothing should take 1 s
    computed = seen[1:]  # the first render is the explorer's start
    assert computed[-1] == burst[-1], computed
    # dropped: most of the burst arrives while a render runs (a quarter is far above
    # what the timing allows even on a loaded machine, and far below 50)
    assert len(computed) < len(burst) // 4, computed
    assert ex.numbers == {"level (m)": burst[-1]}
    assert ex.computed == 1 + len(computed)
    # the status said "working" at once, and the final state once at the end
    assert statuses[0] == WORKING, statuses
    final = burst[-1]
    assert statuses[-1] == announce_html(f"Level L {final:.1f} m: level {final:.4g} m.")
    assert all(status == WORKING for status in statuses[1:-1]), statuses
    assert STALE_CLASS not in ex.output._dom_classes


def test_the_explorer_says_it_is_working_within_50_ms() -> None:
    ex, level, _ = _explorer()
    start = time.perf_counter()
    level.value = 5.0
    # the callback marked the explorer before returning (no thread switch needed)
    marked = time.perf_counter() - start
    assert ex.status.value == WORKING and STALE_CLASS in ex.output._dom_classes
    assert marked < 0.05, marked
    ex.wait(timeout=30)
    assert ex.status.value == announce_html("Level L 5.0 m: level 5 m.")
    assert STALE_CLASS not in ex.output._dom_classes
    assert ex.numbers["level (m)"] == 5.0 and ex.picture is not None


def test_a_computed_state_is_said_once_in_a_polite_status_element() -> None:
    ex, level, _ = _explorer()
    for value in (2.0, 2.5, 3.0, 3.5):  # a drag: only the last state is said
        level.value = value
    ex.wait(timeout=30)
    said = ex.status.value
    assert 'role="status"' in said and 'aria-live="polite"' in said, said
    text = re.sub(r"<[^>]+>", "", said)
    assert text == "Level L 3.5 m: level 3.5 m.", text
    assert len(text.split()) <= 25
    # a control that did not move is not said again
    other = slider("bias (m)", 0.0, -1.0, 1.0, 0.1, readout_format=".1f")
    two = Explorer(
        {"level": slider("level L (m)", 1.0, 1.0, 10.0, 0.1, readout_format=".1f"), "bias": other},
        lambda level, bias: (None, {"sum (m)": level + bias}),
        static=False,
        background=True,
    )
    other.value = 0.5
    two.wait(timeout=30)
    assert re.sub(r"<[^>]+>", "", two.status.value) == "Bias 0.5 m: sum 1.5 m."


def test_reading_the_numbers_waits_for_the_pending_work() -> None:
    ex, level, _ = _explorer()
    level.value = 7.0
    assert ex.numbers == {"level (m)": 7.0}  # no wait() called: the property waits


def test_an_error_in_the_render_is_shown_and_raised_by_wait() -> None:
    ex, level, _ = _explorer(fail_at=3.0)
    level.value = 3.0
    with pytest.raises(ZeroDivisionError, match="a bug in the render"):
        ex.wait(timeout=30)
    assert "ZeroDivisionError" in ex.readout.value and "a bug in the render" in ex.readout.value
    assert "Failed" in ex.status.value and "ZeroDivisionError" in ex.status.value
    # the explorer still works after it: the next value is computed
    level.value = 4.0
    ex.wait(timeout=30)
    assert ex.numbers == {"level (m)": 4.0} and "Level L 4.0 m" in ex.status.value


def test_an_invalid_setting_is_explained_in_the_readout() -> None:
    ex, level, _ = _explorer(invalid_at=2.0)
    level.value = 2.0
    ex.wait(timeout=30)
    assert ex.numbers == {"error": "this level is not possible"}
    assert "this level is not possible" in ex.readout.value


def test_a_timeout_says_so() -> None:
    ex, level, _ = _explorer()
    with ex._lock:  # hold the render back
        level.value = 6.0
        with pytest.raises(TimeoutError, match="still computing"):
            ex.wait(timeout=0.05)
    ex.wait(timeout=30)
    assert ex.numbers == {"level (m)": 6.0}


def test_outside_a_kernel_a_change_is_computed_before_the_assignment_returns() -> None:
    def render(level: float):
        return None, {"level (m)": level}

    level = slider("level L (m)", 1.0, 1.0, 10.0, 0.1)
    ex = Explorer({"level": level}, render, static=False)
    assert ex.background is False  # the tests' process is no kernel
    level.value = 2.0
    assert ex._numbers == {"level (m)": 2.0}


def test_an_idle_worker_ends_and_the_next_change_starts_another(monkeypatch) -> None:
    import dstoolkit.teaching._explorer as explorer_module

    monkeypatch.setattr(explorer_module, "WORKER_IDLE_S", 0.05)
    ex, level, _ = _explorer()
    level.value = 2.0
    ex.wait(timeout=30)
    first = ex._worker
    assert first is not None
    first.join(timeout=30)  # idle for 0.05 s: it ends
    assert not first.is_alive() and ex._worker is None
    level.value = 3.0
    ex.wait(timeout=30)
    assert ex.numbers == {"level (m)": 3.0}
