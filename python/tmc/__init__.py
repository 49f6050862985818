"""tmc: topologically correct and manifold isosurfaces from numpy arrays and volume files.

tmc extracts isosurfaces with R. Grosso's hybrid marching cubes (2016): every
surface has the topology of the trilinear interpolant and is a manifold, and
an extraction streams a volume of any size slab by slab. This package is the
``tmc`` Rust library in-process, with the GIL released while it works.

Two conventions live side by side:

* :func:`marching_cubes` is a drop-in for ``skimage.measure.marching_cubes``:
  the same arguments and the same ``(verts, faces, normals, values)``, with
  vertices in array index order (``volume[i, j, k]`` gives ``(i, j, k)``).
* :func:`extract`, :func:`extract_to`, :func:`extract_labels`,
  :func:`extract_labels_to`, :func:`read_mesh` and :func:`info`
  follow the ``tmc`` command line: a 3-D array is indexed ``[z][y][x]`` (the
  last axis is x, as in a ``.npy`` file), vertices are ``[x, y, z]`` in
  physical coordinates, and a sample is inside iff its value is above the
  isovalue (``inside="low"`` flips that).
"""

from __future__ import annotations

import json
import os
import warnings
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _stored, _tmc
from ._arguments import (
    _as_samples,
    _callback,
    _count,
    _flag,
    _indices,
    _integer,
    _label_list,
    _labels_of_triangles,
    _mapped_file,
    _method,
    _number,
    _ordered,
    _rows,
    _options,
    _select,
    _threads,
    _triple,
    _volume_3d,
)

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

__version__: str = _tmc.__version__

# Paths as Python's own open takes them; bytes go through os.fsdecode (the
# file system encoding with surrogateescape), so a name that is no UTF-8
# reaches the file system as it is.
PathLike = Union[str, bytes, "os.PathLike[str]", "os.PathLike[bytes]"]

