"""Files in and out. Inputs are read only when they are regular files, never past a size cap, so an
endless or device file cannot exhaust memory. Outputs are written whole or not at all: to a
temporary file beside the target, renamed into place once complete, with the permissions a plainly
created file would have, and only over a missing or regular file (never a device, FIFO, socket,
directory, or anything under /proc or /sys). A symbolic link at the output is followed like a shell
redirection: the link stays and its target, which must itself be missing or regular, gets the file.
A folder output (a tileset, a tile cache) is built beside its target under the same rules and
swapped in whole; an existing folder is replaced only when it is empty or holds only the files that
cityshade's marker in it lists as its own, for an output of the same kind.
"""

from __future__ import annotations

import bz2
import contextlib
import gzip
import json
import os
import shutil
import signal
import stat
import tempfile
from pathlib import Path

from .errors import UsageError

# Kernel pseudo-file systems: writing there changes the system, not a file.
_SYSTEM_TREES = (Path("/proc"), Path("/sys"))
# mkstemp adds '.' + name + '.' + 8 random characters + suffix; room for them must be left.
_TEMP_EXTRA = 10
# mkdtemp's '.' + name + '.old.' + 8 random characters, for the folder an output replaces.
_FOLDER_TEMP_EXTRA = 14
# A folder output's marker: its kind, format and the files cityshade wrote, the only ones it replaces.
OUTPUT_MARKER = ".cityshade-output"
MARKER_FORMAT = 1
MARKER_LIMIT = 64 << 20  # lists every file: a million tiles' names fit


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _kind(mode: int) -> str:
    for test, name in (
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISFIFO, "a FIFO"),
        (stat.S_ISSOCK, "a socket"),
        (stat.S_ISDIR, "a directory"),
    ):
        if test(mode):
            return name
    return "not a regular file"


def _resolved(path: Path) -> tuple[str, Path, int | None]:
    """(the path as given, its real path, the real path's mode or None when missing); refuses
    anything under /proc or /sys."""
    shown = str(path)
    real = Path(os.path.realpath(path))
    for tree in _SYSTEM_TREES:
        if real == tree or tree in real.parents:
            raise UsageError(
                f"cannot write {shown!r}: it is under {tree}, a kernel file system; choose another output path"
            )
    try:
        return shown, real, os.stat(real).st_mode
    except (FileNotFoundError, NotADirectoryError):
        return shown, real, None
    except OSError as exc:
        raise UsageError(f"cannot write {shown!r}: {exc.strerror}; choose another output path") from None


def _check_room(shown: str, real: Path, mode: int | None, extra: int):
    """Refuses a target whose nearest existing folder is not a writable directory, or whose name
    with `extra` bytes more (a temporary name's) is too long for the file system."""
    probe = real.parent
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir():
        raise UsageError(f"cannot write {shown!r}: {str(probe)!r} is not a directory")
    if not os.access(probe, os.W_OK) or (mode is not None and not os.access(real, os.W_OK)):
        raise UsageError(f"cannot write {shown!r}: permission denied; choose another output path")
    try:
        name_max = os.pathconf(probe, "PC_NAME_MAX")
    except (OSError, ValueError):
        name_max = 255
    if len(os.fsencode(real.name)) + extra > name_max:
        raise UsageError(
            f"cannot write {shown!r}: the name is too long for this file system (at most {name_max - extra} bytes here)"
        )


def output_target(path: Path) -> Path:
    """The file an output to `path` will replace, after every check; raises UsageError (one line)
    for outputs that must not be written. Creates nothing."""
    shown, real, mode = _resolved(Path(path))
    if mode is not None and stat.S_ISDIR(mode):
        raise UsageError(f"output path {shown!r} is a directory; give a file name such as out/city.png")
    if mode is not None and not stat.S_ISREG(mode):
        raise UsageError(f"cannot write {shown!r}: it is {_kind(mode)}; only new or regular files are replaced")
    _check_room(shown, real, mode, len(os.fsencode(real.suffix)) + _TEMP_EXTRA)
    return real


