"""Benchmark: the Python module against the program on the same scan, in the same run.
Times `mpumesh run SCAN --threshold T -o M --quiet` as a process, and read_volume + run +
write_mesh in this process, alternately, REPEATS times each; prints both medians, their
ratio, and whether the two meshes are the same bytes.
Usage: PYTHONPATH=build/python python3 tools/bench/bench_python.py [SCAN] [THRESHOLD] [REPEATS]"""
import os
import statistics
import subprocess
import sys
import tempfile
import time

import mpumesh

scan = sys.argv[1] if len(sys.argv) > 1 else "data/Cranium.inv3"
threshold = float(sys.argv[2]) if len(sys.argv) > 2 else 226
repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 3
program = os.environ.get("MPUMESH_BIN", "build/tools/mpumesh")

cli_times, py_times = [], []
with tempfile.TemporaryDirectory() as tmp:
    cli_mesh, py_mesh = os.path.join(tmp, "cli.ply"), os.path.join(tmp, "py.ply")
    for _ in range(repeats):
        t = time.perf_counter()
        subprocess.run([program, "run", scan, "--threshold", str(threshold), "-o", cli_mesh, "--quiet"], check=True)
        cli_times.append(time.perf_counter() - t)
        t = time.perf_counter()
        array, spacing, origin, direction = mpumesh.read_volume(scan)
        r = mpumesh.run(array, spacing=spacing, origin=origin, direction=direction, threshold=threshold)
        mpumesh.write_mesh(py_mesh, r)
        py_times.append(time.perf_counter() - t)
    same = open(cli_mesh, "rb").read() == open(py_mesh, "rb").read()
cli, py = statistics.median(cli_times), statistics.median(py_times)
print(f"{scan}, threshold {threshold:g}, {len(r['faces'])} triangles, {repeats} runs each, alternating")
print(f"  mpumesh run (process):                 {cli:7.2f} s  (runs: {', '.join(f'{x:.2f}' for x in cli_times)})")
print(f"  mpumesh.read_volume + run + write_mesh: {py:7.2f} s  (runs: {', '.join(f'{x:.2f}' for x in py_times)})")
print(f"  Python / program: {py / cli:.3f}; the same mesh bytes: {'yes' if same else 'NO'}")
