"""Type stubs of the extension module tmc._tmc (the Rust side; use the
functions of the tmc package instead)."""

from typing import Any, Callable, List, Optional, Sequence, Tuple, final

import numpy as np

__version__: str
__all__ = [
    "SlicedArray",
    "__version__",
    "_restore_record",
    "check_mesh",
    "compare",
    "extract",
    "extract_labels",
    "extract_labels_to",
    "extract_to",
    "info",
    "marching_cubes",
    "preview_mesh",
    "read_mesh",
    "stored_shape",
    "worker_threads",
    "write_mesh",
]

# What to read of a path: series, segment, at, array, level, dataset, and
# True when the path is an array object's store, read on the call's grid.
_Select = Tuple[
    Optional[str], Optional[int], Optional[List[Tuple[str, int]]], Optional[str],
    Optional[int], Optional[str], Optional[bool],
]

@final
class SlicedArray:
    """A lazy array read a slice of planes at a time: ``fetch(first,
    last)`` gives planes ``first..last`` as a 1-D uint8 array of their
    native-order bytes, C order; ``depth`` planes are read at once."""

    def __new__(
        cls,
        fetch: Callable[[int, int], np.ndarray],
        shape: Tuple[int, int, int],
        dtype: str,
        depth: int,
    ) -> SlicedArray: ...

def extract(
    input: Any,
    iso: float,
    spacing: Tuple[float, float, float],
    origin: Tuple[float, float, float],
    mapped: Optional[Tuple[str, int]],
    method: str,
    inside: str,
    close: bool,
    threads: int,
    normals: bool,
    select: _Select,
    progress: Any = ...,
) -> Tuple[np.ndarray, np.ndarray, Optional[np.ndarray], str, Any]:
    """Extracts into arrays in tmc's layout: (vertices float64, triangles
    uint32, normals float32 or None, report JSON, record)."""

def compare(
    input: Any,
    iso: float,
    spacing: Tuple[float, float, float],
    origin: Tuple[float, float, float],
    mapped: Optional[Tuple[str, int]],
    inside: str,
    close: bool,
    threads: int,
    select: _Select,
    runs: int,
    topology_memory: Optional[int] = ...,
) -> str:
    """The figures of tmc compare --json as JSON text."""

def marching_cubes(
    input: np.ndarray,
    iso: float,
    spacing: Tuple[float, float, float],
    mapped: Optional[Tuple[str, int]],
    method: str,
    inside: str,
    threads: int,
) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """scikit-image's (verts float32 [z, y, x], faces int32, normals float32
    toward lower values, values float32) of an array; spacing in [x, y, z]."""

def extract_to(
    input: Any,
    output: str,
    iso: float,
    spacing: Tuple[float, float, float],
    origin: Tuple[float, float, float],
    mapped: Optional[Tuple[str, int]],
    method: str,
    inside: str,
    close: bool,
    threads: int,
    normals: bool,
    select: _Select,
    preview: Optional[str] = ...,
    progress: Any = ...,
) -> str:
    """Streams into a file (with vertex normals if ``normals``, and the
    picture at ``preview``); returns the report JSON."""

def extract_labels(
    input: Any,
    labels: Optional[List[int]],
    background: int,
    spacing: Tuple[float, float, float],
    origin: Tuple[float, float, float],
    mapped: Optional[Tuple[str, int]],
    close: bool,
    threads: int,
    normals: bool,
    select: _Select,
    progress: Any = ...,
) -> List[Tuple[int, Tuple[np.ndarray, np.ndarray, Optional[np.ndarray], str, Any]]]:
    """Every label's mesh in one pass (None: every value present but
    background): (label, extract's tuple for its indicator) per label."""

def extract_labels_to(
    input: Any,
    output: str,
    labels: Optional[List[int]],
    background: int,
    spacing: Tuple[float, float, float],
    origin: Tuple[float, float, float],
    mapped: Optional[Tuple[str, int]],
    close: bool,
    threads: int,
    normals: bool,
    select: _Select,
    stats: bool = ...,
    preview: Optional[str] = ...,
    progress: Any = ...,
) -> str:
    """Streams every label's mesh into the files output names; returns the
    report JSON (with stats, each label's components, genus, closed, area
    and, for a closed surface, enclosed_volume, counted as its chunks
    stream)."""

def read_mesh(
    path: str,
) -> Tuple[np.ndarray, np.ndarray, Optional[np.ndarray], Optional[np.ndarray]]:
    """Reads a mesh file: (vertices float64, triangles uint32, normals
    float32 or None, per-triangle labels uint32 or None)."""

def write_mesh(
    path: str,
    vertices: np.ndarray,
    triangles: np.ndarray,
    record: Any = ...,
    normals: Optional[np.ndarray] = ...,
    labels: Optional[Sequence[int]] = ...,
) -> None:
    """Writes a mesh file, atomically (.tmesh needs the extraction's record),
    with the normals and labels where the format holds them."""

def preview_mesh(
    path: str, vertices: np.ndarray, triangles: np.ndarray, title: str, threads: int
) -> None:
    """Draws a mesh into a PNG picture, atomically."""

def check_mesh(vertices: np.ndarray, triangles: np.ndarray) -> str:
    """The report of tmc check as JSON text."""

def info(
    path: str,
    bins: int = ...,
    plane_step: int = ...,
    select: Optional[_Select] = ...,
) -> str:
    """What tmc info --json prints, as JSON text."""

def worker_threads(threads: int) -> int:
    """The worker threads that `threads` means (0: one per core)."""

def stored_shape(path: str, select: _Select) -> Optional[List[int]]:
    """[nz, ny, nx] as tmc's readers open the array `select` names in the
    store at `path`, or None where they do not open it."""

def _restore_record(state: Tuple[Any, ...]) -> Any:
    """The record of an extraction (opaque) from what it pickled as: how a
    Mesh of tmc.extract pickles and copies with its .tmesh record."""
