"""Argument handling of the package's functions: each argument checked
and turned into what the library's calls (``tmc._tmc``) take, with the
CLI's words for what is refused; arrays taken in place where the library
can read them so."""

from __future__ import annotations

import collections.abc
import mmap
import operator
import os
from typing import Any, List, Mapping, Optional, Tuple

import numpy as np


# The dtypes the library reads in place (the CLI's: u1 i1 u2 i2 u4 i4 f4 f8).
_READ_IN_PLACE = {
    np.dtype(t).str[1:]
    for t in ("u1", "i1", "u2", "i2", "u4", "i4", "u8", "i8", "f2", "f4", "f8")
}


def _labels_of_triangles(labels: Any) -> np.ndarray:
    """``labels`` as a uint32 array, one per triangle: ``TypeError`` for
    other than integers, ``ValueError`` for one below 0 or of 2**32 or more
    (a cast would wrap it to another label)."""
    array = np.asarray(labels)
    if array.size and array.dtype.kind not in "iu":
        raise TypeError(f"labels must be integers, not {array.dtype}")
    if array.size and (array.min() < 0 or array.max() > np.iinfo(np.uint32).max):
        bad = int(np.argwhere((array < 0) | (array > np.iinfo(np.uint32).max)).flat[0])
        raise ValueError(f"label {array.flat[bad]} of triangle {bad} is not a uint32")
    return np.ascontiguousarray(array.reshape(-1), dtype=np.uint32)


def _rows(value: Any, dtype: Any) -> np.ndarray:
    """``value`` as a C-contiguous array of ``dtype``; an empty one of one
    axis (``[]``, which numpy makes shape ``(0,)``) as no rows of three,
    ``(0, 3)``: what a mesh without vertices or triangles holds."""
    array = np.ascontiguousarray(value, dtype=dtype)
    return array.reshape(0, 3) if array.size == 0 and array.ndim == 1 else array


def _indices(triangles: Any) -> np.ndarray:
    """``triangles`` as uint32 vertex indices: ``TypeError`` for other than
    integers (a cast would truncate 1.5 to 1), ``ValueError`` for a negative
    index (a cast would wrap -1 to 4294967295) or one of 2**32 or more (a
    cast would wrap 2**32 + 5 to vertex 5, a valid index of another
    vertex)."""
    array = np.asarray(triangles)
    if array.size and array.dtype.kind not in "iu":
        raise TypeError(f"triangles must be integer vertex indices, not {array.dtype}")
    if array.size and array.dtype.kind == "i" and array.min() < 0:
        row = int(np.argwhere(array < 0)[0][0])
        raise ValueError(f"triangle {row} {array[row].tolist()} has a negative vertex index")
    if array.size and array.dtype.itemsize > 4 and array.max() > np.iinfo(np.uint32).max:
        row = int(np.argwhere(array > np.iinfo(np.uint32).max)[0][0])
        raise ValueError(
            f"triangle {row} {array[row].tolist()} has a vertex index of 2**32 or more "
            "(mesh files hold 32-bit indices)"
        )
    return _rows(array, np.uint32)


def _mapped_file(array: np.ndarray) -> Optional[Tuple[str, int]]:
    """``(file, byte offset of array[0, 0, 0])`` when ``array`` views a
    read-only or shared ``numpy.memmap``, so that tmc maps the file itself
    (and can drop the pages of finished planes); ``None`` otherwise."""
    root: Any = array
    while isinstance(root, np.ndarray) and not isinstance(root.base, mmap.mmap):
        root = root.base
    if not isinstance(root, np.memmap) or root.filename is None:
        return None
    # A copy-on-write map ("c") may hold changes that are not in the file.
    if getattr(root, "mode", "c") not in ("r", "r+", "w+"):
        return None
    start = array.__array_interface__["data"][0]
    root_start = root.__array_interface__["data"][0]
    return os.fsdecode(root.filename), int(root.offset) + (start - root_start)


def _as_samples(volume: Any) -> np.ndarray:
    """``volume`` as an array the library reads in place: the same array
    for the dtypes tmc reads (any order, any strides; 64-bit integers are
    converted to float64 plane by plane as they are read, exact within
    ±2**53), a view for ``bool``; ``TypeError`` for anything else, and for
    a masked array with a masked sample (its mask would be ignored)."""
    if isinstance(volume, np.ma.MaskedArray) and np.ma.getmaskarray(volume).any():
        # np.asarray would drop the mask, and the masked samples' stored
        # values would make the surface.
        raise TypeError(
            "a masked array: tmc extracts whole volumes and would ignore its mask; "
            "pass volume.filled(value) with a value outside the object, or crop the "
            "volume instead (volume[z0:z1, y0:y1, x0:x1] is a view, not a copy)"
        )
    array = volume if isinstance(volume, np.ndarray) else np.asarray(volume)
    dtype = array.dtype
    if dtype.str[1:] in _READ_IN_PLACE:
        return array
    if dtype.kind == "b":
        return array.view(np.uint8)
    raise TypeError(
        f"unsupported dtype '{dtype.str}' (expected u1, i1, u2, i2, u4, i4, u8, i8, "
        "f2, f4 or f8)"
    )


