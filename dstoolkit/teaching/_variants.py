"""Variants of the exercise sheets: the same questions on other numbers.

Variant 0 is the book's data. Variant ``N > 0`` draws the data of each chapter (masses,
readings, intervals) from a seed made of ``N`` and the chapter's name, so that the answers
printed in the book do not answer it. The sheets show a variant's data
(``scripts/sheets.py --variant N``), and the checks compute their expected answers from
the same data: a solver reads ``data("mass")["m_low"]``, never a stored answer.

A draw is kept only if every exercise of the chapter that varies gets another answer than
in the book and, where the chapter's data allow it, than in the :data:`WINDOW` variants
before it (by the exercise's own tolerance); otherwise the next draw from the same seed is
tried. So consecutive variants answer every such question differently as far as the
chapter's ranges of data allow, and any variant differs from the book. A choice among a
few named options (``distinct=False``) follows its variant's data without this condition.
Variants are drawn in order (variant 5 after 1–4), which keeps them the same on every run.
"""

from __future__ import annotations

import hashlib
import hmac
import time
import zlib
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np

from dstoolkit.errors import InvalidInputError

Data = dict[str, Any]

#: The book's data of each chapter with variants (variant 0), by exercise-id prefix; each
#: chapter's module of exercises adds its own (:func:`book_data`).
BOOK: dict[str, Data] = {}

#: Which chapter's data each sheet (source stem) shows.
SHEET_CHAPTER = {
    "mass_functions": "mass",
    "combining_evidence": "combine",
    "dependent_evidence": "dependent",
    "random_sets": "random",
    "noise_to_evidence": "noise",
    "recursive_filter": "filter",
    "level_gauge": "gauge",
    "simulated_gauge": "gauge",
    "lab": "lab",
    "estimating_level": "estimating",
    "beyond_the_paper": "beyond",
}

#: Draws tried before giving up (a draw is refused when an answer equals the book's).
ATTEMPTS = 200
#: A variant's answers differ from those of this many variants before it.
WINDOW = 10

#: Variants from this number on are students' own (:func:`student_variant`): each is drawn
#: on its own, its answers differing from the book's.
STUDENT_VARIANTS = 1_000_000

_state: dict[str, int] = {"variant": 0}
_drawn: dict[tuple[str, int], Data] = {}


def _pick(rng: np.random.Generator, lo: float, hi: float, step: float) -> float:
    """Return a number of the grid lo, lo + step, …, hi, rounded to the grid's decimals."""
    count = int(round((hi - lo) / step)) + 1
    return round(lo + step * int(rng.integers(count)), 6)


def _masses(
    rng: np.random.Generator,
    first: tuple[float, float],
    second: tuple[float, float],
    least: float = 0.1,
    step: float = 0.05,
) -> tuple[float, float, float]:
    """Three masses a, b, 1 − a − b on a grid, the last at least ``least``."""
    while True:
        a, b = _pick(rng, *first, step), _pick(rng, *second, step)
        rest = round(1.0 - a - b, 6)
        if rest >= least - 1e-9:
            return a, b, rest


def _mass(rng: np.random.Generator) -> Data:
    a, b, t = _masses(rng, (0.2, 0.6), (0.1, 0.4))
    return {"m_low": a, "m_low_mid": b, "m_theta": t}


def _combine(rng: np.random.Generator) -> Data:
    m1 = _pick(rng, 0.3, 0.8, 0.05)
    high, mid_high, theta = _masses(rng, (0.3, 0.7), (0.1, 0.3), least=0.05)
    x, y = _pick(rng, 0.9, 0.98, 0.01), _pick(rng, 0.9, 0.98, 0.01)
    q = _pick(rng, 0.2, 0.8, 0.1)
    return {
        "m1_low": m1,
        "m1_theta": round(1 - m1, 6),
        "m2_high": high,
        "m2_mid_high": mid_high,
        "m2_theta": theta,
        "zadeh_x": x,
        "zadeh_x_rest": round(1 - x, 6),
        "zadeh_y": y,
        "zadeh_y_rest": round(1 - y, 6),
        "once_low": q,
        "once_theta": round(1 - q, 6),
    }