class Mesh:
    """A triangle mesh made or read by tmc.

    Attributes
    ----------
    vertices : (N, 3) float64 ndarray
        Vertex positions ``[x, y, z]`` in physical coordinates.
    triangles : (M, 3) uint32 ndarray
        Vertex indices, counter-clockwise seen from outside (the right-hand
        normal points out of the object).
    normals : (N, 3) float32 ndarray or None
        Unit outward normals from the field's gradient (``extract(...,
        normals=True)``), or those a file read by :func:`read_mesh` gives
        one per vertex; else ``None``.
    stats : dict
        What ``tmc extract --json`` reports: the parameters, the grid, the
        paper's Table 1 counts, sizes and timings; empty for a mesh read
        from a file.
    labels : (M,) uint32 ndarray or None
        The label of each triangle, for the surfaces of a label map in one
        file (``tmc extract SEG --labels all -o all.ply``, or
        :func:`extract_labels_to` into one ``.ply`` or ``.tmesh``) read by
        :func:`read_mesh`; else ``None``. ``mesh.triangles[mesh.labels ==
        L]`` is label ``L``'s surface.
    """

    __slots__ = ("vertices", "triangles", "normals", "stats", "labels", "_record")

    def __init__(
        self,
        vertices: np.ndarray,
        triangles: np.ndarray,
        normals: Optional[np.ndarray] = None,
        stats: Optional[Dict[str, Any]] = None,
        labels: Optional[np.ndarray] = None,
    ) -> None:
        """Wraps vertex and triangle arrays (and optional normals, stats and
        per-triangle labels)."""
        self.vertices = vertices
        self.triangles = triangles
        self.normals = normals
        self.stats = {} if stats is None else stats
        self.labels = labels
        # The extraction's grid and chunks (opaque), for writing .tmesh.
        self._record: Any = None

    def __repr__(self) -> str:
        return (
            f"Mesh({len(self.vertices)} vertices, {len(self.triangles)} triangles"
            f"{', normals' if self.normals is not None else ''}"
            f"{', labels' if self.labels is not None else ''})"
        )

    def write(self, path: PathLike) -> None:
        """Writes the mesh to ``path`` in the format its extension names.

        ``.ply`` (binary), ``.obj``, ``.off``, ``.stl`` or ``.tmesh``. The
        file appears whole or not at all: a failed write leaves nothing at
        ``path``. The normals, when the mesh has them, go into PLY
        (``nx ny nz``), OBJ (``vn``, faces ``v//vn``) and ``.tmesh`` (its
        normals attribute), as the CLI's ``--normals`` writes them; OFF and
        STL hold none. The labels, when the mesh has them, go into PLY (a
        ``uint label`` per face, as ``--labels`` writes one file); the other
        formats hold none. A ``.tmesh`` file records the
        extraction that made the mesh (its grid, a chunk per plane): a mesh
        from :func:`extract` writes the bytes :func:`extract_to` would have
        written; a mesh read from a file, or one whose sizes changed, cannot.
        Vertices must be finite as float32 and triangles integer indices
        (``ValueError`` / ``TypeError`` otherwise, nothing written). A
        missing directory raises ``FileNotFoundError`` (as in
        :func:`extract_to`).
        """
        if os.fsdecode(path).lower().endswith(".tmesh") and self._record is None:
            raise ValueError(
                f"{os.fsdecode(path)}: a .tmesh file records the extraction that made the mesh, "
                "and this mesh was not made by tmc.extract; write it with "
                "tmc.extract_to(volume, iso, path)"
            )
        vertices = _rows(self.vertices, np.float64)
        # The files hold float32, which tmc's readers (and others) refuse
        # when not finite: a NaN, or a value past float32's range.
        with np.errstate(over="ignore"):
            finite = np.isfinite(vertices.astype(np.float32)).all(axis=-1)
        if vertices.ndim == 2 and not finite.all():
            i = int(np.argmin(finite))
            raise ValueError(
                f"{os.fsdecode(path)}: vertex {i} {vertices[i].tolist()} is not finite "
                "as the float32 of a mesh file"
            )
        triangles = _indices(self.triangles)
        normals = None
        if self.normals is not None:
            normals = _rows(self.normals, np.float32)
        labels = None
        if self.labels is not None:
            labels = _labels_of_triangles(self.labels)
        _tmc.write_mesh(os.fsdecode(path), vertices, triangles, self._record, normals, labels)

    def preview(self, path: PathLike, *, title: Optional[str] = None, threads: int = 0) -> None:
        """Draws the mesh into the PNG picture ``path``: three orthogonal
        views and one oblique, shaded, with a caption (``title``, the
        triangles, and whether the mesh is closed, its genus and
        components), 1024 pixels wide, as ``tmc
        preview`` draws the mesh written as PLY (framed by its vertices'
        box; the same bytes for the same title). ``title`` defaults to the
        name of the input file the mesh was extracted from, else the
        picture's file name. The file appears whole or not at all; a name
        that does not end in ``.png`` or whose directory is missing raises
        ``ValueError`` / ``FileNotFoundError`` with nothing written.
        ``threads`` draw it (0: one per core); the bytes do not depend on
        them."""
        if title is None:
            source = self.stats.get("input") if isinstance(self.stats, dict) else None
            title = os.path.basename(source if isinstance(source, str) else os.fsdecode(path))
        if not isinstance(title, str):
            raise TypeError(f"title must be a str, not {title!r}")
        vertices = _rows(self.vertices, np.float64)
        _tmc.preview_mesh(os.fsdecode(path), vertices, _indices(self.triangles), title,
                          _threads(threads))

    def check(self) -> Dict[str, Any]:
        """The report of ``tmc check --json``: manifoldness, orientation,
        boundary, components and genus, computed from the indices alone."""
        vertices = _rows(self.vertices, np.float64)
        return json.loads(_tmc.check_mesh(vertices, _indices(self.triangles)))


def _source_args(
    volume: Any, iso: float, spacing: Any, origin: Any, select: Tuple[Any, ...]
) -> Tuple[Any, ...]:
    """The input, isovalue, spacing, origin, mapped-file and selection
    arguments of the library's calls, for an array, an array object kept
    in a Zarr store or HDF5 file (streamed from there, see
    :func:`_stored.stored_array`) or a path."""
    if isinstance(volume, (str, bytes, os.PathLike)):
        if spacing is not None or origin is not None:
            raise ValueError(
                "spacing and origin of a volume file come from its header; "
                "pass them only with an array"
            )
        return (os.fsdecode(volume), _number(iso, "iso"), (1.0, 1.0, 1.0), (0.0, 0.0, 0.0),
                None, select)
    iso = _number(iso, "iso")
    stored = _stored.stored_array(volume, select)
    if stored is not None:
        path, chosen = stored
        spacing = _triple(spacing, "spacing", 1.0)
        origin = _triple(origin, "origin", 0.0)
        return path, iso, spacing, origin, None, chosen
    sliced = _stored.sliced_array(volume, select)
    if sliced is not None:
        return (sliced, iso, _triple(spacing, "spacing", 1.0), _triple(origin, "origin", 0.0),
                None, select)
    array = _volume_3d(_as_samples(volume))
    spacing = _triple(spacing, "spacing", 1.0)
    origin = _triple(origin, "origin", 0.0)
    return array, iso, spacing, origin, _mapped_file(array), select