def _number(value: Any, name: str) -> float:
    """A real number (``iso``, ``level``) as a float: ``TypeError`` naming
    ``name`` for text, bytes or a bool (``float("1")`` would take the
    string ``"1"`` as the number 1, and ``True`` would be 1.0), as for any
    other object that is not a real number."""
    if isinstance(value, (str, bytes, bool, np.bool_)):
        raise TypeError(f"{name} must be a number, not {value!r}")
    try:
        return float(value)
    except OverflowError:
        # An integer past float's range (10**400): was the bare
        # "int too large to convert to float", naming no argument.
        raise ValueError(f"{name} must be a finite number, not {_shown(value)}") from None
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a number, not {value!r}") from None


def _shown(value: Any) -> str:
    """``repr(value)``, cut to its first 30 characters when longer (an
    integer of hundreds of digits)."""
    text = repr(value)
    return text if len(text) <= 30 else f"{text[:30]}... ({len(text)} characters)"


def _ordered(value: Any, name: str, error: type) -> None:
    """``error`` (``ValueError``, the type each caller raises for other
    than three numbers) for a ``value`` whose order is not the caller's
    (a set: ``{3, 1, 2}`` iterates as 1, 2, 3) or that is not a sequence of
    numbers (a dict iterates its keys; ``"123"`` digit by digit)."""
    unordered = (str, bytes, collections.abc.Set, collections.abc.Mapping)
    if isinstance(value, unordered):
        raise error(f"{name} must be three numbers, not {_shown(value)}")


def _volume_3d(array: np.ndarray) -> np.ndarray:
    """``array`` of shape ``(nz, ny, nx)``, or a view of its volume when
    axes of size 1 come first (``(1, nz, ny, nx)`` from a batch or channel
    axis, in any order: as the ``.npy`` reader takes such a file); other
    shapes of more than 3 axes are a ``ValueError`` naming the axis (fewer
    axes are refused by the library)."""
    extra = array.shape[:-3] if array.ndim > 3 else ()
    # A channel axis last, (nz, ny, nx, 1): the volume is volume[..., 0],
    # where volume[0] would be a plane and its channels.
    channel_last = array.shape[-1] == 1 and all(n == 1 for n in extra[:-1])
    for axis, size in enumerate(extra):
        if size != 1:
            raise ValueError(
                f"shape {tuple(array.shape)} is not one volume: axis {axis} has size "
                f"{size}, not 1 (only axes of size 1 may come before (nz, ny, nx)); "
                f"pass one 3-D volume, e.g. {'volume[..., 0]' if channel_last else 'volume[0]'}"
            )
    return array[(0,) * len(extra)] if extra else array


def _callback(progress: Any) -> Any:
    """``progress`` when it is ``None`` or callable; ``TypeError`` otherwise
    (it would fail only at the first report, in the middle of the run)."""
    if progress is None or callable(progress):
        return progress
    raise TypeError(f"progress must be a callable progress(done, total) or None, not {progress!r}")


def _flag(value: Any, name: str) -> bool:
    """A boolean option: ``True``/``False`` or a numpy bool; anything
    else (``"no"``, 1, None) is a ``TypeError`` naming ``name``, since a
    truthy string or number would silently mean True."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise TypeError(f"{name} must be True or False, not {value!r}")


def _options(method: str, inside: str, close: bool, threads: int) -> Tuple[Any, ...]:
    """The method, inside, close and threads arguments of the library's calls."""
    if not isinstance(inside, str):
        raise TypeError(f"inside must be 'high' or 'low', not {inside!r}")
    return _method(method), inside, _flag(close, "close"), _threads(threads)


def _triple(value: Any, name: str, default: float) -> Tuple[float, float, float]:
    """Three floats (``[x, y, z]``), or ``ValueError``."""
    if value is None:
        return (default, default, default)
    _ordered(value, name, ValueError)
    try:
        given = tuple(value)
    except TypeError:
        raise ValueError(f"{name} must be three numbers, not {_shown(value)}") from None
    if len(given) != 3:
        raise ValueError(f"{name} must be three numbers, not {len(given)}")
    if any(isinstance(v, (str, bytes, bool, np.bool_)) for v in given):
        # float("1") and float(True) would take them as numbers.
        raise ValueError(f"{name} must be three numbers, not {_shown(value)}")
    try:
        values = tuple(float(v) for v in given)
    except OverflowError:
        raise ValueError(f"{name} must be three finite numbers, not {_shown(value)}") from None
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be three numbers, not {_shown(value)}") from None
    return values  # type: ignore[return-value]