def _dependent(rng: np.random.Generator) -> Data:
    while True:
        e1 = _masses(rng, (0.3, 0.6), (0.1, 0.4))
        e2 = _masses(rng, (0.1, 0.5), (0.1, 0.5))
        if e2[0] < e1[0]:  # the shared {low}: min(m1, m2) is E2's, as in the book
            return dict(
                zip(
                    ("e1_low", "e1_low_mid", "e1_theta", "e2_low", "e2_mid", "e2_theta"),
                    (*e1, *e2),
                    strict=True,
                )
            )


def _random(rng: np.random.Generator) -> Data:
    x1, x2 = _pick(rng, 0.2, 0.8, 0.1), _pick(rng, 0.2, 0.8, 0.1)
    lo = tuple(int(v) for v in rng.integers(-2, 3, size=3))
    hi = tuple(int(a + w) for a, w in zip(lo, rng.integers(1, 4, size=3), strict=True))
    fold = _masses(rng, (0.1, 0.4), (0.1, 0.4))
    return {
        "x1_a": x1,
        "x1_b": round(1 - x1, 6),
        "x2_a": x2,
        "x2_b": round(1 - x2, 6),
        "mono_lo": lo,
        "mono_hi": hi,
        "square_lo": -_pick(rng, 0.5, 3.0, 0.1),
        "square_hi": _pick(rng, 0.5, 4.0, 0.1),
        "fold_a": fold[0],
        "fold_b": fold[1],
        "fold_c": fold[2],
        "boxes": int(rng.choice([9, 12, 20, 25, 27, 36])),
        "dim": int(rng.integers(2, 5)),
    }


def _noise(rng: np.random.Generator) -> Data:
    s = _pick(rng, 0.2, 1.2, 0.1)
    mode, half = _pick(rng, -9.0, -3.0, 0.1), _pick(rng, 2.0, 5.0, 0.01)
    return {
        "state": (-s, 0.0, s),
        "obs": (round(mode - half, 6), mode, round(mode + half, 6)),
        "p": int(rng.integers(2, 13)),
        "epsilon": _pick(rng, 0.0, 0.3, 0.01),
        "pbox_x": _pick(rng, 0.05, 1.0, 0.05),
        "pbox_p": int(rng.integers(2, 9)),
        "pbox_epsilon": _pick(rng, 0.0, 0.3, 0.01),
        "state_note": "",
        "obs_note": "",
    }


def _filter(rng: np.random.Generator) -> Data:
    xhat = _pick(rng, -1.0, 3.0, 0.5)
    return {
        "hand_xhat": int(xhat) if float(xhat).is_integer() else xhat,
        "hand_z": round(xhat + _pick(rng, -0.9, 0.9, 0.1), 6),
        "hand_epsilon": _pick(rng, 0.05, 0.45, 0.01),
        "count_cuts": int(rng.choice([p for p in range(2, 21) if p != 5])),
        "predict_xhat": int(_pick(rng, 900, 1500, 10)),
        "predict_order": int(rng.integers(40, 81)),
        "z1": _pick(rng, 990.0, 1100.0, 0.1),
        "conflict_epsilon": _pick(rng, 0.12, 0.4, 0.01),
    }


def _gauge(rng: np.random.Generator) -> Data:
    return {
        "case_l": _pick(rng, 1.0, 9.0, 0.1),
        "case_t": _pick(rng, 5.0, 35.0, 0.1),
        "long_l": _pick(rng, 6.0, 12.0, 0.1),
        "long_t": _pick(rng, 5.0, 35.0, 0.1),
        "latency_ms": int(rng.integers(2, 41)),
        "spacing_low": _pick(rng, 1.0, 3.0, 0.1),
        "spacing_high": _pick(rng, 5.0, 10.0, 0.1),
    }


