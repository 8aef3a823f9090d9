"""Output folders written as a whole: a run replaces its own previous output, or nothing.

``clearance report -o DIR`` and ``clearance simulate -o DIR`` write every file into a
fresh *staging* folder ``.DIR.new-<pid>-<random>`` beside ``DIR`` and put it in place of
``DIR`` in one step at the end (:func:`output_folder`). The rules:

* **Only its own output is replaced.** Each command writes a marker file into its folder,
  ``.clearance-<command>`` (:func:`marker_name`), whose first line names the command and the
  layout version. An existing ``DIR`` is replaced only when it is empty, or holds that
  marker (or, from before markers, the command's main file with its header: a report's
  ``clearance.csv``, simulate's ``results.csv``) *and* nothing but files the command writes
  (:class:`Layout`). Anything else (a folder of other files, another command's output, a
  regular file, the current folder or one holding it) is refused with
  :class:`clearance.vehicles.errors.InputError` (exit status 2) before any work, naming what is in
  the way, and nothing is touched. It is checked again just before the swap.
* **One atomic step.** ``DIR`` stays an ordinary folder. Where the system has it (Linux
  3.15 or later with ext4, XFS, Btrfs, tmpfs and most others), ``renameat2(2)`` with
  ``RENAME_EXCHANGE`` (called through :mod:`ctypes`) swaps the staging folder and ``DIR``
  atomically: at every instant ``DIR`` is either the complete previous output or the
  complete new one; the previous one, now under the staging name, is then removed. Where
  the exchange is not available (another kernel or C library, a file system that refuses
  the flag), two renames are used: ``DIR`` to ``.DIR.old-<pid>-<random>``, then the staging
  folder to ``DIR``; a process killed between them leaves no ``DIR``, and the next run puts
  the old folder back before it starts. (A symlink ``DIR`` to versioned folders would
  also swap atomically, but it changes what ``DIR`` is for every other tool, ``cp`` and
  ``rm`` included, and a plain folder from before could not be swapped in one step.)
* **A lock.** While it runs, a command holds ``fcntl.flock`` on ``.DIR.lock`` beside
  ``DIR`` (holding its process id); a second run on the same ``DIR`` refuses at once with
  exit status 2 naming that process. The lock file is removed when the run ends (the
  protocol of :func:`_lock` makes that safe against a run that opened it meanwhile).
* **Leftovers.** Under the lock, no other run can be using a staging or old folder of
  ``DIR``, so the ``.DIR.new-*`` and ``.DIR.old-*`` folders that a killed run left are
  removed, when they are provably ours: empty, or holding only what the command writes.
* **Permissions** are the ordinary ones of the user's umask (0755 folders and 0644 files
  under umask 022), not ``mkdtemp``'s 0700.
* **Errors** of the file system (disk full, read-only, a path under a regular file, a
  missing ``/proc`` entry) while preparing or writing the output become an
  :class:`~clearance.vehicles.errors.InputError` naming ``DIR`` and the cause; the previous output
  is left as it was.

Examples
--------
>>> import tempfile
>>> top = Path(tempfile.mkdtemp())
>>> layout = Layout("demo", files=frozenset({"a.txt"}))
>>> with output_folder(top / "out", layout) as staging:
...     _ = (staging / "a.txt").write_text("new")
>>> sorted(p.name for p in (top / "out").iterdir())
['.clearance-demo', 'a.txt']
>>> foreign = top / "mine"; foreign.mkdir(); _ = (foreign / "thesis.txt").write_text("x")
>>> with output_folder(foreign, layout) as staging:  # doctest: +ELLIPSIS
...     pass
Traceback (most recent call last):
...
clearance.vehicles.errors.OptionError: ...mine: the folder exists and is not a clearance ...
"""

from __future__ import annotations

import ctypes
import errno
import fcntl
import hashlib
import os
import re
import secrets
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from clearance.reports.output.atomic import current_umask
from clearance.vehicles.errors import OptionError

__all__ = ["LAYOUT_VERSION", "Layout", "foreign_entries", "marker_name", "output_folder"]

#: Version of the folder layout, on the marker's first line.
LAYOUT_VERSION = 1

#: Errors of the storage itself: while the output is written, reported as its problem
#: (exit status 2) wherever they come from; any other error only when it names a file in
#: the staging folder.
_STORAGE_ERRNOS = {errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EFBIG, errno.EIO}

#: Longest output folder name used as is in its helpers' names (``.<name>.new-<pid>-<8>``).
_MAX_BASE_BYTES = 200

