"""A ``zarr.Array`` or ``h5py.Dataset`` passed as the volume, streamed
from its store (see :func:`stored_array`) instead of read whole through
``numpy.asarray``."""

from __future__ import annotations

import os
from typing import Any, Optional, Tuple

import numpy as np

from . import _tmc
from ._arguments import _READ_IN_PLACE


def stored_array(volume: Any, select: Tuple[Any, ...]) -> Optional[Tuple[str, Tuple[Any, ...]]]:
    """``(store path, selection)`` to stream a ``zarr.Array`` (in a local
    directory store) or an ``h5py.Dataset`` (in a file on disk) from its
    store, plane by plane, instead of reading it whole through
    ``numpy.asarray``: when nothing else was chosen with ``series`` ...
    ``dataset``, the object's shape is ``(nz, ny, nx)`` (after axes of
    size 1) of a dtype tmc reads, and tmc's readers open the same shape
    there (not a codec or filter they do not read). The selection's last
    entry makes the library read it on the call's grid (spacing 1 and
    origin 0 unless given), as a numpy array, not on the file's. ``None``
    otherwise: the object is then read through numpy, as before. An
    ``h5py`` file open for writing is flushed first, so that the file
    holds what the object shows."""
    if isinstance(volume, np.ndarray) or any(part is not None for part in select):
        return None
    module = type(volume).__module__ or ""
    located: Optional[Tuple[str, Optional[str], Optional[str]]] = None
    if module.startswith("h5py"):
        located = h5py_location(volume)
    elif module.startswith("zarr"):
        located = zarr_location(volume)
    if located is None:
        return None
    try:
        shape = tuple(int(n) for n in volume.shape)
        dtype = np.dtype(volume.dtype)
    except (AttributeError, TypeError, ValueError):
        return None
    if (len(shape) < 3 or any(n != 1 for n in shape[:-3])
            or not (dtype.str[1:] in _READ_IN_PLACE or dtype.kind == "b")):
        return None
    path, array, dataset = located
    chosen = (None, None, None, array, None, dataset, True)
    if _tmc.stored_shape(path, chosen) != list(shape[-3:]):
        return None
    return path, chosen


def h5py_location(dataset: Any) -> Optional[Tuple[str, None, str]]:
    """``(file, None, dataset path)`` of an ``h5py.Dataset`` in a file on
    disk (not an in-memory or other-driver file); flushes a writable file."""
    file = getattr(dataset, "file", None)
    name = getattr(dataset, "name", None)
    if file is None or not isinstance(name, str) or getattr(file, "driver", None) != "sec2":
        return None
    if getattr(file, "mode", "r") != "r":
        file.flush()
    return os.path.abspath(os.fsdecode(file.filename)), None, name


def zarr_location(array: Any) -> Optional[Tuple[str, Optional[str], None]]:
    """``(store directory, array path or None, None)`` of a ``zarr.Array``
    in a local directory store (zarr-python 3's ``LocalStore``, 2's
    ``DirectoryStore``); ``None`` for other stores (memory, zip, remote)."""
    store = getattr(array, "store", None)
    kind = type(store).__name__
    if kind == "LocalStore":
        root = getattr(store, "root", None)
    elif kind in ("DirectoryStore", "NestedDirectoryStore"):
        root = getattr(store, "path", None)
    else:
        return None
    if root is None:
        return None
    inside = str(getattr(array, "path", "") or "").strip("/")
    return os.path.abspath(os.fspath(root)), (inside or None), None
