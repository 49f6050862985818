#!/usr/bin/env python3
"""Read a .tmesh file (tmc's chunked, compressed mesh) with numpy and zstandard.

A standalone reader of the format specified in tmc's src/meshfile/mod.rs
(it shares no code with tmc). Every checksum is verified; a damaged file
raises TmeshError naming what is damaged (the chunk, for a chunk).

As a module:

    from read_tmesh import read_tmesh
    vertices, triangles, info = read_tmesh("mesh.tmesh")
    # vertices: float32 (N, 3); triangles: uint64 (M, 3), global indices,
    # counter-clockwise seen from outside; info: dict (grid, iso, ...);
    # info["normals"]: float32 (N, 3) unit outward vertex normals when the
    # file has them (the normals attribute), else None;
    # info["labels"]: uint32 (M,) the label of each triangle when the file
    # holds several labels' surfaces (tmc extract --labels -o ONE.tmesh,
    # the labels attribute), else None

As a command:

    read_tmesh.py MESH.tmesh                 # print a summary
    read_tmesh.py MESH.tmesh --off OUT.off   # also write an ASCII OFF
    read_tmesh.py MESH.tmesh --ply OUT.ply   # also write an ASCII PLY (with
                                             # nx ny nz if the file has normals)

The command exits with status 1 and one line on stderr if the file cannot
be read (also when it does not fit in memory). Needs: python3 -m pip install numpy zstandard
"""

import argparse
import math
import struct
import sys
import zlib

import numpy as np
import zstandard

MAGIC = b"\x89TMESH\r\n"
END_MAGIC = b"TMESHEND"
VERSION = 1
# Version 2: header byte 99 holds attribute bits (bit 0: vertex normals,
# stored after the triangles in each chunk's payload; bit 1: a uint32 label
# per triangle, stored after the normals).
VERSION_ATTRIBUTES = 2
# Version 3 (what tmc writes now): version 2 with the positions, triangle
# indices and labels packed before compression (the normals as they are):
# positions as the first vertex's float32 bits, then each component XOR the
# same component of the vertex before; indices (one array of 3 x triangles)
# and labels as zig-zag coded wrapping differences from the number before
# (the first from 0); each packed array then as four byte planes, the lowest
# byte of every number first.
VERSION_PACKED = 3
ATTRIBUTE_NORMALS = 1
ATTRIBUTE_LABELS = 2
HEADER_BYTES = 128
CHUNK_HEADER_BYTES = 48
INDEX_ENTRY_BYTES = 32
TRAILER_BYTES = 32


class TmeshError(Exception):
    """The file is not a valid .tmesh file; the message says why and where."""


def _crc(data):
    return zlib.crc32(data) & 0xFFFFFFFF


def _read_at(f, offset, size, what):
    f.seek(offset)
    data = f.read(size)
    if len(data) != size:
        raise TmeshError(f"{what}: the file ends early")
    return data


def _number(v):
    """A float as tmc's messages print it (NaN, inf, 1, 0.5)."""
    if math.isnan(v):
        return "NaN"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return str(int(v)) if v == int(v) and abs(v) < 1e16 else repr(v)


