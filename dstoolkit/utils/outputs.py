"""Output files that lose nothing: checked before any computing, written atomically.

:func:`check_outputs` runs before a command starts its work and refuses, with an
:class:`~dstoolkit.errors.OutputPathError`, an output that is one of the inputs, two outputs
that are one file, a folder or a device, a folder that cannot be written, and (with an
:class:`~dstoolkit.errors.OutputExistsError`) an existing file, unless ``overwrite`` is
given or the file is a figure the same command made earlier (:func:`made_by`).
:func:`atomic_write` writes a temporary file beside the target and moves it into place only
when it is complete, so a failure or an interruption leaves no partial file.

Inside :func:`output_run` (one command of the command line), the check and the write are
one decision: a path that was new when it was checked is created without clobbering (a
hard link, which fails when the name exists), so a file that appeared meanwhile survives;
a file that was allowed to be replaced is replaced only if it is still the file that was
checked. When the run fails or is interrupted, the files and folders it made are removed.
Outputs that are not regular files or new paths (devices, FIFOs, sockets, anything in
``/dev``, ``/proc`` or ``/sys``, and symbolic links to them) are refused, whatever
``overwrite`` says.
"""

from __future__ import annotations

import contextlib
import contextvars
import errno
import os
import stat
import struct
import tempfile
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO

from dstoolkit.errors import OutputExistsError, OutputPathError

__all__ = [
    "atomic_write",
    "check_outputs",
    "figure_tag",
    "made_by",
    "output_run",
    "refuse_special",
]

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: The PNG text key that marks a figure as made by a dstoolkit command.
FIGURE_KEY = "Software"


def figure_tag(command: str) -> dict[str, str]:
    """Return PNG metadata naming the command that made a figure.

    Parameters
    ----------
    command : str
        The command-line command ("study", "measure"...).

    Returns
    -------
    dict of str to str
        For ``Figure.savefig(..., metadata=figure_tag(command))``; :func:`made_by` reads it.

    Examples
    --------
    >>> from dstoolkit.utils.outputs import figure_tag
    >>> figure_tag("study")
    {'Software': 'dstoolkit study'}
    """
    return {FIGURE_KEY: f"dstoolkit {command}"}


def made_by(path: str | os.PathLike[str], command: str) -> bool:
    """Tell whether a PNG file was made by a given dstoolkit command.

    Parameters
    ----------
    path : str or os.PathLike
        The file to look at (only its first chunks are read).
    command : str
        The command that may have made it.

    Returns
    -------
    bool
        True when ``path`` is a PNG whose text chunks carry :func:`figure_tag` of
        ``command``; False for anything else, including a file that cannot be read.

    Examples
    --------
    >>> from dstoolkit.utils.outputs import made_by
    >>> made_by("/nonexistent/figure.png", "study")
    False
    """
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


#: Folders no output may be written into, whatever ``overwrite`` says.
SYSTEM_FOLDERS = (Path("/dev"), Path("/proc"), Path("/sys"))


@dataclass
class _Run:
    """What one command plans to write and what it has made so far."""

    #: resolved output path -> None (must be new) or (device, inode) of the file that
    #: may be replaced
    plan: dict[Path, tuple[int, int] | None] = field(default_factory=dict)
    files: list[Path] = field(default_factory=list)
    folders: list[Path] = field(default_factory=list)

    def discard(self) -> None:
        """Remove the files and the (then empty) folders this run made, newest first."""
        for path in reversed(self.files):
            with contextlib.suppress(OSError):
                os.unlink(path)
        for folder in reversed(self.folders):  # the deepest first; only when empty
            with contextlib.suppress(OSError):
                folder.rmdir()
        self.files.clear()
        self.folders.clear()


_run: contextvars.ContextVar[_Run | None] = contextvars.ContextVar(
    "dstoolkit_output_run", default=None
)


