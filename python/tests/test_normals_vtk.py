"""Vertex normals against VTK: `tmc.extract(..., normals=True)` (the normals
the slab loop computes, the same the CLI's --normals writes) against
vtkFlyingEdges3D with ComputeNormals on the same volume, and the CLI's
PLY and OBJ files with normals read back by VTK's own readers."""

from __future__ import annotations

import numpy as np
import pytest

import tmc
from conftest import run_cli

vtk = pytest.importorskip("vtk", reason="VTK (pip install vtk) is needed for these tests")
from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402

cKDTree = pytest.importorskip("scipy.spatial").cKDTree


def gyroid(shape, spacing):
    """A gyroid sampled on a grid indexed [z][y][x] with `spacing` (x, y, z)."""
    z, y, x = np.meshgrid(*(np.arange(n) * s for n, s in zip(shape, spacing[::-1])), indexing="ij")
    k = 0.3
    return (
        np.sin(k * x) * np.cos(k * y) + np.sin(k * y) * np.cos(k * z) + np.sin(k * z) * np.cos(k * x)
    ).astype(np.float32)


def flying_edges(volume, level, spacing):
    """VTK's Flying Edges with its gradient normals: points (N, 3) and
    normals (N, 3), in world coordinates (x, y, z)."""
    nz, ny, nx = volume.shape
    image = vtk.vtkImageData()
    image.SetDimensions(nx, ny, nz)
    image.SetSpacing(*spacing)
    image.SetOrigin(0.0, 0.0, 0.0)
    # VTK's point order is x fastest: the C order of a [z][y][x] array.
    image.GetPointData().SetScalars(numpy_to_vtk(volume.ravel(), deep=True))
    fe = vtk.vtkFlyingEdges3D()
    fe.SetInputData(image)
    fe.SetValue(0, level)
    fe.ComputeNormalsOn()
    fe.ComputeGradientsOff()
    fe.ComputeScalarsOff()
    fe.Update()
    out = fe.GetOutput()
    points = vtk_to_numpy(out.GetPoints().GetData())
    normals = vtk_to_numpy(out.GetPointData().GetNormals())
    return points, normals


def angles_deg(a, b):
    cos = np.einsum("ij,ij->i", a, b) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


@pytest.mark.parametrize("spacing", [(1.0, 1.0, 1.0), (0.7, 1.3, 2.0)])
def test_normals_agree_with_vtk_flying_edges(spacing):
    volume = gyroid((48, 52, 56), spacing)
    level = 0.2
    mesh = tmc.extract(volume, level, spacing=spacing, normals=True)
    assert mesh.normals is not None and mesh.normals.shape == mesh.vertices.shape
    assert np.allclose(np.linalg.norm(mesh.normals, axis=1), 1.0, atol=1e-5)
    points, normals = flying_edges(volume, level, spacing)
    # Both put vertices on the same edges at the same linear crossing: pair
    # them by position.
    distance, nearest = cKDTree(points).query(mesh.vertices)
    assert np.percentile(distance, 99) < 1e-4 * max(spacing), np.percentile(distance, 99)
    ours, theirs = mesh.normals, normals[nearest]
    # Same line; VTK's sign convention is its own: take it from the median.
    sign = np.sign(np.median(np.einsum("ij,ij->i", ours, theirs)))
    assert sign != 0
    angle = angles_deg(ours, sign * theirs)
    p99 = np.percentile(angle, 99)
    print(f"spacing {spacing}: {len(angle)} vertices, p99 {p99:.4f} deg, max {angle.max():.4f}")
    # The same definition (central differences, linear along the edge, in
    # world coordinates); f32 and rounding differ.
    assert p99 < 0.1, p99
    # tmc's point outward: toward lower values (the inside is above the
    # level), so the field decreases along them.
    step = 0.25 * min(spacing)
    world = mesh.vertices + step * mesh.normals
    index = np.rint(world / np.array(spacing)).astype(int)[:, ::-1]
    inside = (index >= 0).all(axis=1) & (index < np.array(volume.shape)).all(axis=1)
    below = volume[tuple(index[inside].T)] < level + 0.5
    assert below.mean() > 0.95


def read_with_vtk(reader_class, path):
    reader = reader_class()
    reader.SetFileName(str(path))
    reader.Update()
    out = reader.GetOutput()
    points = vtk_to_numpy(out.GetPoints().GetData())
    normals = out.GetPointData().GetNormals()
    return points, None if normals is None else vtk_to_numpy(normals)


def test_cli_ply_and_obj_normals_read_by_vtk(tmp_path):
    volume = gyroid((30, 34, 38), (1.0, 1.0, 1.0))
    npy = tmp_path / "g.npy"
    np.save(npy, volume)
    mesh = tmc.extract(npy, 0.2, normals=True)
    for suffix, reader in [(".ply", vtk.vtkPLYReader), (".obj", vtk.vtkOBJReader)]:
        out = tmp_path / f"g{suffix}"
        run_cli("extract", str(npy), "--iso", "0.2", "--normals", "-o", str(out), "-q")
        points, normals = read_with_vtk(reader, out)
        assert normals is not None, suffix
        # The same vertices in the same order, and the normals of
        # tmc.extract: to the bit from the binary PLY; from the OBJ's text as
        # VTK's parser rounds it (tmc writes the shortest text that reads
        # back to the same float32).
        expected = mesh.vertices.astype(np.float32)
        if suffix == ".ply":
            np.testing.assert_array_equal(points, expected)
            np.testing.assert_array_equal(normals, mesh.normals)
        else:
            np.testing.assert_allclose(points, expected, rtol=1e-6, atol=1e-6)
            np.testing.assert_allclose(normals, mesh.normals, rtol=1e-6, atol=1e-6)
    # Mesh.write writes the normals as the CLI does: the same bytes.
    for suffix in [".ply", ".obj", ".tmesh"]:
        cli = tmp_path / f"cli{suffix}"
        run_cli("extract", str(npy), "--iso", "0.2", "--normals", "-o", str(cli), "-q")
        written = tmp_path / f"written{suffix}"
        mesh.write(written)
        assert written.read_bytes() == cli.read_bytes(), suffix
