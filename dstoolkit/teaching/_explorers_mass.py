"""The explorer of the chapter on mass functions (book/mass_functions.md)."""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

from matplotlib.figure import Figure

from dstoolkit.errors import (
    EvidenceError,
)
from dstoolkit.evidence import (
    MassFunction,
)
from dstoolkit.plots.artists import (
    BelPlArtists,
    MassArtists,
    draw_bel_pl,
    draw_masses,
    update_bel_pl,
    update_masses,
)

from ._explorer import (
    Explorer,
    positions,
    slider,
)
from ._readouts import lowest_and_highest

# -- mass functions on a finite frame ----------------------------------------------------

LEVEL_FRAME = ("low", "mid", "high")


def describe_mass(numbers: Mapping[str, Any]) -> str:
    """Say what the mass-function figure shows: the likeliest level and the ignorance."""
    betp = {name[5:-1]: float(v) for name, v in numbers.items() if name.startswith("BetP(")}
    _, likeliest = lowest_and_highest(betp, ".2f")
    return (
        f"the masses of the focal elements, and each subset's belief and plausibility with "
        f"the pignistic probability: {likeliest} likeliest "
        f"(BetP {max(betp.values()):.2f}), the ignorance m(Θ) is {float(numbers['m(Θ)']):.2f}"
    )


def mass_function_explorer(
    low: float = 0.4, mid: float = 0.0, high: float = 0.1, low_mid: float = 0.3
) -> Explorer:
    """Masses on {low}, {mid}, {high} and {low, mid}; the rest goes to Θ (ignorance).

    Shows Bel and Pl of every subset of Θ = {low, mid, high} and BetP of the singletons.
    Moving mass from Θ to a singleton closes the gap between Bel and Pl. A total over 1
    shows a warning instead of a figure.

    Parameters
    ----------
    low, mid, high, low_mid : float, optional
        The sliders' start values: m({low}), m({mid}), m({high}), m({low, mid}), in [0, 1].

    Returns
    -------
    Explorer
        Controls ``low``, ``mid``, ``high``, ``low_mid``; on the static site ``low`` and
        ``high`` answer. Readout: m(Θ), BetP of each singleton, Pl({low}) − Bel({low}).

    See Also
    --------
    dstoolkit.evidence.MassFunction : Bel, Pl and BetP of a mass function.

    References
    ----------
    The paper's Def. 2 (mass functions). Belief and plausibility are not among the paper's
    equations (its eqs. 2–3 are the evidence energies); they are Shafer's (1976), whose
    theory the paper's §2 builds on.

    Examples
    --------
    >>> ex = mass_function_explorer(low=0.5, mid=0.0, high=0.1, low_mid=0.3)
    >>> round(ex.numbers["m(Θ)"], 2), round(ex.numbers["Pl({low}) − Bel({low})"], 2)
    (0.1, 0.4)
    """
    controls = {
        "low": slider("m({low})", low, 0.0, 1.0, 0.05, readout_format=".2f"),
        "mid": slider("m({mid})", mid, 0.0, 1.0, 0.05, readout_format=".2f"),
        "high": slider("m({high})", high, 0.0, 1.0, 0.05, readout_format=".2f"),
        "low_mid": slider("m({low, mid})", low_mid, 0.0, 1.0, 0.05, readout_format=".2f"),
    }

    @functools.cache
    def drawn() -> tuple[Figure, MassArtists, BelPlArtists]:
        """Return the figure, made by the first render and updated by the others."""
        fig = Figure(figsize=(9.5, 3.0), layout="constrained")
        ax1, ax2 = fig.subplots(1, 2, width_ratios=[1, 2.2])
        return (
            fig,
            draw_masses(ax1, title="masses", animated=True),
            draw_bel_pl(ax2, LEVEL_FRAME, title="belief, plausibility, pignistic", animated=True),
        )

    def render(low: float, mid: float, high: float, low_mid: float):
        given = {"low": low, "mid": mid, "high": high, ("low", "mid"): low_mid}
        rest = 1.0 - sum(given.values())
        if rest < -1e-9:
            raise EvidenceError(
                f"the masses add up to {1 - rest:.2f} > 1; lower a slider (what is left goes to Θ)"
            )
        mf = MassFunction({**given, LEVEL_FRAME: max(rest, 0.0)}, LEVEL_FRAME)
        fig, masses, bel_pl = drawn()
        update_masses(masses, mf)
        update_bel_pl(bel_pl, mf)
        betp = mf.pignistic()
        return fig, {
            "m(Θ)": max(rest, 0.0),
            **{f"BetP({h})": betp[h] for h in LEVEL_FRAME},
            "Pl({low}) − Bel({low})": mf.plausibility("low") - mf.belief("low"),
        }

    # On the site: m({low}) up to what the other start values leave, m({high}) in four
    # steps (a total over 1 shows the warning, as in a kernel).
    live = {
        "low": positions(controls["low"], 8, 0.0, 0.7),
        "high": positions(controls["high"], 4, 0.0, 0.3),
    }
    return Explorer(
        controls,
        render,
        title="A mass function on Θ = {low, mid, high}",
        live=live,
        said=("BetP(low)", "m(Θ)"),
        describe=describe_mass,
    )
