"""Output files that lose nothing: checked before any computing, written atomically.

:func:`check_outputs` runs before a command starts its work and refuses, with an
:class:`~dstoolkit.errors.OutputPathError`, an output that is one of the inputs, two outputs
that are one file, a folder or a device, a folder that cannot be written, and (with an
:class:`~dstoolkit.errors.OutputExistsError`) an existing file, unless ``overwrite`` is
given or the file is a figure the same command made earlier (:func:`made_by`).
:func:`atomic_write` writes a temporary file of its own (made new, never an existing one)
beside the target, flushes it to the disk and moves it into place only when it is complete,
with the permissions (and, as root, the owner) of the file it replaces; the old file stays
until then, and a failure or an interruption removes only the temporary file.

Inside :func:`output_run` (one command of the command line), the check and the write are
one decision: a path that was new when it was checked is created without clobbering (a
hard link, which fails when the name exists), so a file that appeared meanwhile survives;
a file that was allowed to be replaced is replaced only if it is still the file that was
checked (device, inode and change time; a symbolic link put there meanwhile is not
followed), in the folder that was checked (held open since). When the run fails or is
interrupted, it is taken back whole: its new files are removed and the files they replaced
put back, so that a command's outputs are all written or none, and a file at one of its
names that it did not put there (another run's) is never removed.
Outputs that are not regular files or new paths (devices, FIFOs, sockets, anything in
``/dev``, ``/proc`` or ``/sys``, and symbolic links to them) are refused, whatever
``overwrite`` says.
"""

from __future__ import annotations

import contextlib
import contextvars
import errno
import os
import secrets
import stat
import struct
import tempfile
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO

from dstoolkit.errors import OutputExistsError, OutputPathError
from dstoolkit.utils.signals import deferred_signals

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

#: What identifies a file that may be replaced: device, inode and status-change time (a file
#: deleted and made again may get the same inode, never the same change time).
Identity = tuple[int, int, int]


def _identity(info: os.stat_result) -> Identity:
    return (info.st_dev, info.st_ino, info.st_ctime_ns)


@dataclass
class _Planned:
    """An output checked by :func:`check_outputs`: its folder, held open, and its state."""

    folder: Path
    folder_fd: int
    name: str
    #: None: the name must still be free; else the identity of the file it may replace
    replace: Identity | None


@dataclass
class _Placed:
    """An output this run moved into place, and the file it replaced (kept until the end)."""

    folder_fd: int
    name: str
    ours: Identity
    backup: str | None


@dataclass
class _Run:
    """What one command plans to write, and what it has put in place so far."""

    plan: dict[Path, _Planned] = field(default_factory=dict)
    placed: list[_Placed] = field(default_factory=list)
    folders: list[Path] = field(default_factory=list)
    fds: list[int] = field(default_factory=list)

    def discard(self) -> None:
        """Take back what this run did: remove its files, put back the ones they replaced.

        Only a file that is still this run's own is removed (another run's file at the same
        name stays); then the folders it made, if empty, newest first.
        """
        with deferred_signals():
            for done in reversed(self.placed):
                _take_back(done)
            self.placed.clear()
            for folder in reversed(self.folders):  # the deepest first; only when empty
                with contextlib.suppress(OSError):
                    folder.rmdir()
            self.folders.clear()

    def keep(self) -> None:
        """Drop the replaced files' backups: the run succeeded."""
        with deferred_signals():
            for done in self.placed:
                if done.backup is not None:
                    with contextlib.suppress(OSError):
                        os.unlink(done.backup, dir_fd=done.folder_fd)
            self.placed.clear()

    def close(self) -> None:
        for fd in self.fds:
            with contextlib.suppress(OSError):
                os.close(fd)
        self.fds.clear()


def _take_back(done: _Placed) -> None:
    """Undo one placed output, if the file at its name is still the one this run put there."""
    try:
        now = os.stat(done.name, dir_fd=done.folder_fd, follow_symlinks=False)
        ours = _identity(now) == done.ours
    except OSError:
        ours = False
    with contextlib.suppress(OSError):
        if done.backup is not None and ours:
            os.replace(done.backup, done.name, src_dir_fd=done.folder_fd, dst_dir_fd=done.folder_fd)
        elif done.backup is not None:
            os.unlink(done.backup, dir_fd=done.folder_fd)
        elif ours:
            os.unlink(done.name, dir_fd=done.folder_fd)


_run: contextvars.ContextVar[_Run | None] = contextvars.ContextVar(
    "dstoolkit_output_run", default=None
)