_AT_FDCWD = -100
_RENAME_NOREPLACE = 1
_RENAME_EXCHANGE = 2


@dataclass(frozen=True)
class Layout:
    """What one command writes into its output folder.

    Parameters
    ----------
    kind
        The command (``"report"``, ``"simulate"``): names the marker file.
    files
        Names of the files it writes at the top of the folder.
    folders
        Sub-folders it writes, each with the suffixes of the files in it.
    signature
        ``(file name, first-line prefix)``: how an output written before markers existed
        is recognised (its main file with its header).
    """

    kind: str
    files: frozenset[str] = frozenset()
    folders: dict[str, tuple[str, ...]] = field(default_factory=dict)
    signature: tuple[str, str] | None = None


def marker_name(kind: str) -> str:
    """The marker file of ``kind``'s output folder.

    >>> marker_name("report")
    '.clearance-report'
    """
    return f".clearance-{kind}"


def _marker_text(kind: str) -> str:
    return (f"clearance {kind} output, layout {LAYOUT_VERSION}\n"
            f"Written by sumo-clearance. `clearance {kind} -o` replaces this folder only\n"
            "while this file is here and every other file in it is one it writes.\n")


def _is_temp_of(name: str, known: frozenset[str] | tuple[str, ...]) -> bool:
    """A temporary file of an atomic write (``.<name>.<random>.tmp`` or ``.<name>.tmp``)."""
    return (name.startswith(".") and name.endswith(".tmp")
            and any(name[1:].startswith(k + ".") for k in known))


def _marker_kind(folder: Path) -> str | None:
    """The command whose marker ``folder`` holds (``None``: no marker; ``"?"``: unreadable)."""
    kinds = [p.name.removeprefix(".clearance-") for p in folder.glob(".clearance-*")]
    if not kinds:
        return None
    if len(kinds) > 1:
        return "?"
    path = folder / marker_name(kinds[0])
    try:
        if path.is_symlink() or not path.is_file() or path.stat().st_size > 4096:
            return "?"
        first = path.read_text(encoding="utf-8", errors="replace").split("\n", 1)[0]
    except OSError:
        return "?"
    return kinds[0] if re.fullmatch(rf"clearance {re.escape(kinds[0])} output, layout \d+",
                                    first) else "?"


def foreign_entries(folder: Path, layout: Layout) -> list[str]:
    """Entries of ``folder`` (relative paths) that ``layout``'s command does not write.

    Symbolic links are always foreign: the command writes none.

    Examples
    --------
    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp()); (d / "figures").mkdir()
    >>> for name in ("a.csv", "notes.txt", "figures/x.png", "figures/y.doc"):
    ...     _ = (d / name).write_text("")
    >>> foreign_entries(d, Layout("demo", frozenset({"a.csv"}), {"figures": (".png",)}))
    ['figures/y.doc', 'notes.txt']
    >>> foreign_entries(Path(tempfile.mkdtemp()), Layout("demo"))  # empty: nothing foreign
    []
    """
    marker = marker_name(layout.kind)
    out = []
    for entry in sorted(os.scandir(folder), key=lambda e: e.name):
        name = entry.name
        if entry.is_symlink():
            out.append(name)
        elif entry.is_file():
            if not (name == marker or name in layout.files or _is_temp_of(name, layout.files)):
                out.append(name)
        elif entry.is_dir() and name in layout.folders:
            suffixes = layout.folders[name]
            for sub in sorted(os.scandir(entry.path), key=lambda e: e.name):
                ok = (sub.is_file(follow_symlinks=False)
                      and (sub.name.endswith(suffixes)
                           or (sub.name.startswith(".") and sub.name.endswith(".tmp"))))
                if not ok:
                    out.append(f"{name}/{sub.name}")
        else:
            out.append(name)
    return out


def _has_signature(folder: Path, layout: Layout) -> bool:
    if layout.signature is None:
        return False
    name, prefix = layout.signature
    path = folder / name
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            return not path.is_symlink() and fh.readline().startswith(prefix)
    except OSError:
        return False