def _header(h):
    """Decodes the 128-byte file header into the info dict."""
    if h[0:8] != MAGIC:
        raise TmeshError("not a .tmesh file (wrong magic bytes)")
    version, size = struct.unpack_from("<II", h, 8)
    if version not in (VERSION, VERSION_ATTRIBUTES, VERSION_PACKED):
        raise TmeshError(
            f".tmesh version {version} is not supported "
            f"(this reads {VERSION} to {VERSION_PACKED})"
        )
    if struct.unpack_from("<I", h, 124)[0] != _crc(h[:124]):
        raise TmeshError("header checksum mismatch")
    if size != HEADER_BYTES:
        raise TmeshError(f"not a valid .tmesh file: header size {size} is not {HEADER_BYTES}")
    # Fields no checksum vouches for (a writer could get them wrong), as
    # decode_header in src/meshfile/mod.rs refuses them.
    dims = list(struct.unpack_from("<3Q", h, 16))
    if 0 in dims:
        raise TmeshError("not a valid .tmesh file: a grid dimension is 0")
    spacing = list(struct.unpack_from("<3d", h, 40))
    if not all(math.isfinite(v) and v > 0 for v in spacing):
        raise TmeshError(
            "not a valid .tmesh file: the spacing {} {} {} is not finite and positive".format(
                *map(_number, spacing)
            )
        )
    origin = list(struct.unpack_from("<3d", h, 64))
    if not all(math.isfinite(v) for v in origin):
        raise TmeshError(
            "not a valid .tmesh file: the origin {} {} {} is not finite".format(*map(_number, origin))
        )
    iso = struct.unpack_from("<d", h, 88)[0]
    if not math.isfinite(iso):
        raise TmeshError(f"not a valid .tmesh file: the isovalue {iso} is not a finite number")
    for at, field in enumerate(("method", "inside", "close"), start=96):
        if h[at] > 1:
            raise TmeshError(f"not a valid .tmesh file: unknown {field} byte {h[at]}")
    attributes = h[99]
    if version == VERSION and any(h[99:124]):
        raise TmeshError("not a valid .tmesh file: reserved header bytes 99..124 are not zero")
    if attributes & ~(ATTRIBUTE_NORMALS | ATTRIBUTE_LABELS):
        raise TmeshError(f"not a valid .tmesh file: unknown attribute bits {attributes:#04x}")
    if any(h[100:124]):
        raise TmeshError("not a valid .tmesh file: reserved header bytes 100..124 are not zero")
    return {
        "dims": dims,
        "spacing": spacing,
        "origin": origin,
        "iso": iso,
        "method": "mc" if h[96] == 1 else "tmc",
        "inside": "low" if h[97] == 1 else "high",
        "close": h[98] == 1,
        "has_normals": bool(attributes & ATTRIBUTE_NORMALS),
        "has_labels": bool(attributes & ATTRIBUTE_LABELS),
        "packed": version == VERSION_PACKED,
    }


def _words(raw, offset, n):
    """The n uint32 words whose four byte planes start at raw[offset]."""
    planes = np.frombuffer(raw, dtype=np.uint8, offset=offset, count=4 * n).reshape(4, n)
    return np.ascontiguousarray(planes.T).view("<u4").reshape(n)


def _unpack_triples(raw, offset, n):
    """n float32 triples packed (version 3) at raw[offset]."""
    deltas = _words(raw, offset, 3 * n).reshape(n, 3)
    return np.bitwise_xor.accumulate(deltas, axis=0).view("<f4")


def _unpack_numbers(raw, offset, n):
    """n uint32 numbers packed (version 3) at raw[offset]."""
    z = _words(raw, offset, n).astype(np.uint32)
    steps = (z >> np.uint32(1)) ^ (np.uint32(0) - (z & np.uint32(1)))
    return np.cumsum(steps, dtype=np.uint32)


def _plane_bounds(info):
    """The most vertices and triangles one chunk (a grid plane) can hold.

    As tmc's reader computes them (plane_bounds in src/meshfile/reader.rs):
    11 vertices (3 edges, 8 interior) and 32 triangles per sample of the
    plane, padded by 2 along x and y with close; 8 times that with labels
    (at most 8 labels meet in a cell).
    """
    pad = 2 if info["close"] else 0
    samples = (info["dims"][0] + pad) * (info["dims"][1] + pad)
    if info["has_labels"]:
        samples *= 8
    return 11 * samples, 32 * samples