def _lab(rng: np.random.Generator) -> Data:
    return {
        "lag": int(rng.integers(2000, 9001)),
        "temperature": _pick(rng, 10.0, 30.0, 0.5),
        "diameter_mm": int(rng.integers(20, 61)),
        "tolerance_level": _pick(rng, 1.0, 6.0, 0.5),
        "tolerance_mm": int(rng.integers(2, 11)),
        "u_fit": _pick(rng, 0.1, 3.0, 0.1),
        "u_offsets": _pick(rng, 0.1, 3.0, 0.1),
        "u_temperature": _pick(rng, 0.1, 3.0, 0.1),
    }


def _table3_case(rng: np.random.Generator) -> tuple[float, float]:
    """Return a (level m, °C) of the paper's Table 3."""
    from dstoolkit.studies import TABLE3_CASES

    return TABLE3_CASES[int(rng.integers(len(TABLE3_CASES)))]


def _estimating(rng: np.random.Generator) -> Data:
    n1 = int(rng.integers(27, 61))
    spacing = 37.76  # f_F of the paper's 4.6 m case at 26.5 °C, Hz: readings near n f_F
    first = {
        "z1": round(n1 * spacing + _pick(rng, -9.0, 9.0, 0.1), 1),
        "n1": n1,
        "bias": _pick(rng, 2.0, 12.0, 0.1),
    }
    outlier, improvement = _table3_case(rng), _table3_case(rng)
    return first | {
        "outlier_level": outlier[0],
        "outlier_t": outlier[1],
        "band_lo": int(_pick(rng, 800, 1200, 50)),
        "band_hi": int(_pick(rng, 2000, 3000, 100)),
        "imp_level": improvement[0],
        "imp_t": improvement[1],
        "imp_runs": int(rng.integers(10, 31)),
        "imp_seed": int(rng.integers(1, 1000)),
    }


def _intervals(rng: np.random.Generator) -> tuple[float, float, float, float]:
    """Two intervals [lo, hi] on a grid of 0.5 in [0, 6], each 0.5 to 3 wide."""
    bounds = []
    for _ in range(2):
        lo = _pick(rng, 0.0, 4.5, 0.5)
        bounds += [lo, round(lo + _pick(rng, 0.5, 3.0, 0.5), 6)]
    return bounds[0], bounds[1], bounds[2], bounds[3]


def _beyond(rng: np.random.Generator) -> Data:
    while True:  # a noise below its resonance, as the paper's: mode + 3σ < 0
        mode, sigma = _pick(rng, -9.0, -4.0, 0.1), _pick(rng, 0.5, 2.0, 0.01)
        if mode + 3 * sigma <= -0.5:
            break
    cuts = int(rng.choice([p for p in range(2, 13) if p != 3]))  # ten counts: few answers
    while True:
        pred, reading = _intervals(rng), _intervals(rng)
        m_pred, m_reading = _pick(rng, 0.1, 0.9, 0.1), _pick(rng, 0.1, 0.9, 0.1)
        pairs = [
            (a, b, ma * mb)
            for a, ma in ((pred[:2], m_pred), (pred[2:], 1 - m_pred))
            for b, mb in ((reading[:2], m_reading), (reading[2:], 1 - m_reading))
        ]
        gaps = [min(a[1], b[1]) - max(a[0], b[0]) for a, b, _ in pairs]
        conflict = sum(m for (_, _, m), g in zip(pairs, gaps, strict=True) if g < 0)
        # some products empty (K ≥ 0.05), most of the mass kept (K ≤ 0.8); none meets in a
        # single point (the gaps are on a grid of 0.5, exact in binary)
        if 0.045 < conflict < 0.805 and all(g != 0 for g in gaps):  # off the 0.01 grid
            break
    return {
        "w_the": "This sheet's",
        "w_whose": "the",
        "w_note": "",
        "w_lo": round(mode - 3 * sigma, 6),
        "w_mode": mode,
        "w_hi": round(mode + 3 * sigma, 6),
        "w_sigma": sigma,
        "cuts": cuts,
        "side": cuts + 1,
        "cuts_word": str(cuts),
        "np1_lo": pred[0],
        "np1_hi": pred[1],
        "np1_m": m_pred,
        "np2_lo": pred[2],
        "np2_hi": pred[3],
        "np2_m": round(1 - m_pred, 6),
        "nr1_lo": reading[0],
        "nr1_hi": reading[1],
        "nr1_m": m_reading,
        "nr2_lo": reading[2],
        "nr2_hi": reading[3],
        "nr2_m": round(1 - m_reading, 6),
        "fail_level": _pick(rng, 2.0, 9.6, 0.1),
        "fail_t": _pick(rng, 10.0, 30.0, 0.5),
        "fail_runs": int(rng.integers(10, 31)),
        "fail_seed": int(rng.integers(1, 1000)),
        "fail_scale": _pick(rng, 0.6, 0.9, 0.05),
        "off_l": _pick(rng, 2.0, 12.0, 0.1),
        "off_t": _pick(rng, 5.0, 35.0, 0.1),
        "off_tau_ms": int(rng.integers(2, 41)),
    }


