"""Files that are whole or absent, and folders one process at a time.

* :func:`write_atomic` / :func:`atomic_file`: a file is written under a temporary name in its own folder and
  renamed into place, so a reader (or a re-run after a kill or a full disk) sees the old content or the
  new, never a part.
* :class:`Lock`: an advisory ``flock`` on a lock file: ``<folder>/.lock`` (:func:`folder_lock`) or
  ``<file>.lock`` beside a file (:func:`file_lock`). ``wait=False`` refuses what another process holds,
  naming the holder (pid, host, start time, command); ``wait=True`` waits for it (two processes building
  the same cache: one builds, the other then reads the result). The kernel drops
  the lock when its holder dies, so a lock left by a killed process (its file still names it; a released
  one is empty) is taken over, with a message.
  Locks are re-entrant within a process (an experiment's folder and its training loop's may coincide).
  ``flock`` needs a POSIX system; on a network file system it is as reliable as that system's locks.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import socket
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any, BinaryIO

LOCK_NAME = ".lock"


def _new_file_mode() -> int:
    """The permissions ``open()`` gives a new file: 0o666 less the process's umask (read by setting it and setting
    it straight back: done once, at import, before any thread of the library's could create a file meanwhile)."""
    umask = os.umask(0o022)
    os.umask(umask)
    return 0o666 & ~umask


_NEW_FILE_MODE = _new_file_mode()


@contextlib.contextmanager
def replaced_on_success(path: str | Path, suffix: str = ".tmp") -> Iterator[Path]:
    """``with replaced_on_success(path) as tmp:`` write the file ``tmp`` (in ``path``'s folder, ending in ``suffix``,
    e.g. for a program that picks its format by it); it becomes ``path`` in one rename if the block succeeds and is
    removed otherwise. It gets the permissions a new file gets (``mkstemp`` makes it readable by its owner alone)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=suffix)
    os.close(fd)
    try:
        os.chmod(tmp, _NEW_FILE_MODE)
        yield Path(tmp)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


@contextlib.contextmanager
def atomic_file(path: str | Path) -> Iterator[BinaryIO]:
    """``with atomic_file(path) as f:`` write ``f``; ``path`` appears, whole, only if the block succeeds."""
    with replaced_on_success(path) as tmp, open(tmp, "wb") as f:
        yield f
        f.flush()
        os.fsync(f.fileno())


def write_atomic(path: str | Path, content: str | bytes) -> None:
    """Write ``content`` to ``path`` in one rename: on any failure ``path`` keeps what it held before."""
    with atomic_file(path) as f:
        f.write(content.encode() if isinstance(content, str) else content)


def write_json(path: str | Path, value: Any) -> None:
    """``value`` as indented, key-sorted JSON, written atomically."""
    write_atomic(path, json.dumps(value, indent=2, sort_keys=True) + "\n")


def read_json(path: str | Path) -> Any | None:
    """The JSON value in ``path``, or None when the file is missing, empty or does not parse."""
    try:
        return json.loads(Path(path).read_text())
    except (OSError, ValueError):
        return None


class InUseError(RuntimeError):
    """Another live process holds the lock."""


_HELD: dict[Path, list[Any]] = {}  # lock file -> [open file, depth], the locks this process holds


class Lock:
    """``with Lock(lock_file, guards=path, what="run folder"):`` hold the lock (see the module docstring);
    messages name ``guards``, the folder or file the lock protects."""

    def __init__(self, lock_file: str | Path, *, guards: str | Path, what: str, wait: bool = False):
        self.path, self.guards, self.what, self.wait = Path(lock_file).absolute(), Path(guards), what, wait

    def __enter__(self) -> "Lock":
        held = _HELD.get(self.path)
        if held is not None:
            held[1] += 1
            return self
        self.path.parent.mkdir(parents=True, exist_ok=True)
        f = open(self.path, "a+")
        try:
            if not _try_lock(f):
                holder = _holder(f)
                if not self.wait:
                    raise InUseError(f"{self.guards}: this {self.what} is in use by {holder}; wait for it to "
                                     f"finish, or use another one (two runs in one would mix their files)")
                print(f"[lock] waiting for {holder}, which holds {self.guards}", file=sys.stderr)
                fcntl.flock(f, fcntl.LOCK_EX)
            previous = _holder(f)  # a holder that released it emptied the file: this one was killed
            if previous is not None:
                print(f"[lock] {self.guards}: taking over the lock left by {previous}, which is no longer "
                      f"running", file=sys.stderr)
            f.seek(0)
            f.truncate()
            f.write(json.dumps({"pid": os.getpid(), "host": socket.gethostname(), "since": time.time(),
                                "command": " ".join(sys.argv)}) + "\n")
            f.flush()
        except BaseException:
            f.close()
            raise
        _HELD[self.path] = [f, 1]
        return self

    def __exit__(self, *exc: object) -> None:
        held = _HELD[self.path]
        held[1] -= 1
        if held[1] == 0:
            del _HELD[self.path]
            held[0].truncate(0)  # released, not abandoned (see __enter__)
            held[0].close()  # closing drops the flock


def folder_lock(folder: str | Path, *, what: str = "folder", wait: bool = False) -> Lock:
    """The lock of a folder (``<folder>/.lock``; the folder is made if missing)."""
    return Lock(Path(folder) / LOCK_NAME, guards=folder, what=what, wait=wait)


def file_lock(path: str | Path, *, what: str = "file", wait: bool = False) -> Lock:
    """The lock of one file (``<file>.lock`` beside it), e.g. a cache entry that several processes build."""
    path = Path(path)
    return Lock(path.with_name(path.name + ".lock"), guards=path, what=what, wait=wait)


def _try_lock(f) -> bool:
    try:
        fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return True
    except BlockingIOError:
        return False


def _holder(f) -> str | None:
    """Who the lock file says holds (or held) it, in words; None for a new lock file."""
    f.seek(0)
    try:
        info = json.loads(f.read() or "null")
    except ValueError:
        return "an unknown process"
    if not isinstance(info, dict):
        return None
    since = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(info.get("since", 0)))
    return f"process {info.get('pid')} on {info.get('host')} (since {since}: {info.get('command')})"