def _check_entries(entries, info):
    """Refuses, before any chunk is inflated, a chunk claiming more than one
    plane of the grid can have, on a plane beyond the grid or out of plane
    order (so the counts a file can claim are bounded by its grid)."""
    most_v, most_t = _plane_bounds(info)
    # Counts are u32, planes u64: a bound beyond their range admits any.
    most = [np.uint64(min(m, (1 << 32) - 1)) for m in (most_v, most_t)]
    over = np.flatnonzero((entries["nv"] > most[0]) | (entries["nt"] > most[1]))
    if len(over):
        i = int(over[0])
        raise TmeshError(
            f"chunk {i} claims {int(entries[i]['nv'])} vertices and "
            f"{int(entries[i]['nt'])} triangles, more than one plane of the grid "
            f"can have ({most_v} and {most_t})"
        )
    planes = info["dims"][2] + (2 if info["close"] else 0)
    plane = entries["plane"]
    beyond = np.flatnonzero(plane >= np.uint64(planes)) if planes < 1 << 64 else []
    if len(beyond):
        i = int(beyond[0])
        raise TmeshError(
            f"chunk {i} is on plane {int(plane[i])}, beyond the grid's {planes} planes"
        )
    back = np.flatnonzero(plane[1:] <= plane[:-1])
    if len(back):
        i = int(back[0]) + 1
        raise TmeshError(
            f"chunk {i} is on plane {int(plane[i])}, not after the previous "
            f"chunk's plane {int(plane[i - 1])}"
        )


def _index(f, length, info):
    """Reads the trailer and the chunk index; returns (totals, entries,
    index offset)."""
    trailer = _read_at(f, length - TRAILER_BYTES, TRAILER_BYTES, "trailer")
    if trailer[24:32] != END_MAGIC:
        raise TmeshError("truncated: the end marker is missing (the writer did not finish)")
    index_offset, vertices, triangles = struct.unpack_from("<3Q", trailer, 0)
    if not HEADER_BYTES <= index_offset <= length - TRAILER_BYTES - 16:
        raise TmeshError(f"index offset {index_offset} is outside the file")
    head = _read_at(f, index_offset, 16, "chunk index")
    crc, count = struct.unpack_from("<IQ", head, 4)
    room = length - TRAILER_BYTES - index_offset - 16
    if head[0:4] != b"INDX" or count * INDEX_ENTRY_BYTES != room:
        raise TmeshError("the chunk index is damaged")
    raw = _read_at(f, index_offset + 16, room, "chunk index")
    if _crc(raw) != crc:
        raise TmeshError("the chunk index checksum does not match")
    entries = np.frombuffer(
        raw,
        dtype=np.dtype(
            [("offset", "<u8"), ("base", "<u8"), ("nv", "<u4"), ("nt", "<u4"), ("plane", "<u8")]
        ),
    )
    _check_entries(entries, info)
    bases = np.concatenate((np.zeros(1, np.uint64), np.cumsum(entries["nv"], dtype=np.uint64)))
    if (
        not np.array_equal(entries["base"], bases[:-1])
        or (entries["offset"] >= index_offset).any()
        or int(bases[-1]) != vertices
        or int(entries["nt"].sum(dtype=np.uint64)) != triangles
    ):
        raise TmeshError("the index does not add up to the totals")
    return (vertices, triangles), entries, index_offset


