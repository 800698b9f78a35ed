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
corrections the detector reads κ/(2 f_F) + κ τ high, as the paper's did.

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
    """Error samples of one noise and the triangle built from them.

    Made by :func:`characterise_state_noise` and :func:`characterise_observation_noise`, or
    :meth:`from_samples`.

    Parameters
    ----------
    name : str
        What the noise is, for the summary.
    samples : numpy.ndarray, shape (N,)
        The errors, Hz.
    bounds : dstoolkit.evidence.TriangularBounds
        Lower end, mode and upper end of the triangle, Hz.
    details : dict of str to numpy.ndarray, optional
        Per-sample context, each of shape (N,) (e.g. level, order, true and detected
        frequency).

    See Also
    --------
    dstoolkit.evidence.triangular_evidence : The evidence of such a triangle.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3, Figs. 8–9, Tables 1–2.
    """

    name: str
    samples: np.ndarray
    bounds: TriangularBounds
    details: dict[str, np.ndarray] = field(default_factory=dict, repr=False)

    @classmethod
    def from_samples(
        cls, name: str, samples: Any, k: float = 3.0, details: dict[str, np.ndarray] | None = None
    ) -> NoiseCharacterisation:
        """Fit a triangle to error samples: the mode at their mean, the bounds at mean ± ``k`` σ.

        Parameters
        ----------
        name : str
            What the noise is.
        samples : array_like, any shape
            The errors, Hz (flattened).
        k : float, optional
            Half-width of the support in standard deviations (default 3, the paper's convention).
        details : dict of str to numpy.ndarray, optional
            Per-sample context.

        Returns
        -------
        NoiseCharacterisation
            The samples and their triangle.

        See Also
        --------
        dstoolkit.evidence.triangular_from_samples

        References
        ----------
        Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3.

        Examples
        --------
        >>> from dstoolkit.gauge import NoiseCharacterisation
        >>> noise = NoiseCharacterisation.from_samples("v", [-0.1, 0.0, 0.1])
        >>> noise.mode, round(noise.upper, 6)
        (0.0, 0.3)
        """
        x = np.asarray(samples, dtype=float).reshape(-1)
        return cls(name, x, triangular_from_samples(x, k), details or {})

    @property
    def sigma(self) -> float:
        """Sample standard deviation of the errors (ddof = 1), Hz."""
        return float(self.samples.std(ddof=1))

    @property
    def mode(self) -> float:
        """The triangle's mode (the mean of the errors), Hz."""
        return self.bounds.mode

    @property
    def lower(self) -> float:
        """The lower end of the triangle's support, Hz."""
        return self.bounds.lower

    @property
    def upper(self) -> float:
        """The upper end of the triangle's support, Hz."""
        return self.bounds.upper

    def possibility(self, x: Any) -> np.ndarray:
        """π(x), the triangular possibility distribution with this support and mode.

        Parameters
        ----------
        x : float or array_like, any shape
            Noise values, Hz.

        Returns
        -------
        numpy.ndarray
            π(x) in [0, 1], shaped as ``x``.

        References
        ----------
        Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (22).
        """
        return possibility(x, *self.bounds)

    def evidence(
        self, p: int = 3, epsilon: float = 0.05, theta: tuple[float, float] | None = None
    ) -> IntervalEvidence:
        """Build the evidence of Tables 1–2: p α-cuts of mass (1 − ε)/p, and ε on Θ.

        Parameters
        ----------
        p : int, optional
            Number of α-cuts (default 3, the paper's).
        epsilon : float, optional
            Mass ε on the frame Θ (default 0.05).
        theta : tuple of float, optional
            The frame Θ, (lower, upper) in Hz (default: the support widened, as
            :func:`~dstoolkit.evidence.triangular_evidence` does).

        Returns
        -------
        dstoolkit.evidence.IntervalEvidence
            p + 1 focal intervals, Hz.

        See Also
        --------
        dstoolkit.evidence.triangular_evidence

        References
        ----------
        Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (24)–(26), Tables 1–2.
        """
        return triangular_evidence(*self.bounds, p=p, epsilon=epsilon, theta=theta)

    def summary(self) -> str:
        """One line: the number of samples, σ, the mode and the bounds.

        Returns
        -------
        str
            The line, in Hz.
        """
        return (
            f"{self.name}: {self.samples.size} samples, σ = {self.sigma:.3f} Hz, "
            f"mode = {self.mode:.3f} Hz, bounds [{self.lower:.3f}, {self.upper:.3f}] Hz"
        )


