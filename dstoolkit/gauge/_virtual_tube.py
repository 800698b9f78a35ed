"""A virtual tube: the sweep, already shaped by the tube model, to play through real audio.

In the lab the speaker's sweep travels down the tube, comes back from the liquid surface
and reaches the microphone as a standing-wave pattern (paper eqs. 27–29). Without a tube,
the same pattern is computed by :func:`dstoolkit.gauge.synthesize_recording` (the tube is
linear, so it does not matter whether it acts before or after the audio path) and played
instead of the bare sweep. Through a loopback (``scripts/audio-loopback.sh``) the recording
then carries the standing wave *and* everything real about the audio path: the latency of
PortAudio, ALSA and PulseAudio, its buffering, resampling and level. Measuring through it
exercises the whole measurement chain and must give back the simulated level.
"""

from __future__ import annotations

import numpy as np

from dstoolkit.errors import InvalidInputError

from ._sweep import LinearSweep
from ._tube import RecordingConditions, TubeSetup, synthesize_recording

#: Peak of the played signal, full scale. Leaves headroom against clipping in the path.
DEFAULT_AMPLITUDE = 0.5
#: Echoes weaker than this (relative to the direct wave) are left out of the tail.
_ECHO_FLOOR = 1e-3


def virtual_tube_signal(
    setup: TubeSetup,
    sweep: LinearSweep,
    *,
    amplitude: float = DEFAULT_AMPLITUDE,
    conditions: RecordingConditions | None = None,
    seed: int = 0,
) -> np.ndarray:
    """Compute what the microphone of ``setup`` would hear during ``sweep``, scaled.

    Played through a real audio path instead of the bare sweep, it makes the recording carry
    the tube's standing wave and everything real about the path.

    Parameters
    ----------
    setup : TubeSetup
        The simulated gauge (level, temperature, losses, reflections).
    sweep : LinearSweep
        The sweep the speaker plays.
    amplitude : float, optional
        Peak of the returned signal, full scale, in (0, 1] (default :data:`DEFAULT_AMPLITUDE`).
    conditions : RecordingConditions, optional
        Noise to add (microphone, background, speaker jitter); its latency, clipping and
        quantisation are ignored because the real audio path supplies its own.
    seed : int, optional
        Seed of the noises.

    Returns
    -------
    numpy.ndarray, shape (n,)
        Samples in full-scale units. It starts with the sweep's first sample (no latency) and
        lasts the sweep plus the time for the echoes to die down below 1e-3 (at most 1 s).

    Raises
    ------
    InvalidInputError
        An amplitude outside (0, 1].

    See Also
    --------
    synthesize_recording : The recording itself, with latency, clipping and quantisation.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (27)–(29).

    Examples
    --------
    >>> from dstoolkit.gauge import LinearSweep, TubeSetup, virtual_tube_signal
    >>> sweep = LinearSweep(1000.0, 1200.0, duration=0.5, sample_rate=8000.0)
    >>> signal = virtual_tube_signal(TubeSetup(1.3), sweep, amplitude=0.5)
    >>> float(abs(signal).max())
    0.5
    """
    if not 0 < amplitude <= 1:
        raise InvalidInputError(f"amplitude must be in (0, 1], got {amplitude}")
    echoes = setup.echo_count(sweep.f_start, _ECHO_FLOOR)
    tail = min(1.0, max(0.01, echoes * setup.round_trip_s))
    base = RecordingConditions() if conditions is None else conditions
    clean = RecordingConditions(
        source_pressure_pa=1.0,
        speaker_jitter_hz=base.speaker_jitter_hz,
        speaker_jitter_bandwidth_hz=base.speaker_jitter_bandwidth_hz,
        microphone_noise_pa=base.microphone_noise_pa / max(base.source_pressure_pa, 1e-300),
        background_noise_pa=base.background_noise_pa / max(base.source_pressure_pa, 1e-300),
        latency_s=0.0,
        full_scale_pa=1e6,  # no clipping here: the peak is normalised below
        bits=None,
        tail_s=tail,
    )
    pressure = synthesize_recording(setup, sweep, clean, seed=seed).samples
    peak = float(np.max(np.abs(pressure)))
    return pressure * (amplitude / peak)
