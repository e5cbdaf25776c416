"""The extension allanlot._allanlot for pip (pyproject.toml): built by the project's CMake, the
_allanlot target only, then copied into the package.

ALLANLOT_CMAKE_BUILD_DIR names an existing CMake build directory to build in (its cache is
kept as it is: CI reuses the tree its tests run from, so the install costs a link at most);
without it a Release tree without tests or benchmarks is configured under pip's build directory.
CMAKE_BUILD_PARALLEL_LEVEL sets the compile jobs (default: every core), and
CMAKE_CXX_COMPILER_LAUNCHER=ccache is honoured by CMake itself."""
import os
import pathlib
import re
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def version():
    """The project's version, whose one owner is CMakeLists.txt's project()."""
    text = (ROOT / "CMakeLists.txt").read_text(encoding="utf-8")
    return re.search(r"project\(allanlot VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    """build_ext that asks CMake for the extension instead of compiling `sources`."""

    def build_extension(self, ext):
        build_dir = os.environ.get("ALLANLOT_CMAKE_BUILD_DIR")
        if build_dir:
            build_dir = pathlib.Path(build_dir).resolve()
            if not (build_dir / "CMakeCache.txt").is_file():
                raise RuntimeError("ALLANLOT_CMAKE_BUILD_DIR=%s is not a configured CMake build "
                                   "directory (no CMakeCache.txt)" % build_dir)
        else:
            build_dir = pathlib.Path(self.build_temp).resolve() / "cmake"
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build_dir),
                            "-DCMAKE_BUILD_TYPE=Release", "-DALLANLOT_BUILD_TESTS=OFF",
                            "-DALLANLOT_BUILD_BENCH=OFF", "-DALLANLOT_BUILD_PYTHON=ON",
                            "-DPython3_EXECUTABLE=" + sys.executable], check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "_allanlot", "-j", jobs],
                       check=True)
        built = sorted((build_dir / "python" / "allanlot").glob("_allanlot*.so"))
        if not built:
            raise RuntimeError("CMake built no _allanlot module in %s/python/allanlot (is "
                               "pybind11-dev installed? scripts/setup)" % build_dir)
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        self.copy_file(str(built[0]), str(target))


# pip's intermediate files go below build/ (ignored by git), beside the CMake trees.
(ROOT / "build").mkdir(exist_ok=True)
setup(version=version(),
      ext_modules=[Extension("allanlot._allanlot", sources=[])],
      cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": "build/pip"}, "egg_info": {"egg_base": "build"}})
