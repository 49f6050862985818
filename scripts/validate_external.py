"""Independent check of tmc's meshes with third-party tools.

Run by scripts/validate-external inside its virtual environment
(.venv-validate: trimesh, meshio, scikit-image, pynrrd, scipy, numpy from
PyPI); see that script for the set-up. Nothing here imports or reuses tmc's
own checker (src/check): every figure is computed from the mesh file by
trimesh, meshio or numpy, and only compared with what `tmc check --json`
says.

For each volume and isovalue of CASES (the real volumes of ../shared/data,
README isovalues, plus the bundled data/headsq_quarter.nrrd):

1. `tmc extract VOL --iso V -o out.ply`, without and with `--close` (and
   `.obj`, `.off`, `.stl` for a few volumes; `--inside low` for the signed
   distance field, whose object is where the distance is negative);
2. the file is read by trimesh (process=False: no welding or reordering of
   vertices, which tmc shares by topology, not by position) and by meshio,
   and checked:
   * counts: vertices and triangles equal `tmc check FILE --json`'s, in both
     parsers;
   * per component (vertices joined by triangle edges, computed here with
     scipy): vertices, edges, triangles, boundary edges and Euler
     characteristic equal tmc check's per-component list (as multisets);
     the total Euler characteristic of trimesh equals tmc check's;
   * closed: trimesh's is_watertight iff tmc check reports no boundary
     edge; with --close it must be watertight (every surface is closed
     there);
   * winding: trimesh's is_winding_consistent;
   * orientation: tmc's convention is that normals point toward lower
     values (docs/conventions.md "Orientation"; toward higher values with --inside
     low), so the object is on the back side of each triangle. With
     --close the signed volume (divergence theorem over the triangles) must
     be positive. And the volume is sampled (trilinear, scipy) a little in
     front of and behind each triangle's centroid; in every component the
     triangles found facing the right way (outside in front, inside behind)
     must hold more than half of the area judged (a component written
     inside out holds about none of it; single flipped triangles are caught
     by the winding check);
   * no triangle repeats a vertex index or has an index out of range, no
     vertex is unreferenced, no coordinate is NaN or infinite; zero-area
     triangles are only counted (tmc makes none, ties included, see
     docs/conventions.md#ties; `tmc check --strict` fails on them);
   * bounding box inside the volume's physical extent, from the affine of
     `tmc info VOL --json` (with --close: one sample beyond each face of
     the volume, where tmc puts its caps);
   * other formats: an .obj or .off has the .ply's triangles (same indices)
     and vertices (to text precision); an .stl (which cannot share
     vertices, so it is not checked for topology) has the .ply's triangles
     as coordinate triples, in the same order and winding;
3. the area of the open surface (no --close) is compared with that of
   scikit-image's marching_cubes (method "lewiner") on the same volume read
   with pynrrd, at the same isovalue, scaled by the spacing. tmc differs
   from plain marching cubes only in ambiguous cells, so the areas should
   agree within about 1% (--area-tol). For information (not a check), the
   triangles of `tmc extract --method mc` are counted against scikit-image's
   "lorensen" marching cubes.

One table line per mesh, then a summary; exit status 1 when any check
failed. Columns: V, F vertices and triangles as parsed; comp, euler, bnd
components, Euler characteristic and boundary edges computed here; wt, wind
trimesh's is_watertight and is_winding_consistent; vol sign of the signed
volume (--close); orient the smallest per-component fraction of judged area
facing the right way, judged the share of the area judged (low on a label
volume, whose outside pockets around single zero samples are thinner than
the sampling distance); degen, unref, zero triangles repeating a vertex,
unreferenced vertices, zero-area triangles; bbox inside the extent; same
equal to the .ply of the same extraction; area_sk relative area difference
tmc - scikit-image; mc=lor whether --method mc has as many triangles as
scikit-image's lorensen.
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import meshio
import nrrd
import numpy as np
import scipy
import scipy.ndimage
import scipy.sparse
import scipy.sparse.csgraph
import skimage
import skimage.measure
import trimesh

# (file, isovalues, extra `tmc extract` options, extra formats). The
# isovalues are the README's of ../shared/data: the first of each volume,
# all of them for cthead, bonsai and engine. The signed distance field is
# negative inside, so its object is `--inside low` (its README line).
# Extra formats are written without --close; "stl+close" also with it (an
# STL's signed volume needs no shared vertices).
CASES = [
    ("cthead.nrrd", [550, 1600], [], []),
    ("headsq_quarter.nrrd", [500], [], []),
    ("engine.nrrd", [80, 180], [], []),
    ("bonsai.nrrd", [40, 100], [], []),
    ("stent_ct.nrrd", [600], [], []),
    ("lidc_chest_ct.nrrd", [36], [], []),
    ("mni152_2009a_gm.nrrd", [128], [], []),
    ("hydrogen.nrrd", [0.1], [], ["obj"]),
    ("neghip.nrrd", [60], [], []),
    ("fuel.nrrd", [30], [], ["obj", "off", "stl"]),
    ("carotid.nrrd", [100], [], []),
    ("bolt.nrrd", [127.5], [], []),
    ("frog_tissues.nrrd", [0.5], [], []),
    ("sdf_bunny_128.nrrd", [0], ["--inside", "low"], ["stl+close"]),
    ("mayavi_heart.nrrd", [100], [], ["obj", "off", "stl"]),
    ("ironprot.nrrd", [64], [], []),
]
# The copy shipped in the repository (the same data as ../shared/data's).
# Distances (times the smallest spacing) at which orientation_by_samples looks
# in front of and behind a triangle, nearest first.
H_REL = (0.05, 0.25)

BUNDLED = ("data/headsq_quarter.nrrd", [500], [], ["obj", "off", "stl", "stl+close"])


def iso_text(v: float) -> str:
    return f"{v:g}"


# ----------------------------------------------------------------------------
# tmc


def run(cmd: list[str]) -> subprocess.CompletedProcess:
    return subprocess.run(cmd, capture_output=True, text=True)


def tmc_json(cmd: list[str]) -> tuple[dict | None, str]:
    """Runs a tmc command printing one JSON object; (object, error)."""
    p = run(cmd)
    try:
        return json.loads(p.stdout), ("" if p.returncode == 0 else f"exit {p.returncode}: {p.stderr.strip()}")
    except json.JSONDecodeError:
        return None, f"exit {p.returncode}, no JSON: {p.stderr.strip()[:300]}"


# ----------------------------------------------------------------------------
# mesh figures, computed here


@dataclass
class Row:
    case: str
    fmt: str
    fails: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    cols: dict = field(default_factory=dict)

    def check(self, ok: bool, what: str) -> bool:
        if not ok:
            self.fails.append(what)
        return ok


def edge_table(faces: np.ndarray, nv: int):
    """Unique undirected edges (as int64 keys) and how many triangles use each."""
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]).astype(np.int64)
    e.sort(axis=1)
    keys = e[:, 0] * nv + e[:, 1]
    uniq, counts = np.unique(keys, return_counts=True)
    return uniq, counts


def components(faces: np.ndarray, nv: int) -> tuple[int, np.ndarray]:
    """Component label of every vertex (vertices joined by triangle edges)."""
    f = faces.astype(np.int64)
    rows = np.concatenate([f[:, 0], f[:, 1], f[:, 2]])
    cols = np.concatenate([f[:, 1], f[:, 2], f[:, 0]])
    g = scipy.sparse.coo_matrix((np.ones(len(rows), dtype=np.int8), (rows, cols)), shape=(nv, nv))
    return scipy.sparse.csgraph.connected_components(g, directed=False)


def per_component(faces: np.ndarray, nv: int, labels: np.ndarray) -> list[tuple]:
    """(vertices, edges, triangles, euler, boundary edges) of each component
    that has a triangle, sorted."""
    if len(faces) == 0:
        return []
    fl = labels[faces[:, 0]]
    ncomp = int(labels.max()) + 1
    tri = np.bincount(fl, minlength=ncomp)
    referenced = np.zeros(nv, dtype=bool)
    referenced[faces.ravel()] = True
    verts = np.bincount(labels[referenced], minlength=ncomp)
    uniq, counts = edge_table(faces, nv)
    el = labels[uniq // nv]
    edges = np.bincount(el, minlength=ncomp)
    bnd = np.bincount(el[counts == 1], minlength=ncomp)
    out = []
    for c in np.nonzero(tri)[0]:
        out.append((int(verts[c]), int(edges[c]), int(tri[c]), int(verts[c] - edges[c] + tri[c]), int(bnd[c])))
    return sorted(out)


def signed_volume(tris: np.ndarray) -> float:
    """Signed volume of triangles (n, 3, 3) by the divergence theorem."""
    t = tris.astype(np.float64)
    return float(np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6.0)


def area_of(tris: np.ndarray) -> np.ndarray:
    t = tris.astype(np.float64)
    return 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)


@dataclass
class Volume:
    path: Path
    info: dict
    data: np.ndarray | None = None  # (x, y, z), float64 (pynrrd)
    spacing: np.ndarray | None = None

    @property
    def affine(self) -> np.ndarray:
        return np.array(self.info["affine"], dtype=np.float64)

    def extent(self, close: bool) -> tuple[np.ndarray, np.ndarray]:
        """Physical bounding box of the samples (one sample more each way
        with --close, where tmc's caps lie)."""
        dims = np.array(self.info["dims"], dtype=np.float64)
        lo, hi = (-1.0, dims) if close else (0.0, dims - 1.0)
        lo = np.broadcast_to(lo, (3,))
        corners = np.array(
            [[(lo, hi)[i][0], (lo, hi)[j][1], (lo, hi)[k][2], 1.0] for i in (0, 1) for j in (0, 1) for k in (0, 1)]
        )
        w = corners @ self.affine.T
        return w[:, :3].min(axis=0), w[:, :3].max(axis=0)

    def load(self) -> None:
        if self.data is None:
            data, header = nrrd.read(str(self.path))  # index order x, y, z
            self.data = np.asarray(data, dtype=np.float64)
            self.spacing = np.linalg.norm(np.asarray(header["space directions"], dtype=np.float64), axis=1)


def orientation_by_samples(
    vol: Volume,
    tris: np.ndarray,
    labels_f: np.ndarray,
    iso: float,
    inside_low: bool,
    close: bool,
    h_rel: tuple[float, ...],
):
    """Samples the volume (trilinear) a distance h (h_rel times the smallest
    spacing) in front of and behind each
    triangle's centroid. A triangle whose front sample is outside and back
    sample inside (value <= iso < value; mirrored with --inside low) faces
    the right way, the reverse the wrong way; a triangle with both samples on
    one side is not judged (on data that ties with the isovalue, and around
    the interior vertices, triangles lie where the interpolant is not
    crossed). Returns, over the components with a judged triangle, the
    smallest fraction of judged area facing the right way, how many
    components were judged, and the fraction of the total area judged.

    With --close, tmc pads the volume with one layer of samples that are
    outside and tie with the isovalue (src/volume/padded.rs documents NaN,
    which counts as such a tie), so the samples here are padded with the
    isovalue itself: a tie is outside for either --inside. Triangles that
    cross from the last sample into that tie layer are judged unreliably
    (the interpolant does not cross the isovalue there), hence a majority
    per component rather than every triangle."""
    vol.load()
    data = np.pad(vol.data, 1, constant_values=iso) if close else vol.data
    shift = 1.0 if close else 0.0
    t = tris.astype(np.float64)
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    a = np.linalg.norm(n, axis=1)
    keep = a > 0
    n, a, t, lab = n[keep], a[keep], t[keep], labels_f[keep]
    c = t.mean(axis=1)
    u = n / a[:, None]
    inv = np.linalg.inv(vol.affine)

    def sample(p):
        idx = np.c_[p, np.ones(len(p))] @ inv.T
        return scipy.ndimage.map_coordinates(data, idx[:, :3].T + shift, order=1, mode="nearest")

    good = np.zeros(len(a), dtype=bool)
    bad = np.zeros(len(a), dtype=bool)
    for h in h_rel:  # a triangle not judged at one distance is tried at the next
        h *= float(np.min(vol.spacing))
        todo = ~(good | bad)
        front, back = sample(c[todo] + h * u[todo]), sample(c[todo] - h * u[todo])
        if inside_low:
            good[todo] = (front >= iso) & (back < iso)
            bad[todo] = (back >= iso) & (front < iso)
        else:
            good[todo] = (front <= iso) & (back > iso)
            bad[todo] = (back <= iso) & (front > iso)
    ncomp = int(labels_f.max()) + 1 if len(labels_f) else 0
    ga = np.bincount(lab[good], weights=a[good], minlength=ncomp)
    ba = np.bincount(lab[bad], weights=a[bad], minlength=ncomp)
    judged = ga + ba
    has = judged > 0
    frac = ga[has] / judged[has]
    return (
        (float(frac.min()) if len(frac) else 1.0),
        int(has.sum()),
        float(judged.sum() / max(a.sum(), 1e-300)),
    )


# ----------------------------------------------------------------------------
# one mesh


def check_mesh(
    row: Row,
    path: Path,
    vol: Volume,
    iso: float,
    close: bool,
    inside_low: bool,
    tmc: str,
    ref: trimesh.Trimesh | None,
    ref_check: dict | None,
) -> tuple[trimesh.Trimesh | None, dict | None]:
    """Checks one output file; returns its trimesh and tmc check report (for
    the other formats of the same extraction to be compared with)."""
    fmt = path.suffix[1:]
    stl = fmt == "stl"
    # --- parse, twice
    try:
        mesh = trimesh.load(str(path), process=False, force="mesh")
    except Exception as e:  # noqa: BLE001 - any parser error is a failure
        row.check(False, f"trimesh cannot read: {e}")
        return None, None
    try:
        mm = meshio.read(str(path))
        mio_points = len(mm.points)
        mio_tris = sum(len(c.data) for c in mm.cells if c.type == "triangle")
        mio_other = sum(len(c.data) for c in mm.cells if c.type != "triangle")
        row.check(mio_other == 0, f"meshio: {mio_other} cells that are not triangles")
    except Exception as e:  # noqa: BLE001
        row.check(False, f"meshio cannot read: {e}")
        mio_points = mio_tris = None
    v = np.asarray(mesh.vertices)
    f = np.asarray(mesh.faces, dtype=np.int64).reshape(-1, 3)
    nv, nf = len(v), len(f)
    row.cols.update(V=nv, F=nf)

    # --- tmc's own report (not for STL: it cannot share vertices)
    if stl:
        rep = ref_check
        if ref is None or rep is None:
            row.check(False, "no .ply of the same extraction to compare the .stl with")
            return mesh, None
        row.check(nf == rep["triangles"], f"triangles {nf} != tmc check of the .ply {rep['triangles']}")
        if mio_tris is not None:
            row.check(mio_tris == rep["triangles"], f"meshio triangles {mio_tris} != {rep['triangles']}")
        tris = v[f]
        same = len(tris) == len(ref.faces) and np.array_equal(tris, np.asarray(ref.vertices)[ref.faces])
        row.check(same, "STL triangles differ from the .ply's (coordinates, order or winding)")
        row.cols["same"] = "yes" if same else "NO"
        if close:
            sv = signed_volume(tris)
            row.cols["vol"] = "+" if sv > 0 else "-"
            row.check(sv > 0, f"signed volume {sv:.6g} not positive with --close")
        row.check(bool(np.isfinite(v).all()), "non-finite coordinates")
        lo, hi = vol.extent(close)
        tol = 1e-5 * float(np.max(hi - lo)) + 1e-6
        inb = nf == 0 or bool((v.min(axis=0) >= lo - tol).all() and (v.max(axis=0) <= hi + tol).all())
        row.cols["bbox"] = "ok" if inb else "OUT"
        row.check(inb, "vertices outside the volume's extent")
        row.cols["zero"] = int((area_of(tris) == 0).sum())
        return mesh, None

    rep, err = tmc_json([tmc, "check", str(path), "--json"])
    if rep is None:
        row.check(False, f"tmc check: {err}")
        return mesh, None
    row.check(not err, f"tmc check failed: {err}")
    row.check(nv == rep["vertices"], f"vertices {nv} != tmc check {rep['vertices']}")
    row.check(nf == rep["triangles"], f"triangles {nf} != tmc check {rep['triangles']}")
    if mio_points is not None:
        row.check(mio_points == rep["vertices"], f"meshio vertices {mio_points} != {rep['vertices']}")
        row.check(mio_tris == rep["triangles"], f"meshio triangles {mio_tris} != {rep['triangles']}")

    # --- indices, coordinates
    bad_index = int(((f < 0) | (f >= nv)).any(axis=1).sum()) if nf else 0
    row.check(bad_index == 0, f"{bad_index} triangles with an index out of range")
    if bad_index:
        return mesh, rep
    degen = int(((f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 0] == f[:, 2])).sum())
    referenced = np.zeros(nv, dtype=bool)
    referenced[f.ravel()] = True
    unref = int(nv - referenced.sum())
    tris = v[f]
    zero = int((area_of(tris) == 0).sum())
    row.cols.update(degen=degen, unref=unref, zero=zero)
    row.check(degen == 0, f"{degen} triangles repeat a vertex")
    row.check(unref == 0, f"{unref} unreferenced vertices")
    row.check(bool(np.isfinite(v).all()), "non-finite coordinates")

    # --- topology: trimesh, and our own per-component figures
    euler = mesh.euler_number
    row.cols["euler"] = euler
    row.check(euler == rep["euler"], f"Euler characteristic {euler} (trimesh) != tmc check {rep['euler']}")
    ncomp, labels = components(f, nv)
    mine = per_component(f, nv, labels)
    theirs = sorted(
        (c["vertices"], c["edges"], c["triangles"], c["euler"], c["boundary_edges"]) for c in rep["per_component"]
    )
    row.cols["comp"] = len(mine)
    row.check(len(mine) == rep["components"], f"{len(mine)} components != tmc check {rep['components']}")
    row.check(mine == theirs, "per-component vertices/edges/triangles/Euler/boundary differ from tmc check")
    bnd = sum(c[4] for c in mine)
    row.cols["bnd"] = bnd
    row.check(bnd == rep["boundary_edges"], f"{bnd} boundary edges != tmc check {rep['boundary_edges']}")
    wt = bool(mesh.is_watertight)
    row.cols["wt"] = "yes" if wt else "no"
    row.check(wt == (rep["boundary_edges"] == 0), f"trimesh watertight={wt} but tmc check boundary edges {rep['boundary_edges']}")
    if close:
        row.check(wt, "not watertight with --close")
    wind = bool(mesh.is_winding_consistent)
    row.cols["wind"] = "yes" if wind else "NO"
    row.check(wind, "winding not consistent (trimesh)")

    # --- orientation
    if close:
        sv = signed_volume(tris)
        row.cols["vol"] = "+" if sv > 0 else "-"
        row.check(sv > 0, f"signed volume {sv:.6g} not positive with --close")
    if nf:
        frac, judged, cover = orientation_by_samples(vol, tris, labels[f[:, 0]], iso, inside_low, close, H_REL)
        row.cols["judged"] = f"{100 * cover:.0f}%"
        row.cols["orient"] = f"{frac:.3f}"
        row.check(frac > 0.5, f"a component's normals point the wrong way on {100 * (1 - frac):.1f}% of its area")

    # --- extent
    lo, hi = vol.extent(close)
    tol = 1e-5 * float(np.max(hi - lo)) + 1e-6
    inb = nf == 0 or bool((v.min(axis=0) >= lo - tol).all() and (v.max(axis=0) <= hi + tol).all())
    row.cols["bbox"] = "ok" if inb else "OUT"
    row.check(inb, f"vertices outside the volume's extent: {v.min(axis=0)}..{v.max(axis=0)} vs {lo}..{hi}")

    # --- other formats against the .ply of the same extraction
    if ref is not None:
        same_f = np.array_equal(f, np.asarray(ref.faces))
        rv = np.asarray(ref.vertices, dtype=np.float64)
        scale = max(float(np.abs(rv).max()) if len(rv) else 1.0, 1e-30)
        same_v = v.shape == rv.shape and float(np.abs(v - rv).max() if len(v) else 0.0) <= 1e-6 * scale
        row.cols["same"] = "yes" if same_f and same_v else "NO"
        row.check(same_f, "triangles differ from the .ply's")
        row.check(same_v, "vertices differ from the .ply's beyond text precision")
    return mesh, rep


