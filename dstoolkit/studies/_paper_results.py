"""What the paper reports, kept as data to compare with (paper Table 3, §4).

These are the paper's printed figures, not results of this toolkit: chapters and the
``table3`` command print them beside what dstoolkit computes.
"""

from __future__ import annotations

#: Table 3 cases: (level in m, temperature in °C).
TABLE3_CASES: tuple[tuple[float, float], ...] = (
    (1.3, 27.0),
    (2.1, 26.5),
    (2.6, 26.5),
    (3.6, 26.5),
    (4.6, 26.5),
    (5.6, 26.5),
    (6.6, 26.5),
    (7.6, 26.5),
    (8.6, 23.9),
    (9.6, 23.9),
)

#: Table 3, mean absolute level error (m) per level: the paper's method, Nassreddine's
#: filter, direct measurement (eqs. 32–33).
TABLE3_MEAN_ABS_ERROR_M: dict[float, dict[str, float]] = {
    1.3: {"dependent_evidence": 0.0126, "nassreddine": 0.016, "direct": 0.238},
    2.1: {"dependent_evidence": 0.0254, "nassreddine": 0.0364, "direct": 0.0441},
    2.6: {"dependent_evidence": 0.0144, "nassreddine": 0.0297, "direct": 0.0591},
    3.6: {"dependent_evidence": 0.0141, "nassreddine": 0.0312, "direct": 0.0468},
    4.6: {"dependent_evidence": 0.0160, "nassreddine": 0.0337, "direct": 0.0552},
    5.6: {"dependent_evidence": 0.018, "nassreddine": 0.0374, "direct": 0.0661},
    6.6: {"dependent_evidence": 0.0238, "nassreddine": 0.0436, "direct": 0.088},
    7.6: {"dependent_evidence": 0.0299, "nassreddine": 0.0530, "direct": 0.1060},
    8.6: {"dependent_evidence": 0.0216, "nassreddine": 0.0456, "direct": 0.1295},
    9.6: {"dependent_evidence": 0.0435, "nassreddine": 0.0732, "direct": 0.1624},
}

#: Runtime of one run (s) on a 3 GHz E8400, smallest and largest over the levels.
PAPER_RUNTIME_RANGE_S: dict[str, tuple[float, float]] = {
    "dependent_evidence": (1.81, 35.15),
    "nassreddine": (0.88, 8.36),
}

#: Noise figures of §4 (Hz): state noise v and observation noise w (σ, lower, mode, upper).
STATE_NOISE_HZ = {"sigma": 0.1, "lower": -0.3, "mode": 0.0, "upper": 0.3}
#: The observation noise w of §4 (Hz): σ, lower, mode, upper.
OBSERVATION_NOISE_HZ = {"sigma": 1.23, "lower": -10.59, "mode": -6.9, "upper": -3.21}

#: The experiment's sweep: 1000 → 2400 Hz in 5 s at 44.1 kHz, PVC tube of 75 mm.
SWEEP = {
    "f_start_hz": 1000.0,
    "f_stop_hz": 2400.0,
    "duration_s": 5.0,
    "sample_rate_hz": 44100,
    "tube_diameter_m": 0.075,
}
