#!/usr/bin/env python3
"""Makes docs/images/hole.png: a hole in scikit-image's marching cubes that
tmc does not make, on the bundled CT head.

Usage: scripts/make-hole-picture.py [TMC] [--out PNG]

TMC is the tmc binary (default target/release/tmc); PNG defaults to
docs/images/hole.png. Needs numpy, scikit-image and matplotlib from PyPI.

The case: data/headsq_quarter.nrrd (int16) at isovalue 1150, one of the two
isovalues of data/README.md. Integer data at an integer isovalue has samples
equal to the isovalue (ties). scikit-image's default marching cubes
(method='lewiner') can then take different decisions on a face shared by two
cells, and the two cells' triangles do not meet: the mesh has a hole.

The script, deterministically:

1. meshes the whole volume, padded with one layer of its minimum so that
   every surface is closed, with scikit-image (method='lewiner' and
   method='lorensen') and with `tmc extract --close` (the same closing), and
   counts each mesh's boundary edges (an edge used by exactly one triangle;
   on a closed surface every one of them is a hole);
2. takes the hole whose boundary vertex is first in (z, y, x) order, crops a
   neighbourhood of 6x6x6 samples around it (written as .npy and given to
   tmc as is, no padding), meshes the crop with both tools and counts the
   boundary edges that are not on the crop's border, i.e. holes;
3. draws the two meshes of the crop near the hole (the triangles within one
   cell of it) side by side, scikit-image's lewiner on the left and tmc on
   the right, the hole's edges in red and the cell face holding it dashed.

It prints the counts of steps 1 and 2. scikit-image's method='lorensen' has
no hole here, so it is counted but not drawn.

Coordinates: tmc's x is the fastest axis of the .npy (its last index);
scikit-image's vertices are in array index order (z, y, x). Both are in
sample units here (spacing 1, as the .npy has none).
"""
import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
ISO = 1150.0
HALF = 3  # the crop spans 2 * HALF samples along each axis


def read_nrrd(path):
    """A raw, attached-header NRRD (as data/headsq_quarter.nrrd) as an array
    of shape (nz, ny, nx)."""
    data = Path(path).read_bytes()
    end = data.index(b"\n\n") + 2
    fields = {}
    for line in data[:end].decode("ascii").splitlines()[1:]:
        if ":" in line and not line.startswith("#"):
            key, value = line.split(":", 1)
            fields[key.strip()] = value.strip().lstrip("=").strip()
    assert fields["encoding"] == "raw", fields["encoding"]
    dtype = {"short": "i2", "int16": "i2", "signed short": "i2"}[fields["type"]]
    order = "<" if fields.get("endian", "little") == "little" else ">"
    sizes = [int(s) for s in fields["sizes"].split()]
    samples = np.frombuffer(data[end:], dtype=order + dtype, count=int(np.prod(sizes)))
    return samples.reshape(sizes[::-1])


def boundary_edges(faces):
    """Edges (sorted vertex pairs) used by exactly one triangle."""
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    return unique[counts == 1]


def interior(vertices, edges, shape_xyz):
    """The edges not lying in one border plane of a grid of shape_xyz samples."""
    a, b = vertices[edges[:, 0]], vertices[edges[:, 1]]
    upper = np.asarray(shape_xyz, dtype=float) - 1
    on_border = np.zeros(len(edges), dtype=bool)
    for axis in range(3):
        for plane in (0.0, upper[axis]):
            on_border |= (a[:, axis] == plane) & (b[:, axis] == plane)
    return edges[~on_border]


def read_ply(path):
    """tmc's binary little-endian PLY: float x y z, uchar-uint face lists."""
    data = Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").split("\n")
    nv = int(next(l for l in header if l.startswith("element vertex")).split()[2])
    nf = int(next(l for l in header if l.startswith("element face")).split()[2])
    vertices = np.frombuffer(data, dtype="<f4", count=3 * nv, offset=end).reshape(nv, 3)
    rec = np.dtype([("n", "u1"), ("v", "<u4", 3)])
    faces = np.frombuffer(data, dtype=rec, count=nf, offset=end + 12 * nv)
    assert (faces["n"] == 3).all()
    return vertices.astype(float), faces["v"].astype(np.int64)


def tmc_mesh(tmc, volume_path, out_dir, name, *extra):
    out = Path(out_dir) / f"{name}.ply"
    subprocess.run([str(tmc), "extract", str(volume_path), "--iso", f"{ISO:g}", "-o", str(out),
                    "--quiet", *extra], check=True)
    return read_ply(out)


