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


@pytest.mark.parametrize(
    "line",
    [
        "[" * 100_000 + "]" * 100_000,  # deeper than the JSON parser goes
        "[" * 200 + "]" * 200,  # parsed, but deeper than any encoded answer
        '{"$": "float"}',  # a tag without its value
        '{"$": "dict", "v": [1, 2]}',  # a dict whose items are no pairs
        '{"$": "tuple", "v": 3}',
    ],
)
def test_a_line_written_by_hand_is_an_opaque_answer_never_an_error(line: str):
    # a test cell's output is the learner's to write: whatever it holds, the grader reads
    # an answer (that equals nothing) and goes on grading
    value = loads(line)
    assert isinstance(value, Opaque) or _holds_opaque(value), value
    assert not grade_value("mass.bel", value, 0).correct


def _holds_opaque(value: object) -> bool:
    while isinstance(value, list) and value:
        value = value[0]
    return isinstance(value, Opaque)


CHANNEL_CHEATS = {
    "a line too deep to parse": "out.write('[' * 100000 + ']' * 100000 + '\\n')",
    "a line with no end": "out.write('[' * 20_000_000)",
    "a forged record": 'out.write(\'{"case": 0, "value": {"$": "dict"}}\\n\')',
}


@pytest.mark.slow
@pytest.mark.parametrize("how", sorted(CHANNEL_CHEATS))
def test_writing_to_the_graders_channel_gives_a_wrong_answer_not_an_aborted_grading(how: str):
    source = (
        "import sys\n"
        "def dempster_rule(m1, m2):\n"
        "    frame = sys._getframe()\n"
        "    while 'out' not in frame.f_locals:\n"
        "        frame = frame.f_back\n"
        "    out = frame.f_locals['out']\n"
        f"    {CHANNEL_CHEATS[how]}\n"
        "    out.flush()\n"
        "    return {}\n"
    )
    verdict = grade_coding("combine.dempster-code", [source], "dempster_rule")
    assert not verdict.correct, verdict.message
