"""Output files that lose nothing: checked before any computing, written atomically.

:func:`check_outputs` runs before a command starts its work and refuses, with an
:class:`~dstoolkit.errors.OutputPathError`, an output that is one of the inputs, two outputs
that are one file, a folder or a device, a folder that cannot be written, and (with an
:class:`~dstoolkit.errors.OutputExistsError`) an existing file, unless ``overwrite`` is
given or the file is a figure the same command made earlier (:func:`made_by`).
:func:`atomic_write` writes a temporary file beside the target and renames it over the
target only when it is complete, so a failure or an interruption leaves no partial file.
"""

from __future__ import annotations

import contextlib
import os
import struct
import tempfile
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import IO

from dstoolkit.errors import OutputExistsError, OutputPathError

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: The PNG text key that marks a figure as made by a dstoolkit command.
FIGURE_KEY = "Software"


def figure_tag(command: str) -> dict[str, str]:
    """PNG metadata naming the command that made a figure (``savefig(metadata=...)``)."""
    return {FIGURE_KEY: f"dstoolkit {command}"}


def made_by(path: str | os.PathLike[str], command: str) -> bool:
    """True when ``path`` is a PNG whose text chunks say ``dstoolkit <command>`` made it."""
    want = f"{FIGURE_KEY}\0dstoolkit {command}".encode()
    try:
        with open(path, "rb") as fh:
            if fh.read(8) != PNG_SIGNATURE:
                return False
            for _ in range(64):  # text chunks come before the image data
                head = fh.read(8)
                if len(head) < 8:
                    return False
                size, tag = struct.unpack(">I4s", head)
                if tag == b"IDAT" or size > 1 << 16:
                    return False
                body = fh.read(size)
                fh.seek(4, os.SEEK_CUR)  # CRC
                if tag == b"tEXt" and body == want:
                    return True
    except OSError:
        return False
    return False


def _writable_folder(path: Path) -> None:
    """Create the output's folder if needed and make sure a file can be created in it."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".probe")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise OutputPathError(f"cannot write {path}: {exc.strerror or exc}; choose another "
                              "place") from None


def check_outputs(
    outputs: Mapping[str, str | os.PathLike[str]],
    *,
    inputs: Sequence[str | os.PathLike[str]] = (),
    overwrite: bool = False,
    replaceable: Callable[[Path], bool] | None = None,
) -> dict[str, Path]:
    """Check output paths before any work; return them as Paths.

    Parameters
    ----------
    outputs
        ``{what: path}``, e.g. ``{"the CSV": "t.csv", "the figure": "t.png"}``.
    inputs
        Files the command reads: no output may be one of them.
    overwrite
        Allow replacing existing files (``--overwrite``).
    replaceable
        Says whether an existing file may be replaced anyway (a figure the same command
        made, :func:`made_by`).
    """
    checked: dict[str, Path] = {}
    seen: dict[Path, str] = {}
    in_paths = [Path(p) for p in inputs]
    for what, raw in outputs.items():
        path = Path(raw)
        text = os.fspath(raw)
        if text.endswith(os.sep) or path.name in ("", ".", ".."):
            raise OutputPathError(f"{what}: {str(raw)!r} is a folder, not a file name")
        key = path.resolve()
        if key in seen:
            raise OutputPathError(f"{what} and {seen[key]} would both be written to {path}; "
                                  "give them different names")
        seen[key] = what
        for source in in_paths:
            same = key == source.resolve()
            with contextlib.suppress(OSError):
                same = same or (path.exists() and os.path.samefile(path, source))
            if same:
                raise OutputPathError(f"{what} would overwrite the input {source}; choose "
                                      "another output name")
        if path.is_symlink() or path.exists():
            if path.is_dir():
                raise OutputPathError(f"{what}: {path} is a folder; give a file name")
            if path.exists() and not path.is_file():
                raise OutputPathError(f"{what}: {path} is not a regular file (a device or a "
                                      "pipe); give a file name")
            if not overwrite and not (replaceable is not None and replaceable(path)):
                raise OutputExistsError(f"{what}: {path} exists; pass --overwrite "
                                        "(overwrite=True) to replace it, or choose another name")
        _writable_folder(path)
        checked[what] = path
    return checked


def atomic_write(path: str | os.PathLike[str], write: Callable[[IO[bytes]], object]) -> Path:
    """Write ``path`` through ``write(file)`` into a temporary file beside it, then rename.

    The target appears complete or not at all; the temporary file is removed on failure.
    Missing parent folders are created.
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".part")
    try:
        with os.fdopen(fd, "wb") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    return target


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
