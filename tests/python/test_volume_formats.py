"""Volume meshes read by an independent reader: meshio (Debian's python3-meshio) reads every
format `mpumesh tetmesh` writes (gmsh MSH 4.1, VTK .vtu, medit .mesh, Abaqus .inp) with the
node count, the tetrahedra and the regions that mpumesh's report gives; for a label map's
complex, with a group per label and per interface.

Run by ctest (tests/CMakeLists.txt) with MPUMESH_BIN at the built program."""
import json
import os
import subprocess

import meshio
import nibabel
import numpy as np
import pytest

BIN = os.environ["MPUMESH_BIN"]


def two_balls(path):
    """Two balls (radius 6 and 4 mm) apart, 1000 inside, 0 outside, 0.6 x 0.6 x 1.2 mm."""
    x, y, z = np.meshgrid(np.arange(50) * 0.6, np.arange(30) * 0.6, np.arange(18) * 1.2, indexing="ij")
    a = np.sqrt((x - 9) ** 2 + (y - 9) ** 2 + (z - 10) ** 2) < 6
    b = np.sqrt((x - 22) ** 2 + (y - 9) ** 2 + (z - 10) ** 2) < 4
    affine = np.diag([0.6, 0.6, 1.2, 1.0])
    nibabel.save(nibabel.Nifti1Image(np.where(a | b, 1000.0, 0.0).astype(np.float32), affine), str(path))


@pytest.fixture(scope="module")
def volume(tmp_path_factory):
    d = tmp_path_factory.mktemp("volume")
    two_balls(d / "balls.nii.gz")
    subprocess.run([BIN, "run", str(d / "balls.nii.gz"), "--threshold", "500", "-o", str(d / "balls.ply"),
                    "--backend", "cpu", "--quiet"], check=True)
    return d


@pytest.mark.parametrize("ext", ["msh", "vtu", "mesh", "inp"])
def test_meshio_reads_what_mpumesh_writes(volume, ext):
    out, report = volume / f"balls.{ext}", volume / f"balls_{ext}.json"
    subprocess.run([BIN, "tetmesh", str(volume / "balls.ply"), "-o", str(out), "--report", str(report), "--quiet"],
                   check=True)
    r = json.loads(report.read_text())
    m = meshio.read(str(out))
    tets = [c for c in m.cells if c.type == "tetra"]
    assert len(m.points) == r["nodes"]
    assert sum(len(c.data) for c in tets) == r["tetrahedra"]
    assert r["regions"] == 2
    # Each tetrahedron's region, as each format keeps it.
    if ext == "msh":
        regions = np.concatenate([m.cell_data["gmsh:physical"][i] for i, c in enumerate(m.cells) if c.type == "tetra"])
    elif ext == "vtu":
        regions = m.cell_data["region"][0]
    elif ext == "mesh":
        regions = np.concatenate([m.cell_data["medit:ref"][i] for i, c in enumerate(m.cells) if c.type == "tetra"])
    else:
        regions = np.zeros(r["tetrahedra"], dtype=int)
        for name, blocks in m.cell_sets.items():
            if name.upper().startswith("REGION_"):
                regions[blocks[0]] = int(name.split("_")[1])
    assert sorted(set(int(v) for v in regions)) == [1, 2]
    # Every tetrahedron positive, and their volume the surface's.
    p = m.points[np.concatenate([c.data for c in tets])]
    vol = np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6
    assert (vol > 0).all()
    assert abs(vol.sum() - r["surface_volume_mm3"]) < 1e-6 * r["surface_volume_mm3"]
    if ext == "inp":  # the mesh only, with its sets
        text = out.read_text()
        assert "*STEP" not in text.upper() and "*NSET, NSET=BOUNDARY" in text


