"""Atomic file output: single files and whole result directories.

A file is written to a temporary name beside the target and renamed over it; a result directory
is written into a sibling temporary directory and swapped in as a whole (an atomic exchange of
the two names where the kernel offers it). A crash or an exception while writing never leaves a
half-written file, and never a directory mixing new and old files. Files get the permissions
the user's umask allows (``tempfile`` alone would make them 0600).

Every ``--out`` goes through :func:`check_out_dir` or :func:`check_out_file` before any work
starts, and a run holds :func:`claim_out_dir` while it writes: a second run on the same
directory is refused while the first one lives. A write that fails for lack of space (or any
other I/O error) raises :class:`WriteFailed`, one line that says what is intact.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import errno
import fcntl
import functools
import json
import os
import shutil
import stat
import sys
import tempfile
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from rotaflex.core.errors import InputError

_TMP_TAG = ".rotaflex-tmp-"
_LOCK_TAG = ".rotaflex-lock"
#: errors that mean the file system is full (space, quota, file size)
_FULL = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)


class WriteFailed(RuntimeError):
    """Writing an output failed (full disk, I/O error); the message says what is intact.

    Parameters
    ----------
    name : str
        The file being written (``"result.nc"``).
    cause : OSError
        The error the system gave.
    intact : str
        What the user still has, e.g. ``"the earlier result in out/ is intact"``.
    """

    def __init__(self, name: str, cause: OSError, intact: str = ""):
        self.name, self.cause, self.intact = name, cause, intact
        if _is_full(cause):
            what = "no space left on device"
        else:
            what = f"could not write ({cause.strerror or type(cause).__name__})"
        super().__init__(f"{what} while writing {name}" + (f"; {intact}" if intact else ""))

    def __reduce__(self):  # pickles (a sweep worker sends it to the client) with its arguments
        return (type(self), (self.name, self.cause, self.intact))

    def with_intact(self, intact: str) -> WriteFailed:
        return WriteFailed(self.name, self.cause, intact)


def _is_full(exc: BaseException) -> bool:
    return isinstance(exc, OSError) and (exc.errno in _FULL or "No space left on device" in str(exc))


@functools.cache
def _umask() -> int:
    # os.umask can only be read by setting it: read once per process and restore at once
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _chmod_default(path: Path, *, directory: bool = False) -> None:
    os.chmod(path, (0o777 if directory else 0o666) & ~_umask())


@contextmanager
def atomic_path(target: str | Path) -> Iterator[Path]:
    """Yield a temporary path; on success it is renamed to ``target``, on error removed.

    An ``OSError`` while the temporary file is made, written or renamed becomes
    :class:`WriteFailed` naming ``target`` (and saying that an earlier ``target`` is intact).
    """
    target = Path(target)
    tmp_path: Path | None = None
    try:
        try:
            target.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
            os.close(fd)
            tmp_path = Path(tmp)
            yield tmp_path
            _chmod_default(tmp_path)
            os.replace(tmp_path, target)
        except OSError as exc:
            intact = f"the earlier {target.name} in {target.parent} is intact" if target.exists() else ""
            raise WriteFailed(target.name, exc, intact) from exc
    finally:
        if tmp_path is not None and tmp_path.exists():
            tmp_path.unlink()


def write_atomic(target: str | Path, writer: Callable[[Path], Any]) -> Path:
    """Call ``writer(tmp_path)`` and move the file to ``target`` only if it succeeds."""
    with atomic_path(target) as tmp:
        writer(tmp)
    return Path(target)


def write_text_atomic(target: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``target`` atomically."""
    return write_atomic(target, lambda p: p.write_text(text, encoding="utf-8"))


def write_json_atomic(target: str | Path, data: Any) -> Path:
    """Write ``data`` as indented JSON to ``target`` atomically."""
    return write_text_atomic(target, json.dumps(data, indent=2, default=_json_default) + "\n")


#: datasets up to this size are encoded in memory and written as plain bytes [bytes]
NETCDF_IN_MEMORY = 512 * 1024**2


