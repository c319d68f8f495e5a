"""The Python module `mpumesh` as a package: its one extension is built by the project's
CMake build (the target mpumesh_python, with the libraries it links) in the build folder
that scripts/setup.sh uses (build/, or $MPUMESH_BUILD_DIR), configured there when it is
not yet, and copied into the wheel. setuptools' own work files go under that folder too,
so that the source tree stays clean."""
import os
import re
import shutil
import subprocess
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
BUILD = Path(os.environ.get("MPUMESH_BUILD_DIR", ROOT / "build")).resolve()


def version():
    """The project's version, from CMakeLists.txt's project() line."""
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(mpumesh VERSION ([0-9.]+)", text).group(1)


class CMakeExtension(build_ext):
    def build_extension(self, ext):
        if not (BUILD / "CMakeCache.txt").exists():
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(BUILD), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release"],
                           check=True)
        subprocess.run(["cmake", "--build", str(BUILD), "--target", "mpumesh_python", "-j", str(os.cpu_count() or 1)],
                       check=True)
        built = sorted((BUILD / "python").glob("mpumesh.cpython-*.so"))
        if not built:
            raise RuntimeError(f"{BUILD / 'python'}: the build made no mpumesh module")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[-1], target)


work = BUILD / "python-package"
work.mkdir(parents=True, exist_ok=True)
setup(
    version=version(),
    packages=[],
    py_modules=[],
    ext_modules=[Extension("mpumesh", sources=[])],
    cmdclass={"build_ext": CMakeExtension},
    options={"build": {"build_base": str(work / "build")}, "egg_info": {"egg_base": str(work)}},
)
