"""The acoustic standing-wave level gauge of the paper's §4.

The speed of sound (eq. 33), the sweep, the tube simulator, resonance detection, the level
equations (eqs. 32, 39, 40, 43), noise characterisation (Figs. 8–9) and the gauge's
state-space model (eqs. 36–43).
"""

from __future__ import annotations

from dstoolkit.errors import (
    DetectionError,
)

from ._acoustics import (
    DEFAULT_BAND,
    SpeedModel,
    fundamental_frequency,
    plane_wave_cutoff,
    resonance_frequencies,
    resonance_orders,
    round_trip_time,
    speed_of_sound,
    speed_of_sound_cramer,
    speed_of_sound_ideal_gas,
    speed_of_sound_paper,
)
from ._gauge_model import (
    GAUGE_OBS_NOISE,
    GAUGE_STATE_NOISE,
    PAPER_THETA,
    GaugeSequence,
    gauge_state_space_model,
    simulate_gauge,
)
from ._latency import (
    FIRST_ARRIVAL,
    LatencyEstimate,
    estimate_latency,
    valid_correlation,
)
from ._level import (
    ResonanceSeriesFit,
    direct_levels,
    fit_resonance_series,
    level_from_fundamental,
    level_from_resonance,
    observation,
    observation_inverse,
    orders_eq43,
    state_transition,
    state_transition_derivative,
)
from ._noise_characterisation import (
    PAPER_CALIBRATION_LEVELS,
    NoiseCharacterisation,
    characterise_observation_noise,
    characterise_state_noise,
)
from ._resonance import (
    DetectionResult,
    detect_resonances,
    detection_precision_hz,
    envelope,
    latency_offset,
    model_peak_frequencies,
    sweep_rate_offset,
)
from ._sweep import (
    PAPER_SWEEP,
    LinearSweep,
)
from ._tube import (
    Recording,
    RecordingConditions,
    TubeSetup,
    model_envelope,
    spl_to_pa,
    synthesize_recording,
    typical_conditions,
    wall_attenuation,
)
from ._virtual_tube import (
    DEFAULT_AMPLITUDE,
    virtual_tube_signal,
)

__all__ = [
    "DEFAULT_AMPLITUDE",
    "DEFAULT_BAND",
    "DetectionError",
    "DetectionResult",
    "FIRST_ARRIVAL",
    "LatencyEstimate",
    "GAUGE_OBS_NOISE",
    "GAUGE_STATE_NOISE",
    "GaugeSequence",
    "LinearSweep",
    "NoiseCharacterisation",
    "PAPER_CALIBRATION_LEVELS",
    "PAPER_SWEEP",
    "PAPER_THETA",
    "Recording",
    "RecordingConditions",
    "ResonanceSeriesFit",
    "SpeedModel",
    "TubeSetup",
    "characterise_observation_noise",
    "characterise_state_noise",
    "detect_resonances",
    "detection_precision_hz",
    "direct_levels",
    "envelope",
    "estimate_latency",
    "fit_resonance_series",
    "fundamental_frequency",
    "gauge_state_space_model",
    "latency_offset",
    "level_from_fundamental",
    "level_from_resonance",
    "model_envelope",
    "model_peak_frequencies",
    "observation",
    "observation_inverse",
    "orders_eq43",
    "plane_wave_cutoff",
    "resonance_frequencies",
    "resonance_orders",
    "round_trip_time",
    "simulate_gauge",
    "speed_of_sound",
    "speed_of_sound_cramer",
    "speed_of_sound_ideal_gas",
    "speed_of_sound_paper",
    "spl_to_pa",
    "state_transition",
    "state_transition_derivative",
    "sweep_rate_offset",
    "synthesize_recording",
    "typical_conditions",
    "valid_correlation",
    "virtual_tube_signal",
    "wall_attenuation",
]
