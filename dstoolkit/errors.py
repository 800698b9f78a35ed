"""Errors and warnings raised by dstoolkit.

Every error derives from :class:`DstoolkitError`, so ``except DstoolkitError`` catches
anything the package raises on purpose; every warning derives from
:class:`DstoolkitWarning`. Each also derives from the built-in class a caller would expect
(``ValueError`` for bad input, ``RuntimeError`` for the environment, ``ImportError`` for a
missing extra). Every message says what was wrong and what to do.

Examples
--------
>>> from dstoolkit.errors import DstoolkitError, InvalidInputError
>>> from dstoolkit.gauge import speed_of_sound
>>> try:
...     speed_of_sound(20.0, model="linear")
... except DstoolkitError as exc:
...     print(type(exc).__name__, isinstance(exc, ValueError))
InvalidInputError True
"""

from __future__ import annotations

__all__ = [
    "AudioDropoutError",
    "AudioDropoutWarning",
    "AudioServerError",
    "AudioStallError",
    "AudioUnavailableError",
    "BrokenExtraError",
    "DetectionError",
    "DstoolkitError",
    "DstoolkitWarning",
    "EvidenceError",
    "GradingFailure",
    "InconsistentDataError",
    "InvalidInputError",
    "MemoryBudgetError",
    "MissingExtraError",
    "NoAudioDeviceError",
    "NotMonotoneError",
    "OutputExistsError",
    "OutputPathError",
    "RecordingFileError",
    "RecordingNotFoundError",
    "TotalConflictError",
    "VertexMethodWarning",
    "WorkLimitError",
    "require_extra",
]


class DstoolkitError(Exception):
    """Base class of every error the package raises on purpose.

    See Also
    --------
    DstoolkitWarning : Base class of the warnings.
    """


class InvalidInputError(DstoolkitError, ValueError):
    """An argument of the wrong type, shape or value; the message names it and what to give.

    Also a ``ValueError``.
    """


class EvidenceError(InvalidInputError):
    """Invalid evidence: bad masses, bad focal elements, incompatible frames.

    Also raised by the filters for models and inputs that do not fit the evidence.
    """


class TotalConflictError(EvidenceError):
    """Dempster's rule is undefined: the conflict K equals 1.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (1).
    """


class NotMonotoneError(DstoolkitError, ValueError):
    """A function declared monotone is not monotone on the box it was given.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), Prop. 2.
    """


class InconsistentDataError(DstoolkitError, RuntimeError):
    """A set-membership (bounded-error) filter found no state consistent with the data.

    Also a ``RuntimeError``.
    """


class DetectionError(DstoolkitError, ValueError):
    """A recording could not be turned into resonance frequencies.

    The message says why (silence, clipping, no sweep, no tube echo, too few resonances) and
    what to do. Also a ``ValueError``.
    """


class AudioUnavailableError(DstoolkitError, RuntimeError):
    """Real audio is not available: sounddevice/PortAudio missing, or no device.

    Also a ``RuntimeError``.
    """


class NoAudioDeviceError(AudioUnavailableError):
    """PortAudio works but found no usable device, or a device failed to open."""


class AudioStallError(AudioUnavailableError, TimeoutError):
    """The audio stream stopped moving: no samples came back before the stream's deadline.

    Also a ``TimeoutError``.
    """


class AudioServerError(AudioUnavailableError):
    """The sound server (or the device) went away during a measurement."""


class AudioDropoutError(DetectionError):
    """The audio stream lost or inserted samples during a measurement (an xrun)."""


class RecordingFileError(DstoolkitError, ValueError):
    """A file that is not a readable WAV recording, or metadata that cannot be stored.

    Also a ``ValueError``.
    """


class RecordingNotFoundError(RecordingFileError, FileNotFoundError):
    """The recording to read does not exist.

    Also a ``FileNotFoundError``.
    """


class MemoryBudgetError(DstoolkitError, MemoryError):
    """A computation would allocate more than the memory budget allows.

    One place sets the budget: :func:`dstoolkit.evidence.set_memory_budget`, or the
    environment variable ``DSTOOLKIT_MEMORY_BUDGET``. Also a ``MemoryError``.
    """


class WorkLimitError(DstoolkitError, RuntimeError):
    """An iteration reached its cap without finishing: the input drives it to run away.

    Also a ``RuntimeError``.
    """


class OutputPathError(DstoolkitError, OSError):
    """An output path cannot be used.

    It is an input, a folder or unwritable, or two outputs of one command share it. Also an
    ``OSError``.
    """


class OutputExistsError(OutputPathError, FileExistsError):
    """An output file exists already and ``overwrite`` (``--overwrite``) was not given.

    Also a ``FileExistsError``.
    """


class MissingExtraError(DstoolkitError, ImportError):
    """An optional part of the package was used without the extra that installs it.

    Also an ``ImportError``; the message names the ``pip install`` command.

    See Also
    --------
    require_extra : Raises it.
    """


class BrokenExtraError(DstoolkitError, RuntimeError):
    """An installed optional dependency failed to import: the environment misconfigures it.

    For example ``MPLBACKEND`` naming no backend of matplotlib; the message says which
    module failed and why.
    """


class GradingFailure(DstoolkitError, AssertionError):  # noqa: N818 - a failed test
    """A graded answer failed its test; the message is the check's verdict.

    Also an ``AssertionError``.
    """


class DstoolkitWarning(UserWarning):
    """Base class of every warning the package issues.

    See Also
    --------
    DstoolkitError : Base class of the errors.
    """


class VertexMethodWarning(DstoolkitWarning):
    """The vertex method's hypothesis visibly fails: an extremum lies inside the box.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), Prop. 1.
    """


class AudioDropoutWarning(DstoolkitWarning, RuntimeWarning):
    """The audio stream lost input or inserted silence in the output (an xrun).

    Also a ``RuntimeWarning``.
    """


def require_extra(module: str, extra: str, purpose: str) -> None:
    """Import ``module``, or raise :class:`MissingExtraError` naming the extra to install.

    Parameters
    ----------
    module : str
        The module to import, e.g. ``"matplotlib"``.
    extra : str
        The extra of dstoolkit that installs it, e.g. ``"plots"``.
    purpose : str
        What needs it, for the message (e.g. ``"dstoolkit.plots"``).

    Raises
    ------
    MissingExtraError
        The module cannot be imported; the message names ``pip install 'dstoolkit[extra]'``.

    Examples
    --------
    >>> from dstoolkit.errors import MissingExtraError, require_extra
    >>> require_extra("numpy", "core", "the evidence algebra")
    >>> try:
    ...     require_extra("no_such_module_here", "plots", "the figures")
    ... except MissingExtraError as exc:
    ...     print(exc)
    the figures needs 'no_such_module_here', which is not installed. ... 'dstoolkit[plots]'
    """
    import importlib

    try:
        importlib.import_module(module)
    except ImportError as exc:
        raise MissingExtraError(
            f"{purpose} needs {module!r}, which is not installed. "
            f"Install the extra: pip install 'dstoolkit[{extra}]'"
        ) from exc
    except Exception as exc:  # installed, but its import fails: a setting in the environment
        raise BrokenExtraError(
            f"{purpose} needs {module!r}, which is installed but failed to import: {exc}. "
            "Check the environment variables that configure it (for matplotlib, MPLBACKEND)"
        ) from exc
