"""The energy of evidence as the paper defines it and with Θ left out (paper eqs. 2, A1)."""

from __future__ import annotations

import numpy as np
import pytest

from dstoolkit import IntervalEvidence, MassFunction
from dstoolkit.errors import EvidenceError
from dstoolkit.evidence import (
    appendix_pair,
    combine_dependent,
    decorrelate,
    dependence,
    discount,
    energy,
    joint_energy,
)

FRAME = ("low", "mid", "high")
VACUOUS = IntervalEvidence([-10.0], [10.0], [1.0])


def test_the_vacuous_interval_evidence_counts_fully_with_the_papers_energy() -> None:
    assert energy(VACUOUS) == 1.0
    assert energy(VACUOUS, theta="left_out") == 0.0


def test_a_finite_frame_leaves_theta_out_either_way() -> None:
    e = MassFunction({"low": 0.5, ("low", "mid"): 0.3, FRAME: 0.2}, FRAME)
    assert energy(e) == energy(e, theta="left_out") == pytest.approx(0.65)
    assert energy(MassFunction.vacuous(FRAME), theta="left_out") == 0.0


def test_on_the_appendix_pair_discounting_does_not_scale_the_papers_energy() -> None:
    e1, e2 = appendix_pair()
    dep = dependence(e1, e2)
    d1, _, _ = decorrelate(e1, e2)
    assert energy(d1) == pytest.approx(0.7873, abs=1e-4)
    assert dep.r12 * dep.energy1 == pytest.approx(0.6506, abs=1e-4)
    # the mass 1 − R12 on Θ = [-0.3, 2.6] counts with weight w_min/d(Θ) = 1.6/2.9
    assert energy(d1) == pytest.approx(dep.r12 * dep.energy1 + (1 - dep.r12) * 1.6 / 2.9)


@pytest.mark.parametrize("seed", range(20))
def test_with_theta_left_out_discounting_scales_the_energy(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 6))
    lo = rng.uniform(-2, 0, n)
    hi = lo + rng.uniform(0.1, 3, n)
    e = IntervalEvidence(lo, hi, rng.dirichlet(np.ones(n)))
    rate = float(rng.uniform(0, 1))
    discounted = discount(e, rate)
    assert energy(discounted, theta="left_out") == pytest.approx(
        (1 - rate) * energy(e, theta="left_out")
    )


def test_the_option_reaches_the_combination() -> None:
    e1, e2 = appendix_pair()
    out = dependence(e1, e2, theta="left_out")
    assert out.energy1 == pytest.approx(energy(e1, theta="left_out"))
    assert out.joint_energy == pytest.approx(joint_energy(e1, e2, theta="left_out"))
    paper = combine_dependent(e1, e2).pignistic_expectation_1d()
    left_out = combine_dependent(e1, e2, theta="left_out").pignistic_expectation_1d()
    assert paper != left_out
    assert combine_dependent(e1, e2, theta="paper").pignistic_expectation_1d() == paper


def test_an_unknown_definition_is_refused() -> None:
    with pytest.raises(EvidenceError, match="theta must be one of"):
        energy(VACUOUS, theta="counted")  # type: ignore[arg-type]
