"""Small file helpers shared by every writer: atomic writes and JSON-safe values."""

from __future__ import annotations

import math
import os
import uuid
from pathlib import Path

__all__ = ["atomic_write", "json_safe"]


def atomic_write(path, data) -> Path:
    """Write ``data`` (bytes or str, UTF-8) to ``path`` atomically: a temporary file next to it
    (honouring the umask), flushed and fsynced, then renamed over ``path``. A crash leaves either
    the old file or the new one, never half of it. Returns the path."""
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
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    return path


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
