"""Volume meshes and complexes from Python, and their meshio objects: `run(..., volume=True)`
returns the volume mesh that `run --volume` writes, node for node; `labels=` and a mesh of
several parts give one complex with its label pairs; `to_meshio` gives a meshio.Mesh whose
files (meshio's own writers, binary or ASCII) `mpumesh quality` and `mpumesh tetmesh` read
back with the same tetrahedra, regions and volume.

Run by ctest (tests/CMakeLists.txt) with PYTHONPATH at the built module and MPUMESH_BIN at
the built program."""
import json
import os
import subprocess

import meshio
import nibabel
import numpy as np
import pytest

import mpumesh

BIN = os.environ["MPUMESH_BIN"]
SPACING = (0.6, 0.6, 1.2)


def grid(shape=(16, 30, 30)):
    """Voxel centres in mm, arrays in (z, y, x) order."""
    z, y, x = np.meshgrid(*(np.arange(n, dtype=float) for n in shape), indexing="ij")
    return x * SPACING[0], y * SPACING[1], z * SPACING[2]


def ball_volume():
    x, y, z = grid()
    return np.where((x - 9) ** 2 + (y - 9) ** 2 + (z - 9) ** 2 < 36, 1000.0, 0.0).astype(np.float32)


def split_ball_labels():
    """A ball of radius 6 mm cut by the plane x + 0.3 z = 11 into labels 1 and 2."""
    x, y, z = grid()
    inside = (x - 9) ** 2 + (y - 9) ** 2 + (z - 9) ** 2 < 36
    return np.where(inside, np.where(x + 0.3 * z < 11, 1, 2), 0).astype(np.int16)


def signed_volumes(points, tets):
    p = points[tets]
    return np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6


def enclosed_volume(points, faces):
    p = points[faces]
    return np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6


@pytest.fixture(scope="module")
def ball_run():
    return mpumesh.run(ball_volume(), spacing=SPACING, threshold=500, particles=1500, backend="cpu", volume=True)


@pytest.fixture(scope="module")
def complex_run():
    return mpumesh.run(split_ball_labels(), spacing=SPACING, labels="all", particles=1500, backend="cpu",
                       volume=True)


def test_volume_true_returns_the_tetrahedra_of_the_surface(ball_run):
    r = ball_run
    pts, tets, region = r["points"], r["tetrahedra"], r["region"]
    assert pts.shape[1] == 3 and pts.dtype == np.float64
    assert tets.shape[1] == 4 and tets.dtype == np.int64 and len(tets) > 1000
    assert region.shape == (len(tets),) and set(region.tolist()) == {1}
    assert (signed_volumes(pts, tets) > 0).all()
    # The surface's vertices are the first nodes; the boundary is the surface.
    n = len(r["vertices"])
    assert np.array_equal(pts[:n], r["vertices"])
    assert sorted(map(tuple, np.sort(r["boundary"], axis=1).tolist())) == \
        sorted(map(tuple, np.sort(r["faces"], axis=1).tolist()))
    tet_volume = signed_volumes(pts, tets).sum()
    assert abs(tet_volume / enclosed_volume(r["vertices"], r["faces"]) - 1) < 1e-9
    assert r["report"]["volume_mesh"]["tetrahedra"] == len(tets)


def test_the_volume_mesh_is_the_one_run_volume_writes(tmp_path):
    img = tmp_path / "ball.nii.gz"
    nibabel.save(nibabel.Nifti1Image(np.transpose(ball_volume(), (2, 1, 0)), np.diag([*SPACING, 1.0])), str(img))
    out = tmp_path / "ball.vtu"
    subprocess.run([BIN, "run", str(img), "--threshold", "500", "--particles", "1500", "--backend", "cpu", "-o",
                    str(tmp_path / "ball.ply"), "--volume", str(out), "--quiet"], check=True)
    array, spacing, origin, direction = mpumesh.read_volume(str(img))
    r = mpumesh.run(array, spacing=spacing, origin=origin, direction=direction, threshold=500, particles=1500,
                    backend="cpu", volume=True)
    m = meshio.read(str(out))
    assert np.array_equal(m.points, r["points"])
    assert np.array_equal(m.cells_dict["tetra"], r["tetrahedra"])


def test_labels_give_one_complex_with_its_label_pairs_and_regions(complex_run):
    r = complex_run
    fl = r["face_labels"]
    assert fl.shape == (len(r["faces"]), 2) and (fl[:, 0] < fl[:, 1]).all()
    assert {tuple(p) for p in fl.tolist()} == {(0, 1), (0, 2), (1, 2)}
    assert set(r["region"].tolist()) == {1, 2}
    assert r["boundary_labels"].shape == (len(r["boundary"]), 2)
    assert [label["label"] for label in r["report"]["complex"]["labels"]] == [1, 2]
    # Conformity: each interface triangle (1, 2) is a face of one tetrahedron of each label.
    faces = {}
    for t, tet in enumerate(r["tetrahedra"].tolist()):
        for k in range(4):
            faces.setdefault(tuple(sorted(tet[:k] + tet[k + 1:])), []).append(int(r["region"][t]))
    shared = [tuple(sorted(f)) for f, ab in zip(r["boundary"].tolist(), r["boundary_labels"].tolist())
              if tuple(ab) == (1, 2)]
    assert shared and all(sorted(faces[f]) == [1, 2] for f in shared)