def write_netcdf(target: str | Path, dataset: Any) -> Path:
    """Write an ``xarray.Dataset`` to NetCDF-4 (h5netcdf) at ``target`` atomically.

    HDF5 does not survive a full disk: after a failed write its object teardown raises in
    ``__dealloc__`` and the process can die with SIGSEGV (reproduced with ``rotor transient``
    on a 40 KiB tmpfs). So the file is encoded in memory (datasets up to
    :data:`NETCDF_IN_MEMORY`) and written as plain bytes, where a full disk is an ordinary
    ``OSError``; larger datasets are checked against the free space first.

    Raises
    ------
    WriteFailed
        Not enough space (checked before HDF5 starts) or a failed write.
    """
    target = Path(target)
    nbytes = float(getattr(dataset, "nbytes", 0))
    need = 1.05 * nbytes + 64 * 1024  # data + HDF5 metadata (a few KiB per variable)
    try:
        free = shutil.disk_usage(target.parent).free
    except OSError:
        free = None
    if free is not None and free < need:
        intact = f"the earlier {target.name} in {target.parent} is intact" if target.exists() else ""
        cause = OSError(
            errno.ENOSPC, f"No space left on device (needs ~{need / 2**20:.3g} MiB, {free / 2**20:.3g} free)"
        )
        raise WriteFailed(target.name, cause, intact)
    with _no_dask_import(), h5_lookup_cache():
        if nbytes <= NETCDF_IN_MEMORY:
            return write_atomic(target, lambda p: p.write_bytes(_netcdf_bytes(dataset)))
        return write_atomic(target, lambda p: dataset.to_netcdf(p, engine="h5netcdf"))


def _netcdf_bytes(dataset: Any) -> bytes:
    """The NetCDF-4 encoding of ``dataset`` in memory.

    xarray picks its write lock from the active dask scheduler; with a Dask client open (a
    ``--scheduler`` sweep writes its cases here) that is a distributed lock named by the
    target, which cannot be named by an in-memory buffer. The data are numpy arrays, so the
    local (synchronous) scheduler's thread lock is the right one. Without dask loaded there is
    no scheduler to override (:func:`_no_dask_import` keeps xarray from loading it).
    """
    dask = sys.modules.get("dask")
    if dask is None:
        return dataset.to_netcdf(engine="h5netcdf")
    with dask.config.set(scheduler="synchronous"):
        return dataset.to_netcdf(engine="h5netcdf")


#: (class, attribute) of h5netcdf whose name-to-object lookups :func:`h5_lookup_cache` caches
_H5_LOOKUPS = (
    ("h5netcdf.core", "BaseObject", "_h5ds"),
    ("h5netcdf.core", "Group", "_h5group"),
    ("h5netcdf.dimensions", "Dimension", "_h5ds"),
)
_h5_patch_lock = threading.Lock()
_h5_patch_depth = 0
#: (class, attribute, original property) replaced while :func:`h5_lookup_cache` is active
_h5_patched: list[tuple[type, str, property]] = []


def _cached_lookup(original: property) -> property:
    """``original`` (a property that looks an HDF5 object up by path from the root file) with a
    per-file cache of the objects it found."""
    from h5py import h5i

    def get(self):
        path = getattr(self, "_h5path", None)
        root = self._root if path is not None else None
        if root is None or getattr(self, "_phony", False):
            return original.fget(self)
        cache = root.__dict__.setdefault("_rotaflex_h5_lookups", {})
        obj = cache.get(path)
        # an object whose link was deleted has no name (h5netcdf replaces the scale of a
        # dimension by the coordinate variable of the same name): look it up again then
        if obj is None or h5i.get_name(obj.id) is None:
            obj = cache[path] = original.fget(self)
        return obj

    return property(get, doc=original.__doc__)


@contextmanager
def h5_lookup_cache() -> Iterator[None]:
    """Let h5netcdf find the HDF5 objects of a file it writes in a cache instead of by path.

    h5netcdf (1.x) keeps no HDF5 objects: every access to a variable's dataset, a dimension's
    scale or a group opens it again from the root by path (``h5py.Group.__getitem__``, ~30 us),
    about 22 times per variable while xarray writes it. A result of the gear steady verb
    (42 variables, 48 kB): 138 ms CPU to encode without this context, 67 ms with it
    (``benchmarks/bench_sweep_chains.py --example netcdf``). While it is active the lookups of
    a file are cached on h5netcdf's file object (gone with it); a cached object whose link was
    deleted is looked up again. The bytes written can differ in HDF5's internal layout
    (objects stay open longer); the groups, variables, dimension scales, attributes and data
    are the same (``tests/sweep/test_case_files.py``).

    Changes nothing if h5netcdf's internals differ from the ones this was written against
    (1.8: the ``_h5ds``/``_h5group`` properties). Nested and threaded use is counted; the
    patched lookups give the same objects as the originals, so a thread reading another file
    meanwhile only finds them faster.
    """
    global _h5_patch_depth
    import importlib

    with _h5_patch_lock:
        if _h5_patch_depth == 0:
            try:
                targets = [(getattr(importlib.import_module(mod), cls), attr) for mod, cls, attr in _H5_LOOKUPS]
            except (ImportError, AttributeError):  # pragma: no cover - other h5netcdf
                targets = []
            originals = [(c, a, c.__dict__.get(a)) for c, a in targets]
            if all(isinstance(o, property) for _, _, o in originals):
                for c, a, o in originals:
                    setattr(c, a, _cached_lookup(o))
                    _h5_patched.append((c, a, o))
        _h5_patch_depth += 1
    try:
        yield
    finally:
        with _h5_patch_lock:
            _h5_patch_depth -= 1
            if _h5_patch_depth == 0:
                for c, a, o in _h5_patched:
                    setattr(c, a, o)
                _h5_patched.clear()


