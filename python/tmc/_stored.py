"""Array objects passed as the volume that tmc reads without holding them
whole: a ``zarr.Array`` or ``h5py.Dataset`` streamed from its store by
tmc's own readers (see :func:`stored_array`), and other lazy arrays
(dask, xarray, Zarr arrays in memory) read a slice of planes at a time
through their own library (see :func:`sliced_array`), instead of whole
through ``numpy.asarray``."""

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
    if located is None or volume_shape(volume) is None:
        return None
    shape = tuple(int(n) for n in volume.shape)
    path, array, dataset = located
    chosen = (None, None, None, array, None, dataset, True)
    if _tmc.stored_shape(path, chosen) != list(shape[-3:]):
        return None
    return path, chosen


def volume_shape(volume: Any) -> Optional[Tuple[Tuple[int, ...], np.dtype]]:
    """The shape and dtype of an array object that tmc can read as it is
    stored: ``(nz, ny, nx)`` after axes of size 1, none of them empty, of
    a dtype tmc reads (or bool); ``None`` otherwise."""
    try:
        shape = tuple(int(n) for n in volume.shape)
        dtype = np.dtype(volume.dtype)
    except (AttributeError, TypeError, ValueError):
        return None
    if (len(shape) < 3 or any(n != 1 for n in shape[:-3]) or 0 in shape
            or not (dtype.str[1:] in _READ_IN_PLACE or dtype.kind == "b")):
        return None
    return shape, dtype


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


# The libraries whose arrays are read a slice at a time when tmc's readers
# cannot stream them from their store (see :func:`sliced_array`).
_LAZY_MODULES = ("dask", "xarray", "zarr", "h5py")

# The most bytes of samples read in one slice. The library keeps a slice
# per worker and two more (and one being read), so this bounds the memory a
# lazy array takes.
LAYER_BYTES = 32 << 20


def sliced_array(volume: Any, select: Tuple[Any, ...]) -> Optional[_tmc.SlicedArray]:
    """A lazy array (a ``dask.array``, an ``xarray.DataArray`` not in
    memory, a ``zarr.Array`` or ``h5py.Dataset`` that
    :func:`stored_array` does not stream) wrapped to be read a slice of
    planes at a time, ``volume[..., first:last, :, :]`` computed by its own
    library, so that it is never in memory whole; ``None`` for anything
    else (it is then read through ``numpy.asarray``): numpy arrays, arrays
    of other libraries, an ``xarray.DataArray`` already in memory (read in
    place), a shape other than ``(nz, ny, nx)`` after axes of size 1, a
    dtype tmc does not read, or a selection (``series`` ... ``dataset``)."""
    if isinstance(volume, np.ndarray) or any(part is not None for part in select):
        return None
    module = (type(volume).__module__ or "").split(".")[0]
    if module not in _LAZY_MODULES:
        return None
    if module == "xarray" and getattr(volume, "_in_memory", True):
        return None
    described = volume_shape(volume)
    if described is None:
        return None
    shape, dtype = described
    native = np.dtype(np.uint8) if dtype.kind == "b" else dtype.newbyteorder("=")
    lead = (0,) * (len(shape) - 3)
    plane_bytes = shape[-1] * shape[-2] * native.itemsize
    depth = layer_depth(volume, shape[-3], plane_bytes)

    nz, ny, nx = shape[-3:]

    def fetch(first: int, last: int) -> np.ndarray:
        block = np.asarray(volume[lead + (slice(first, last),)])
        # What the array's library computed must be what the array says it
        # is (a buggy map_blocks may differ): cast or reshaped, it would
        # make the mesh of other samples than numpy.asarray(volume) holds.
        # The byte order may differ; the value is the same.
        if block.dtype.newbyteorder("=") != dtype.newbyteorder("="):
            raise TypeError(
                f"planes {first}..{last} of the array came back as {block.dtype}, "
                f"not the {dtype} the array declares"
            )
        if block.shape != (last - first, ny, nx):
            raise ValueError(
                f"planes {first}..{last} of the array came back in shape {block.shape}, "
                f"not {(last - first, ny, nx)}"
            )
        return np.ascontiguousarray(block, dtype=native).reshape(-1).view(np.uint8)

    return _tmc.SlicedArray(fetch, (nz, ny, nx), native.str[1:], depth)


def layer_depth(volume: Any, planes: int, plane_bytes: int) -> int:
    """Planes to read in one slice: whole chunks (or shards) along z, as
    many as fit in :data:`LAYER_BYTES`, so that no chunk is computed or
    decompressed twice in a pass; fewer planes than a chunk when one chunk
    is larger than that, and as many planes as fit when the array says
    nothing of its chunks. Dask chunks of several depths along z are
    taken by the first one's: a chunk that a slice boundary cuts is then
    computed once per slice it meets."""
    most = max(1, LAYER_BYTES // max(1, plane_bytes))
    chunks = getattr(volume, "shards", None) or getattr(volume, "chunks", None)
    try:
        along = chunks[-3] if chunks else None
        chunk = int(along[0] if isinstance(along, tuple) else along) if along else 0
    except (TypeError, ValueError, IndexError):
        chunk = 0
    if chunk <= 0:
        return min(planes, most)
    if chunk > most:
        return most
    return min(planes, chunk * (most // chunk))
