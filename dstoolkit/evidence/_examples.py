"""Worked examples: the paper's Appendix A evidence and Zadeh's two doctors."""

from __future__ import annotations

import numpy as np

from dstoolkit.errors import EvidenceError

from ._combination import discount
from ._finite_frame import MassFunction
from ._intervals import IntervalEvidence

#: Appendix A of the paper: the two-element example of eq. (A2) and E1, E2 of the worked one.
APPENDIX_A2 = ((-0.3, 2.6, 0.3), (0.3, 1.9, 0.7))

#: E1 of Appendix A's worked example: rows (lo, hi, mass).
APPENDIX_E1 = ((-0.30, 2.60, 0.3), (0.30, 1.90, 0.6), (0.32, 1.93, 0.1))

#: E2 of Appendix A's worked example: rows (lo, hi, mass).
APPENDIX_E2 = ((0.21, 3.50, 0.1), (0.41, 1.61, 0.3), (0.30, 1.90, 0.6))

#: The value the paper prints for En'(E1) (it is the energy of APPENDIX_A2).
PAPER_EN1 = 0.8655

#: The mass the paper prints for A6 of the combined evidence.
PAPER_A6 = 0.1890


def appendix_pair() -> tuple[IntervalEvidence, IntervalEvidence]:
    """E1 and E2 of the paper's worked example (Appendix A).

    Returns
    -------
    tuple of IntervalEvidence
        E1 and E2, three intervals each, not merged.

    See Also
    --------
    appendix_evidence : the same focal elements with other masses.

    References
    ----------
    The paper's Appendix A, eqs. (A2)–(A9).

    Examples
    --------
    >>> e1, e2 = appendix_pair()
    >>> e1.mass.tolist()
    [0.3, 0.6, 0.1]
    """
    return (
        IntervalEvidence.from_pairs(APPENDIX_E1, merge=False),
        IntervalEvidence.from_pairs(APPENDIX_E2, merge=False),
    )


def appendix_evidence(
    m1: tuple[float, float] = (0.6, 0.1), m2: tuple[float, float] = (0.3, 0.6)
) -> tuple[IntervalEvidence, IntervalEvidence]:
    """Build E1 and E2 of the paper's Appendix A with chosen masses.

    The masses of their 2nd and 3rd focal elements are given; what is left goes to the
    first (widest) one. Defaults: the paper's.

    Parameters
    ----------
    m1, m2 : tuple of float
        The masses of the 2nd and 3rd focal elements of E1 and of E2,
        each pair summing to at most 1.

    Returns
    -------
    tuple of IntervalEvidence
        E1 and E2.

    Raises
    ------
    EvidenceError
        For masses that are negative or sum to more than 1.

    See Also
    --------
    appendix_pair : the paper's masses.

    References
    ----------
    The paper's Appendix A.

    Examples
    --------
    >>> e1, e2 = appendix_evidence(m1=(0.5, 0.2))
    >>> e1.mass.round(4).tolist()
    [0.3, 0.5, 0.2]
    """
    out = []
    for rows, (b, c), name in ((APPENDIX_E1, m1, "E1"), (APPENDIX_E2, m2, "E2")):
        rest = 1.0 - b - c
        if rest < -1e-9:
            raise EvidenceError(
                f"the masses of {name} add up to {b + c:.2f} > 1 without its widest focal "
                "element; lower one of them"
            )
        lo, hi = np.array(rows)[:, :2].T
        out.append(IntervalEvidence(lo, hi, [max(rest, 0.0), b, c], merge=False))
    return out[0], out[1]


#: The frame of Zadeh's example: the three diagnoses of the two doctors.
ZADEH_FRAME = ("meningitis", "concussion", "tumour")


def zadeh_sources(x: float, y: float, epsilon: float = 0.0) -> tuple[MassFunction, MassFunction]:
    """Zadeh's two doctors: m1(meningitis) = x, m2(concussion) = y, the rest on tumour.

    Both are discounted at rate ``epsilon`` (mass ε to Θ) before they are combined.

    Parameters
    ----------
    x, y : float in [0, 1]
        The two doctors' confidence in their diagnoses.
    epsilon : float in [0, 1]
        The discount rate.

    Returns
    -------
    tuple of MassFunction
        m1 and m2 on the frame {meningitis, concussion, tumour}.

    Raises
    ------
    EvidenceError
        For numbers outside [0, 1].

    See Also
    --------
    dempster : whose verdict on these two is Zadeh's paradox.

    Examples
    --------
    >>> from dstoolkit.evidence import dempster
    >>> dempster(*zadeh_sources(0.99, 0.99))
    MassFunction({tumour}: 1)
    """
    m1 = MassFunction({"meningitis": x, "tumour": 1.0 - x}, ZADEH_FRAME)
    m2 = MassFunction({"concussion": y, "tumour": 1.0 - y}, ZADEH_FRAME)
    return discount(m1, epsilon), discount(m2, epsilon)