@contextmanager
def _no_dask_import():
    """Keep ``to_netcdf`` from importing dask (0.1 s) and dask.distributed (0.3-0.6 s) only to
    learn that no dask scheduler or client is active.

    xarray asks dask which scheduler is active, and dask tries ``distributed.get_client()``.
    In a process that has not imported dask there is no dask collection, scheduler or client,
    so both imports are made to fail fast while the file is written, which both libraries
    handle as "no dask" (:func:`defer_dask` first, so that xarray caches nothing from the
    failed imports). With dask loaded but not distributed, only distributed is kept out,
    unless a dask ``scheduler`` is configured. Left alone in a Dask sweep.
    """
    if "dask" not in sys.modules and defer_dask():
        blocked = ("dask", "distributed")
    elif "distributed" not in sys.modules and not _dask_scheduler_configured():
        blocked = ("distributed",)
    else:
        blocked = ()
    for name in blocked:
        sys.modules[name] = None  # type: ignore[assignment] - makes `import name` fail
    try:
        yield
    finally:
        for name in blocked:
            if name in sys.modules and sys.modules[name] is None:
                del sys.modules[name]


def _dask_scheduler_configured() -> bool:
    """A dask ``scheduler`` set in its config (file, environment or code) leads dask to another
    branch that caches whether distributed imports: never fake the answer then."""
    try:
        import dask
    except ImportError:  # pragma: no cover - dask is a dependency
        return False
    return dask.config.get("scheduler", None) is not None


class _DaskArrayType(type):
    """Metaclass of :class:`_DaskArray`: isinstance/issubclass checks that never import dask."""

    def __instancecheck__(cls, obj) -> bool:
        array = getattr(sys.modules.get("dask.array"), "Array", None)
        return array is not None and isinstance(obj, array)

    def __subclasscheck__(cls, sub) -> bool:
        array = getattr(sys.modules.get("dask.array"), "Array", None)
        return array is not None and issubclass(sub, array)


class _DaskArray(metaclass=_DaskArrayType):
    """Stands for ``dask.array.Array`` in isinstance checks: true exactly for dask arrays once
    ``dask.array`` is loaded, false (without importing it) before, when none can exist."""


def defer_dask() -> bool:
    """Let xarray tell numpy data from dask data without importing dask while none is loaded.

    xarray imports dask for two questions it asks of every new variable and index: is this a
    dask array (it fills a per-library cache of array types by importing ``dask.array``,
    0.4-0.5 s) and is it a dask collection (``dask.base``, 0.1 s). Neither can be true before
    dask is imported, so:

    - xarray's cache entry for dask gets :class:`_DaskArray`, which is ``dask.array.Array``
      once that module is loaded (a Dask sweep loads it) and matches nothing before; the
      entry's other fields import dask when read;
    - its dask-collection test answers False, without importing, while dask is not loaded,
      and asks dask otherwise.

    Idempotent and cheap. Changes nothing if xarray already filled the entry (then dask is
    loaded anyway) or if its internals differ from the ones this was written against
    (xarray 2026.x): then xarray imports dask as it always did.

    Returns
    -------
    bool
        Whether both answers are in place (False: xarray will import dask when it asks).
    """
    try:
        from xarray.namedarray import pycompat, utils

        cache, entry = pycompat._cached_duck_array_modules, pycompat.DuckArrayModule
        original = utils.is_dask_collection
        utils.module_available("dask")  # cached now: never from inside _no_dask_import
    except (ImportError, AttributeError):  # pragma: no cover - other xarray internals
        return False
    if "dask" not in cache:

        class _LazyDask(entry):
            type = (_DaskArray,)

            def __init__(self):  # the other fields come from the real entry, if ever read
                pass

            @functools.cached_property
            def _loaded(self):
                return entry("dask")

            module = property(lambda self: self._loaded.module)
            version = property(lambda self: self._loaded.version)
            available = property(lambda self: self._loaded.available)

        cache["dask"] = _LazyDask()
    if not getattr(original, "_rotaflex_deferred", False):

        @functools.wraps(original)
        def is_dask_collection(x: object) -> bool:
            return sys.modules.get("dask") is not None and original(x)

        is_dask_collection._rotaflex_deferred = True  # type: ignore[attr-defined]
        utils.is_dask_collection = is_dask_collection
    return _DaskArray in cache["dask"].type


