"""Writing output files atomically, with the usual permissions, and never a stray temp file.

Every file camtol writes goes through here: the content is written to a temporary file
in the target directory and renamed into place, so a failure (or an interrupt) never
leaves a half-written file behind. ``tempfile.mkstemp`` creates files readable by the
owner only; the final file gets the permissions an ordinary ``open`` would give it
(0666 less the umask).

Temporary files have a recognisable name, ``.<name>.camtol-tmp-<pid>-<random><suffix>``.
They are removed when the write fails, when the process receives SIGTERM, SIGINT or SIGHUP
(a handler removes them and then lets the signal take its usual effect), and at exit.
A process killed outright (SIGKILL, power loss) cannot clean up: the next camtol run that
writes into the same directory removes the temporary files of processes that no longer
exist (:func:`remove_stale_temporaries`).

Operating-system errors (directory missing or not writable, disk full, a path under
``/proc``...) become one :class:`~camtol.exceptions.OutputError` line naming the file.
"""

from __future__ import annotations

import atexit
import errno
import os
import re
import signal
import tempfile
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from types import FrameType

from camtol.exceptions import OutputError

__all__ = [
    "TEMP_MARKER",
    "atomic_output",
    "atomic_write",
    "check_writable",
    "os_error_message",
    "remove_stale_temporaries",
]

#: Marker in the name of every temporary file camtol creates.
TEMP_MARKER = ".camtol-tmp-"
_TEMP_RE = re.compile(r"^\..*\.camtol-tmp-(\d+)-[A-Za-z0-9_]+")
_live: set[str] = set()
_lock = threading.RLock()  # re-entrant: the signal handler may interrupt a holder
_installed = False
_HANDLED = ("SIGTERM", "SIGINT", "SIGHUP")


def _default_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def _cleanup() -> None:
    with _lock:
        paths = list(_live)
        _live.clear()
    for tmp in paths:
        try:
            os.unlink(tmp)
        except OSError:
            pass


def _on_signal(signum: int, frame: FrameType | None) -> None:
    _cleanup()
    previous = _previous.get(signum)
    if callable(previous):
        previous(signum, frame)
        return
    if previous == signal.SIG_IGN:
        return
    signal.signal(signum, signal.SIG_DFL)  # die of the signal, as without the handler
    os.kill(os.getpid(), signum)


_previous: dict[int, object] = {}


def _install_handlers() -> None:
    """Remove live temporary files on SIGTERM/SIGINT/SIGHUP and at exit (once)."""
    global _installed
    if _installed:
        return
    _installed = True
    atexit.register(_cleanup)
    if threading.current_thread() is not threading.main_thread():
        return
    for name in _HANDLED:
        sig = getattr(signal, name, None)
        if sig is None:
            continue
        try:
            _previous[sig] = signal.getsignal(sig)
            signal.signal(sig, _on_signal)
        except (ValueError, OSError):  # pragma: no cover - not the main interpreter
            continue


def _pid_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True  # exists, another user's
    except OSError:
        return True
    return True


def remove_stale_temporaries(directory: str | Path) -> list[Path]:
    """Remove camtol temporary files in ``directory`` whose process no longer runs.

    Parameters
    ----------
    directory : str or Path
        Directory to clean (not recursive).

    Returns
    -------
    list of Path
        The files removed.
    """
    removed: list[Path] = []
    try:
        entries = list(os.scandir(directory))
    except OSError:
        return removed
    for entry in entries:
        m = _TEMP_RE.match(entry.name)
        if m is None or _pid_alive(int(m.group(1))):
            continue
        try:
            os.unlink(entry.path)
            removed.append(Path(entry.path))
        except OSError:
            pass
    return removed