def _method(method: str) -> str:
    """The library's method name for tmc's or scikit-image's."""
    names = {"tmc": "tmc", "lewiner": "tmc", "mc": "mc", "lorensen": "mc"}
    if not isinstance(method, str):
        raise TypeError(f"method must be 'tmc' or 'mc', not {method!r}")
    if method not in names:
        raise ValueError(
            f"unknown method {method!r} (expected 'tmc' or 'mc'; "
            "scikit-image's 'lewiner' means 'tmc' and 'lorensen' means 'mc')"
        )
    return names[method]


def _integer(value: Any, name: str, what: str = "an integer") -> int:
    """``value`` as a Python int when it is an integer (numpy's included),
    else ``TypeError`` naming ``name``: 1.5 or "2" are refused, not
    rounded or parsed, and a bool is no number here."""
    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be {what}, not {value!r}")
    try:
        return operator.index(value)
    except TypeError:
        raise TypeError(f"{name} must be {what}, not {value!r}") from None


def _threads(threads: int) -> int:
    """``threads`` as the CLI's ``--threads`` takes it: a whole number, 0
    (all cores) to 1024; 1.5 or "2" are refused (TypeError), not rounded."""
    threads = _integer(threads, "threads")
    if threads < 0:
        raise ValueError(f"threads must be 0 (all cores) or more, not {threads}")
    if threads > 1024:
        raise ValueError(f"threads must be at most 1024, not {threads}")
    return threads


def _count(value: Any, name: str) -> int:
    """A whole number of 0 or more, or ``ValueError`` naming ``name`` (the
    binding's OverflowError said only "can't convert negative int", or "int
    too big to convert" past 2**64); ``TypeError`` naming it for other than
    an integer (1.5, a bool)."""
    value = _integer(value, name)
    if value < 0:
        raise ValueError(f"{name} must be 0 or more, not {value}")
    if value > np.iinfo(np.int64).max:
        raise ValueError(f"{name} must be less than 2**63, not {value}")
    return value


def _select(
    series: Any, segment: Any, at: Any, array: Any = None, level: Any = None,
    dataset: Any = None,
) -> Tuple[Optional[str], Optional[int], Optional[List[Tuple[str, int]]], Optional[str],
           Optional[int], Optional[str], Optional[bool]]:
    """What to read of a path, as one tuple for the library: the series
    (as text: a number or a UID), segment, at, array, level and dataset
    arguments, and ``None`` (:func:`_stored_array` sets it to ``True`` for
    the store of an array object, read on the call's grid). ``TypeError`` for a series that is neither (a bool was the
    series "True"), for a segment or level that is no whole number (1.5
    was segment 1, "a" a ``ValueError`` of ``int``), for an ``at`` that is
    not a mapping of axis names or positions to entries, and for an array
    or dataset path that is not text."""
    if series is not None and (
        isinstance(series, (bool, np.bool_)) or not isinstance(series, (int, np.integer, str))
    ):
        raise TypeError(f"series must be a number or a UID string, not {series!r}")
    if series is not None and not isinstance(series, str):
        series = operator.index(series)
    if segment is not None:
        segment = _integer(segment, "segment", "a segment number")
        if segment < 1:
            raise ValueError(f"segment must be a segment number (1 or more), not {segment}")
    picks = None
    if at is not None:
        if not isinstance(at, Mapping):
            raise TypeError(f"at must be a mapping of axes to entries, like {{'c': 1}}, not {at!r}")
        picks = []
        for axis, entry in at.items():
            if isinstance(axis, (bool, np.bool_)) or not isinstance(axis, (str, int, np.integer)):
                raise TypeError(f"at: an axis is a name or a position, not {axis!r}")
            entry = _integer(entry, f"at[{axis!r}]", "an entry number")
            if entry < 0:
                raise ValueError(f"at[{axis!r}] must be 0 or more, not {entry}")
            picks.append((str(axis) if isinstance(axis, str) else str(operator.index(axis)), entry))
    for name, path in (("array", array), ("dataset", dataset)):
        if path is not None and not isinstance(path, str):
            raise TypeError(f"{name} must be a path inside the file, as a str, not {path!r}")
        if path is not None and "\0" in path:
            raise ValueError(f"{name} must not hold a NUL character")
    if level is not None:
        level = _count(level, "level")
    return ((None if series is None else str(series)), segment, picks, array, level, dataset, None)


def _label_list(labels: Any) -> Optional[List[int]]:
    """``None`` for ``"all"``, else the labels as a list of ints."""
    if isinstance(labels, str):
        if labels != "all":
            raise ValueError(f"labels must be 'all' or a sequence of integers, not {labels!r}")
        return None
    if isinstance(labels, (int, np.integer)):
        labels = [labels]
    try:
        # A bool is an int to operator.index: True would be label 1.
        if any(isinstance(label, (bool, np.bool_)) for label in labels):
            raise TypeError
        chosen = [operator.index(label) for label in labels]
    except TypeError:
        raise TypeError(
            f"labels must be 'all' or a sequence of integers, not {labels!r}"
        ) from None
    if not chosen:
        raise ValueError("labels is empty: give 'all' or at least one label")
    return chosen
