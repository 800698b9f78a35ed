"""The explorer of the chapter on the simulated gauge (book/simulated_gauge.md)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

from dstoolkit.gauge import (
    PAPER_SWEEP,
    RecordingConditions,
    TubeSetup,
    detect_resonances,
    spl_to_pa,
    synthesize_recording,
)
from dstoolkit.plots.artists import (
    KeptFigure,
    gauge_detection_figure,
    update_gauge_detection,
)

from ._explorer import (
    Explorer,
    positions,
    slider,
)
from ._readouts import gauge_reading

# -- the acoustic level gauge: a recording, its resonances and the level --------------------------

#: Recording conditions of the gauge chapter and its explorer: the paper's speaker jitter
#: (σ_v = 0.1 Hz), a quiet microphone (30 dB SPL), 10 ms of audio latency; the background
#: noise is the explorer's slider.
GAUGE_CONDITIONS = RecordingConditions(
    speaker_jitter_hz=0.1,
    microphone_noise_pa=spl_to_pa(30.0),
    background_noise_pa=spl_to_pa(50.0),
    latency_s=0.01,
)


def describe_gauge(numbers: Mapping[str, Any]) -> str:
    """Say what the gauge explorer's figure shows: where the level lies against the truth."""
    error = float(numbers["fit error (mm)"])
    side = "above" if error > 0 else "below"
    return (
        f"the recording's envelope with its {numbers['resonances']} detected resonances "
        f"against the model's lines n c/(2L), and their detection errors below; the series "
        f"fit puts the level {abs(error):.1f} mm {side} the truth, eq. 43 gets "
        f"{numbers['eq. 43 orders wrong']} orders wrong"
    )


def gauge_explorer(
    level_m: float = 4.6,
    temperature_c: float = 26.5,
    top_reflection: float = 0.3,
    background_db: float = 50.0,
    seed: int = 0,
) -> Explorer:
    """Return a simulated acoustic level gauge: a recording, its resonances and the level.

    Level, temperature, the top's reflection R_t and the background noise give the
    recording's envelope and its detected resonances beside the model n c/(2L), the
    detection error z_k − n_k f_F, and the level by the series fit and by eqs. 32/43. One
    recording (the paper's sweep, seeded) is synthesised and analysed per change.

    Parameters
    ----------
    level_m : float, optional
        The level L, m.
    temperature_c : float, optional
        The temperature T, °C.
    top_reflection : float, optional
        The reflection R_t of the tube's top, in [0, 0.9].
    background_db : float, optional
        The background noise, dB SPL.
    seed : int, optional
        The recording's seed (its noise draws are kept).

    Returns
    -------
    Explorer
        Controls ``level``, ``temperature``, ``top_reflection``, ``background``; on the
        static site ``level`` and ``temperature`` answer. Readout:
        the level by the series fit and by eqs. 32/43, wrong orders, and the resonances
        found, missed and spurious.

    See Also
    --------
    dstoolkit.gauge.synthesize_recording, dstoolkit.gauge.detect_resonances

    References
    ----------
    The paper's §4, eqs. 29–32 and 43.

    Examples
    --------
    >>> ex = gauge_explorer(level_m=2.0)
    >>> abs(ex.numbers["fit error (mm)"]) < 50.0
    True
    """
    controls = {
        "level": slider("level L (m)", level_m, 1.0, 10.6, 0.1, readout_format=".1f"),
        "temperature": slider(
            "temperature T (°C)", temperature_c, 0.0, 30.0, 0.5, readout_format=".1f"
        ),
        "top_reflection": slider(
            "top reflection R_t", top_reflection, 0.0, 0.9, 0.05, readout_format=".2f"
        ),
        "background": slider(
            "background noise (dB SPL)", background_db, 30.0, 100.0, 5.0, readout_format=".0f"
        ),
    }

    figure = KeptFigure(gauge_detection_figure, update_gauge_detection)

    def render(level: float, temperature: float, top_reflection: float, background: float):
        setup = TubeSetup(level, temperature, top_reflection=top_reflection)
        cond = replace(GAUGE_CONDITIONS, background_noise_pa=spl_to_pa(background))
        det = detect_resonances(synthesize_recording(setup, PAPER_SWEEP, cond, seed=seed))
        numbers = gauge_reading(setup, det)  # before the figure changes: it may raise
        return figure(setup, det), numbers

    live = {
        "level": positions(controls["level"], 9, 1.6, 9.6),
        "temperature": positions(controls["temperature"], 1, 5.0, 5.0),
    }
    return Explorer(
        controls,
        render,
        title="A simulated acoustic level gauge",
        live=live,
        said=("series-fit L (m)", "resonances"),
        describe=describe_gauge,
    )
