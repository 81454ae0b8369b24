"""Writing output files atomically, with the usual permissions.

Every file camtol writes goes through here: the content is written to a temporary file
in the target directory and renamed into place, so a failure (or an interrupt) never
leaves a half-written file behind. ``tempfile.mkstemp`` creates files readable by the
owner only; the final file gets the permissions an ordinary ``open`` would give it
(0666 less the umask).
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_output", "atomic_write"]


def _default_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


@contextmanager
def atomic_output(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; rename it into place on success.

    For writers that want a file name (e.g. matplotlib's ``savefig``). On an exception
    the temporary file is removed and ``path`` is left untouched.

    Parameters
    ----------
    path : str or Path
        Final file name; its directory must exist.

    Yields
    ------
    Path
        Temporary file in the same directory as ``path``, for the caller to write.
    """
    p = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=p.suffix or ".tmp", dir=p.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, _default_mode())
        os.replace(tmp, p)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def atomic_write(path: str | Path, data: str | bytes) -> None:
    """Write text (UTF-8, newlines as given) or bytes to ``path`` atomically.

    Parameters
    ----------
    path : str or Path
        File to write; replaced if it exists.
    data : str or bytes
        Content; text is encoded as UTF-8.
    """
    payload = data.encode("utf-8") if isinstance(data, str) else data
    with atomic_output(path) as tmp:
        tmp.write_bytes(payload)