@contextlib.contextmanager
def output_run() -> Iterator[_Run]:
    """Hold one command's outputs, so that a failed command leaves no files behind.

    Inside the ``with`` block, paths checked by :func:`check_outputs` are written by
    :func:`atomic_write` without clobbering; when the body fails (an exception, Ctrl-C, a
    signal turned into an exception) the files and folders it made are removed.

    Yields
    ------
    run
        The run; its ``discard()`` removes what was made, for a command that failed but
        returns an exit status instead of raising.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from dstoolkit.utils.outputs import atomic_write, output_run
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> try:
    ...     with output_run():
    ...         _ = atomic_write(folder / "a.txt", lambda fh: fh.write(b"half"))
    ...         raise KeyboardInterrupt
    ... except KeyboardInterrupt:
    ...     pass
    >>> (folder / "a.txt").exists()
    False
    """
    run = _Run()
    token = _run.set(run)
    try:
        yield run
    except BaseException:
        run.discard()
        raise
    finally:
        _run.reset(token)


def _link_chain(path: Path) -> list[Path]:
    """``path`` and every path its symbolic links lead through (at most 40 links)."""
    chain = [Path(os.path.abspath(path))]
    current = chain[0]
    for _ in range(40):
        try:
            target = os.readlink(current)
        except OSError:  # not a link, or missing
            break
        current = Path(os.path.abspath(current.parent / target))
        chain.append(current)
    with contextlib.suppress(OSError, RuntimeError):
        chain.append(path.resolve())
    return chain


def _system_path(path: Path) -> Path | None:
    """Find the system folder (``/dev``, ``/proc``, ``/sys``) that ``path`` lies in.

    A link on the way to its file counts too; None when there is none.
    """
    for candidate in _link_chain(path):
        for folder in SYSTEM_FOLDERS:
            if candidate == folder or folder in candidate.parents:
                return folder
    return None


def refuse_special(path: Path, what: str) -> None:
    """Refuse an output that is not a regular file or a new path.

    Parameters
    ----------
    path : pathlib.Path
        The output path.
    what : str
        What the output is, as the message should name it.

    Raises
    ------
    OutputPathError
        For a folder, a device, a FIFO, a socket, a path in ``/dev``, ``/proc`` or ``/sys``,
        or a symbolic link to one of them.

    Examples
    --------
    >>> from pathlib import Path
    >>> from dstoolkit.utils.outputs import refuse_special
    >>> refuse_special(Path("/dev/null"), "the figure")
    Traceback (most recent call last):
    ...
    dstoolkit.errors.OutputPathError: the figure: /dev/null is not a regular file or a new path: ...
    """
    system = _system_path(path)
    if system is not None:
        raise OutputPathError(
            f"{what}: {path} is not a regular file or a new path: it is in "
            f"{system}, where files are devices or kernel state; give a "
            "file name elsewhere"
        )
    try:
        info = os.stat(path)
    except FileNotFoundError:
        return
    except OSError as exc:
        raise OutputPathError(
            f"{what}: cannot use {path}: {exc.strerror or exc}; choose another place"
        ) from None
    if stat.S_ISDIR(info.st_mode):
        raise OutputPathError(f"{what}: {path} is a folder; give a file name")
    if not stat.S_ISREG(info.st_mode):
        raise OutputPathError(
            f"{what}: {path} is not a regular file (a device, a pipe or a socket); give a file name"
        )


def _make_folder(folder: Path) -> None:
    """``mkdir -p``, remembering in the current run which folders it made."""
    missing: list[Path] = []
    for parent in (folder, *folder.parents):
        if parent.exists() or parent.is_symlink():
            break
        missing.append(parent)
    folder.mkdir(parents=True, exist_ok=True)
    run = _run.get()
    if run is not None:
        run.folders.extend(reversed(missing))