def test_a_mesh_of_two_parts_is_remeshed_as_a_complex_of_two():
    x, y, z = grid((16, 30, 40))
    two = np.where(((x - 7) ** 2 + (y - 9) ** 2 + (z - 9) ** 2 < 16) |
                   ((x - 17) ** 2 + (y - 9) ** 2 + (z - 9) ** 2 < 12), 1000.0, 0.0).astype(np.float32)
    surface = mpumesh.run(two, spacing=SPACING, threshold=500, particles=2000, backend="cpu")
    r = mpumesh.remesh(surface["vertices"], surface["faces"], particles=2000, backend="cpu")
    assert {tuple(p) for p in r["face_labels"].tolist()} == {(0, 1), (0, 2)}
    assert r["report"]["complex"]["crossing_pairs"] == 0


def quality(path):
    out = subprocess.run([BIN, "quality", str(path), "--json"], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


@pytest.mark.parametrize("options", [{}, {"binary": False}, {"compression": None}, {"header_type": "UInt64"}])
def test_to_meshio_files_read_back_with_the_same_tetrahedra(ball_run, tmp_path, options):
    m = mpumesh.to_meshio(ball_run)
    assert isinstance(m, meshio.Mesh)
    assert len(m.cells_dict["tetra"]) == len(ball_run["tetrahedra"])
    assert set(m.point_data) == {"normals", "k1", "k2", "K", "H"}
    n = len(ball_run["vertices"])
    assert np.array_equal(m.point_data["normals"][:n], ball_run["normals"])
    assert np.isnan(m.point_data["K"][n:]).all()
    path = tmp_path / "ball.vtu"
    meshio.write(str(path), m, **options)
    q = quality(path)
    assert q["tetrahedra"] == len(ball_run["tetrahedra"]) and q["nodes"] == len(ball_run["points"])
    assert abs(q["volume_mm3"] / signed_volumes(ball_run["points"], ball_run["tetrahedra"]).sum() - 1) < 1e-9


def test_to_meshio_of_a_complex_keeps_its_labels(complex_run, tmp_path):
    m = mpumesh.to_meshio(complex_run)
    assert set(m.cell_data) == {"region", "label_a", "label_b"}
    tri = [i for i, c in enumerate(m.cells) if c.type == "triangle"][0]
    assert np.array_equal(m.cell_data["label_a"][tri], complex_run["boundary_labels"][:, 0])
    path = tmp_path / "complex.vtu"
    meshio.write(str(path), m)
    q = quality(path)
    assert q["regions"] == 2 and q["tetrahedra"] == len(complex_run["tetrahedra"])
    # The surface alone: meshio's cells and the label pairs per face.
    surface = {k: v for k, v in complex_run.items() if k in ("vertices", "faces", "face_labels")}
    s = mpumesh.to_meshio(surface)
    assert [c.type for c in s.cells] == ["triangle"]
    assert np.array_equal(s.cell_data["label_b"][0], complex_run["face_labels"][:, 1])


def test_a_surface_written_by_meshio_is_filled_by_tetmesh(tmp_path):
    r = mpumesh.run(ball_volume(), spacing=SPACING, threshold=500, particles=1500, backend="cpu")
    m = mpumesh.to_meshio(r)
    assert [c.type for c in m.cells] == ["triangle"]
    surface = tmp_path / "ball.ply"
    meshio.write(str(surface), m)
    subprocess.run([BIN, "tetmesh", str(surface), "-o", str(tmp_path / "ball.msh"), "--quiet"], check=True)
    assert quality(tmp_path / "ball.msh")["tetrahedra"] > 1000


def test_a_damaged_binary_file_is_refused_naming_it(ball_run, tmp_path):
    path = tmp_path / "cut.vtu"
    meshio.write(str(path), mpumesh.to_meshio(ball_run))
    text = path.read_text()
    at = text.index('Name="connectivity"')
    start = text.index(">", at) + 1
    path.write_text(text[:start + 40] + text[start + 400:])  # the compressed blocks cut
    out = subprocess.run([BIN, "quality", str(path)], capture_output=True, text=True)
    assert out.returncode != 0
    assert out.stderr.count("\n") == 1 and str(path) in out.stderr, out.stderr


@pytest.mark.parametrize("bad, words", [
    ({"vertices": np.zeros((3, 3))}, "no 'faces'"),
    ({"vertices": np.zeros((3, 3)), "faces": [[0, 1, 2]], "normals": np.zeros((9, 3))}, "one value or row per vertex"),
    ({"vertices": np.zeros((3, 3)), "faces": [[0, 1, 2]], "face_labels": [1, 2]}, "'face_labels' must be n x 2"),
    ({"vertices": np.zeros((3, 3)), "faces": [[0, 1, 2]], "tetrahedra": [[0, 1, 2, 3]]}, "no 'points'"),
])
def test_to_meshio_refuses_a_malformed_result(bad, words):
    with pytest.raises(ValueError) as e:
        mpumesh.to_meshio(bad)
    assert words in str(e.value), str(e.value)


def test_the_docstrings_name_every_key():
    for key in ("vertices", "faces", "normals", "k1", "K", "H", "face_labels", "report", "points", "tetrahedra",
                "region", "boundary", "boundary_region", "boundary_labels"):
        assert key in mpumesh.run.__doc__ and key in mpumesh.remesh.__doc__, key
    assert "meshio.Mesh" in mpumesh.to_meshio.__doc__