# ----------------------------------------------------------------------------
# driver


COLUMNS = [
    ("case", 32),
    ("fmt", 4),
    ("V", 9),
    ("F", 9),
    ("comp", 5),
    ("euler", 6),
    ("bnd", 6),
    ("wt", 3),
    ("wind", 4),
    ("vol", 3),
    ("orient", 6),
    ("judged", 6),
    ("degen", 5),
    ("unref", 5),
    ("zero", 6),
    ("bbox", 4),
    ("same", 4),
    ("area_sk", 8),
    ("mc=lor", 6),
    ("result", 6),
]


def print_header() -> None:
    print(" ".join(f"{n:>{w}}" if i else f"{n:<{w}}" for i, (n, w) in enumerate(COLUMNS)))


def print_row(row: Row) -> None:
    vals = dict(row.cols, case=row.case, fmt=row.fmt, result="ok" if not row.fails else "FAIL")
    print(" ".join(f"{str(vals.get(n, '-')):>{w}}" if i else f"{str(vals.get(n, '-')):<{w}}" for i, (n, w) in enumerate(COLUMNS)))
    for msg in row.fails:
        print(f"    FAIL: {msg}")
    for msg in row.notes:
        print(f"    note: {msg}")
    sys.stdout.flush()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("data", nargs="?", default=None, help="folder of the real volumes (default ../shared/data)")
    ap.add_argument("--tmc", required=True, help="tmc binary")
    ap.add_argument("--repo", default=str(Path(__file__).resolve().parent.parent), help="repository root")
    ap.add_argument("--work", default=None, help="folder for the meshes (default: a temporary one, removed)")
    ap.add_argument("--only", default=None, help="only volumes whose file name contains this")
    ap.add_argument("--area-tol", type=float, default=0.01, help="relative area difference allowed vs scikit-image")
    ap.add_argument(
        "--skimage-max-samples",
        type=float,
        default=40e6,
        help="skip the scikit-image comparison for volumes with more samples (default 4e7: all of ../shared/data)",
    )
    args = ap.parse_args()
    repo = Path(args.repo)
    data = Path(args.data) if args.data else repo.parent / "shared" / "data"
    print(
        f"tmc {args.tmc}\ntrimesh {trimesh.__version__}, meshio {meshio.__version__}, scikit-image "
        f"{skimage.__version__}, pynrrd {nrrd.__version__}, scipy {scipy.__version__}, numpy {np.__version__}\n"
        f"data {data}"
    )
    cases = []
    if not data.is_dir():
        print(f"skipping the volumes of {data}: no such folder")
    else:
        for name, isos, opts, extra in CASES:
            p = data / name
            if not p.is_file():
                print(f"skipping {p}: missing")
                continue
            cases.append((p, name, isos, opts, extra))
    bp = repo / BUNDLED[0]
    if bp.is_file():
        cases.append((bp, "bundled:" + bp.name, *BUNDLED[1:]))
    else:
        print(f"skipping {bp}: missing")
    if args.only:
        cases = [c for c in cases if args.only in c[1]]

    work = Path(args.work) if args.work else Path(tempfile.mkdtemp(prefix="tmc-validate-"))
    work.mkdir(parents=True, exist_ok=True)
    rows: list[Row] = []
    area_diffs: list[tuple[float, str]] = []
    mc_counts: list[tuple[bool, str]] = []
    skipped_sk: list[str] = []
    t0 = time.time()
    print_header()
    try:
        for path, label, isos, opts, extra in cases:
            info, err = tmc_json([args.tmc, "info", str(path), "--json"])
            if info is None or err:
                r = Row(label, "-")
                r.check(False, f"tmc info: {err}")
                rows.append(r)
                print_row(r)
                continue
            vol = Volume(path, info)
            inside_low = "--inside" in opts and opts[opts.index("--inside") + 1] == "low"
            for iso in isos:
                for close in (False, True):
                    case = f"{label.removesuffix('.nrrd')}@{iso_text(iso)}" + (" close" if close else "")
                    if inside_low:
                        case += " low"
                    if close:
                        fmts = ["ply"] + [e.removesuffix("+close") for e in extra if e.endswith("+close")]
                    else:
                        fmts = ["ply"] + [e for e in extra if "+" not in e]
                    ref = ref_check = None
                    for fmt in fmts:
                        row = Row(case, fmt)
                        out = work / f"{label.replace(':', '_').removesuffix('.nrrd')}_{iso_text(iso)}{'_close' if close else ''}.{fmt}"
                        cmd = [args.tmc, "extract", str(path), "--iso", iso_text(iso), "-o", str(out), "--quiet", *opts]
                        if close:
                            cmd.append("--close")
                        p = run(cmd)
                        if not row.check(p.returncode == 0, f"{' '.join(cmd)}: exit {p.returncode}: {p.stderr.strip()}"):
                            rows.append(row)
                            print_row(row)
                            continue
                        mesh, rep = check_mesh(row, out, vol, float(iso), close, inside_low, args.tmc, ref, ref_check)
                        if fmt == "ply":
                            ref, ref_check = mesh, rep
                            if not close and mesh is not None:
                                samples = int(np.prod(info["dims"]))
                                if samples > args.skimage_max_samples:
                                    skipped_sk.append(case)
                                    row.notes.append(f"scikit-image comparison skipped: {samples} samples")
                                else:
                                    vol.load()
                                    verts, faces, _, _ = skimage.measure.marching_cubes(
                                        vol.data, level=float(iso), spacing=tuple(vol.spacing), method="lewiner"
                                    )
                                    a_sk = skimage.measure.mesh_surface_area(verts, faces)
                                    a_tmc = float(area_of(np.asarray(mesh.vertices)[mesh.faces]).sum())
                                    d = (a_tmc - a_sk) / a_sk
                                    area_diffs.append((d, case))
                                    row.cols["area_sk"] = f"{100 * d:+.3f}%"
                                    row.check(abs(d) <= args.area_tol, f"area {a_tmc:.6g} vs scikit-image {a_sk:.6g}: {100 * d:+.3f}%")
                                    # Not a check, a pointer for whoever reads a
                                    # difference: tmc's plain MC path against
                                    # scikit-image's classic (lorensen) MC.
                                    mc_out = out.with_name(out.stem + "_mc.ply")
                                    pm = run([*cmd[:cmd.index("-o")], "-o", str(mc_out), "--quiet", *opts, "--method", "mc"])
                                    if pm.returncode == 0:
                                        n_mc = len(trimesh.load(str(mc_out), process=False, force="mesh").faces)
                                        mc_out.unlink(missing_ok=True)
                                        _, f_lo, _, _ = skimage.measure.marching_cubes(
                                            vol.data, level=float(iso), spacing=tuple(vol.spacing), method="lorensen"
                                        )
                                        mc_counts.append((n_mc == len(f_lo), case))
                                        row.cols["mc=lor"] = "yes" if n_mc == len(f_lo) else f"{n_mc - len(f_lo):+d}"
                                    else:
                                        row.notes.append(f"tmc --method mc failed: {pm.stderr.strip()}")
                        rows.append(row)
                        print_row(row)
                        if not args.work:
                            out.unlink(missing_ok=True)
            vol.data = None
    finally:
        if not args.work:
            shutil.rmtree(work, ignore_errors=True)

    failed = [r for r in rows if r.fails]
    print()
    print(f"summary: {len(rows)} meshes checked, {len(rows) - len(failed)} passed, {len(failed)} failed ({time.time() - t0:.0f} s)")
    if area_diffs:
        d, c = max(area_diffs, key=lambda x: abs(x[0]))
        print(f"area vs scikit-image marching_cubes (lewiner), {len(area_diffs)} surfaces: max |difference| {100 * abs(d):.3f}% ({c})")
    if mc_counts:
        odd = [c for same, c in mc_counts if not same]
        print(
            f"tmc --method mc triangles equal scikit-image lorensen's on {len(mc_counts) - len(odd)} of "
            f"{len(mc_counts)} surfaces (information only)" + (f"; not on {', '.join(odd)}" if odd else "")
        )
    if skipped_sk:
        print(f"scikit-image comparison skipped (more than {args.skimage_max_samples:g} samples): {', '.join(skipped_sk)}")
    for r in failed:
        print(f"FAILED {r.case} {r.fmt}: {'; '.join(r.fails)}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