def _refusal(display: Path, folder: Path, layout: Layout) -> str | None:
    """Why the existing ``folder`` may not be replaced by ``layout``'s output (None: it may)."""
    if folder.is_symlink() or not folder.is_dir():
        return f"{display}: exists and is not a folder; nothing was written"
    what = f"a clearance {layout.kind} output"
    try:
        entries = os.listdir(folder)
        if not entries:
            return None
        kind = _marker_kind(folder)
        foreign = foreign_entries(folder, layout)
    except OSError as exc:
        return f"{display}: cannot read the folder: {exc.strerror}"
    if kind not in (None, layout.kind):
        other = "another clearance command's" if kind == "?" else f"clearance {kind}'s"
        return (f"{display}: the folder holds {other} output, not {what}; give another "
                "-o folder. Nothing was written")
    if kind is None and not _has_signature(folder, layout):
        foreign = foreign or sorted(entries)
    if foreign:
        shown = ", ".join(foreign[:5]) + (f" and {len(foreign) - 5} more"
                                            if len(foreign) > 5 else "")
        return (f"{display}: the folder exists and is not {what} (it holds {shown}); "
                f"{layout.kind} replaces only its own earlier output. Give a new or empty "
                "folder, or move those files away. Nothing was written")
    return None


# --------------------------------------------------------------------------- swapping


def _renameat2(src: Path, dst: Path, flags: int) -> bool:
    """``renameat2(src, dst, flags)``; False when this system or file system cannot."""
    try:
        func = ctypes.CDLL(None, use_errno=True).renameat2
    except (AttributeError, OSError):
        return False
    func.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p,
                     ctypes.c_uint]
    if func(_AT_FDCWD, os.fsencode(src), _AT_FDCWD, os.fsencode(dst), flags) == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.EINVAL, errno.ENOSYS, errno.ENOTSUP, errno.EOPNOTSUPP):
        return False
    raise OSError(err, os.strerror(err), os.fspath(dst))


def _exchange(a: Path, b: Path) -> bool:
    """Swap the names ``a`` and ``b`` atomically; False when the system cannot."""
    return _renameat2(a, b, _RENAME_EXCHANGE)


def _swap_in(staging: Path, target: Path) -> None:
    """Put ``staging`` in place of ``target``; the previous ``target`` is removed after."""
    if not os.path.lexists(target):
        if not _renameat2(staging, target, _RENAME_NOREPLACE):
            os.rename(staging, target)
        _fsync_dir(target.parent)
        return
    if _exchange(staging, target):
        _fsync_dir(target.parent)
        # the previous output, now under the staging name (a leftover if this fails)
        shutil.rmtree(staging, ignore_errors=True)
        return
    old = target.parent / f".{_base(target)}.old-{os.getpid()}-{secrets.token_hex(4)}"
    os.rename(target, old)
    try:
        os.rename(staging, target)
    except BaseException:
        os.rename(old, target)
        raise
    _fsync_dir(target.parent)
    shutil.rmtree(old, ignore_errors=True)


def _fsync_dir(folder: Path) -> None:
    try:
        fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


# ---------------------------------------------------------------------- lock, leftovers


def _lock(display: Path, path: Path) -> int:
    """Hold ``flock`` on the lock file ``path``; refuse when another run holds it.

    The holder removes the file when it ends. A run that opened the file before that
    finds, once it holds the lock, that ``path`` is no longer the file it locked, and
    opens it again.
    """
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o666)
        except OSError as exc:
            raise OptionError(f"{display}: cannot write in the folder {path.parent}: "
                             f"{exc.strerror}") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(fd, 32, 0).decode("ascii", "replace").strip() or "?"
            os.close(fd)
            raise OptionError(f"{display}: another clearance run (process {holder}) is "
                             "writing this folder; wait for it to finish or give another "
                             "-o folder") from None
        try:
            same = os.path.samestat(os.fstat(fd), os.stat(path))
        except FileNotFoundError:
            same = False
        if not same:
            os.close(fd)
            continue
        try:
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        except OSError as exc:
            _unlock(fd, path)
            raise OptionError(f"{display}: cannot write in the folder {path.parent}: "
                             f"{exc.strerror}") from None
        return fd


def _unlock(fd: int, path: Path) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass
    os.close(fd)


def _leftovers(target: Path, tag: str) -> list[Path]:
    pattern = re.compile(rf"\.{re.escape(_base(target))}\.{tag}-.+")
    try:
        names = os.listdir(target.parent)
    except OSError:
        return []
    return sorted(target.parent / n for n in names if pattern.fullmatch(n))


def _is_ours(folder: Path, layout: Layout) -> bool:
    try:
        return (not folder.is_symlink() and folder.is_dir()
                and _marker_kind(folder) in (None, layout.kind)
                and not foreign_entries(folder, layout))
    except OSError:
        return False