@contextlib.contextmanager
def atomic_output(path: Path):
    """Yields a temporary path beside `path`'s target; on success it becomes the target, on error
    (or a signal the CLI turns into an exception) it is removed."""
    target = output_target(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = None
    try:  # from before the file exists: a signal right after mkstemp still removes it
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=target.suffix, dir=target.parent)
        os.close(fd)
        yield Path(tmp)
        output_target(path)  # the target may have been swapped for a special file meanwhile
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, target)
    finally:
        if tmp is not None and os.path.exists(tmp):
            os.unlink(tmp)


def _folder_target(path: Path, extra: int) -> tuple[str, Path, int | None]:
    """A folder output's real path, after the rules for files: nothing under /proc or /sys, only a
    missing path or a directory, a writable parent, room for `extra` bytes more in its name."""
    shown, real, mode = _resolved(Path(path))
    if mode is not None and not stat.S_ISDIR(mode):
        kind = "a file" if stat.S_ISREG(mode) else _kind(mode)
        raise UsageError(f"cannot write {shown!r}: it exists and is not a directory ({kind}); choose another folder")
    _check_room(shown, real, mode, extra)
    return shown, real, mode


def _walk_error(exc: OSError):
    raise exc


def _check_owned(shown: str, folder: Path, kind: str):
    """Fails with one line unless `folder` holds only what cityshade wrote there as a `kind` output:
    its marker lists those files, and anything else (a file of the user's, a link) must stay."""
    marker = folder / OUTPUT_MARKER
    if not os.path.lexists(marker):
        raise UsageError(
            f"{shown!r} exists and is not an earlier output of this command: it has no {OUTPUT_MARKER} file "
            "(nor do outputs of older cityshade versions); delete it yourself or choose another folder"
        )
    data = read_input_bytes(marker, MARKER_LIMIT, "cityshade output marker")
    try:
        written = json.loads(data)
    except (ValueError, RecursionError):
        written = None
    if not isinstance(written, dict) or not isinstance(written.get("files"), list):
        raise UsageError(f"{str(marker)!r} is damaged; delete {shown!r} yourself or choose another folder")
    if written.get("kind") != kind:
        raise UsageError(f"{shown!r} holds another kind of cityshade output, not a {kind}; choose another folder")
    if written.get("format") != MARKER_FORMAT:
        raise UsageError(
            f"{shown!r} was written by another cityshade version (its {OUTPUT_MARKER} is not of format "
            f"{MARKER_FORMAT}); delete it yourself or choose another folder"
        )
    owned = {name for name in written["files"] if isinstance(name, str)} | {OUTPUT_MARKER}
    try:
        for root, folders, files in os.walk(folder, onerror=_walk_error):  # never into a link
            for name in folders + files:
                entry = Path(root, name)
                mode = os.lstat(entry).st_mode
                inside = entry.relative_to(folder).as_posix()
                if not stat.S_ISDIR(mode) and not (stat.S_ISREG(mode) and inside in owned):
                    raise UsageError(
                        f"{shown!r} holds {inside!r}, which cityshade did not write there; "
                        "move it out or choose another folder"
                    )
    except OSError as exc:
        raise UsageError(f"cannot replace {shown!r}: {exc.strerror} in it; choose another folder") from None


def check_replaceable_folder(path: Path, kind: str) -> Path:
    """The real folder a `kind` output (e.g. "3dtiles") to `path` will take the place of, after every
    check; fails with one line unless it is missing, empty or an earlier `kind` output holding only
    the files cityshade wrote there. Creates nothing."""
    shown, real, mode = _folder_target(path, _FOLDER_TEMP_EXTRA)
    if mode is not None and any(real.iterdir()):
        _check_owned(shown, real, kind)
    return real


def _mark(folder: Path, kind: str):
    """Writes the marker that lets a later run of the same command replace `folder`."""
    files = sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())
    marker = {"kind": kind, "format": MARKER_FORMAT, "files": files}
    (folder / OUTPUT_MARKER).write_text(json.dumps(marker, indent=0), encoding="utf-8")


