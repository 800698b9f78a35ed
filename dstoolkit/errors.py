"""Errors raised by dstoolkit.

Every error says what was wrong and what to do about it. They derive from ``ValueError`` (or
``RuntimeError`` for environment problems) so callers may catch them broadly.
"""

from __future__ import annotations


class EvidenceError(ValueError):
    """Invalid evidence: bad masses, bad focal elements, incompatible frames."""


class TotalConflictError(EvidenceError):
    """Dempster's rule (eq. 1) is undefined: the conflict K equals 1."""


class NotMonotoneError(ValueError):
    """A function declared monotone (Prop. 2) is not monotone on the box it was given."""


class InconsistentDataError(RuntimeError):
    """A set-membership (bounded-error) filter found no state consistent with the data."""


class DetectionError(ValueError):
    """A recording could not be turned into resonance frequencies."""


class AudioUnavailableError(RuntimeError):
    """Real audio is not available: sounddevice/PortAudio missing or no device."""
