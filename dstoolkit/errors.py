"""Errors raised by dstoolkit.

Every error derives from :class:`DstoolkitError`, so ``except DstoolkitError`` catches
anything the package raises on purpose; every warning derives from
:class:`DstoolkitWarning`. Each also derives from the built-in class a caller would expect
(``ValueError`` for bad input, ``RuntimeError`` for the environment, ``ImportError`` for a
missing extra). Every message says what was wrong and what to do.
"""

from __future__ import annotations


class DstoolkitError(Exception):
    """Base class of every error the package raises on purpose."""


class InvalidInputError(DstoolkitError, ValueError):
    """An argument of the wrong type, shape or value; the message names it and what to give."""


class EvidenceError(InvalidInputError):
    """Invalid evidence: bad masses, bad focal elements, incompatible frames."""


class TotalConflictError(EvidenceError):
    """Dempster's rule (eq. 1) is undefined: the conflict K equals 1."""


class NotMonotoneError(DstoolkitError, ValueError):
    """A function declared monotone (Prop. 2) is not monotone on the box it was given."""


class InconsistentDataError(DstoolkitError, RuntimeError):
    """A set-membership (bounded-error) filter found no state consistent with the data."""


class DetectionError(DstoolkitError, ValueError):
    """A recording could not be turned into resonance frequencies."""


class AudioUnavailableError(DstoolkitError, RuntimeError):
    """Real audio is not available: sounddevice/PortAudio missing or no device."""


class NoAudioDeviceError(AudioUnavailableError):
    """PortAudio works but found no usable device, or a device failed to open."""


class AudioStallError(AudioUnavailableError, TimeoutError):
    """The audio stream stopped moving: no samples came back before the stream's deadline."""


class AudioServerError(AudioUnavailableError):
    """The sound server (or device) went away during a measurement."""


class AudioDropoutError(DetectionError):
    """The audio stream lost or inserted samples during a measurement (an xrun)."""


class RecordingFileError(DstoolkitError, ValueError):
    """A file that is not a readable WAV recording, or metadata that cannot be stored."""


class RecordingNotFoundError(RecordingFileError, FileNotFoundError):
    """The recording to read does not exist."""


class MemoryBudgetError(DstoolkitError, MemoryError):
    """A computation would allocate more than the memory budget allows (one place sets it:
    :func:`dstoolkit.evidence.set_memory_budget`, or ``DSTOOLKIT_MEMORY_BUDGET``)."""


class WorkLimitError(DstoolkitError, RuntimeError):
    """An iteration reached its cap without finishing: the input drives it to run away."""


class OutputPathError(DstoolkitError, OSError):
    """An output path cannot be used: it is an input, a folder, unwritable, or two outputs
    of one command share it."""


class OutputExistsError(OutputPathError, FileExistsError):
    """An output file exists already and ``overwrite`` (``--overwrite``) was not given."""


class MissingExtraError(DstoolkitError, ImportError):
    """An optional part of the package was used without the extra that installs it."""


class GradingFailure(DstoolkitError, AssertionError):  # noqa: N818 - a failed test
    """A graded answer failed its test; the message is the check's verdict."""


class DstoolkitWarning(UserWarning):
    """Base class of every warning the package issues."""


class VertexMethodWarning(DstoolkitWarning):
    """The vertex method's hypothesis (Prop. 1: no extremum inside the box) visibly fails."""


class AudioDropoutWarning(DstoolkitWarning, RuntimeWarning):
    """The audio stream lost input or inserted silence in the output (an xrun)."""


def require_extra(module: str, extra: str, purpose: str) -> None:
    """Import ``module`` or raise :class:`MissingExtraError` naming the extra to install."""
    import importlib

    try:
        importlib.import_module(module)
    except ImportError as exc:
        raise MissingExtraError(
            f"{purpose} needs {module!r}, which is not installed. "
            f"Install the extra: pip install 'dstoolkit[{extra}]'"
        ) from exc