@contextlib.contextmanager
def atomic_folder(path: Path, kind: str):
    """Yields a temporary folder beside `path`; on success it gets a `kind` marker and takes `path`'s
    place (check_replaceable_folder says which folder may be replaced), on error or a signal it is
    removed: `path` holds the old folder or the new one, never a half-written one."""
    path = check_replaceable_folder(path, kind)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = old = None
    try:
        tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", dir=path.parent))
        yield tmp
        _mark(tmp, kind)
        os.chmod(tmp, 0o777 & ~_umask())
        check_replaceable_folder(path, kind)  # a file may have been put there meanwhile
        if path.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{path.name}.old.", dir=path.parent))
            os.replace(path, old / path.name)
        os.replace(tmp, path)
    finally:
        for left in (tmp, old):
            if left is not None and left.exists():
                shutil.rmtree(left, ignore_errors=True)


def output_folder(path: Path) -> Path:
    """A folder outputs go into (each written as a file): refused with one line if it exists as
    something else or cannot be written."""
    _folder_target(path, 0)
    return Path(path)


def write_bytes(path: Path, data: bytes):
    with atomic_output(path) as tmp:
        tmp.write_bytes(data)


def write_text(path: Path, text: str):
    write_bytes(path, text.encode("utf-8"))


def write_png(image, path: Path):
    """An HxW(x3/4) uint8 or uint16 array as a PNG."""
    from PIL import Image

    with atomic_output(path) as tmp:
        Image.fromarray(image).save(tmp, format="PNG")


def write_figure(figure, path: Path, **options):
    """A matplotlib figure as a PNG."""
    with atomic_output(path) as tmp:
        figure.savefig(tmp, format="png", **options)


class InputError(UsageError):
    """An input file that cannot be read; `reason` is the message without the file name."""

    def __init__(self, path: Path, reason: str):
        super().__init__(f"{path}: {reason}")
        self.reason = reason


def _open_input(path: Path, what: str):
    """An open binary handle on the regular file `path`; InputError naming it otherwise."""
    try:
        handle = open(path, "rb", opener=_open_nonblocking)
    except FileNotFoundError:
        raise InputError(path, f"no such {what}; check the path") from None
    except IsADirectoryError:
        raise InputError(path, f"this is a directory, not a {what}") from None
    except OSError as exc:
        raise InputError(path, f"cannot read the {what} ({exc.strerror})") from None
    info = os.fstat(handle.fileno())
    if not stat.S_ISREG(info.st_mode):
        handle.close()
        raise InputError(path, f"this is {_kind(info.st_mode)}, not a {what}; give a regular file")
    return handle


def checked_input_size(path: Path, what: str, formats: str) -> int:
    """The size of `path`, a readable non-empty regular file; else a UsageError naming the file,
    why, and the `formats` of a `what` (a map, a DEM) to give instead."""
    try:
        info = path.stat()
    except OSError as exc:
        raise UsageError(f"{path}: cannot read the {what} ({exc.strerror or exc})") from None
    if stat.S_ISDIR(info.st_mode):
        raise UsageError(f"{path}: is a directory; give a {what} file ({formats})")
    if not stat.S_ISREG(info.st_mode):
        raise UsageError(f"{path}: not a regular file (a device, FIFO or socket); give a {what} file ({formats})")
    if info.st_size == 0:
        raise UsageError(f"{path}: the file is empty; give a {what} file ({formats})")
    return info.st_size


def read_input_bytes(path: Path, limit: int, what: str = "file") -> bytes:
    """The bytes of a regular file of at most `limit` bytes; raises InputError otherwise, naming
    the file and never quoting its content."""
    path = Path(path)
    with _open_input(path, what) as handle:
        size = os.fstat(handle.fileno()).st_size
        if size > limit:
            raise InputError(path, f"{size} bytes is more than the {limit} bytes a {what} may have")
        try:
            data = handle.read(limit + 1)
        except OSError as exc:
            raise InputError(path, f"cannot read the {what} ({exc.strerror})") from None
    if len(data) > limit:  # it grew while being read
        raise InputError(path, f"more than the {limit} bytes a {what} may have")
    return data


DECOMPRESSORS = {"gz": lambda raw: gzip.GzipFile(fileobj=raw, mode="rb"), "bz2": bz2.BZ2File}