@contextlib.contextmanager
def output_run() -> Iterator[_Run]:
    """Hold one command's outputs, so that a failed command leaves everything as it was.

    Inside the ``with`` block, paths checked by :func:`check_outputs` are written by
    :func:`atomic_write` without clobbering anything that appeared or changed since the
    check. A file replaced with ``overwrite`` is kept aside (a hard link beside it) until
    the block ends. When the body fails (an exception, Ctrl-C, a signal turned into an
    exception by :func:`~dstoolkit.utils.signals.stop_on_signals`), the run is taken back
    as a whole: the files it wrote are removed, the files they replaced are put back, and
    the folders it made are removed; a file that another program or run put at one of its
    names meanwhile is left alone. The outputs of a command are thus all written or none.

    Yields
    ------
    run
        The run; its ``discard()`` takes it back, for a command that failed but returns an
        exit status instead of raising.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from dstoolkit.utils.outputs import atomic_write, check_outputs, output_run
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "a.txt").write_text("old")
    >>> try:
    ...     with output_run():
    ...         _ = check_outputs({"the text": folder / "a.txt"}, overwrite=True)
    ...         _ = atomic_write(folder / "a.txt", lambda fh: fh.write(b"new"))
    ...         raise KeyboardInterrupt
    ... except KeyboardInterrupt:
    ...     pass
    >>> (folder / "a.txt").read_text(), sorted(p.name for p in folder.iterdir())
    ('old', ['a.txt'])
    """
    run = _Run()
    token = _run.set(run)
    try:
        yield run
        run.keep()
    except BaseException:
        run.discard()
        raise
    finally:
        run.close()
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
        key = _resolved(path, what)
        if key in seen:
            raise OutputPathError(
                f"{what} and {seen[key]} would both be written to {path}; give them different names"
            )
        seen[key] = what
        for source in in_paths:
            same = key == _resolved(source, "the input")
            with contextlib.suppress(OSError):
                same = same or (path.exists() and os.path.samefile(path, source))
            if same:
                raise OutputPathError(
                    f"{what} would overwrite the input {source}; choose another output name"
                )
        refuse_special(path, what)
        replace: Identity | None = None
        if path.is_symlink() or path.exists():
            if not overwrite and not (replaceable is not None and replaceable(path)):
                raise OutputExistsError(
                    f"{what}: {path} exists; pass --overwrite "
                    "(overwrite=True) to replace it, or choose another name"
                )
            with contextlib.suppress(OSError):
                replace = _identity(os.lstat(path))
        _writable_folder(path)
        run = _run.get()
        name_key = _name_key(path)
        if run is not None and name_key not in run.plan:  # a stricter earlier check stays
            fd = _open_folder(path)
            run.fds.append(fd)
            run.plan[name_key] = _Planned(path.parent, fd, path.name, replace)
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
    if run is not None:
        planned = run.plan.get(_name_key(target))
        if planned is None:  # not checked: replace what is there now, if it stays so
            planned = _Planned(target.parent, _open_folder(target), target.name, None)
            run.fds.append(planned.folder_fd)
            with contextlib.suppress(OSError):
                planned.replace = _identity(
                    os.stat(target.name, dir_fd=planned.folder_fd, follow_symlinks=False)
                )
        _write_and_place(target, write, planned.folder_fd, planned, run)
        return target
    fd = _open_folder(target)
    try:
        _write_and_place(target, write, fd, None, run)
    finally:
        os.close(fd)
    return target


def _name_key(path: Path) -> Path:
    """Key an output by its path as given, made absolute: no link on the way is followed.

    A link made or changed meanwhile leads the write nowhere new: it goes to the folder
    held open at the check, or is refused.
    """
    return Path(os.path.abspath(path))


def _resolved(path: Path, what: str) -> Path:
    try:
        return path.resolve()
    except (OSError, RuntimeError) as exc:  # a symbolic link loop
        raise OutputPathError(
            f"{what}: cannot follow {path}: {getattr(exc, 'strerror', None) or exc}; "
            "give a path without a symbolic link loop"
        ) from None


def _open_folder(path: Path) -> int:
    """Open the output's folder, so that its files are made in it even if it is moved."""
    try:
        return os.open(path.parent, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError as exc:
        raise OutputPathError(
            f"cannot write {path}: {exc.strerror or exc}; choose another place"
        ) from None


def _write_and_place(
    target: Path,
    write: Callable[[IO[bytes]], object],
    folder_fd: int,
    planned: _Planned | None,
    run: _Run | None,
) -> None:
    """Write a temporary file of our own in the folder, then put it at ``target``'s name."""
    name = target.name
    tmp, fd = _own_temporary(folder_fd, name)
    try:
        with os.fdopen(fd, "wb") as fh:
            write(fh)
            fh.flush()
            _take_mode_and_owner(fh.fileno(), folder_fd, name)
            os.fsync(fh.fileno())
        with deferred_signals():
            if planned is None:
                refuse_special(target, "the output")
                os.replace(tmp, name, src_dir_fd=folder_fd, dst_dir_fd=folder_fd)
                placed = None
            else:
                placed = _place_checked(tmp, target, planned)
            if run is not None and placed is not None:
                run.placed.append(placed)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp, dir_fd=folder_fd)
        raise