def os_error_message(path: str | Path, exc: OSError) -> str:
    """One line for an operating-system error on an output file.

    Parameters
    ----------
    path : str or Path
        The output file.
    exc : OSError
        The error.

    Returns
    -------
    str
        ``cannot write 'out.csv': <reason>`` with a hint for the common causes.
    """
    reason = exc.strerror or type(exc).__name__
    hint = {
        errno.ENOSPC: "the disk is full",
        errno.EDQUOT: "the disk quota is exceeded",
        errno.EACCES: "permission denied: choose a directory you can write to",
        errno.EPERM: "operation not permitted: choose a directory you can write to",
        errno.EROFS: "the file system is read-only",
        errno.EISDIR: "it is a directory: give a file name",
        errno.ENOENT: "the directory does not exist",
        errno.ENOTDIR: "a component of the path is not a directory",
        errno.ENAMETOOLONG: "the file name is too long",
    }.get(exc.errno or 0, reason)
    return f"cannot write {str(path)!r}: {hint}"


def check_writable(path: str | Path) -> None:
    """Check, before any work, that ``path`` can be written as a regular file.

    Parameters
    ----------
    path : str or Path
        The output file to be created or replaced.

    Raises
    ------
    OutputError
        The path is a directory, its directory does not exist or is not writable, or a
        file cannot be created there (tried with a temporary file that is removed).
    """
    p = Path(path)
    if p.is_dir():
        raise OutputError(f"cannot write {str(p)!r}: it is a directory; give a file name")
    parent = p.parent
    if not parent.is_dir():
        raise OutputError(f"cannot write {str(p)!r}: directory {str(parent)!r} does not exist")
    if p.exists() and not p.is_file():
        raise OutputError(f"cannot write {str(p)!r}: it exists and is not a regular file")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{p.name}{TEMP_MARKER}{os.getpid()}-", dir=parent)
    except OSError as exc:
        raise OutputError(os_error_message(p, exc)) from None
    os.close(fd)
    os.unlink(tmp)


@contextmanager
def atomic_output(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; rename it into place on success.

    For writers that want a file name (e.g. matplotlib's ``savefig``). On an exception
    (or a signal) the temporary file is removed and ``path`` is left untouched. Temporary
    files of dead camtol processes in the same directory are removed first.

    Parameters
    ----------
    path : str or Path
        Final file name; its directory must exist.

    Yields
    ------
    Path
        Temporary file in the same directory as ``path``, for the caller to write.

    Raises
    ------
    OutputError
        The file cannot be written (an operating-system error, in one line).
    """
    from camtol.textfile import is_input_file

    p = Path(path)
    if p.is_dir():
        raise OutputError(f"cannot write {str(p)!r}: it is a directory; give a file name")
    if is_input_file(p):
        raise OutputError(
            f"cannot write {str(p)!r}: it is an input of this command; camtol never"
            " overwrites an input: choose another output name"
        )
    _install_handlers()
    remove_stale_temporaries(p.parent)
    try:
        fd, tmp = tempfile.mkstemp(
            prefix=f".{p.name}{TEMP_MARKER}{os.getpid()}-",
            suffix=p.suffix or ".tmp",
            dir=p.parent,
        )
    except OSError as exc:
        raise OutputError(os_error_message(p, exc)) from None
    with _lock:
        _live.add(tmp)
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, _default_mode())
        os.replace(tmp, p)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise OutputError(os_error_message(p, exc)) from None
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    finally:
        with _lock:
            _live.discard(tmp)


def atomic_write(path: str | Path, data: str | bytes) -> None:
    """Write text (UTF-8, newlines as given) or bytes to ``path`` atomically.

    Parameters
    ----------
    path : str or Path
        File to write; replaced if it exists.
    data : str or bytes
        Content; text is encoded as UTF-8.

    Raises
    ------
    OutputError
        The file cannot be written (disk full, permission denied...), in one line.
    """
    payload = data.encode("utf-8") if isinstance(data, str) else data
    with atomic_output(path) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(payload)
            fh.flush()
            os.fsync(fh.fileno())