def _chunk(f, i, e, next_nv, limit, decompressor, has_normals, has_labels, packed):
    """Reads chunk i, whose payload must end by byte limit (where the next
    chunk or the index starts); returns (vertices float32 (n, 3), relative
    triangles uint32 (m, 3), normals float32 (n, 3) or None, labels uint32
    (m,) or None)."""
    name = f"chunk {i} (plane {int(e['plane'])}, byte {int(e['offset'])})"
    h = _read_at(f, int(e["offset"]), CHUNK_HEADER_BYTES, name)
    if h[0:4] != b"CHNK" or struct.unpack_from("<I", h, 40)[0] != _crc(h[:40]):
        raise TmeshError(f"{name}: chunk header damaged")
    if any(h[44:48]):
        raise TmeshError(f"{name}: chunk header bytes 44..48 are not zero")
    crc, plane, base, nv, nt, size = struct.unpack_from("<IQQIIQ", h, 4)
    if (plane, base, nv, nt) != (int(e["plane"]), int(e["base"]), int(e["nv"]), int(e["nt"])):
        raise TmeshError(f"{name}: chunk header disagrees with the index")
    # Before anything of that size is read (Python allocates what is asked).
    if int(e["offset"]) + CHUNK_HEADER_BYTES + size > limit:
        raise TmeshError(
            f"{name}: payload of {size} bytes runs past the chunk's room (byte {limit})"
        )
    payload = _read_at(f, int(e["offset"]) + CHUNK_HEADER_BYTES, size, name)
    if _crc(payload) != crc:
        raise TmeshError(f"{name}: payload checksum mismatch (the data is damaged)")
    expect = 12 * (nv + nt + (nv if has_normals else 0)) + (4 * nt if has_labels else 0)
    # The frame must state exactly that size before it is inflated: when a
    # frame states its size, zstandard allocates that much and ignores
    # max_output_size (which bounds frames that do not).
    try:
        stated = zstandard.frame_content_size(payload)
        if stated != expect:
            raise TmeshError(f"{name}: payload frame size disagrees with the counts")
        raw = decompressor.decompress(payload, max_output_size=expect)
    except zstandard.ZstdError as err:
        raise TmeshError(f"{name}: {err}") from None
    if len(raw) != expect:
        raise TmeshError(f"{name}: payload has the wrong size")
    at = 12 * (nv + nt)
    if packed:
        vertices = _unpack_triples(raw, 0, nv)
        triangles = _unpack_numbers(raw, 12 * nv, 3 * nt).reshape(nt, 3)
    else:
        vertices = np.frombuffer(raw, dtype="<f4", count=3 * nv).reshape(nv, 3)
        triangles = np.frombuffer(raw, dtype="<u4", offset=12 * nv, count=3 * nt).reshape(nt, 3)
    normals = None
    if has_normals:
        normals = np.frombuffer(raw, dtype="<f4", offset=at, count=3 * nv).reshape(nv, 3)
        at += 12 * nv
    labels = None
    if has_labels:
        if packed:
            labels = _unpack_numbers(raw, at, nt)
        else:
            labels = np.frombuffer(raw, dtype="<u4", offset=at, count=nt)
    bad = np.flatnonzero(~np.isfinite(vertices).all(axis=1))
    if len(bad):
        raise TmeshError(
            f"{name}: vertex {int(bad[0])} has a coordinate that is not a finite number"
        )
    if nt and int(triangles.max()) >= nv + next_nv:
        raise TmeshError(f"{name}: a triangle points beyond the next chunk")
    if has_normals:
        bad = np.flatnonzero(~np.isfinite(normals).all(axis=1))
        if len(bad):
            raise TmeshError(
                f"{name}: the normal of vertex {int(bad[0])} has a component "
                "that is not a finite number"
            )
    return vertices, triangles, normals, labels


