"""The grader decides scores where no learner's code ran (dstoolkit.teaching._isolation).

Values cross as plain data (an object of the learner's class is never asked its value);
a coding answer runs from its source in a fresh interpreter where dstoolkit, files,
sockets and new processes are out of reach, each case under a time limit, and only its
outcomes come back. The nbgrader pipeline (tests/test_nbgrader_course.py) runs the same
grader on whole submissions.
"""

from __future__ import annotations

import inspect
import textwrap

import pytest

from answer_key import plain_solutions
from dstoolkit.teaching import hand_in
from dstoolkit.teaching._isolation import grade_coding, grade_value, run_isolated
from dstoolkit.teaching._sandbox import Opaque, dumps, loads
from dstoolkit.teaching.grading import HAND_IN

DEMPSTER = "import itertools\n\n" + textwrap.dedent(
    inspect.getsource(plain_solutions.dempster_rule)
)


def test_plain_data_round_trips_and_objects_stay_opaque():
    value = {frozenset({"low"}): 0.5, ("a", 1): [1.0, float("nan"), None], "s": {1, 2}}
    back = loads(dumps(value))
    assert back[frozenset({"low"})] == 0.5 and back["s"] == frozenset({1, 2})
    assert back[("a", 1)][0] == 1.0 and back[("a", 1)][1] != back[("a", 1)][1]  # NaN
    asked = []

    class Sly(float):
        def __repr__(self):
            asked.append("repr")
            return "0.8"

    opaque = loads(dumps(Sly(0.1)))
    assert isinstance(opaque, Opaque) and asked == []
    assert not grade_value("mass.bel", opaque, 0).correct


def test_a_value_is_graded_from_what_was_handed_in(capsys):
    hand_in("mass.bel", 0.8)
    line = capsys.readouterr().out.splitlines()[0]
    assert line == "handed in: mass.bel 0.8"
    assert grade_value("mass.bel", loads(line.split(" ", 3)[3]), 0).correct
    assert not grade_value("mass.bel", 0.3, 0).correct
    assert "not answered" in grade_value("mass.bel", ..., 0).message


def test_the_test_cells_call_is_what_the_grader_reads():
    found = HAND_IN.search('# a comment\nfrom x import y\n\nhand_in("combine.dempster-code", f)')
    assert found is not None and found.groups() == ("combine.dempster-code", "f")


@pytest.mark.slow
def test_a_right_function_passes_in_isolation_even_when_it_writes_to_stderr():
    noisy = DEMPSTER.replace(
        "    combined: dict = {}",
        "    import sys\n    print('note', file=sys.stderr)\n    combined: dict = {}",
    )
    for source in (DEMPSTER, noisy):
        verdict = grade_coding("combine.dempster-code", [source], "dempster_rule")
        assert verdict.correct, verdict.message
        assert "random" in verdict.message  # the hidden random cases ran too


BYPASSES = {
    "a default argument": "from dstoolkit import dempster\n"
    "def dempster_rule(m1, m2, _d=dempster):\n    return _d(m1, m2)\n",
    "an import inside": "def dempster_rule(m1, m2):\n    import dstoolkit\n    return {}\n",
    "dstoolkit's folder put on the path": "import sys\n"
    "def dempster_rule(m1, m2):\n"
    "    sys.path[:0] = [p for p in sys.argv] + ['/work']\n"
    "    import dstoolkit.teaching\n    return {}\n",
    "reading its source": "def dempster_rule(m1, m2):\n    return open('/etc/hostname').read()\n",
    "a worker process": "def dempster_rule(m1, m2):\n"
    "    import os\n    os.system('true')\n    return {}\n",
    "a socket": "def dempster_rule(m1, m2):\n"
    "    import _socket\n    s = _socket.socket()\n    s.connect(('127.0.0.1', 9))\n",
    "widening the audit hook": "import sys, builtins\n"
    "def dempster_rule(m1, m2):\n"
    "    sys.modules['__main__']._refuse = lambda *a: None\n"
    "    builtins.PermissionError = lambda *a: None\n"
    "    return open('/etc/hostname').read()\n",
}


@pytest.mark.slow
@pytest.mark.parametrize("how", sorted(BYPASSES))
def test_no_way_out_of_the_isolated_interpreter(how: str):
    verdict = grade_coding("combine.dempster-code", [BYPASSES[how]], "dempster_rule")
    assert not verdict.correct, verdict.message
    # refused by the isolation itself (not by a slip of the cheat)
    assert (
        "dstoolkit is not available" in verdict.message
        or "not allowed while" in (verdict.message)
        or "raises TypeError" in verdict.message
    ), verdict.message


@pytest.mark.slow
def test_each_case_has_a_time_limit_and_an_exit_ends_nothing_but_the_case():
    endless = "def dempster_rule(m1, m2):\n    while True:\n        pass\n"
    verdict = grade_coding("combine.dempster-code", [endless], "dempster_rule", per_case=0.5)
    assert verdict.message.startswith("✘ combine.dempster-code: stopped after 0.5 s on case 1")
    leaves = "import os\ndef dempster_rule(m1, m2):\n    os._exit(0)\n"
    verdict = grade_coding("combine.dempster-code", [leaves], "dempster_rule", per_case=2)
    assert "your code ended the grading process" in verdict.message


@pytest.mark.slow
def test_the_outcomes_come_from_the_answer_cells_in_order():
    from dstoolkit.teaching._coding import Case

    sources = ["def helper(x):\n    return 2 * x\n", "1 / 0\n", "def f(x):\n    return helper(x)\n"]
    for report in run_isolated(sources, "f", [Case("one", (1.5,)), Case("two", ("ab",))], 2):
        assert report.ready
        assert [p["raised"] for p in report.problems] == ["ZeroDivisionError"]
        assert list(zip(range(2), report.outcomes, strict=False)) == [(0, 3.0), (1, "abab")]


def test_a_stub_is_not_answered_yet():
    stub = 'def dempster_rule(m1, m2):\n    """Doc."""\n'
    assert (
        "not answered yet" in grade_coding("combine.dempster-code", [stub], "dempster_rule").message
    )
