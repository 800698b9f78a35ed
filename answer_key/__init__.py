"""The course's answer key: what a teacher shows, never what a student installs.

This package lives at the repository's top level, outside ``dstoolkit`` (pyproject's package
discovery includes ``dstoolkit*`` only, so the wheel has none of it; ``MANIFEST.in`` keeps it
out of the sdist). The teacher's edition
of the sheets, the nbgrader source, the book's folded solutions and the tests import it from
a checkout of the repository::

    from answer_key import solution
    solution("mass.bel")          # the value the check expects (current variant)
    solution("mass.bel", variant=3)
    solution("combine.dempster-code")  # the plain function (no dstoolkit inside)

The values are computed with dstoolkit from each exercise's data (no typed-in numbers); the
plain solutions of the coding exercises are :mod:`answer_key.plain_solutions`.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from types import FunctionType
from typing import Any

from dstoolkit.teaching._checking import get
from dstoolkit.teaching._variants import using_variant

from . import plain_solutions
from .plain_solutions import HELPERS

#: The plain solution of each coding exercise.
PLAIN: dict[str, Callable[..., Any]] = {
    "mass.bel-pl-code": plain_solutions.bel_pl,
    "mass.betp-code": plain_solutions.pignistic,
    "combine.dempster-code": plain_solutions.dempster_rule,
    "combine.discount-code": plain_solutions.discount_rule,
    "dependent.energy-code": plain_solutions.interval_energy,
    "dependent.coefficients-code": plain_solutions.dependency,
    "dependent.combine-code": plain_solutions.dependent_rule,
    "noise.triangular-code": plain_solutions.triangular_rows,
    "noise.cdf-code": plain_solutions.cdf_bounds,
    "random.vertex-code": plain_solutions.vertex_image,
    "random.product-code": plain_solutions.product_relation,
    "bounded.step-code": plain_solutions.bounded_step,
    "gauge.orders-code": plain_solutions.orders_in_band,
    "estimating.eq43-code": plain_solutions.level_from_two_readings,
    "beyond.sigma-code": plain_solutions.triangle_sigma,
    "filter.step-code": plain_solutions.filter_step,
    "recursion.ut-code": plain_solutions.unscented_moments,
    "recursion.rts-code": plain_solutions.rts_scalar,
    "belief.mobius-code": plain_solutions.mass_from_belief,
    "belief.lower-code": plain_solutions.lower_expectation,
}


def plain(exercise_id: str) -> Callable[..., Any]:
    """Return the plain solution (no dstoolkit inside) of the coding exercise ``exercise_id``.

    Raises
    ------
    KeyError
        ``exercise_id`` is not a coding exercise (the message lists those that are).
    """
    try:
        return PLAIN[exercise_id]
    except KeyError:
        raise KeyError(
            f"{exercise_id!r} is not a coding exercise; coding exercises: {sorted(PLAIN)}"
        ) from None


def solution(exercise_id: str, variant: int | None = None) -> Any:
    """Return the answer to an exercise (for teachers, the book's solutions and the tests).

    Parameters
    ----------
    exercise_id : str
        The exercise, e.g. ``"mass.bel"``.
    variant : int, optional
        Whose data: 0 for the book's, ``N`` for a variant's sheet; by default the current one
        (see ``dstoolkit.teaching.set_variant``).

    Returns
    -------
    object
        A copy of the value the check expects (changing it changes nothing the check
        compares with), or for a coding exercise a copy of its plain function.

    Raises
    ------
    KeyError
        No exercise ``exercise_id``.
    """
    exercise = get(exercise_id)
    if exercise_id in PLAIN:
        value = PLAIN[exercise_id]
        twin = FunctionType(
            value.__code__, value.__globals__, value.__name__, value.__defaults__, value.__closure__
        )
        twin.__dict__.update(copy.deepcopy(value.__dict__))
        twin.__doc__, twin.__qualname__ = value.__doc__, value.__qualname__
        twin.__module__ = value.__module__
        return twin
    with using_variant(variant):
        return copy.deepcopy(exercise._expected())


__all__ = ["HELPERS", "PLAIN", "plain", "solution"]
