"""Volume meshes read by an independent reader: meshio (Debian's python3-meshio) reads every
format `mpumesh tetmesh` writes (gmsh MSH 4.1, VTK .vtu, medit .mesh, Abaqus .inp) with the
node count, the tetrahedra and the regions that mpumesh's report gives.

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