def _writable_folder(path: Path) -> None:
    """Create the output's folder if needed and make sure a file can be created in it."""
    try:
        _make_folder(path.parent)
        fd, probe = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".probe")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise OutputPathError(
            f"cannot write {path}: {exc.strerror or exc}; choose another place"
        ) from None


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
    outputs : mapping of str to path
        ``{what: path}``, e.g. ``{"the CSV": "t.csv", "the figure": "t.png"}``.
    inputs : sequence of path, optional
        Files the command reads: no output may be one of them.
    overwrite : bool, optional
        Allow replacing existing files (``--overwrite``).
    replaceable : callable, optional
        Says whether an existing file may be replaced anyway (a figure the same command
        made, :func:`made_by`).

    Returns
    -------
    dict of str to pathlib.Path
        The same keys, with each path as a :class:`~pathlib.Path`.

    Raises
    ------
    OutputPathError
        An output that is an input, two outputs that are one file, a folder, a device, or a
        folder that cannot be written.
    OutputExistsError
        An existing file, unless ``overwrite`` or ``replaceable`` allows it.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from dstoolkit.utils.outputs import check_outputs
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> check_outputs({"the CSV": folder / "t.csv"})["the CSV"].name
    't.csv'
    >>> check_outputs({"the CSV": folder / "t.csv", "the copy": folder / "t.csv"})
    Traceback (most recent call last):
    ...
    dstoolkit.errors.OutputPathError: the copy and the CSV would both be written to ...
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
            raise OutputPathError(
                f"{what} and {seen[key]} would both be written to {path}; give them different names"
            )
        seen[key] = what
        for source in in_paths:
            same = key == source.resolve()
            with contextlib.suppress(OSError):
                same = same or (path.exists() and os.path.samefile(path, source))
            if same:
                raise OutputPathError(
                    f"{what} would overwrite the input {source}; choose another output name"
                )
        refuse_special(path, what)
        replace: tuple[int, int] | None = None
        if path.is_symlink() or path.exists():
            if not overwrite and not (replaceable is not None and replaceable(path)):
                raise OutputExistsError(
                    f"{what}: {path} exists; pass --overwrite "
                    "(overwrite=True) to replace it, or choose another name"
                )
            with contextlib.suppress(OSError):
                info = os.lstat(path)
                replace = (info.st_dev, info.st_ino)
        _writable_folder(path)
        run = _run.get()
        if run is not None:
            run.plan.setdefault(key, replace)  # a stricter earlier check stays
        checked[what] = path
    return checked


def atomic_write(path: str | os.PathLike[str], write: Callable[[IO[bytes]], object]) -> Path:
    """Write ``path`` through ``write(file)`` into a temporary file, then move it into place.

    The temporary file lies beside ``path``.

    The target appears complete or not at all; the temporary file is removed on failure.
    Missing parent folders are created. A target that is not a regular file or a new path
    (:func:`refuse_special`) is refused. Inside :func:`output_run`, a path checked by
    :func:`check_outputs` as new is created without clobbering, and a path allowed to be
    replaced is replaced only if it is still the file that was checked; otherwise an
    :class:`~dstoolkit.errors.OutputExistsError` says that the file appeared meanwhile.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write.
    write : callable
        Called once with the temporary file opened for binary writing.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    OutputPathError
        The target is a folder, a device, a FIFO, a socket, or in a system folder.
    OutputExistsError
        The target appeared, or changed, after it was checked.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from dstoolkit.utils.outputs import atomic_write
    >>> target = pathlib.Path(tempfile.mkdtemp()) / "out" / "a.txt"
    >>> atomic_write(target, lambda fh: fh.write(b"done")).read_bytes()
    b'done'
    """
    target = Path(path)
    refuse_special(target, "the output")
    _make_folder(target.parent)
    run = _run.get()
    key = target.resolve()
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".part")
    try:
        with os.fdopen(fd, "wb") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o666 & ~_umask())
        if run is not None and key in run.plan:
            _place_checked(tmp, target, run.plan[key])
        else:
            refuse_special(target, "the output")
            os.replace(tmp, target)
        if run is not None:
            run.files.append(target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    return target


def _place_checked(tmp: str, target: Path, replace: tuple[int, int] | None) -> None:
    """Move ``tmp`` to ``target`` only if ``target`` is as it was checked.

    That is absent (then a hard link creates it, failing if the name appeared), or the same
    file as before.
    """
    appeared = OutputExistsError(
        f"{target} appeared or changed while this command ran; it was kept. Run again "
        "with another output name (or --overwrite to replace it)"
    )
    try:
        info = os.lstat(target)
    except FileNotFoundError:
        info = None
    if info is not None:
        if replace is None or (info.st_dev, info.st_ino) != replace:
            raise appeared
        refuse_special(target, "the output")
        os.replace(tmp, target)
        return
    try:
        os.link(tmp, target)
    except FileExistsError:
        raise appeared from None
    except OSError as exc:
        if exc.errno not in (
            errno.EPERM,
            errno.EOPNOTSUPP,
            errno.EXDEV,
            errno.EMLINK,
            errno.ENOSYS,
        ):
            raise
        # no hard links here (some network or FAT file systems): rename into the name
        # that was still free a moment ago
        if os.path.lexists(target):
            raise appeared from None
        os.replace(tmp, target)
        return
    os.unlink(tmp)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