DRAW: dict[str, Callable[[np.random.Generator], Data]] = {
    "mass": _mass,
    "combine": _combine,
    "dependent": _dependent,
    "random": _random,
    "noise": _noise,
    "filter": _filter,
    "gauge": _gauge,
    "lab": _lab,
    "estimating": _estimating,
    "beyond": _beyond,
}


def book_data(chapter: str, values: Data) -> None:
    """Register the book's data of ``chapter`` (variant 0).

    Its variants are drawn by ``DRAW[chapter]`` with the same keys.
    """
    BOOK[chapter] = values


def valid_variant(variant: Any) -> int:
    """``variant`` as an int ≥ 0, or :class:`~dstoolkit.errors.InvalidInputError`."""
    if isinstance(variant, bool) or not isinstance(variant, int | np.integer) or variant < 0:
        raise InvalidInputError(
            f"a variant is a whole number ≥ 0 (0 is the book's data), not {variant!r}"
        )
    return int(variant)


def set_variant(variant: int) -> int:
    """Make the checks use the data of ``variant`` (the setup cell of a variant's sheet calls it).

    Parameters
    ----------
    variant : int
        0 for the book's data, ``N > 0`` for the numbers of ``scripts/sheets.py
        --variant N``.

    Returns
    -------
    int
        The variant used before.

    Raises
    ------
    InvalidInputError
        ``variant`` is not a whole number ≥ 0.

    See Also
    --------
    check : compares an answer with the solution computed from the variant's data.

    Examples
    --------
    >>> from dstoolkit.teaching import check, set_variant
    >>> previous = set_variant(3)
    >>> bool(check("mass.bel", 0.8))   # the book's answer, not variant 3's
    False
    >>> set_variant(previous)
    3
    """
    variant = valid_variant(variant)
    previous = _state["variant"]
    _state["variant"] = variant
    return previous


def current_variant() -> int:
    """Return the variant the checks use now (see :func:`set_variant`)."""
    return _state["variant"]


@contextmanager
def using_variant(variant: int | None) -> Iterator[int]:
    """Within the block the checks use ``variant`` (``None``: leave it as it is)."""
    if variant is None:
        yield current_variant()
        return
    previous = set_variant(variant)
    try:
        yield variant
    finally:
        _state["variant"] = previous


def data(chapter: str, variant: int | None = None) -> Data:
    """Return the data of ``chapter`` in ``variant`` (by default the current one).

    ``chapter`` is an exercise-id prefix such as ``"mass"``. Variant 0 is the book's.
    """
    if chapter not in BOOK:
        raise InvalidInputError(
            f"no variant data for {chapter!r}; chapters with variants: {sorted(BOOK)}"
        )
    variant = current_variant() if variant is None else valid_variant(variant)
    if variant == 0:
        return BOOK[chapter]
    if variant >= STUDENT_VARIANTS:
        if (chapter, variant) not in _drawn:
            _drawn[(chapter, variant)] = _draw(chapter, variant)
        return _drawn[(chapter, variant)]
    for earlier in range(1, variant + 1):
        if (chapter, earlier) not in _drawn:
            _drawn[(chapter, earlier)] = _draw(chapter, earlier)
    return _drawn[(chapter, variant)]