def characterise_state_noise(
    conditions: RecordingConditions | None = None,
    sweep: LinearSweep = PAPER_SWEEP,
    runs: int = 10,
    points: int = 100,
    seed: int = 0,
) -> NoiseCharacterisation:
    """Measure the state noise v as the paper did: the speaker's frequency error.

    The simulated speaker's frequency error δf is read at ``points`` frequencies spread
    uniformly over the sweep in each of ``runs`` calibration runs (the paper's oscilloscope
    measurement), and a triangle is fitted to the errors.

    Parameters
    ----------
    conditions : RecordingConditions, optional
        The speaker's jitter (default: the paper's σ_v = 0.1 Hz).
    sweep : LinearSweep, optional
        The sweep (default :data:`PAPER_SWEEP`).
    runs : int, optional
        Calibration runs, ≥ 1 (default 10).
    points : int, optional
        Frequencies per run, ≥ 1 (default 100, as the paper's).
    seed : int, optional
        Seed of the jitter.

    Returns
    -------
    NoiseCharacterisation
        ``runs × points`` errors, Hz, with the frequency and run of each in ``details``.

    Raises
    ------
    InvalidInputError
        ``runs`` or ``points`` below 1.

    See Also
    --------
    characterise_observation_noise : The observation noise w.
    GAUGE_STATE_NOISE : The paper's figure.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3, Fig. 8, Table 1.

    Examples
    --------
    >>> from dstoolkit.gauge import characterise_state_noise
    >>> v = characterise_state_noise(runs=5, seed=1)
    >>> v.samples.shape
    (500,)
    >>> 0.02 < v.sigma < 0.3
    True
    """
    cond = RecordingConditions(speaker_jitter_hz=0.1) if conditions is None else conditions
    if runs < 1 or points < 1:
        raise InvalidInputError(f"need runs >= 1 and points >= 1, got {runs}, {points}")
    rng = np.random.default_rng(seed)
    freqs = np.linspace(sweep.f_start, sweep.f_stop, points)
    t = sweep.time_at(freqs)
    errors = np.stack(
        [np.interp(t, *speaker_frequency_error(sweep, cond, rng)) for _ in range(runs)]
    )
    return NoiseCharacterisation.from_samples(
        "state noise v (speaker)",
        errors.ravel(),
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
    """Measure the observation noise w = true − detected resonance frequency, as the paper did.

    Recordings are synthesised at each level, their resonances detected by
    :func:`detect_resonances`, and each detected resonance matched to the order n of the model
    (n f_F + κ/(2 f_F) + κ τ is the first-order prediction of where it appears; later echoes
    move it by less than f_F/2, so the match is unambiguous).

    Parameters
    ----------
    levels_m : array_like, shape (N,), optional
        Calibration levels, m (default :data:`PAPER_CALIBRATION_LEVELS`, the paper's 30 from
        1.3 to 10.6 m).
    temperature_c : float or array_like, broadcastable to (N,), optional
        Air temperature(s), °C (default 25).
    conditions : RecordingConditions, optional
        Noise and latency of the recordings (default :func:`typical_conditions`: σ_v = 0.1 Hz
        speaker jitter, 30 dB SPL microphone noise, 50 dB SPL background, 10 ms latency).
    sweep : LinearSweep, optional
        The sweep (default :data:`PAPER_SWEEP`).
    tube : dict, optional
        Extra :class:`TubeSetup` parameters (reflections, losses).
    runs_per_level : int, optional
        Recordings per level (default 1).
    seed : int, optional
        Seed of the recordings' noises.
    correct_sweep_rate, correct_latency : bool, optional
        Passed to the detector; False (default) mimics the paper's detector, whose w has its
        mode near −6.9 Hz.

    Returns
    -------
    NoiseCharacterisation
        One error per detected resonance, Hz, with the level, order, true and detected
        frequency of each in ``details``.

    Raises
    ------
    DetectionError
        A recording in which the resonances cannot be detected.
    InvalidInputError
        A level or temperature that is not valid.

    See Also
    --------
    characterise_state_noise : The state noise v.
    GAUGE_OBS_NOISE : The paper's figure.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (40), §4.3, Fig. 9, Table 2.

    Examples
    --------
    >>> from dstoolkit.gauge import characterise_observation_noise
    >>> w = characterise_observation_noise([2.0, 4.0], seed=0)
    >>> bool(w.mode < 0)  # a detector that reads f_0 + κ t reads high
    True
    """
    cond = conditions if conditions is not None else typical_conditions()
    levels = np.atleast_1d(np.asarray(levels_m, dtype=float))
    temps = np.broadcast_to(np.asarray(temperature_c, dtype=float), levels.shape)
    rng = np.random.default_rng(seed)
    cols: dict[str, list[np.ndarray]] = {
        k: [] for k in ("level_m", "order", "true_hz", "detected_hz")
    }
    for level, temp in zip(
        np.repeat(levels, runs_per_level), np.repeat(temps, runs_per_level), strict=True
    ):
        setup = TubeSetup(float(level), float(temp), **(tube or {}))
        rec = synthesize_recording(setup, sweep, cond, seed=rng)
        det = detect_resonances(
            rec, correct_sweep_rate=correct_sweep_rate, correct_latency=correct_latency
        )
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
        details["true_hz"] - details["detected_hz"],
        details=details,
    )