def _recover(target: Path, layout: Layout) -> None:
    """Under the lock: put back an old output a killed swap left, remove stale folders."""
    if not os.path.lexists(target):
        olds = [p for p in _leftovers(target, "old") if _is_ours(p, layout)]
        if olds:
            newest = max(olds, key=lambda p: p.stat().st_mtime_ns)
            os.rename(newest, target)
    for stale in _leftovers(target, "new") + _leftovers(target, "old"):
        if _is_ours(stale, layout):
            shutil.rmtree(stale, ignore_errors=True)


# ------------------------------------------------------------------------------ entry


def _base(target: Path) -> str:
    """``target``'s name in the names of its lock, staging and old folders.

    A name too long to take ``.`` and ``.new-<pid>-<random>`` under the 255-byte limit of
    file names is cut, with a hash of the whole name:

    >>> len(_base(Path("x" * 250)).encode())
    117
    """
    raw = os.fsencode(target.name)
    if len(raw) <= _MAX_BASE_BYTES:
        return target.name
    return os.fsdecode(raw[:100]) + "~" + hashlib.sha256(raw).hexdigest()[:16]


def _resolve(display: Path) -> Path:
    """The real path of the output folder ``display``; refuse what cannot be one."""
    real = Path(os.path.realpath(display))
    if not real.name or real.parent == real:
        raise OptionError(f"{display}: cannot be an output folder (it is the root)")
    if len(os.fsencode(real.name)) > 255:
        raise OptionError(f"{display}: the folder's name is longer than 255 bytes")
    cwd = Path(os.path.realpath(Path.cwd()))
    if real == cwd or real in cwd.parents:
        raise OptionError(f"{display}: cannot be an output folder: it is the current folder"
                         " or holds it; give a folder name such as out")
    return real


def _inside(filename: object, folder: Path) -> bool:
    if not isinstance(filename, str | bytes | os.PathLike):
        return False
    path = Path(os.fsdecode(filename))
    return path == folder or folder in path.parents


def _storage_error(display: Path, exc: OSError) -> OptionError:
    where = f" ({exc.filename})" if exc.filename else ""
    return OptionError(f"{display}: cannot write the output{where}: {exc.strerror}; the "
                      "previous output, if any, is unchanged")


@contextmanager
def output_folder(path: str | os.PathLike[str], layout: Layout) -> Iterator[Path]:
    """Stage a command's output folder and swap it in for ``path`` when the block ends.

    Parameters
    ----------
    path
        The output folder as the user gave it (``-o DIR``); messages name it so.
    layout
        What the command writes (decides which existing folder it may replace).

    Yields
    ------
    Path
        The staging folder to write into (marker already written). When the block ends
        normally it becomes ``path`` in one atomic step; when the block raises, it is
        removed and ``path`` is left as it was.

    Raises
    ------
    InputError
        ``path`` is not a folder this command may replace, another run holds it, or the
        file system refuses (the message names ``path`` and why).
    """
    display = Path(path)
    real = _resolve(display)
    try:
        real.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OptionError(f"{display}: cannot create the folder {real.parent}: "
                         f"{exc.strerror}") from None
    lock_path = real.parent / f".{_base(real)}.lock"
    fd = _lock(display, lock_path)
    staging: Path | None = None
    try:
        try:
            _recover(real, layout)
        except OSError as exc:
            raise _storage_error(display, exc) from None
        if os.path.lexists(real) and (why := _refusal(display, real, layout)):
            raise OptionError(why)
        try:
            staging = Path(tempfile.mkdtemp(prefix=f".{_base(real)}.new-{os.getpid()}-",
                                            dir=real.parent))
            os.chmod(staging, 0o777 & ~current_umask())
            (staging / marker_name(layout.kind)).write_text(_marker_text(layout.kind),
                                                           encoding="utf-8")
        except OSError as exc:
            raise _storage_error(display, exc) from None
        try:
            yield staging
        except OSError as exc:
            if exc.errno in _STORAGE_ERRNOS or _inside(exc.filename, staging):
                raise _storage_error(display, exc) from None
            raise
        except OptionError as exc:  # a file that could not be written: named as in DIR
            if str(staging) not in str(exc):
                raise
            raise OptionError(str(exc).replace(str(staging), str(display))) from None
        if os.path.lexists(real) and (why := _refusal(display, real, layout)):
            raise OptionError(why)
        try:
            _swap_in(staging, real)
        except OSError as exc:
            raise _storage_error(display, exc) from None
        staging = None
    finally:
        if staging is not None:
            shutil.rmtree(staging, ignore_errors=True)
        _unlock(fd, lock_path)