def _json_default(obj: Any) -> Any:
    import numpy as np

    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


# -- whole directories ------------------------------------------------------------------------
_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Atomically swap the names ``a`` and ``b`` (Linux ``renameat2``); False if unsupported."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return False
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    rc = fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE)
    return rc == 0


def _stale_siblings(target: Path) -> list[Path]:
    return sorted(target.parent.glob(f".{target.name}{_TMP_TAG}*"))


def _pid_alive(pid: int) -> bool:
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # alive, another user's
        return True
    return True


def _owner(stale: Path) -> int:
    """The pid in a working name ``.NAME.rotaflex-tmp-PID-XXXX`` (0 for older names)."""
    rest = stale.name.rsplit(_TMP_TAG, 1)[-1]
    head = rest.split("-", 1)[0].split(".", 1)[0]
    return int(head) if head.isdigit() else 0


def recover_dir(target: str | Path) -> None:
    """Finish or undo a directory swap that a killed process left half done.

    If ``target`` is missing but a complete previous version was parked beside it (the
    two-rename fallback was interrupted), that version is put back; leftover temporary
    directories of processes that no longer run are removed. Working directories of a live
    process (another run writing the same target) are never touched.
    """
    target = Path(target)
    for stale in _stale_siblings(target):
        owner = _owner(stale)
        if owner and owner != os.getpid() and _pid_alive(owner):
            continue
        if not target.exists() and stale.name.endswith(".old"):
            os.replace(stale, target)
        else:
            shutil.rmtree(stale, ignore_errors=True)


def replace_dir(target: str | Path, writer: Callable[[Path], list[Path]]) -> list[Path]:
    """Write a directory as a set: ``writer(tmp_dir)`` fills a sibling temporary directory, which
    then replaces ``target`` in one step.

    Parameters
    ----------
    target : path
        The result directory; its parent must exist. A previous ``target`` is replaced as a
        whole (its files are not merged with the new ones).
    writer : callable
        ``writer(tmp_dir) -> list of written paths`` (inside ``tmp_dir``).

    Returns
    -------
    list of Path
        The written paths, under ``target``.

    Raises
    ------
    WriteFailed
        An ``OSError`` while writing (full disk, ...): the message names the file and says
        that the earlier ``target`` is intact (or that nothing was written); the working
        directory is removed.
    """
    target = Path(target)
    existed = target.exists()
    intact = f"the earlier result in {target} is intact" if existed else f"nothing was written to {target}"
    recover_dir(target)
    tmp = None
    try:
        tmp = new = Path(tempfile.mkdtemp(prefix=f".{target.name}{_TMP_TAG}{os.getpid()}-", dir=target.parent))
        _chmod_default(tmp, directory=True)
        written = writer(tmp)
        if target.exists():
            if not _exchange(tmp, target):
                parked = target.parent / f".{target.name}{_TMP_TAG}{os.getpid()}.old"
                os.replace(target, parked)
                os.replace(tmp, target)
                tmp = parked
        else:
            os.replace(tmp, target)
    except WriteFailed as exc:
        raise exc.with_intact(intact) from exc.cause
    except OSError as exc:
        raise WriteFailed(target.name, exc, intact) from exc
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)  # the old version, or the failed new one
    return [target / Path(p).relative_to(new) for p in written]


# -- checked output paths -----------------------------------------------------------------------
#: special files an output must never replace (character/block devices, pipes, sockets)
_SPECIAL = {stat.S_IFCHR: "a device", stat.S_IFBLK: "a device", stat.S_IFIFO: "a pipe", stat.S_IFSOCK: "a socket"}


def _special(p: Path) -> str:
    """``"a device"`` etc. if ``p`` (followed through links) is a special file or lies under /dev."""
    try:
        mode = os.stat(p).st_mode
    except OSError:
        mode = 0
    kind = _SPECIAL.get(stat.S_IFMT(mode), "")
    if not kind and Path(os.path.abspath(p)).parts[1:2] in (("dev",), ("proc",), ("sys",)):
        kind = "a system path (/dev, /proc or /sys)"
    return kind


