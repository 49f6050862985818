"""Type stubs of the tmc package (see tmc/__init__.py for the docs)."""

import os
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, bytes, "os.PathLike[str]", "os.PathLike[bytes]"]
_ArrayOrPath = Union[npt.ArrayLike, PathLike]

__version__: str
__all__ = [
    "Mesh",
    "marching_cubes",
    "extract",
    "extract_to",
    "extract_labels",
    "extract_labels_to",
    "compare",
    "read_mesh",
    "info",
    "__version__",
]

class Mesh:
    """A triangle mesh made or read by tmc."""

    vertices: npt.NDArray[np.float64]
    triangles: npt.NDArray[np.uint32]
    normals: Optional[npt.NDArray[np.float32]]
    stats: Dict[str, Any]
    labels: Optional[npt.NDArray[np.uint32]]
    def __init__(
        self,
        vertices: np.ndarray,
        triangles: np.ndarray,
        normals: Optional[np.ndarray] = ...,
        stats: Optional[Dict[str, Any]] = ...,
        labels: Optional[np.ndarray] = ...,
    ) -> None:
        """Wraps vertex and triangle arrays (and optional normals, stats and
        per-triangle labels)."""
    def write(self, path: PathLike) -> None:
        """Writes the mesh as PLY, OBJ, OFF, STL or .tmesh (by extension),
        atomically (a missing directory: ``FileNotFoundError``)."""
    def preview(
        self, path: PathLike, *, title: Optional[str] = ..., threads: int = ...
    ) -> None:
        """Draws the mesh into a PNG picture (four shaded views and a
        caption), as ``tmc preview`` draws it."""
    def check(self) -> Dict[str, Any]:
        """The report of ``tmc check --json``."""

def extract(
    volume: _ArrayOrPath,
    iso: float,
    *,
    spacing: Optional[Sequence[float]] = ...,
    origin: Optional[Sequence[float]] = ...,
    method: str = ...,
    inside: str = ...,
    close: bool = ...,
    threads: int = ...,
    normals: bool = ...,
    series: Optional[Union[int, str]] = ...,
    segment: Optional[int] = ...,
    at: Optional[Mapping[Union[str, int], int]] = ...,
    array: Optional[str] = ...,
    level: Optional[int] = ...,
    dataset: Optional[str] = ...,
    progress: Optional[Callable[[int, int], Any]] = ...,
) -> Mesh:
    """Extracts the isosurface at ``iso`` into a Mesh (tmc's conventions)."""

def extract_to(
    volume: _ArrayOrPath,
    iso: float,
    output: PathLike,
    *,
    spacing: Optional[Sequence[float]] = ...,
    origin: Optional[Sequence[float]] = ...,
    method: str = ...,
    inside: str = ...,
    close: bool = ...,
    threads: int = ...,
    normals: bool = ...,
    series: Optional[Union[int, str]] = ...,
    segment: Optional[int] = ...,
    at: Optional[Mapping[Union[str, int], int]] = ...,
    array: Optional[str] = ...,
    level: Optional[int] = ...,
    dataset: Optional[str] = ...,
    preview: Optional[PathLike] = ...,
    progress: Optional[Callable[[int, int], Any]] = ...,
) -> Dict[str, Any]:
    """Streams the isosurface into a mesh file without holding the mesh
    (with ``normals``, the vertex normals too, as ``tmc extract --normals``;
    with ``preview``, its picture, as ``tmc extract --preview``); a missing
    output directory raises ``FileNotFoundError`` before the run."""

def extract_labels(
    volume: _ArrayOrPath,
    labels: Union[str, Sequence[int]] = ...,
    *,
    background: int = ...,
    spacing: Optional[Sequence[float]] = ...,
    origin: Optional[Sequence[float]] = ...,
    close: bool = ...,
    threads: int = ...,
    normals: bool = ...,
    series: Optional[Union[int, str]] = ...,
    segment: Optional[int] = ...,
    at: Optional[Mapping[Union[str, int], int]] = ...,
    array: Optional[str] = ...,
    level: Optional[int] = ...,
    dataset: Optional[str] = ...,
    progress: Optional[Callable[[int, int], Any]] = ...,
) -> Dict[int, Mesh]:
    """Every label's surface of a label map in one pass, keyed by label:
    each the extraction of the label's 0/1 indicator at 0.5."""

def extract_labels_to(
    volume: _ArrayOrPath,
    output: PathLike,
    labels: Union[str, Sequence[int]] = ...,
    *,
    background: int = ...,
    spacing: Optional[Sequence[float]] = ...,
    origin: Optional[Sequence[float]] = ...,
    close: bool = ...,
    threads: int = ...,
    normals: bool = ...,
    stats: bool = ...,
    series: Optional[Union[int, str]] = ...,
    segment: Optional[int] = ...,
    at: Optional[Mapping[Union[str, int], int]] = ...,
    array: Optional[str] = ...,
    level: Optional[int] = ...,
    dataset: Optional[str] = ...,
    preview: Optional[PathLike] = ...,
    progress: Optional[Callable[[int, int], Any]] = ...,
) -> Dict[str, Any]:
    """Streams every label's surface into files in one pass (``{label}`` in
    ``output`` for a file per label, the one placeholder, else one .ply or
    .tmesh with a per-face label), as ``tmc extract --labels``; a missing
    output directory raises ``FileNotFoundError``; returns its report
    (with ``stats``, each label's components, genus, closed, area and,
    for a closed surface, enclosed_volume, as ``--json`` gives them)."""

def compare(
    volume: _ArrayOrPath,
    iso: float,
    *,
    runs: int = ...,
    spacing: Optional[Sequence[float]] = ...,
    origin: Optional[Sequence[float]] = ...,
    inside: str = ...,
    close: bool = ...,
    threads: int = ...,
    topology_memory: Optional[int] = ...,
    series: Optional[Union[int, str]] = ...,
    segment: Optional[int] = ...,
    at: Optional[Mapping[Union[str, int], int]] = ...,
    array: Optional[str] = ...,
    level: Optional[int] = ...,
    dataset: Optional[str] = ...,
) -> Dict[str, Any]:
    """TMC against standard MC on one volume, as ``tmc compare --json``."""

def read_mesh(path: PathLike) -> Mesh:
    """Reads a .tmesh, PLY, OBJ or OFF file, with its vertex normals and
    per-triangle labels where it has them."""

def info(
    path: PathLike,
    *,
    bins: int = ...,
    plane_step: int = ...,
    series: Optional[Union[int, str]] = ...,
    segment: Optional[int] = ...,
    at: Optional[Mapping[Union[str, int], int]] = ...,
    array: Optional[str] = ...,
    level: Optional[int] = ...,
    dataset: Optional[str] = ...,
) -> Dict[str, Any]:
    """What ``tmc info --json`` prints for a volume file (a DICOM series or
    segment chosen, or the series of a DICOM directory listed)."""

def marching_cubes(
    volume: npt.ArrayLike,
    level: Optional[float] = ...,
    *,
    spacing: Sequence[float] = ...,
    gradient_direction: str = ...,
    step_size: int = ...,
    allow_degenerate: bool = ...,
    method: str = ...,
    mask: Optional[npt.ArrayLike] = ...,
    threads: int = ...,
) -> Tuple[
    npt.NDArray[np.float32],
    npt.NDArray[np.int32],
    npt.NDArray[np.float32],
    npt.NDArray[np.float32],
]:
    """scikit-image's marching_cubes with tmc's topology: (verts, faces, normals, values)."""