def two_labels(path):
    """A ball of radius 8 mm cut by the plane x = 1 into labels 1 and 2, 0.6 x 0.6 x 1.5 mm."""
    x, y, z = np.meshgrid(np.arange(36) * 0.6, np.arange(36) * 0.6, np.arange(16) * 1.5, indexing="ij")
    ball = np.sqrt((x - 10.5) ** 2 + (y - 10.5) ** 2 + (z - 11.25) ** 2) < 8
    labels = np.where(ball, np.where(x < 11.5, 1, 2), 0).astype(np.int16)
    nibabel.save(nibabel.Nifti1Image(labels, np.diag([0.6, 0.6, 1.5, 1.0])), str(path))


@pytest.fixture(scope="module")
def complex_volume(tmp_path_factory):
    d = tmp_path_factory.mktemp("complex_volume")
    two_labels(d / "labels.nii.gz")
    subprocess.run([BIN, "run", str(d / "labels.nii.gz"), "--labels", "all", "-o", str(d / "complex.ply"),
                    "--volume", str(d / "complex.msh"), "--report", str(d / "complex.json"), "--backend", "cpu",
                    "--quiet"], check=True)
    return d


def tet_volumes(points, tets):
    p = points[tets]
    return np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6


@pytest.mark.parametrize("ext", ["msh", "vtu", "mesh", "inp"])
def test_meshio_reads_a_complexs_volume_mesh_with_its_groups(complex_volume, ext):
    d = complex_volume
    out = d / f"complex.{ext}"
    report = d / "complex.json"
    if ext != "msh":  # the run wrote the .msh; `tetmesh` of its complex the others
        report = d / f"complex_{ext}.json"
        subprocess.run([BIN, "tetmesh", str(d / "complex.ply"), "-o", str(out), "--report", str(report), "--quiet"],
                       check=True)
    r = json.loads(report.read_text())
    r = r.get("volume_mesh", r)
    m = meshio.read(str(out))
    volume_cells = {c.type for c in m.cells} - {"triangle"}
    assert volume_cells == {"tetra"}
    tets = np.concatenate([c.data for c in m.cells if c.type == "tetra"])
    assert len(tets) == r["tetrahedra"]
    # Each tetrahedron's label and each interface triangle's two, as each format keeps them.
    if ext == "msh":
        names = {tag: name for name, (tag, dim) in m.field_data.items()}
        phys = [names[int(c[0])] for c, b in zip(m.cell_data["gmsh:physical"], m.cells)]
        labels = np.concatenate([np.full(len(b.data), int(n.split("_")[1])) for n, b in zip(phys, m.cells)
                                 if b.type == "tetra"])
        assert {n for n in phys if n.startswith("interface_")} == {"interface_0_1", "interface_0_2", "interface_1_2"}
    elif ext == "vtu":
        kinds = [c.type for c in m.cells]
        labels = m.cell_data["label"][kinds.index("tetra")]
        tri = kinds.index("triangle")
        pairs = set(zip(m.cell_data["label_a"][tri].tolist(), m.cell_data["label_b"][tri].tolist()))
        assert pairs == {(0, 1), (0, 2), (1, 2)}
    elif ext == "mesh":
        kinds = [c.type for c in m.cells]
        labels = m.cell_data["medit:ref"][kinds.index("tetra")]
        assert "# interface 3: labels 1 2" in out.read_text()
        assert set(m.cell_data["medit:ref"][kinds.index("triangle")].tolist()) == {1, 2, 3}
    else:
        labels = np.zeros(len(tets), dtype=int)
        for name, blocks in m.cell_sets.items():
            if name.upper().startswith("LABEL_"):
                labels[blocks[0]] = int(name.split("_")[1])
        assert {"INTERFACE_0_1", "INTERFACE_0_2", "INTERFACE_1_2"} <= set(m.point_sets)
        assert out.read_text().count("*SURFACE, NAME=INTERFACE_") == 3
    assert sorted(set(int(v) for v in labels)) == [1, 2]
    # None inverted; each label's tetrahedra fill its boundary.
    vol = tet_volumes(m.points, tets)
    assert (vol > 0).all()
    for entry in r["labels"]:
        mine = vol[labels == entry["label"]].sum()
        assert abs(mine - entry["boundary_volume_mm3"]) < 1e-6 * entry["boundary_volume_mm3"]
