"""workflow/Snakefile on a folder of small phantoms, with --cores 2: every scan meshed by
its own job, an index of all, and a scan that fails while the others finish."""
import os
import re
import subprocess

from scan_phantoms import ball_scan

SOURCE = os.environ["MPUMESH_SOURCE_DIR"]
BIN = os.environ["MPUMESH_BIN"]


def snakemake(tmp_path, scans, out):
    return subprocess.run(
        ["snakemake", "-s", os.path.join(SOURCE, "workflow", "Snakefile"), "--cores", "2", "--keep-going",
         "--directory", str(tmp_path), "--config", f"input_dir={scans}", f"output_dir={out}", f"mpumesh={BIN}",
         "threads=1", "run_options=--particles 1500 --backend cpu"],
        capture_output=True, text=True)


def test_meshes_every_scan_and_writes_an_index(tmp_path):
    scans = tmp_path / "scans"
    scans.mkdir()
    ball_scan(scans / "small.nii.gz", 5.0)
    ball_scan(scans / "large.nii.gz", 7.0)
    out = tmp_path / "meshes"
    r = snakemake(tmp_path, scans, out)
    assert r.returncode == 0, r.stdout + r.stderr
    for name in ("small", "large"):
        assert (out / f"{name}.ply").stat().st_size > 1000
        assert '"triangles"' in (out / f"{name}.json").read_text()
    index = (out / "index.html").read_text()
    assert index.count("<tr>") == 3 and "failed" not in index.split("</style>")[1]
    # The larger ball has the larger volume in the index.
    volumes = [float(v) for v in re.findall(r"<td>(\d+)</td><td>[\d.]+</td></tr>", index)]
    assert len(volumes) == 2 and volumes[0] > volumes[1], index  # large sorts before small


def test_a_scan_that_fails_leaves_the_others_done_and_is_reported(tmp_path):
    scans = tmp_path / "scans"
    scans.mkdir()
    ball_scan(scans / "good.nii.gz", 5.0)
    ball_scan(scans / "fine.nii.gz", 6.0)
    (scans / "broken.nii.gz").write_bytes(b"this is no NIfTI file")
    out = tmp_path / "meshes"
    r = snakemake(tmp_path, scans, out)
    assert r.returncode != 0
    assert "broken" in r.stdout + r.stderr
    for name in ("good", "fine"):
        assert (out / f"{name}.ply").exists(), r.stdout + r.stderr
    assert not (out / "broken.ply").exists()
    assert "mpumesh: error:" in (out / "logs" / "broken.log").read_text()
    index = (out / "index.html").read_text()
    assert "failed: mpumesh: error:" in index and "broken" in index
    assert index.count("good.ply") == 1 and index.count("fine.ply") == 1
