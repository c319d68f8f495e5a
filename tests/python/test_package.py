"""The module as a package: `python3 -m build --no-isolation --wheel` makes a wheel and
`pip install --no-build-isolation .` installs from the repository, each into a fresh
virtual environment (with Debian's site packages, where numpy is), from which `mpumesh`
imports outside the source tree and meshes a small phantom.

Run by ctest (tests/CMakeLists.txt) with MPUMESH_SOURCE_DIR at the repository and
MPUMESH_BUILD_DIR at the build folder, whose module the package takes (setup.py)."""
import os
import subprocess
import sys
import zipfile
from pathlib import Path

SOURCE = Path(os.environ["MPUMESH_SOURCE_DIR"])
# The package is built by the build folder's CMake; the test's own PYTHONPATH (the build
# folder's module) must not reach the environment under test.
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}

PHANTOM = """
import sys, numpy as np, mpumesh
assert mpumesh.__file__.startswith(sys.prefix), mpumesh.__file__
z, y, x = np.mgrid[0:14, 0:24, 0:24]
ball = np.where((x - 12) ** 2 + (y - 12) ** 2 + (2 * z - 14) ** 2 < 64, 1000.0, 0.0).astype(np.float32)
r = mpumesh.run(ball, spacing=(0.6, 0.6, 1.2), threshold=500, particles=800, backend="cpu", volume=True)
print(mpumesh.__version__, len(r["faces"]), len(r["tetrahedra"]))
"""


def venv(path):
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(path)], check=True, env=ENV)
    return path / "bin" / "python"


def run_phantom(python, cwd):
    out = subprocess.run([str(python), "-c", PHANTOM], cwd=cwd, env=ENV, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    version, faces, tets = out.stdout.split()
    assert int(faces) > 500 and int(tets) > 500
    return version


def test_a_wheel_installs_into_a_fresh_environment(tmp_path):
    dist = tmp_path / "dist"
    subprocess.run([sys.executable, "-m", "build", "--no-isolation", "--wheel", "--outdir", str(dist), str(SOURCE)],
                   check=True, env=ENV, capture_output=True)
    wheels = list(dist.glob("mpumesh-*.whl"))
    assert len(wheels) == 1
    names = zipfile.ZipFile(wheels[0]).namelist()
    assert any(n.startswith("mpumesh.cpython-") and n.endswith(".so") for n in names), names
    print(f"wheel {wheels[0].name}: {wheels[0].stat().st_size} bytes")
    python = venv(tmp_path / "env")
    subprocess.run([str(python), "-m", "pip", "install", "--no-index", str(wheels[0])], check=True, env=ENV,
                   capture_output=True)
    work = tmp_path / "elsewhere"
    work.mkdir()
    version = run_phantom(python, work)
    assert wheels[0].name.startswith(f"mpumesh-{version}-")


def test_pip_installs_from_the_repository(tmp_path):
    python = venv(tmp_path / "env")
    subprocess.run([str(python), "-m", "pip", "install", "--no-build-isolation", "--no-index", str(SOURCE)],
                   check=True, env=ENV, capture_output=True)
    run_phantom(python, tmp_path)
    # Uninstalled, it is gone from the environment.
    subprocess.run([str(python), "-m", "pip", "uninstall", "-y", "mpumesh"], check=True, env=ENV, capture_output=True)
    gone = subprocess.run([str(python), "-c", "import mpumesh"], cwd=tmp_path, env=ENV, capture_output=True)
    assert gone.returncode != 0


def test_the_source_tree_stays_clean():
    # setuptools' work files (egg-info, build/lib, dist) go under the build folder.
    stray = [p.name for p in SOURCE.iterdir() if p.name.endswith(".egg-info") or p.name == "dist"]
    stray += [p.name for p in (SOURCE / "build").glob("lib*")] if (SOURCE / "build").is_dir() else []
    assert not stray, stray