def _draw(chapter: str, variant: int) -> Data:
    from ._checking import REGISTRY

    rng = np.random.default_rng([variant, zlib.crc32(chapter.encode())])
    # reverse order of ids (the first draw's; then the quickest solvers first): the filter's
    # slowest solver (conflict-start) is tried last
    varying = [
        ex
        for ex_id, ex in sorted(REGISTRY.items(), reverse=True)
        if ex_id.split(".")[0] == chapter
        and getattr(ex, "varies", False)
        and getattr(ex, "distinct", True)
    ]
    before = range(max(1, variant - WINDOW), variant) if variant < STUDENT_VARIANTS else ()
    others = [[ex._expected_in(v) for v in (0, *before)] for ex in varying]
    key = (chapter, variant)
    book = [sols[0] for sols in others]
    fallback: Data | None = None
    seconds: dict[str, float] = {}  # each solver's time: the quick ones are tried first
    for _ in range(ATTEMPTS):
        candidate = DRAW[chapter](rng)
        _drawn[key] = candidate
        try:
            with using_variant(variant):
                differs = _differs(varying, book, others, fallback is not None, seconds)
        finally:
            del _drawn[key]
        if differs == (True, True):
            return candidate
        if differs[0] and fallback is None:
            fallback = candidate
    if fallback is not None:
        # the chapter's grid of data has fewer answers than WINDOW variants need: the
        # first draw whose answers differ from the book's (the same on every run)
        return fallback
    raise InvalidInputError(
        f"no data for variant {variant} of {chapter!r} whose answers differ from the "
        f"book's in {ATTEMPTS} draws: widen the ranges of _{chapter}() in {__name__}"
    )


def _differs(
    varying: list[Any],
    book: list[Any],
    others: list[list[Any]],
    stop_at_window: bool,
    seconds: dict[str, float],
) -> tuple[bool, bool]:
    """Whether the current draw's answers differ from the book's, and from the window's.

    Solves exercise after exercise, the quickest so far first (``seconds``, each solver's
    time, is updated), and stops at the first answer that equals the book's (the draw is
    refused) or, with ``stop_at_window`` (a fallback is already kept), at the first that
    equals an earlier variant's: a refused draw costs its quick solvers only. The order
    changes no outcome: ``(True, True)`` needs every answer to differ from all, and without
    ``stop_at_window`` ``(True, False)`` means every answer differs from the book's.
    """
    from ._checking import answers_differ

    window = True
    order = sorted(range(len(varying)), key=lambda i: seconds.get(varying[i].id, 0.0))
    for i in order:
        ex, start = varying[i], time.perf_counter()
        fresh = ex.solve()
        seconds[ex.id] = time.perf_counter() - start
        if not answers_differ(ex, fresh, book[i]):
            return False, False
        if window and not all(answers_differ(ex, fresh, e) for e in others[i][1:]):
            window = False
            if stop_at_window:
                return True, False
    return True, window


def student_variant(secret: str, student_id: str) -> int:
    """Return the variant of one student: a number from the course's secret and their id.

    The same student always gets the same variant; without the secret (kept in the
    course's ``nbgrader_config.py``, never released) nobody can tell another student's.

    Parameters
    ----------
    secret : str
        The course's secret.
    student_id : str
        nbgrader's id of the student.

    Returns
    -------
    int
        A variant of at least :data:`STUDENT_VARIANTS`.

    Examples
    --------
    >>> from dstoolkit.teaching._variants import STUDENT_VARIANTS, student_variant
    >>> student_variant("s3cret", "alice") == student_variant("s3cret", "alice")
    True
    >>> student_variant("s3cret", "alice") >= STUDENT_VARIANTS
    True
    """
    if not secret:
        raise InvalidInputError("a course secret is needed for students' own variants")
    digest = hmac.new(secret.encode(), student_id.encode(), hashlib.sha256).hexdigest()
    return STUDENT_VARIANTS + int(digest[:12], 16) % 10**9


def chapter_of_sheet(stem: str) -> str | None:
    """Return the chapter (exercise-id prefix) whose data the sheet ``stem`` shows, if it varies."""
    return SHEET_CHAPTER.get(stem)
