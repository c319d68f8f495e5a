"""Benchmark: workflow/Snakefile on a folder of CT-like phantoms (balls of 4-9 mm radius,
0.6 x 0.6 x 2 mm voxels, noise 40 HU), with --cores 1 and then --cores 2 (one thread a
job), in the same run; prints each wall time and their ratio.
Usage: python3 tools/bench/bench_workflow.py [SCANS] (needs nibabel, numpy, snakemake)"""
import os
import subprocess
import sys
import tempfile
import time

import nibabel
import numpy as np

count = int(sys.argv[1]) if len(sys.argv) > 1 else 6
source = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
program = os.path.abspath(os.environ.get("MPUMESH_BIN", os.path.join(source, "build", "tools", "mpumesh")))
rng = np.random.default_rng(1)


def scan(path, radius, shape=(20, 40, 40), spacing=(0.6, 0.6, 2.0)):
    z, y, x = np.meshgrid(*(np.arange(n, dtype=float) for n in shape), indexing="ij")
    p = np.stack([x * spacing[0], y * spacing[1], z * spacing[2]], axis=-1)
    centre = np.array([shape[2] * spacing[0], shape[1] * spacing[1], shape[0] * spacing[2]]) / 2
    d = (radius - np.linalg.norm(p - centre, axis=-1)) / min(spacing)
    data = 500 + 500 * np.clip(d, -1, 1) + rng.normal(0, 40, shape)
    nibabel.save(nibabel.Nifti1Image(np.transpose(data.astype(np.int16), (2, 1, 0)), np.diag(list(spacing) + [1.0])),
                 path)


with tempfile.TemporaryDirectory() as tmp:
    scans = os.path.join(tmp, "scans")
    os.makedirs(scans)
    for i in range(count):
        scan(os.path.join(scans, f"ball{i}.nii.gz"), 4.0 + 5.0 * i / max(count - 1, 1))
    times = {}
    for cores in (1, 2):
        out = os.path.join(tmp, f"meshes{cores}")
        t = time.perf_counter()
        r = subprocess.run(["snakemake", "-s", os.path.join(source, "workflow", "Snakefile"), "--cores", str(cores),
                            "--directory", tmp, "--quiet", "--config", f"input_dir={scans}", f"output_dir={out}",
                            f"mpumesh={program}", "threads=1", "threshold=500"], capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"snakemake failed:\n{r.stdout}{r.stderr}")
        times[cores] = time.perf_counter() - t
        meshed = sum(f.endswith(".ply") for f in os.listdir(out))
        print(f"--cores {cores}: {times[cores]:6.2f} s for {meshed} of {count} scans")
print(f"2 cores / 1 core: {times[2] / times[1]:.2f}")