def read_tmesh(path):
    """Reads a .tmesh file.

    Returns (vertices, triangles, info): vertices float32 of shape (N, 3),
    triangles uint64 of shape (M, 3) with global vertex indices, and a dict
    with the grid (dims, spacing, origin), iso, method, inside, close, the
    counts (vertices, triangles, chunks) and normals: float32 (N, 3) unit
    outward vertex normals when the file has them, else None, and labels:
    uint32 (M,) the label of each triangle when the file has them, else
    None. Raises TmeshError on a damaged or
    truncated file.
    """
    with open(path, "rb") as f:
        f.seek(0, 2)
        length = f.tell()
        if length < HEADER_BYTES + TRAILER_BYTES:
            raise TmeshError(f"{length} bytes is too short for a .tmesh file")
        info = _header(_read_at(f, 0, HEADER_BYTES, "header"))
        (nv, nt), entries, index_offset = _index(f, length, info)
        vertices = np.empty((nv, 3), dtype=np.float32)
        triangles = np.empty((nt, 3), dtype=np.uint64)
        has_normals = info.pop("has_normals")
        normals = np.empty((nv, 3), dtype=np.float32) if has_normals else None
        has_labels = info.pop("has_labels")
        packed = info.pop("packed")
        labels = np.empty(nt, dtype=np.uint32) if has_labels else None
        decompressor = zstandard.ZstdDecompressor()
        t = 0
        for i, e in enumerate(entries):
            last = i + 1 == len(entries)
            next_nv = 0 if last else int(entries[i + 1]["nv"])
            limit = index_offset if last else int(entries[i + 1]["offset"])
            v, tri, n, lab = _chunk(
                f, i, e, next_nv, limit, decompressor, has_normals, has_labels, packed
            )
            base = int(e["base"])
            vertices[base : base + len(v)] = v
            if n is not None:
                normals[base : base + len(v)] = n
            triangles[t : t + len(tri)] = tri.astype(np.uint64) + np.uint64(base)
            if lab is not None:
                labels[t : t + len(tri)] = lab
            t += len(tri)
    info.update(vertices=nv, triangles=nt, chunks=len(entries), normals=normals, labels=labels)
    return vertices, triangles, info


def write_off(path, vertices, triangles):
    """Writes an ASCII OFF file (9 significant digits: float32 round-trips)."""
    with open(path, "w") as out:
        out.write(f"OFF\n{len(vertices)} {len(triangles)} 0\n")
        np.savetxt(out, vertices, fmt="%.9g")
        np.savetxt(out, triangles, fmt="3 %d %d %d")


def write_ply(path, vertices, triangles, normals=None):
    """Writes an ASCII PLY file (9 significant digits: float32 round-trips),
    with nx ny nz when normals are given."""
    with open(path, "w") as out:
        out.write(
            "ply\nformat ascii 1.0\ncomment written by read_tmesh.py\n"
            f"element vertex {len(vertices)}\n"
            "property float x\nproperty float y\nproperty float z\n"
            + ("property float nx\nproperty float ny\nproperty float nz\n" if normals is not None else "")
            + f"element face {len(triangles)}\n"
            "property list uchar uint vertex_indices\nend_header\n"
        )
        rows = vertices if normals is None else np.hstack((vertices, normals))
        np.savetxt(out, rows, fmt="%.9g")
        np.savetxt(out, triangles, fmt="3 %d %d %d")


def main(argv=None):
    parser = argparse.ArgumentParser(description="Read a .tmesh file, print a summary.")
    parser.add_argument("mesh", help="the .tmesh file")
    parser.add_argument("--off", metavar="OUT", help="also write an ASCII OFF file")
    parser.add_argument("--ply", metavar="OUT", help="also write an ASCII PLY file")
    args = parser.parse_args(argv)
    try:
        vertices, triangles, info = read_tmesh(args.mesh)
        if args.off:
            write_off(args.off, vertices, triangles)
        if args.ply:
            write_ply(args.ply, vertices, triangles, info["normals"])
    except (TmeshError, OSError) as err:
        print(f"read_tmesh: {args.mesh}: {err}", file=sys.stderr)
        return 1
    except MemoryError as err:
        # numpy says how much it could not allocate; Python may say nothing.
        what = f": {err}" if str(err) else ""
        print(f"read_tmesh: {args.mesh}: out of memory{what}", file=sys.stderr)
        return 1
    dims = "x".join(str(d) for d in info["dims"])
    print(
        f"{args.mesh}: {info['vertices']} vertices, {info['triangles']} triangles, "
        f"{info['chunks']} chunks; grid {dims}, spacing {info['spacing']}, "
        f"origin {info['origin']}; iso {info['iso']}, method {info['method']}, "
        f"inside {info['inside']}, close {info['close']}, "
        f"normals {info['normals'] is not None}, "
        f"labels {'none' if info['labels'] is None else len(np.unique(info['labels']))}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