def _common_checks(text: str, field: str, inputs: tuple[str | Path, ...], what: str) -> Path:
    if text.strip() == "":
        raise InputError(field, text, f"{what} path (an empty string would write into the current directory)")
    p = Path(text).expanduser()
    kind = _special(p)
    if kind:
        raise InputError(field, text, f"{what} path, not {kind}")
    for parent in p.absolute().parents:
        if parent.exists() and not parent.is_dir():
            raise InputError(field, text, f"a path not under the file {str(parent)!r}")
    parent = p.absolute().parent
    if not parent.exists():
        raise InputError(field, text, f"{what} whose parent exists ({str(parent)!r} does not)")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(field, text, f"{what} in a writable location ({str(parent)!r} is read-only)")
    for inp in inputs:
        if Path(inp).exists() and p.exists() and os.path.samefile(p, inp):
            raise InputError(field, text, f"{what} other than the input file {str(inp)!r}")
    return p


def check_out_dir(
    path: str | Path, *, marker: tuple[str, ...] = (), field: str = "--out", inputs: tuple[str | Path, ...] = ()
) -> Path:
    """Refuse an unusable output directory before any computation starts.

    Parameters
    ----------
    path : str or Path
        The ``--out`` value as typed.
    marker : tuple of str
        Names of which at least one must exist in an existing, non-empty ``path`` (so that a
        directory of other files is never replaced or mixed with results); empty: no check.
    field : str
        Name of the option in messages.
    inputs : tuple of path
        Input files of the run: their directories (and any directory above) are refused, since
        replacing the result directory would replace the input.

    Raises
    ------
    InputError
        Empty path, an existing file, a device, pipe or socket (or anything under /dev), a path
        under a file, a missing or read-only parent, the current directory or one above it, a
        directory holding an input, a non-empty directory that is not an earlier result of
        this command.
    """
    text = str(path)
    p = _common_checks(text, field, inputs, "a directory")
    if p.exists() and not p.is_dir():
        raise InputError(field, text, "a directory, not an existing file")
    here = Path.cwd().resolve()
    full = p.resolve()
    if full == here or full in here.parents:
        raise InputError(field, text, "a directory other than the current one or one above it (it would be replaced)")
    if full.parent == full:
        raise InputError(field, text, "a directory other than the file-system root")
    for inp in inputs:
        if full in Path(inp).resolve().parents:
            raise InputError(
                field, text, f"a directory that does not hold the input {str(inp)!r} (it would be replaced)"
            )
    if p.exists():
        if not os.access(p, os.W_OK | os.X_OK):
            raise InputError(field, text, "a writable directory")
        entries = [e.name for e in p.iterdir()]
        if marker and entries and not any(m in entries for m in marker):
            raise InputError(
                field,
                text,
                "a new or empty directory, or an earlier output of this command (it holds other files, "
                "which would be replaced)",
            )
    return p


def check_out_file(path: str | Path, *, field: str = "--out", inputs: tuple[str | Path, ...] = ()) -> Path:
    """Refuse an unusable output file before anything is written.

    Refused: an empty path, an existing directory, a device, pipe or socket (or anything under
    /dev), a path under a file, a missing or read-only parent directory, an input file.
    """
    text = str(path)
    p = _common_checks(text, field, inputs, "a file")
    if p.is_dir() or text.endswith(("/", os.sep)):
        raise InputError(field, text, "a file path, not a directory")
    return p


@contextmanager
def claim_out_dir(path: str | Path, *, field: str = "--out") -> Iterator[Path]:
    """Hold ``path`` for this run: a second run on the same output is refused while this one lives.

    The claim is an exclusive ``flock`` on ``.NAME.rotaflex-lock`` beside the directory, which
    holds the owner's pid (for the message). The kernel drops the lock when the process dies,
    so a killed run never blocks the next; the lock file is removed on exit.

    Raises
    ------
    InputError
        Another live process holds the claim (names its pid).
    """
    p = Path(path)
    real = p.resolve()  # one lock whatever the spelling (./out, out/, a link to it)
    lock = real.parent / f".{real.name}{_LOCK_TAG}"
    while True:
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o666 & ~_umask())
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            owner = os.pread(fd, 32, 0).decode(errors="replace").strip() or "?"
            os.close(fd)
            raise InputError(
                field,
                str(path),
                f"a directory no other run is writing (rotaflex pid {owner} is writing it now; wait for "
                "it to finish or choose another directory)",
            ) from None
        # the file may have been removed by its previous owner between open and flock: retry
        try:
            same = os.fstat(fd).st_ino == os.stat(lock).st_ino
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    try:
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        yield p
    finally:
        try:
            os.unlink(lock)
        except OSError:
            pass
        os.close(fd)
