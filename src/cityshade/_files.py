"""Files in and out. Inputs are read only when they are regular files, never past a size cap, so an
endless or device file cannot exhaust memory. Outputs are written whole or not at all: to a
temporary file beside the target, renamed into place once complete, with the permissions a plainly
created file would have, and only over a missing or regular file (never a device, FIFO, socket,
directory, or anything under /proc or /sys). A symbolic link at the output is followed like a shell
redirection: the link stays and its target, which must itself be missing or regular, gets the file.
"""

from __future__ import annotations

import contextlib
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


def output_target(path: Path) -> Path:
    """The file an output to `path` will replace, after every check; raises UsageError (one line)
    for outputs that must not be written. Creates nothing."""
    path = Path(path)
    shown = str(path)
    real = Path(os.path.realpath(path))
    for tree in _SYSTEM_TREES:
        if real == tree or tree in real.parents:
            raise UsageError(
                f"cannot write {shown!r}: it is under {tree}, a kernel file system; choose another output path"
            )
    try:
        mode = os.stat(real).st_mode
    except (FileNotFoundError, NotADirectoryError):
        mode = None
    except OSError as exc:
        raise UsageError(f"cannot write {shown!r}: {exc.strerror}; choose another output path") from None
    if mode is not None and stat.S_ISDIR(mode):
        raise UsageError(f"output path {shown!r} is a directory; give a file name such as out/city.png")
    if mode is not None and not stat.S_ISREG(mode):
        raise UsageError(f"cannot write {shown!r}: it is {_kind(mode)}; only new or regular files are replaced")
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
    if len(os.fsencode(real.name)) + len(os.fsencode(real.suffix)) + _TEMP_EXTRA > name_max:
        raise UsageError(
            f"cannot write {shown!r}: the file name is too long for this file system "
            f"(at most {name_max - _TEMP_EXTRA - len(os.fsencode(real.suffix))} bytes here)"
        )
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


def check_replaceable_folder(path: Path, is_replaceable) -> Path:
    """Fails with one line unless `path` is missing, an empty folder or one `is_replaceable` accepts."""
    path = Path(path)
    if path.exists() and not (path.is_dir() and (not any(path.iterdir()) or is_replaceable(path))):
        raise UsageError(f"{str(path)!r} exists and is not an earlier output of this command; choose another folder")
    output_target(path / "x")
    return path


@contextlib.contextmanager
def atomic_folder(path: Path, is_replaceable):
    """Yields a temporary folder beside `path`; on success it takes `path`'s place (an existing
    folder there is replaced only when `is_replaceable(path)` says it is an earlier output), on error
    or a signal it is removed: `path` holds the old folder or the new one, never a half-written one."""
    path = check_replaceable_folder(path, is_replaceable)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = old = None
    try:
        tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", dir=path.parent))
        yield tmp
        os.chmod(tmp, 0o777 & ~_umask())
        if path.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{path.name}.old.", dir=path.parent))
            os.replace(path, old / path.name)
        os.replace(tmp, path)
    finally:
        for left in (tmp, old):
            if left is not None and left.exists():
                shutil.rmtree(left, ignore_errors=True)


def output_folder(path: Path) -> Path:
    """A folder outputs go into: refused with one line if it exists as something else."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise UsageError(f"output folder {str(path)!r} exists and is not a directory; choose another folder")
    output_target(path / "x")
    return path


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


def read_input_bytes(path: Path, limit: int, what: str = "file") -> bytes:
    """The bytes of a regular file of at most `limit` bytes; raises InputError otherwise, naming
    the file and never quoting its content."""
    path = Path(path)
    try:
        with open(path, "rb", opener=_open_nonblocking) as handle:
            info = os.fstat(handle.fileno())
            if not stat.S_ISREG(info.st_mode):
                raise InputError(path, f"this is {_kind(info.st_mode)}, not a {what}; give a regular file")
            if info.st_size > limit:
                raise InputError(path, f"{info.st_size} bytes is more than the {limit} bytes a {what} may have")
            data = handle.read(limit + 1)
    except FileNotFoundError:
        raise InputError(path, f"no such {what}; check the path") from None
    except IsADirectoryError:
        raise InputError(path, f"this is a directory, not a {what}") from None
    except OSError as exc:
        raise InputError(path, f"cannot read the {what} ({exc.strerror})") from None
    if len(data) > limit:  # it grew while being read
        raise InputError(path, f"more than the {limit} bytes a {what} may have")
    return data


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
