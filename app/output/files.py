"""Output paths: formats by suffix, early checks, and atomic writes.

Every writer works in a temporary file next to the destination and renames it into place
only when the whole file is written, so a failure or Ctrl-C never leaves a half-written
output (and never clobbers an existing file with one). A temporary file's name holds the
writing process's id; a run that was killed (SIGKILL, power loss) leaves one behind, and
the next write to the same destination deletes it once that process is gone.
"""

from __future__ import annotations

import os
import re
import socket
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Literal

from ..errors import OutputError

OutputFormat = Literal["png", "gif", "mp4"]
OUTPUT_FORMATS: tuple[str, ...] = ("png", "gif", "mp4")
PARTIAL = ".partial"  # temporary files are named .STEM.HOST_PID-RANDOM.partial.SUFFIX


def _host() -> str:
    """This machine's name as a file-name part (a folder may be shared between machines or
    containers, whose process ids mean nothing here)."""
    name = re.sub(r"[^A-Za-z0-9]", "", socket.gethostname())[:24]
    return name or "host"


def format_by_suffix(path: str | os.PathLike[str], formats: tuple[str, ...], what: str, allowed: str) -> str:
    """The lower-case suffix of ``path`` if it is one of ``formats``; otherwise an
    :class:`OutputError` saying what ``what`` has and that ``allowed`` is what to use."""
    suffix = Path(path).suffix.lower().lstrip(".")
    if suffix not in formats:
        shown = f"'.{suffix}'" if suffix else "no suffix"
        raise OutputError(f"{os.fspath(path)}: {what} has {shown}; use {allowed}")
    return suffix


def output_format(path: str | os.PathLike[str]) -> OutputFormat:
    """The format of an output path from its suffix; :class:`OutputError` if unsupported."""
    return format_by_suffix(path, OUTPUT_FORMATS, "output", ".png (one frame), .gif or .mp4")  # type: ignore


def check_output_dir(path: str | os.PathLike[str]) -> None:
    """Fail early (before rendering) if ``path`` cannot be written."""
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    try:
        parent_there, folder = parent.is_dir(), path.is_dir()
    except ValueError:  # a NUL in the name
        raise OutputError(f"{os.fspath(path)!r}: a file name cannot hold a NUL character") from None
    except OSError as exc:  # a name or path too long for the file system, say
        raise cannot_write(path, exc) from None
    if not parent_there:
        raise OutputError(f"{os.fspath(path)}: output folder {os.fspath(parent)!r} does not exist")
    if folder:
        raise OutputError(f"{os.fspath(path)}: is a folder; give a file name")
    try:  # a real probe: permission bits say nothing for root or for special file systems
        fd, probe = tempfile.mkstemp(prefix=".gaitlab-probe-", dir=parent)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise OutputError(f"{os.fspath(path)}: output folder {os.fspath(parent)!r} is not writable "
                          f"({exc.strerror or exc})") from None


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def cannot_write(path: str | os.PathLike[str], exc: OSError) -> OutputError:
    """The one-line error for an OS failure while writing ``path``."""
    return OutputError(f"{os.fspath(path)}: cannot write: {exc.strerror or exc}")


def _process_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # someone else's live process
        return True
    return True


def stale_partials(final: str | os.PathLike[str]) -> list[Path]:
    """Temporary files left next to ``final`` by writers on this machine that are no longer
    running (another machine's are never touched: its process ids mean nothing here)."""
    final = Path(final)
    parent = final.parent if str(final.parent) else Path(".")
    pattern = re.compile(rf"^\.{re.escape(final.stem)}\.{re.escape(_host())}_(\d+)-[^.]*{re.escape(PARTIAL)}"
                         rf"{re.escape(final.suffix)}$")
    found = []
    try:
        names = os.listdir(parent)
    except OSError:
        return []
    for name in names:
        match = pattern.match(name)
        if match and not _process_alive(int(match.group(1))):
            found.append(parent / name)
    return found


def remove_stale_partials(final: str | os.PathLike[str]) -> int:
    """Delete what :func:`stale_partials` finds; the number deleted."""
    removed = 0
    for path in stale_partials(final):
        try:
            path.unlink()
            removed += 1
        except OSError:
            pass
    return removed


class AtomicPath:
    """A temporary path next to ``final`` (same suffix) that is renamed into place on commit."""

    def __init__(self, final: str | os.PathLike[str]) -> None:
        self.final = Path(final)
        check_output_dir(self.final)
        remove_stale_partials(self.final)
        try:
            fd, tmp = tempfile.mkstemp(prefix=f".{self.final.stem}.{_host()}_{os.getpid()}-",
                                       suffix=f"{PARTIAL}{self.final.suffix}", dir=self.final.parent)
        except OSError as exc:
            raise cannot_write(self.final, exc) from None
        os.close(fd)
        self.tmp = Path(tmp)

    def commit(self) -> Path:
        try:
            os.chmod(self.tmp, 0o666 & ~_umask())  # as a plain open() would (mkstemp makes 0600)
            os.replace(self.tmp, self.final)
        except OSError as exc:
            self.discard()
            raise cannot_write(self.final, exc) from None
        return self.final

    def discard(self) -> None:
        try:
            self.tmp.unlink(missing_ok=True)
        except OSError:
            pass

    def __enter__(self) -> AtomicPath:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.commit()
            return
        self.discard()
        if isinstance(exc, OSError):
            raise cannot_write(self.final, exc) from None


def write_together(outputs: Sequence[tuple[str | os.PathLike[str], Callable[[Path], object]]]) -> None:
    """Write several files, all or none: each ``(path, write)`` pair's ``write`` fills a
    temporary file beside ``path``, and they are renamed into place only once every one
    has succeeded (a failure deletes them all and leaves any earlier files as they were).
    The renames themselves are one after another: should one fail (rare: the folder
    was checked), the files already renamed stay and the rest are deleted."""
    staged: list[AtomicPath] = []
    try:
        for final, write in outputs:
            staged.append(AtomicPath(final))
            try:
                write(staged[-1].tmp)
            except OSError as exc:
                raise cannot_write(final, exc) from None
    except BaseException:
        for out in staged:
            out.discard()
        raise
    for k, out in enumerate(staged):
        try:
            out.commit()  # (discards its own file when it fails)
        except BaseException:
            for rest in staged[k + 1:]:
                rest.discard()
            raise


def atomic_write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` through a temporary file renamed into place."""
    with AtomicPath(path) as out:
        out.tmp.write_text(text, encoding="utf-8")
    return Path(path)