def extract(
    volume: Any,
    iso: float,
    *,
    spacing: Optional[Sequence[float]] = None,
    origin: Optional[Sequence[float]] = None,
    method: str = "tmc",
    inside: str = "high",
    close: bool = False,
    threads: int = 0,
    normals: bool = False,
    series: Optional[Union[int, str]] = None,
    segment: Optional[int] = None,
    at: Optional[Mapping[Union[str, int], int]] = None,
    array: Optional[str] = None,
    level: Optional[int] = None,
    dataset: Optional[str] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Mesh:
    """Extracts the isosurface at ``iso`` into a :class:`Mesh`, with the
    ``tmc extract`` conventions.

    Parameters
    ----------
    volume : ndarray or path
        A 3-D array indexed ``[z][y][x]`` (u8, i8, u16, i16, u32, i32, f32 or
        f64; any order, any strides, a ``numpy.memmap``: read in place, not
        copied), or the path of any volume file ``tmc extract`` reads,
        streamed plane by plane. A ``zarr.Array`` in a local directory
        store and an ``h5py.Dataset`` of a file on disk opened for reading
        are streamed from there too, with an array's grid (``spacing`` and
        ``origin`` as given, not the file's). Lazy arrays (a
        ``dask.array``, an ``xarray.DataArray`` backed by dask, other Zarr
        arrays and HDF5 datasets) are read a slice of whole chunks at a
        time, through their own library, never whole; other array-likes
        are read through ``numpy.asarray``.
    iso : float
        The isovalue (finite). A sample is inside iff its value is above it.
    spacing, origin : 3 floats, optional
        ``[x, y, z]`` sample spacing and first-sample position of an array
        (default 1 and 0). A file's come from its header.
    method : {"tmc", "mc"}
        Grosso's topologically correct hybrid marching cubes, or standard
        marching cubes.
    inside : {"high", "low"}
        Which side of ``iso`` is the object ("low" for distance fields).
    close : bool
        Treat everything outside the volume as outside the object, so that
        every surface is closed.
    threads : int
        Worker threads; 0 uses every core.
    normals : bool
        Also compute unit outward vertex normals from the field's gradient.
    series : int or str, optional
        The series of a DICOM directory to read, by its SeriesNumber or
        SeriesInstanceUID (``info(path)`` lists them), as ``--series``.
    segment : int, optional
        The segment of a DICOM Segmentation object to read alone, as 0 to
        1 (so ``iso=0.5`` is its surface), as ``--segment``; without it a
        SEG reads as the label map of its segments.
    at : mapping, optional
        The entry to read of each axis before z, y, x of a Zarr array or
        HDF5 dataset, as ``--at``: ``{"c": 1, "t": 0}`` by the OME-Zarr
        axis names, or ``{0: 2}`` by position (0 the slowest); an axis of
        one entry needs none. Only the chunks holding that entry are read.
    array : str, optional
        The array of a Zarr store to read, by its path inside the store
        (``"labels/0"``), as ``--array``: the same as the path
        ``"store.zarr/labels/0"``.
    level : int, optional
        The level of an OME-Zarr image pyramid to read (0, the finest, by
        default), as ``--level``.
    dataset : str, optional
        The dataset of an HDF5 file (``"/scan/ct"``), as ``--dataset``: the
        same as the path ``"file.h5:/scan/ct"``.
    progress : callable, optional
        Called as ``progress(done, total)`` (cell layers written, cell
        layers in all) on the calling thread while the run goes, when the
        counts change (at most every 50 ms), and with ``done == total`` at
        the end of a run that succeeded: for a progress bar
        (``tqdm``'s ``bar.update``). An exception it raises stops the run,
        as Ctrl-C does, and is raised (by the last call, after the run, the
        outputs are already written).

    Returns
    -------
    Mesh
        Vertices ``[x, y, z]`` (float64, physical coordinates), triangles
        (uint32), normals if asked for, and ``stats``.

    Raises
    ------
    ValueError, TypeError
        Bad input or arguments, with the CLI's words. ``OSError`` for a file
        that cannot be read; ``KeyboardInterrupt`` on Ctrl-C.
    """
    *source, chosen = _source_args(volume, iso, spacing, origin,
                                   _select(series, segment, at, array, level, dataset))
    options = _options(method, inside, close, threads)
    vertices, triangles, vertex_normals, report, record = _tmc.extract(
        *source, *options, _flag(normals, "normals"), chosen, progress=_callback(progress),
    )
    mesh = Mesh(vertices, triangles, vertex_normals, json.loads(report))
    mesh._record = record
    return mesh


def extract_to(
    volume: Any,
    iso: float,
    output: PathLike,
    *,
    spacing: Optional[Sequence[float]] = None,
    origin: Optional[Sequence[float]] = None,
    method: str = "tmc",
    inside: str = "high",
    close: bool = False,
    threads: int = 0,
    normals: bool = False,
    series: Optional[Union[int, str]] = None,
    segment: Optional[int] = None,
    at: Optional[Mapping[Union[str, int], int]] = None,
    array: Optional[str] = None,
    level: Optional[int] = None,
    dataset: Optional[str] = None,
    preview: Optional[PathLike] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Dict[str, Any]:
    """Streams the isosurface at ``iso`` into the file ``output`` without
    holding the mesh in memory (the CLI's memory bound, for volumes of any
    size).

    ``output``'s extension chooses the format: ``.tmesh``, ``.ply``,
    ``.obj``, ``.off`` or ``.stl``. The file appears whole or not at all (an
    error or Ctrl-C leaves nothing at ``output``). With ``normals=True`` the
    unit outward vertex normals from the field's gradient are written too,
    the bytes ``tmc extract --normals`` writes: PLY ``nx ny nz``, OBJ ``vn``,
    the ``.tmesh`` normals attribute (OFF and STL hold none: with them
    ``normals=True`` raises ``ValueError``, as the CLI refuses). The other
    arguments are those of :func:`extract`. Returns the run's report
    (``tmc extract --json``'s keys that describe the run). An output whose
    directory is missing raises ``FileNotFoundError`` before the volume is
    read (``NotADirectoryError``, ``IsADirectoryError``, ``PermissionError``
    for the other output paths that cannot be written), as
    :meth:`Mesh.write` does. No placeholder of ``output`` is filled in: a
    ``{NAME}`` (``{stem}``, ``{iso}``) raises ``ValueError`` naming it.
    With ``preview="FILE.png"`` the picture ``tmc extract --preview``
    draws is made from the same stream of chunks (titled with the input
    file's name, or ``output``'s for an array): the same bytes as the CLI's
    for the same file; if the picture fails, the mesh is removed too.
    """
    picture = None if preview is None else os.fsdecode(preview)
    samples, *rest, chosen = _source_args(volume, iso, spacing, origin,
                                          _select(series, segment, at, array, level, dataset))
    options = _options(method, inside, close, threads)
    report = _tmc.extract_to(
        samples, os.fsdecode(output), *rest, *options, _flag(normals, "normals"), chosen, picture,
        progress=_callback(progress),
    )
    return json.loads(report)


def compare(
    volume: Any,
    iso: float,
    *,
    runs: int = 7,
    spacing: Optional[Sequence[float]] = None,
    origin: Optional[Sequence[float]] = None,
    inside: str = "high",
    close: bool = False,
    threads: int = 0,
    topology_memory: Optional[int] = None,
    series: Optional[Union[int, str]] = None,
    segment: Optional[int] = None,
    at: Optional[Mapping[Union[str, int], int]] = None,
    array: Optional[str] = None,
    level: Optional[int] = None,
    dataset: Optional[str] = None,
) -> Dict[str, Any]:
    """TMC against standard marching cubes on one volume, as ``tmc
    compare --json`` reports it, without writing a mesh.

    A warm-up of each method, then ``runs`` pairs (1 to 1000), interleaved,
    timed; every ambiguous cell through the kernel to count the cells TMC
    triangulates differently from MC; each mesh once more through the
    checker for its components, Euler characteristic and genus, unless the
    meshes would need more than ``topology_memory`` bytes (2 GiB by
    default; then those are ``None`` and ``topology_note`` says why).
    ``volume`` and the other arguments are those of :func:`extract`.

    Returns
    -------
    dict
        ``tmc`` and ``mc`` (each: ``seconds`` of every run,
        ``median_seconds``, ``min_seconds``, ``max_seconds``, ``triangles``,
        ``vertices``, ``components``, ``euler``, ``genus`` and the paper's
        Table 1 counts), ``ratio`` (``median`` of the paired TMC/MC time
        ratios and the 95% bootstrap interval ``low``, ``high``),
        ``differing_cells`` (``cells`` and by kind: ``face_decisions``,
        ``tunnels``, ``contours_12``, ``interior_vertices``), and the run's
        ``input`` (``None`` for an array), ``iso``, ``inside``, ``close``,
        ``threads``, ``runs`` and ``topology_note``.
    """
    runs = _integer(runs, "runs")
    if not 1 <= runs <= 1000:
        raise ValueError(f"runs must be 1 to 1000, not {runs}")
    limit = None if topology_memory is None else _count(topology_memory, "topology_memory")
    source, iso, spacing3, origin3, mapped, chosen = _source_args(
        volume, iso, spacing, origin, _select(series, segment, at, array, level, dataset))
    _, inside, close, threads = _options("tmc", inside, close, threads)
    report = _tmc.compare(source, iso, spacing3, origin3, mapped, inside, close, threads,
                          chosen, runs, limit)
    return json.loads(report)


def _label_args(
    volume: Any,
    labels: Any,
    background: Any,
    spacing: Any,
    origin: Any,
    close: Any,
    threads: Any,
    normals: Any,
    series: Any,
    segment: Any,
    at: Any,
    zarr_array: Any,
    level: Any,
    dataset: Any,
) -> Tuple[Any, Tuple[Any, ...]]:
    """The input and the other arguments of the library's label calls.
    An array is taken as :func:`_source_args` takes it (64-bit integer
    labels in place; the library refuses a 64-bit label at or beyond
    ±2**53: read as a float64, 2**53 + 1 would be 2**53)."""
    chosen = _label_list(labels)
    array, _, spacing3, origin3, mapped, select = _source_args(
        volume, 0.5, spacing, origin, _select(series, segment, at, zarr_array, level, dataset))
    rest = (chosen, _integer(background, "background"), spacing3, origin3, mapped,
            _flag(close, "close"), _threads(threads), _flag(normals, "normals"), select)
    return array, rest


def extract_labels(
    volume: Any,
    labels: Union[str, Sequence[int]] = "all",
    *,
    background: int = 0,
    spacing: Optional[Sequence[float]] = None,
    origin: Optional[Sequence[float]] = None,
    close: bool = False,
    threads: int = 0,
    normals: bool = False,
    series: Optional[Union[int, str]] = None,
    segment: Optional[int] = None,
    at: Optional[Mapping[Union[str, int], int]] = None,
    array: Optional[str] = None,
    level: Optional[int] = None,
    dataset: Optional[str] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Dict[int, Mesh]:
    """The surface of every label of a segmentation label map, in one pass
    over the volume, as ``tmc extract --labels`` extracts them.

    Label ``L``'s mesh is exactly what ``extract((seg == L).astype(np.uint8),
    0.5, ...)`` gives with the same options (the same vertex, triangle and
    normal arrays): the boundary of the label's samples as the trilinear
    interpolant of its 0/1 indicator has it, with Grosso's TMC. But the
    volume is read once, however many labels, and no indicator volume is
    made: the pass holds what one extraction holds, plus a slab's worth of
    label codes per worker.

    Parameters
    ----------
    volume : ndarray or path
        A 3-D label map indexed ``[z][y][x]`` (any integer dtype, read in
        place, 64-bit ones with labels within ±(2**53 - 1); bool; float16,
        float32 or float64 holding whole numbers; any order or strides),
        or the path
        of any volume file ``tmc extract`` reads (NRRD, NIfTI, Zarr, a
        DICOM Segmentation ...).
    labels : "all" or sequence of int
        The labels to extract; "all" is every value present but
        ``background``. A label that is absent gets an empty mesh.
    background : int
        The value "all" leaves out (default 0).
    spacing, origin : 3 floats, optional
        ``[x, y, z]`` sample spacing and first-sample position of an array.
    close : bool
        Treat everything outside the volume as no label, so that every
        label's surface is a closed 2-manifold.
    threads : int
        Worker threads; 0 uses every core.
    normals : bool
        Unit outward vertex normals from the gradient of each label's
        indicator, as :func:`extract` computes them.
    series, segment, at, array, level, dataset : optional
        What to read of a path (a DICOM series or segment, a Zarr array,
        level or entry, an HDF5 dataset), as in :func:`extract`.
    progress : callable, optional
        ``progress(done, total)`` in cell layers of the pass, as in
        :func:`extract`.

    Returns
    -------
    dict of int to Mesh
        One :class:`Mesh` per label, keyed by the label's integer value, in
        the order of ``labels`` (ascending for "all"); each mesh's ``stats``
        is what :func:`extract` reports for the label's indicator.

    Raises
    ------
    ValueError
        A sample that is not a whole number (NaN, a fraction, an infinity;
        the message names the first one's position ``(x, y, z)``), a label
        asked for twice, no label but the background, bad arguments.
        ``TypeError`` for an unsupported dtype, ``OSError`` for a file that
        cannot be read, ``KeyboardInterrupt`` on Ctrl-C.
    """
    array, rest = _label_args(volume, labels, background, spacing, origin, close, threads,
                              normals, series, segment, at, array, level, dataset)
    meshes = _tmc.extract_labels(array, *rest, progress=_callback(progress))
    result: Dict[int, Mesh] = {}
    for label, (vertices, triangles, vertex_normals, report, record) in meshes:
        mesh = Mesh(vertices, triangles, vertex_normals, json.loads(report))
        mesh._record = record
        result[int(label)] = mesh
    return result


def extract_labels_to(
    volume: Any,
    output: PathLike,
    labels: Union[str, Sequence[int]] = "all",
    *,
    background: int = 0,
    spacing: Optional[Sequence[float]] = None,
    origin: Optional[Sequence[float]] = None,
    close: bool = False,
    threads: int = 0,
    normals: bool = False,
    stats: bool = False,
    series: Optional[Union[int, str]] = None,
    segment: Optional[int] = None,
    at: Optional[Mapping[Union[str, int], int]] = None,
    array: Optional[str] = None,
    level: Optional[int] = None,
    dataset: Optional[str] = None,
    preview: Optional[PathLike] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Dict[str, Any]:
    """Streams the surface of every label into files in one pass, the
    bytes ``tmc extract --labels`` writes, without holding the meshes.

    ``output`` names the files: with ``{label}`` in it (``"out/{label}.ply"``)
    one file per label, ``{label}`` replaced by the label's value (the one
    placeholder: any other ``{NAME}`` is a ``ValueError``), in any
    format :func:`extract_to` writes (``.tmesh``, ``.ply``, ``.obj``,
    ``.off``, ``.stl``); without, one ``.ply`` or ``.tmesh`` holding every
    label, each triangle with its label (PLY: a ``uint label`` face
    property; ``.tmesh``: the labels attribute). The files appear all,
    whole, or none (an error or Ctrl-C leaves none behind). The other
    arguments are those of :func:`extract_labels` (a missing output
    directory raises ``FileNotFoundError``, as in :func:`extract_to`), and:

    stats : bool
        Count each label's ``components``, ``genus``, ``closed``, ``area``
        and ``enclosed_volume`` while its chunks stream, as ``tmc extract
        --labels --json`` does (the same code, so the same figures to the
        last bit), in memory that does not grow with the meshes. Off by
        default: the counting runs on the one thread that writes the
        files, and about doubles the time of a pass (docs/python.md).
    preview : path, optional
        Also draw every label's surface into this PNG while the pass
        streams, each in its label's colour (the label's number modulo
        16 picks one of sixteen), as ``tmc extract --labels ... --preview``
        does (titled
        with the input file's name, or the output's for an array; the
        number of labels with a surface and the verdict of all the
        surfaces together in the caption). The files are taken back if the
        picture fails.

    Returns the report of ``tmc extract --labels --json``: ``input``
    (``"array"`` for an array), ``close``, ``method``, ``background``,
    ``labels`` (per label: ``label``, ``output``, ``triangles``,
    ``vertices``, ``samples``, ``voxel_volume`` and, with ``stats``,
    ``components``, ``genus`` (absent when a component is not an oriented
    manifold), ``closed`` (a closed, oriented manifold), ``area`` and
    ``enclosed_volume`` (absent when the surface is not closed: over an
    open surface the sum is no volume), in world units) and the seconds
    spent.
    """
    array, rest = _label_args(volume, labels, background, spacing, origin, close, threads,
                              normals, series, segment, at, array, level, dataset)
    picture = None if preview is None else os.fsdecode(preview)
    report = _tmc.extract_labels_to(array, os.fsdecode(output), *rest, stats=_flag(stats, "stats"),
                                    preview=picture, progress=_callback(progress))
    return json.loads(report)


def read_mesh(path: PathLike) -> Mesh:
    """Reads a ``.tmesh``, PLY, OBJ or OFF file into a :class:`Mesh`
    (vertices float64, triangles uint32; a polygon becomes a fan of
    triangles).

    ``normals`` holds the file's vertex normals where it gives one per
    vertex: a ``.tmesh`` written with normals, PLY ``nx ny nz``, an
    ``NOFF`` file, OBJ ``vn`` where every face corner names one and the
    corners of each vertex name the same; else ``None`` (OBJ normals given
    per corner, a vertex's faces shaded apart, are not per-vertex).
    ``labels`` holds the label of each triangle of a labelled ``.tmesh`` or
    a PLY whose faces have an integer ``label`` property (as ``tmc extract
    SEG --labels all -o all.ply`` writes them); else ``None``. A file that
    declares normals or labels but has no vertices or triangles gives
    empty arrays."""
    vertices, triangles, normals, labels = _tmc.read_mesh(os.fsdecode(path))
    return Mesh(vertices, triangles, normals, labels=labels)


def info(
    path: PathLike,
    *,
    bins: int = 1024,
    plane_step: int = 0,
    series: Optional[Union[int, str]] = None,
    segment: Optional[int] = None,
    at: Optional[Mapping[Union[str, int], int]] = None,
    array: Optional[str] = None,
    level: Optional[int] = None,
    dataset: Optional[str] = None,
) -> Dict[str, Any]:
    """What ``tmc info --json`` prints for a volume file: format, grid,
    index-to-world affine, value range, NaN count, and Otsu's suggested
    isovalues (``suggested_iso``, ``suggested_iso_single``); a DICOM
    Segmentation's ``segments``. ``series``, ``segment``, ``at``,
    ``array``, ``level`` and ``dataset`` are those of :func:`extract`; a DICOM directory of several series without ``series``
    gives their listing instead (``input``, ``format``, ``series``: one
    dict per series with ``number``, ``uid``, ``modality``, ``description``,
    ``dims``, ``readable`` ...)."""
    return json.loads(
        _tmc.info(os.fsdecode(path), _count(bins, "bins"), _count(plane_step, "plane_step"),
                  _select(series, segment, at, array, level, dataset))
    )


def marching_cubes(
    volume: Any,
    level: Optional[float] = None,
    *,
    spacing: Sequence[float] = (1.0, 1.0, 1.0),
    gradient_direction: str = "descent",
    step_size: int = 1,
    allow_degenerate: bool = True,
    method: str = "tmc",
    mask: Optional[np.ndarray] = None,
    threads: int = 0,
) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """scikit-image's ``marching_cubes``, with tmc's topology and speed.

    ``from tmc import marching_cubes`` replaces ``from
    skimage.measure import marching_cubes``: same arguments, same return
    values, and a mesh with the topology of the trilinear interpolant that
    is a manifold (closed where the surface does not leave the volume).

    Parameters
    ----------
    volume : (M, N, P) ndarray
        The samples; read in place for u8, i8, u16, i16, u32, i32, f32 and
        f64 (any order or strides, ``numpy.memmap`` included).
    level : float, optional
        The isovalue; default the mean of the volume's minimum and maximum
        (of its finite samples: NaN samples are outside, as everywhere in
        tmc).
    spacing : 3 floats
        Sample spacing along the array's axes (M, N, P).
    gradient_direction : {"descent", "ascent"}
        "descent": the object has values above ``level``; "ascent": below.
        Decides the faces' winding (as in scikit-image) and which side ties
        and ambiguous cells join (tmc's inside).
    step_size : int
        Use every ``step_size``-th sample along each axis (a view, no copy).
    allow_degenerate : bool
        If False, merge vertices at equal positions and drop the triangles
        that collapse (as scikit-image does).
    method : {"tmc", "lewiner", "mc", "lorensen"}
        "tmc" (alias "lewiner", scikit-image's default, which aims at the same
        topology) or standard marching cubes ("mc", alias "lorensen").
    mask : ndarray of bool, optional
        Accepted only when it is all True: tmc cannot skip cells without
        changing the surface, and says so rather than ignore the mask.
    threads : int
        Worker threads (tmc's own argument); 0 uses every core.

    Returns
    -------
    verts : (V, 3) float32
        Vertex positions in array index order, times ``spacing``.
    faces : (F, 3) int32
        Triangles, wound as scikit-image winds them for ``gradient_direction``.
    normals : (V, 3) float32
        Unit normals from the field's gradient, pointing toward lower values
        (as scikit-image's, whatever ``gradient_direction``), in physical
        space: with anisotropic spacing they are the true surface normals,
        where scikit-image's ignore the spacing.
    values : (V,) float32
        The largest sample of the smallest grid element (edge, face or cell)
        each vertex lies on: for the usual vertex, on a cell edge, the larger
        of the edge's two samples (scikit-image's "maximum value of the data
        in the local region near each vertex").

    Raises
    ------
    ValueError
        Bad arguments, a level outside the data range, a mask with False.
    RuntimeError
        No surface at ``level`` (as scikit-image).
    """
    array = _as_samples(volume)
    allow_degenerate = _flag(allow_degenerate, "allow_degenerate")
    if array.ndim != 3:
        raise ValueError(
            f"expected a 3-D array of shape (nz, ny, nx), found shape {list(array.shape)}"
        )
    if min(array.shape) < 2:
        # Before the range below, whose numpy error ("zero-size array to
        # reduction operation") would not say what is wrong.
        raise ValueError(
            f"shape {tuple(array.shape)}: marching_cubes needs at least 2 samples "
            "along every axis"
        )
    _ordered(spacing, "spacing", ValueError)
    if len(spacing) != 3:
        raise ValueError("`spacing` must consist of three floats.")
    spacing = tuple(_number(s, "spacing") for s in spacing)
    if not all(np.isfinite(s) and s > 0 for s in spacing):
        # Checked here, in the caller's axis order (the library's message
        # would list them x first).
        raise ValueError(f"spacing {list(spacing)} must be finite and positive")
    # As scikit-image's volume[::1.5] would: no rounding.
    step = _integer(step_size, "step_size")
    if step < 1:
        raise ValueError("step_size must be at least one.")
    if gradient_direction == "descent":
        inside = "high"
    elif gradient_direction == "ascent":
        inside = "low"
    else:
        raise ValueError(
            f"Incorrect input {gradient_direction} in `gradient_direction`, see docstring."
        )
    if mask is not None:
        mask = np.asarray(mask)
        if mask.shape != array.shape:
            raise ValueError("volume and mask must have the same shape.")
        if not mask.all():
            raise ValueError(
                "mask: tmc extracts whole volumes and cannot skip the masked cells "
                "without changing the surface; crop the volume instead "
                "(volume[z0:z1, y0:y1, x0:x1] is a view, not a copy)"
            )
    low, high = _finite_range(array)
    if level is None:
        if low is None:
            raise ValueError(
                "level: the volume has no finite sample, so there is no range "
                "to take the middle of; give level"
            )
        level = 0.5 * (low + high)
    level = _number(level, "level")
    spacing_ijk = tuple(float(s) * step for s in spacing)
    if step > 1:
        array = array[::step, ::step, ::step]
    # The arrays come in scikit-image's layout and types, normals toward
    # lower values whatever ``inside``: nothing left to convert here.
    verts, faces, normals, values = _tmc.marching_cubes(
        array,
        float(level),
        spacing_ijk[::-1],
        _mapped_file(array),
        _method(method),
        inside,
        _threads(threads),
    )
    if len(faces) == 0:
        if low is None or not low <= float(level) <= high:
            raise ValueError("Surface level must be within volume data range.")
        raise RuntimeError("No surface found at the given iso value.")
    if not allow_degenerate:
        verts, faces, normals, values = _without_degenerate(verts, faces, normals, values)
    return verts, faces, normals, values


def _finite_range(array: np.ndarray) -> Tuple[Optional[float], Optional[float]]:
    """The least and the greatest finite sample of ``array``, or ``(None,
    None)`` when it has none (all NaN or infinite)."""
    if array.dtype.kind not in "fc":
        return float(array.min()), float(array.max())
    with warnings.catch_warnings():
        # An all-NaN array warns and gives NaN, taken below.
        warnings.simplefilter("ignore", RuntimeWarning)
        low, high = float(np.nanmin(array)), float(np.nanmax(array))
    if np.isfinite(low) and np.isfinite(high):
        return low, high
    # Infinite samples (rare): the finite ones, copied.
    finite = array[np.isfinite(array)]
    if finite.size == 0:
        return None, None
    return float(finite.min()), float(finite.max())


def _without_degenerate(
    verts: np.ndarray, faces: np.ndarray, normals: np.ndarray, values: np.ndarray
) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """scikit-image's ``allow_degenerate=False``: vertices at equal
    positions merged, triangles with a repeated vertex dropped, unused
    vertices removed (first occurrence kept, in order)."""
    _, first, inverse = np.unique(verts, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    merged = first[inverse][faces]
    keep = (merged[:, 0] != merged[:, 1]) & (merged[:, 1] != merged[:, 2]) & (
        merged[:, 0] != merged[:, 2]
    )
    merged = merged[keep]
    used = np.unique(merged)
    renumber = np.full(len(verts), -1, dtype=np.int64)
    renumber[used] = np.arange(len(used))
    return (
        verts[used],
        renumber[merged].astype(np.int32),
        normals[used],
        values[used],
    )