class CappedStream:
    """A binary input stream that raises InputError once more than `limit` bytes have been read
    from it in all, or one line is longer than `line_limit` bytes: what a small compressed file
    expands to is known only while reading it."""

    def __init__(self, path: Path, stream, limit: int, line_limit: int, what: str):
        self.path, self._stream, self.limit, self.line_limit, self.what = path, stream, limit, line_limit, what
        self.read_bytes = 0
        self.lines = 0  # newlines read so far

    def _counted(self, data: bytes) -> bytes:
        self.read_bytes += len(data)
        self.lines += data.count(b"\n")
        if self.read_bytes > self.limit:
            raise InputError(self.path, f"more than the {self.limit} bytes a {self.what} may have (uncompressed)")
        return data

    def read(self, size: int) -> bytes:
        return self._counted(self._stream.read(size))

    def readline(self) -> bytes:
        line = self._stream.readline(self.line_limit + 1)
        if len(line) > self.line_limit:
            raise InputError(
                self.path,
                f"line {self.lines + 1} is longer than the {self.line_limit} bytes a {self.what} line may have",
            )
        return self._counted(line)

    def __iter__(self):
        while line := self.readline():
            yield line


@contextlib.contextmanager
def open_input_stream(path: Path, limit: int, line_limit: int, what: str = "file", compression: str | None = None):
    """A CappedStream over the regular file `path`, decompressed when `compression` is 'gz' or
    'bz2'; raises InputError (naming the file, never quoting it) as read_input_bytes does. Damaged
    compressed data raises the decompressor's OSError, EOFError or zlib.error while reading."""
    path = Path(path)
    with _open_input(path, what) as handle:
        stream = DECOMPRESSORS[compression](handle) if compression else handle
        with stream:
            yield CappedStream(path, stream, limit, line_limit, what)


def _open_nonblocking(name, flags):
    # O_NONBLOCK: opening a FIFO with no writer must not hang before it can be refused.
    return os.open(name, flags | os.O_NONBLOCK)


# SIGTERM and SIGHUP end a command like Ctrl-C does: by an exception, so every `finally` runs and
# no temporary output is left (their default action kills the process without running them).
# SIGINT is handled here too so that it can be deferred like them.
_EXIT_SIGNALS = (signal.SIGTERM, signal.SIGHUP, signal.SIGINT)
_deferred: list[int] = []  # signals that arrived while deferred
_deferring = False


def _leave(signum, frame):
    if _deferring:
        _deferred.append(signum)
        return
    _exit_for(signum)


def _exit_for(signum: int):
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise SystemExit(128 + signum)


@contextlib.contextmanager
def signals_as_exit():
    previous = {sig: signal.signal(sig, _leave) for sig in _EXIT_SIGNALS}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


@contextlib.contextmanager
def signals_deferred():
    """Holds SIGTERM, SIGHUP and SIGINT until the block ends: for a write into a helper process
    (ffmpeg) that must not be cut in the middle, or the helper is killed instead of finishing
    cleanly (and a killed ffmpeg can still create its output after the temporary file is removed)."""
    global _deferring
    outer, _deferring = _deferring, True
    try:
        yield
    finally:
        _deferring = outer
        if not outer and _deferred:
            signum = _deferred[0]
            _deferred.clear()
            _exit_for(signum)


def inside_folder(folder: Path, name, what: str) -> Path:
    """The real path of `name`, a relative path read from a file (a manifest's entry), inside
    `folder`, as Python 3.12 tarfile's data filter confines members: an absolute path, one that
    climbs out with '..' or one through a symbolic link leading out of `folder` raises UsageError,
    one line starting with `what` (the file and the entry), never quoting or sizing what lies outside."""
    base = os.path.realpath(folder)
    if not isinstance(name, str) or not name or "\x00" in name:
        raise UsageError(f"{what}: expected a file name relative to {folder}")
    if os.path.isabs(name):
        reason = "the path is absolute"
    else:
        real = os.path.realpath(os.path.join(base, name))
        if real == base or real.startswith(base.rstrip(os.sep) + os.sep):
            return Path(real)
        climbs = os.path.normpath(name).split(os.sep)[0] == os.pardir
        reason = f"the path {'climbs out of' if climbs else 'passes a symbolic link leading out of'} {folder}"
    raise UsageError(f"{what}: {reason}; only files inside {folder} are used")
