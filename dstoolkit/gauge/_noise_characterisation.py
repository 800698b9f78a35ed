"""The gauge's noises measured as the paper measured them (§4.3, Figs. 8–9), in simulation.

State noise v (speaker): the paper recorded the speaker's output with an oscilloscope and
took the error of the emitted frequency at about 100 points from 1000 to 2500 Hz;
σ_v = 0.1 Hz, mode 0, bounds ±3σ. Here: the simulated speaker's frequency error δf at
``points`` frequencies spread over the sweep, in each of ``runs`` calibration runs.

Observation noise w (microphone + detector): the paper detected the resonances of about 30
levels from 1.3 to 10.6 m and took the errors against the true values; σ_w = 1.23 Hz,
mode −6.9 Hz, bounds [−10.59, −3.21]. Here: synthesised recordings at those levels, detected
with :func:`dstoolkit.gauge.detect_resonances`, and w = true − detected, the sign of
paper eq. 40 (g(x) = z + w: a reading that is too high gives w < 0). Without the offset
corrections the detector reads k/(2 f_F) + k τ high, as the paper's did.

Both become triangles (mode = mean, bounds = mean ± 3σ) and evidence (eqs. 22–26) by
:func:`dstoolkit.evidence.triangular_evidence`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from dstoolkit.errors import InvalidInputError
from dstoolkit.evidence import (
    IntervalEvidence,
    TriangularBounds,
    possibility,
    triangular_evidence,
    triangular_from_samples,
)

from ._resonance import detect_resonances
from ._sweep import PAPER_SWEEP, LinearSweep
from ._tube import (
    RecordingConditions,
    TubeSetup,
    speaker_frequency_error,
    synthesize_recording,
    typical_conditions,
)

#: The paper's calibration levels for w: about 30 from 1.3 to 10.6 m (§4.3).
PAPER_CALIBRATION_LEVELS = np.linspace(1.3, 10.6, 30)
PAPER_CALIBRATION_LEVELS.flags.writeable = False


@dataclass(frozen=True)
class NoiseCharacterisation:
    """Error samples of one noise and the triangle built from them (Figs. 8–9).

    ``details`` holds per-sample context (e.g. level, order, true and detected frequency).
    """

    name: str
    samples: np.ndarray
    bounds: TriangularBounds
    details: dict[str, np.ndarray] = field(default_factory=dict, repr=False)

    @classmethod
    def from_samples(cls, name: str, samples: Any, k: float = 3.0,
                     details: dict[str, np.ndarray] | None = None) -> NoiseCharacterisation:
        """Mode at the mean, bounds at mean ± ``k`` σ (the paper's convention)."""
        x = np.asarray(samples, dtype=float).reshape(-1)
        return cls(name, x, triangular_from_samples(x, k), details or {})

    @property
    def sigma(self) -> float:
        """Sample standard deviation of the errors (ddof = 1)."""
        return float(self.samples.std(ddof=1))

    @property
    def mode(self) -> float:
        return self.bounds.mode

    @property
    def lower(self) -> float:
        return self.bounds.lower

    @property
    def upper(self) -> float:
        return self.bounds.upper

    def possibility(self, x: Any) -> np.ndarray:
        """π(x), the triangle with support [lower, upper] and this mode (eq. 22)."""
        return possibility(x, *self.bounds)

    def evidence(self, p: int = 3, epsilon: float = 0.05,
                 theta: tuple[float, float] | None = None) -> IntervalEvidence:
        """The evidence of Tables 1–2: p α-cuts of mass (1 − ε)/p and ε on Θ (eqs. 24–26)."""
        return triangular_evidence(*self.bounds, p=p, epsilon=epsilon, theta=theta)

    def summary(self) -> str:
        return (f"{self.name}: {self.samples.size} samples, σ = {self.sigma:.3f} Hz, "
                f"mode = {self.mode:.3f} Hz, bounds [{self.lower:.3f}, {self.upper:.3f}] Hz")


def characterise_state_noise(
    conditions: RecordingConditions | None = None,
    sweep: LinearSweep = PAPER_SWEEP,
    runs: int = 10,
    points: int = 100,
    seed: int = 0,
) -> NoiseCharacterisation:
    """v from ``runs`` calibration runs of the speaker: its frequency error at ``points``
    frequencies spread uniformly over the sweep (the oscilloscope measurement of §4.3).

    Default conditions: the paper's σ_v = 0.1 Hz of speaker jitter.
    """
    cond = RecordingConditions(speaker_jitter_hz=0.1) if conditions is None else conditions
    if runs < 1 or points < 1:
        raise InvalidInputError(f"need runs >= 1 and points >= 1, got {runs}, {points}")
    rng = np.random.default_rng(seed)
    freqs = np.linspace(sweep.f_start, sweep.f_stop, points)
    t = sweep.time_at(freqs)
    errors = np.stack([np.interp(t, *speaker_frequency_error(sweep, cond, rng))
                       for _ in range(runs)])
    return NoiseCharacterisation.from_samples(
        "state noise v (speaker)", errors.ravel(),
        details={"frequency_hz": np.tile(freqs, runs), "run": np.repeat(np.arange(runs), points)},
    )


def characterise_observation_noise(
    levels_m: Any = PAPER_CALIBRATION_LEVELS,
    temperature_c: Any = 25.0,
    conditions: RecordingConditions | None = None,
    sweep: LinearSweep = PAPER_SWEEP,
    tube: dict[str, Any] | None = None,
    runs_per_level: int = 1,
    seed: int = 0,
    correct_sweep_rate: bool = False,
    correct_latency: bool = False,
) -> NoiseCharacterisation:
    """w = true − detected resonance frequency over synthesised calibration recordings.

    Parameters
    ----------
    levels_m, temperature_c
        Calibration levels (default the paper's 30 from 1.3 to 10.6 m) and temperature(s).
    conditions
        Noise and latency of the recordings (default: σ_v = 0.1 Hz speaker jitter, 30 dB SPL
        microphone noise, 50 dB SPL background, 10 ms latency).
    tube
        Extra :class:`~dstoolkit.gauge.TubeSetup` parameters (reflections, losses).
    correct_sweep_rate, correct_latency
        Passed to the detector; False (default) mimics the paper's detector.

    Notes
    -----
    Each detected resonance is matched to the order n of the model, n f_F + k/(2 f_F) + k τ
    being the first-order prediction of where it appears (later echoes move it by less than
    f_F/2, so the match is unambiguous).
    """
    cond = conditions if conditions is not None else typical_conditions()
    levels = np.atleast_1d(np.asarray(levels_m, dtype=float))
    temps = np.broadcast_to(np.asarray(temperature_c, dtype=float), levels.shape)
    rng = np.random.default_rng(seed)
    cols: dict[str, list[np.ndarray]] = {k: [] for k in
                                        ("level_m", "order", "true_hz", "detected_hz")}
    for level, temp in zip(np.repeat(levels, runs_per_level), np.repeat(temps, runs_per_level),
                           strict=True):
        setup = TubeSetup(float(level), float(temp), **(tube or {}))
        rec = synthesize_recording(setup, sweep, cond, seed=rng)
        det = detect_resonances(rec, correct_sweep_rate=correct_sweep_rate,
                                correct_latency=correct_latency)
        f_f = setup.fundamental_hz
        predicted_offset = sweep.rate * (0.5 / f_f + cond.latency_s)
        n = np.rint((det.raw_frequencies - predicted_offset) / f_f)
        cols["level_m"].append(np.full(n.size, level))
        cols["order"].append(n)
        cols["true_hz"].append(n * f_f)
        cols["detected_hz"].append(det.frequencies)
    details = {k: np.concatenate(v) for k, v in cols.items()}
    return NoiseCharacterisation.from_samples(
        "observation noise w (microphone and detector)",
        details["true_hz"] - details["detected_hz"], details=details)
