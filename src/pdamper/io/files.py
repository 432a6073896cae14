"""Small file helpers shared by every writer (atomic writes, JSON-safe values) and the one netCDF reader."""

from __future__ import annotations

import errno
import gc
import math
import os
import sys
import uuid
from pathlib import Path

from ..errors import InputError

__all__ = ["atomic_write", "json_safe", "netcdf_bytes", "read_dataset", "remove_stale_temporaries", "write_dataset"]


#: What a failed write means to the user, by errno: (the cause, what to do); the rest: the system's words.
_WRITE_FAILURES = {
    errno.ENOSPC: ("no space left on the device", "free some space or write elsewhere"),
    errno.EDQUOT: ("the disk quota is exceeded", "free some space or write elsewhere"),
    errno.EROFS: ("the file system is read-only", "write elsewhere"),
    errno.EACCES: ("the directory is not writable", "write elsewhere or change its permissions"),
    errno.EPERM: ("the directory is not writable", "write elsewhere or change its permissions"),
    errno.ENOENT: ("its directory does not exist (any more)", "write elsewhere"),
    errno.EFBIG: ("the file is too large for this file system", "write elsewhere"),
}


def atomic_write(path, data) -> Path:
    """Write ``data`` (bytes or str, UTF-8) to ``path`` atomically: a temporary file next to it
    (honouring the umask), flushed and fsynced, then renamed over ``path`` and the directory
    fsynced (the rename survives a power cut). A crash leaves either the old file or the new one,
    never half of it. Returns the path.

    A write the system refuses (a full disk, a read-only directory) raises
    :class:`~pdamper.errors.InputError` naming the file and the cause; the temporary file is
    removed and ``path`` keeps what it had."""
    path = Path(path)
    if isinstance(data, str):
        data = data.encode("utf-8")
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{uuid.uuid4().hex[:8]}.tmp")
    try:
        with open(tmp, "xb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(exc, OSError):
            why, fix = _WRITE_FAILURES.get(exc.errno, (exc.strerror or str(exc), "write elsewhere"))
            kept = "its previous content is unchanged" if path.exists() else "nothing was written"
            raise InputError(f"cannot write {path}: {why} ({errno.errorcode.get(exc.errno, 'OSError')}); {kept}; "
                             f"{fix}") from None
        raise
    _sync_directory(path.parent)
    return path


def netcdf_bytes(ds) -> bytes:
    """An xarray Dataset as netCDF-4 (h5netcdf) bytes, whatever Dask client the process has open.

    xarray picks its write lock by the active Dask scheduler: with a ``dask.distributed.Client``
    open in the process (``Client(LocalCluster())`` in a notebook) it asks that client for a
    distributed lock named after the target, which fails for an in-memory buffer ("Semaphore or
    Lock ... not known"). The datasets pdamper writes hold numpy arrays, so the write is run
    under Dask's synchronous scheduler, which gives xarray a local lock and leaves the user's
    client alone."""
    import dask

    with dask.config.set(scheduler="synchronous"):
        return bytes(ds.to_netcdf(engine="h5netcdf"))


def write_dataset(path, ds) -> Path:
    """Write an xarray Dataset to ``path`` as netCDF atomically (:func:`netcdf_bytes`,
    :func:`atomic_write`); safe beside a ``dask.distributed.Client``."""
    return atomic_write(path, netcdf_bytes(ds))


#: The first bytes of an HDF5 file (netCDF-4), at offset 0, 512, 1024, 2048 ... (the HDF5 file format).
_HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"


def read_dataset(path, what: str = "netCDF file"):
    """The xarray Dataset of a netCDF-4 file pdamper wrote (``results.nc``, a fields file, a case's
    signals), loaded into memory; a file that is not one, or is damaged, is an
    :class:`~pdamper.errors.InputError` naming it (a file without the HDF5 signature is refused
    before it is opened). h5netcdf, given a damaged file, fails half-way and its destructor then
    prints "Exception ignored in ... File.close": that is kept quiet while the file is let go."""
    import xarray as xr

    from ..errors import checked_file, shown, shown_path

    p = checked_file(path, what)
    try:
        with open(p, "rb") as fh:
            head = fh.read(8)
            if head != _HDF5_SIGNATURE:  # the signature may also sit at 512, 1024 ... after a user block
                fh.seek(512)
                if fh.read(8) != _HDF5_SIGNATURE:
                    raise InputError(f"{shown_path(p)}: not a netCDF-4 (HDF5) file ({what}); give a file pdamper "
                                     "wrote (results.nc, a fields file)")
    except OSError as exc:
        raise InputError(f"cannot read {shown_path(p)} ({what}): {exc.strerror or exc}") from None
    old_hook = sys.unraisablehook
    sys.unraisablehook = _quiet  # h5netcdf's destructor of a file it failed to open (a damaged one) speaks
    try:
        try:
            return xr.load_dataset(p, engine="h5netcdf")
        except Exception as exc:  # h5py/h5netcdf raise OSError, ValueError, KeyError ... for a damaged file
            why = shown(" ".join(str(exc).split()) or type(exc).__name__, 200)
        gc.collect(0)  # the half-opened file (young, in a reference cycle) goes now, while its destructor is quiet
    finally:
        sys.unraisablehook = old_hook
    raise InputError(f"{shown_path(p)}: a damaged netCDF file ({what}): {why}")


def _quiet(unraisable) -> None:
    """An unraisable-exception hook that says nothing."""


def remove_stale_temporaries(directory) -> list[Path]:
    """Remove the temporary files :func:`atomic_write` left in ``directory`` when its process was
    killed (``kill -9``, a power cut) between writing and renaming; a file of a process still
    running is kept. Returns the files removed."""
    removed = []
    for f in Path(directory).glob(".*.tmp"):
        parts = f.name.rsplit(".", 3)  # ".<name>", "<pid>", "<hex>", "tmp"
        if len(parts) != 4 or not parts[1].isdigit():
            continue
        try:
            os.kill(int(parts[1]), 0)
        except ProcessLookupError:
            pass  # its writer is gone
        except OSError:
            continue  # alive (or not ours to ask): keep it
        else:
            continue
        try:
            f.unlink()
            removed.append(f)
        except OSError:
            pass
    return removed


def _sync_directory(directory: Path) -> None:
    """fsync a directory so that a rename in it is on disk (best effort: not every system can)."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def json_safe(obj):
    """JSON-ready copy of ``obj``: numpy scalars and arrays to Python, NaN/inf to None, complex
    numbers to ``[re, im]``."""
    import numpy as np

    if isinstance(obj, dict):
        return {str(k): json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_safe(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return json_safe(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, (complex, np.complexfloating)):
        return [json_safe(obj.real), json_safe(obj.imag)]
    return obj