def skimage_mesh(volume, method):
    from skimage.measure import marching_cubes

    vertices, faces, _, _ = marching_cubes(volume.astype(np.float32), ISO, method=method)
    return vertices[:, ::-1].astype(float), faces.astype(np.int64)  # (z,y,x) -> (x,y,z)


def outward(volume, vertices, faces):
    """+1 if the triangles' normals (right-hand rule) point toward lower
    values (outside), -1 if toward higher values: the majority over the
    triangles, judged by the trilinear interpolant a third of a sample in
    front of each one."""
    tris = vertices[faces]
    normals = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    lengths = np.linalg.norm(normals, axis=1)
    good = lengths > 1e-9
    probe = tris[good].mean(axis=1) + normals[good] / lengths[good, None] / 3
    upper = np.array(volume.shape[::-1]) - 1
    probe = np.clip(probe, 0, upper)
    base = np.minimum(np.floor(probe).astype(int), upper - 1)
    t = probe - base
    values = np.zeros(len(probe))
    for corner in np.ndindex(2, 2, 2):  # (dx, dy, dz)
        weight = np.prod([np.where(corner[a], t[:, a], 1 - t[:, a]) for a in range(3)], axis=0)
        values += weight * volume[base[:, 2] + corner[2], base[:, 1] + corner[1], base[:, 0] + corner[0]]
    return 1 if np.mean(values < ISO) > 0.5 else -1


