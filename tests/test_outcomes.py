"""Every chapter states its learning outcomes, and each outcome is assessed by exercises.

* Every chapter of _toc.yml's numbered parts has ``book/outcomes/<stem>.yml`` in the shared
  format: each outcome starts with a measurable verb of a fixed list, names at least one
  exercise, and only exercises that the chapter has; every exercise of the chapter serves
  at least one outcome; the ids read ``<the chapter's label prefix>-o<k>`` and are unique
  in the book.
* The course's outcomes (``book/outcomes/course.yml``) name chapter outcomes only, and every
  chapter feeds at least one of them.
* The rules catch what they are meant to catch (a file that breaks each one is refused).
* The extension puts the box under a chapter's title with a link to each exercise.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "scripts"))
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import dstoolkit_outcomes as outcomes  # noqa: E402
import sheets  # noqa: E402

CHAPTERS = [Path(d).name for d in outcomes.toc_chapters(ROOT)]
FOLDER = ROOT / "book" / "outcomes"


def _labels(stem: str) -> list[str]:
    return sheets.chapter_exercises(ROOT / "book" / f"{stem}.md")


def test_the_toc_reader_finds_the_numbered_chapters() -> None:
    assert CHAPTERS == list(sheets.chapter_numbers(ROOT / "_toc.yml"))
    assert "teaching" not in CHAPTERS and len(CHAPTERS) >= 12


@pytest.mark.parametrize("stem", CHAPTERS)
def test_every_chapter_has_outcomes_tied_to_its_exercises(stem: str) -> None:
    path = FOLDER / f"{stem}.yml"
    assert path.exists(), f"chapter {stem} has no {path.relative_to(ROOT)}"
    found = outcomes.load(path)
    labels = _labels(stem)
    assert labels, f"chapter {stem} has no exercise"
    prefix = outcomes.label_prefix(labels)
    assert outcomes.problems(found, labels, path.name, prefix) == []
    for outcome in found:
        assert outcome["exercises"], outcome["id"]
        assert set(outcome["exercises"]) <= set(labels), outcome["id"]
        assert outcomes.first_word(outcome["text"]) in outcomes.VERBS, outcome["text"]
    assert {x for o in found for x in o["exercises"]} == set(labels)


def test_outcome_ids_are_unique_in_the_book() -> None:
    ids = [o["id"] for stem in CHAPTERS for o in outcomes.load(FOLDER / f"{stem}.yml")]
    assert len(ids) == len(set(ids)), sorted({i for i in ids if ids.count(i) > 1})


def test_the_course_outcomes_name_chapter_outcomes_and_every_chapter_feeds_one() -> None:
    by_chapter = {
        stem: [o["id"] for o in outcomes.load(FOLDER / f"{stem}.yml")] for stem in CHAPTERS
    }
    known = [oid for ids in by_chapter.values() for oid in ids]
    course = outcomes.load(FOLDER / "course.yml")
    assert outcomes.problems(course, known, "course.yml", "course") == []
    named = {oid for o in course for oid in o["exercises"]}
    for stem, ids in by_chapter.items():
        assert named & set(ids), f"no course outcome builds on chapter {stem}; add one of {ids}"


GOOD = [{"id": "xy-o1", "text": "compute a thing", "exercises": ["xy-ex-a", "xy-ex-b"]}]


@pytest.mark.parametrize(
    ("change", "labels", "says"),
    [
        ({"text": "understand a thing"}, ["xy-ex-a", "xy-ex-b"], "measurable verb"),
        ({"exercises": []}, ["xy-ex-a", "xy-ex-b"], "names no exercise"),
        ({"exercises": ["xy-ex-a", "xy-ex-z"]}, ["xy-ex-a", "xy-ex-b"], "xy-ex-z"),
        ({}, ["xy-ex-a", "xy-ex-b", "xy-ex-c"], "xy-ex-c serves no outcome"),
        ({"id": "zz-o1"}, ["xy-ex-a", "xy-ex-b"], "should read xy-o<k>"),
    ],
    ids=["verb", "no-exercise", "unknown-label", "unserved-exercise", "prefix"],
)
def test_each_rule_catches_what_breaks_it(change: dict, labels: list[str], says: str) -> None:
    assert outcomes.problems(GOOD, ["xy-ex-a", "xy-ex-b"], "x.yml", "xy") == []
    found = outcomes.problems([{**GOOD[0], **change}], labels, "x.yml", "xy")
    assert any(says in problem for problem in found), found


def test_a_duplicate_id_is_caught() -> None:
    found = outcomes.problems(GOOD + GOOD, ["xy-ex-a", "xy-ex-b"], "x.yml", "xy")
    assert any("used twice" in p for p in found), found


@pytest.mark.parametrize(
    "text",
    [
        "outcomes: []\n",
        "- id: xy-o1\n",
        "outcomes:\n  - id: xy-o1\n    text: compute\n",
        "outcomes:\n  - {id: xy-o1, text: compute a, exercises: xy-ex-a}\n",
        "outcomes: [\n",
    ],
    ids=["empty", "no-key", "no-exercises", "exercises-not-a-list", "not-yaml"],
)
def test_a_malformed_file_says_what_to_write(tmp_path, text: str) -> None:
    path = tmp_path / "x.yml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(outcomes.OutcomesError, match="x.yml"):
        outcomes.load(path)


def test_the_box_links_every_exercise_of_each_outcome() -> None:
    from sphinx import addnodes

    found = outcomes.load(FOLDER / "random_sets.yml")
    box = outcomes.outcomes_box(found)
    assert box.children[0].astext() == outcomes.CHAPTER_LEAD
    items = list(box.children[1].children)
    assert [item["ids"] for item in items] == [[o["id"]] for o in found]
    for item, outcome in zip(items, found, strict=True):
        refs = list(item.findall(addnodes.pending_xref))
        assert [r["reftarget"] for r in refs] == outcome["exercises"]
        assert {r["reftype"] for r in refs} == {"numref"}
        assert item.astext().lower().startswith(outcome["text"].lower())