def _own_temporary(folder_fd: int, name: str) -> tuple[str, int]:
    """Create a new temporary file (never one that exists) beside ``name``."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC
    for _ in range(100):
        tmp = f".{name}.{secrets.token_hex(4)}.part"
        try:
            return tmp, os.open(tmp, flags, 0o600, dir_fd=folder_fd)
        except FileExistsError:
            continue
    raise OutputPathError(f"cannot make a temporary file beside {name}; choose another place")


def _take_mode_and_owner(fd: int, folder_fd: int, name: str) -> None:
    """Give the new file the permissions (and, as root, the owner) of the file it replaces.

    A new name gets the usual permissions (0666 less the umask).
    """
    try:
        old = os.stat(name, dir_fd=folder_fd, follow_symlinks=False)
    except OSError:
        old = None
    if old is None or not stat.S_ISREG(old.st_mode):
        os.fchmod(fd, 0o666 & ~_umask())
        return
    if os.geteuid() == 0:
        os.fchown(fd, old.st_uid, old.st_gid)
    os.fchmod(fd, stat.S_IMODE(old.st_mode))


def _place_checked(tmp: str, target: Path, planned: _Planned) -> _Placed | None:
    """Move ``tmp`` to ``target`` only if ``target`` is as it was checked.

    That is absent (then a hard link creates it, failing if the name appeared), or the same
    file as before (which is kept aside, a hard link beside it, until the run ends). The
    folder must still be the one checked.
    """
    fd, name = planned.folder_fd, planned.name
    appeared = OutputExistsError(
        f"{target} appeared or changed while this command ran; it was kept. Run again "
        "with another output name (or --overwrite to replace it)"
    )
    try:
        same_folder = _identity(os.stat(planned.folder))[:2] == _identity(os.fstat(fd))[:2]
    except OSError:
        same_folder = False
    if not same_folder:
        raise OutputPathError(
            f"the folder of {target} was moved or replaced while this command ran; "
            "nothing was written there. Run again"
        )
    try:
        info: os.stat_result | None = os.stat(name, dir_fd=fd, follow_symlinks=False)
    except FileNotFoundError:
        info = None
    if info is not None:
        if planned.replace is None or _identity(info) != planned.replace:
            raise appeared
        backup = _keep_aside(fd, name)
        try:
            os.replace(tmp, name, src_dir_fd=fd, dst_dir_fd=fd)
        except BaseException:
            if backup is not None:
                with contextlib.suppress(OSError):
                    os.unlink(backup, dir_fd=fd)
            raise
        return _Placed(fd, name, _identity(os.stat(name, dir_fd=fd, follow_symlinks=False)), backup)
    if planned.replace is not None:
        raise appeared  # the file to replace was removed meanwhile
    try:
        os.link(tmp, name, src_dir_fd=fd, dst_dir_fd=fd, follow_symlinks=False)
    except FileExistsError:
        raise appeared from None
    except OSError as exc:
        if exc.errno not in _NO_HARD_LINKS:
            raise
        # no hard links here (some network or FAT file systems): rename into the name
        # that was still free a moment ago
        if _exists_at(fd, name):
            raise appeared from None
        os.replace(tmp, name, src_dir_fd=fd, dst_dir_fd=fd)
    else:
        os.unlink(tmp, dir_fd=fd)
    return _Placed(fd, name, _identity(os.stat(name, dir_fd=fd, follow_symlinks=False)), None)


_NO_HARD_LINKS = (errno.EPERM, errno.EOPNOTSUPP, errno.EXDEV, errno.EMLINK, errno.ENOSYS)


def _exists_at(fd: int, name: str) -> bool:
    try:
        os.stat(name, dir_fd=fd, follow_symlinks=False)
    except FileNotFoundError:
        return False
    return True


def _keep_aside(fd: int, name: str) -> str | None:
    """Link the file about to be replaced to a new name beside it; None where links fail."""
    for _ in range(100):
        backup = f".{name}.{secrets.token_hex(4)}.old"
        try:
            os.link(name, backup, src_dir_fd=fd, dst_dir_fd=fd, follow_symlinks=False)
        except FileExistsError:
            continue
        except OSError as exc:
            if exc.errno in _NO_HARD_LINKS:
                return None
            raise
        return backup
    return None


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