def draw(path, panels, box, face, offset, view=(12, -25)):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    elev, azim = np.radians(view)
    eye = np.array([np.cos(elev) * np.cos(azim), np.cos(elev) * np.sin(azim), np.sin(elev)])
    light = eye + np.array([0.3, 0.2, 0.5])
    light /= np.linalg.norm(light)
    fig = plt.figure(figsize=(9.6, 5.0), dpi=100)
    for i, (title, vertices, faces, sign, holes) in enumerate(panels):
        ax = fig.add_subplot(1, 2, i + 1, projection="3d", proj_type="ortho")
        ax.computed_zorder = False
        tris = vertices[faces]
        centroids = tris.mean(axis=1)
        keep = np.all([(centroids[:, a] >= box[a][0]) & (centroids[:, a] <= box[a][1]) for a in range(3)], axis=0)
        tris = tris[keep]
        normals = sign * np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
        lengths = np.linalg.norm(normals, axis=1, keepdims=True)
        normals = np.divide(normals, lengths, out=np.zeros_like(normals), where=lengths > 0)
        shade = 0.45 + 0.55 * np.abs(normals @ light)
        front = (normals @ eye) >= 0
        outside = np.array([0.45, 0.62, 0.88])  # the outer side: blue
        inside = np.array([0.95, 0.72, 0.35])  # the inner side, seen through a hole or from behind: orange
        colours = np.where(front[:, None], outside, inside) * shade[:, None]
        ax.add_collection3d(Poly3DCollection(tris, facecolors=np.column_stack([colours, np.ones(len(tris))]),
                                             edgecolors=(0.15, 0.15, 0.25, 0.4), linewidths=0.4, zorder=1))
        ax.add_collection3d(Line3DCollection([face[[0, 1]], face[[1, 2]], face[[2, 3]], face[[3, 0]]],
                                             colors="0.35", linewidths=1.2, linestyles="dashed", zorder=2))
        if len(holes):
            ax.add_collection3d(Line3DCollection(vertices[holes], colors="red", linewidths=2.5, zorder=3))
        ax.set_xlim(box[0]); ax.set_ylim(box[1]); ax.set_zlim(box[2])
        ax.set_box_aspect([hi - lo for lo, hi in box])
        ax.view_init(elev=view[0], azim=view[1])
        for axis, setter, labeller in ((0, ax.set_xticks, ax.set_xticklabels),
                                       (1, ax.set_yticks, ax.set_yticklabels),
                                       (2, ax.set_zticks, ax.set_zticklabels)):
            ticks = np.arange(box[axis][0], box[axis][1] + 1)
            setter(ticks)
            labeller([str(int(t + offset[axis])) for t in ticks])
        ax.set_xlabel("x"); ax.set_ylabel("y"); ax.set_zlabel("z")
        ax.tick_params(labelsize=7)
        ax.set_title(title, fontsize=10)
    fig.text(0.5, 0.02, "blue: outer side of the surface; orange: inner side; dashed: the cell face "
             "holding the hole; data/headsq_quarter.nrrd at 1150, axes in sample indices",
             ha="center", fontsize=8)
    fig.subplots_adjust(left=0.02, right=0.98, top=0.88, bottom=0.06, wspace=0.05)
    fig.savefig(path, dpi=100)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("tmc", nargs="?", default=str(REPO / "target/release/tmc"))
    parser.add_argument("--out", default=str(REPO / "docs/images/hole.png"))
    args = parser.parse_args()

    head = read_nrrd(REPO / "data/headsq_quarter.nrrd")  # (nz, ny, nx)
    with tempfile.TemporaryDirectory() as tmp:
        # 1. The whole volume, closed.
        padded = np.pad(head, 1, constant_values=head.min())
        counts = {}
        for method in ("lewiner", "lorensen"):
            v, f = skimage_mesh(padded, method)
            counts[method] = (len(f), boundary_edges(f))
            if method == "lewiner":
                lewiner_v = v - 1  # undo the padding
        v, f = tmc_mesh(args.tmc, REPO / "data/headsq_quarter.nrrd", tmp, "whole", "--close")
        counts["tmc"] = (len(f), boundary_edges(f))
        import skimage

        print(f"scikit-image {skimage.__version__}; data/headsq_quarter.nrrd at {ISO:g}, "
              f"closed (padded / --close):")
        for name, label in (("lewiner", "scikit-image method='lewiner' (default)"),
                            ("lorensen", "scikit-image method='lorensen'"), ("tmc", "tmc extract --close")):
            print(f"  {label:42} {counts[name][0]:7d} triangles, {len(counts[name][1]):4d} boundary edges")

        # 2. The neighbourhood of the first hole.
        edges = counts["lewiner"][1]
        if len(edges) == 0:
            sys.exit("no hole in scikit-image's lewiner mesh: nothing to draw")
        first = min(map(tuple, lewiner_v[edges.ravel()]), key=lambda p: (p[2], p[1], p[0]))
        corner = np.floor(np.asarray(first)).astype(int) - HALF + 1  # x, y, z of the crop's first sample
        corner = np.clip(corner, 0, np.array(head.shape[::-1]) - 2 * HALF)
        x0, y0, z0 = corner
        crop = np.ascontiguousarray(head[z0:z0 + 2 * HALF, y0:y0 + 2 * HALF, x0:x0 + 2 * HALF])
        crop_path = Path(tmp) / "crop.npy"
        np.save(crop_path, crop)
        shape_xyz = crop.shape[::-1]
        sk_v, sk_f = skimage_mesh(crop, "lewiner")
        sk_holes = interior(sk_v, boundary_edges(sk_f), shape_xyz)
        lo_v, lo_f = skimage_mesh(crop, "lorensen")
        lo_holes = interior(lo_v, boundary_edges(lo_f), shape_xyz)
        tm_v, tm_f = tmc_mesh(args.tmc, crop_path, tmp, "crop")
        tm_holes = interior(tm_v, boundary_edges(tm_f), shape_xyz)
        print(f"crop x {x0}..{x0 + 2 * HALF - 1}, y {y0}..{y0 + 2 * HALF - 1}, z {z0}..{z0 + 2 * HALF - 1} "
              f"(sample indices), boundary edges not on the crop's border:")
        print(f"  scikit-image method='lewiner' (default)    {len(sk_f):7d} triangles, {len(sk_holes):4d}")
        print(f"  scikit-image method='lorensen'             {len(lo_f):7d} triangles, {len(lo_holes):4d}")
        print(f"  tmc extract                                {len(tm_f):7d} triangles, {len(tm_holes):4d}")

        # 3. The picture.
        ends = sk_v[sk_holes.ravel()]
        # The cell face holding the hole: the axis along which its edges do not move.
        flat = int(np.argmin(np.ptp(ends, axis=0)))
        lo = np.floor(ends.min(axis=0))
        u, w = [a for a in range(3) if a != flat]
        face = np.array([lo, lo, lo, lo])
        face[:, flat] = ends[0, flat]
        face[1, u] += 1; face[2, u] += 1; face[2, w] += 1; face[3, w] += 1
        box = [(max(np.floor(ends[:, a].min()) - 1, 0), min(np.ceil(ends[:, a].max()) + 1, shape_xyz[a] - 1))
               for a in range(3)]
        panels = [
            (f"scikit-image marching_cubes (method='lewiner', the default)\n"
             f"{len(sk_holes)} boundary edges inside the crop (red)", sk_v, sk_f, outward(crop, sk_v, sk_f),
             sk_holes),
            (f"tmc extract (Grosso's TMC)\n{len(tm_holes)} boundary edges inside the crop",
             tm_v, tm_f, outward(crop, tm_v, tm_f), tm_holes),
        ]
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        draw(args.out, panels, box, face, corner)
        print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
