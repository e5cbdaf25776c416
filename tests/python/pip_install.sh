#!/bin/sh
# `pip install --no-build-isolation .` and `pip wheel --no-build-isolation .` of the package
# (pyproject.toml, setup.py), as a Python user runs them, into a fresh venv with the system's
# site packages (numpy, matplotlib from Debian). The extension is taken from the CMake tree the
# other tests run from (ALLANLOT_CMAKE_BUILD_DIR), so the check costs pip's own work only,
# about 15 s, and the installed package must import from outside the source tree.
#   tests/python/pip_install.sh SOURCE_DIR CMAKE_BUILD_DIR PYTHON
set -eu
src=$1
build=$2
python=$3
# The ASan build preloads the sanitizer runtimes for Python (tests/CMakeLists.txt): only the
# interpreter that imports the instrumented module gets them, not pip, CMake or the compiler.
preload=${LD_PRELOAD:-}
unset LD_PRELOAD PYTHONPATH
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM

"$python" -m venv --system-site-packages "$tmp/venv"
export ALLANLOT_CMAKE_BUILD_DIR="$build"
pip_quiet="--quiet --disable-pip-version-check --no-deps --no-index --no-build-isolation"
# pip builds in the source tree; its intermediate files go below SOURCE/build/ (setup.py).
"$tmp/venv/bin/python" -m pip install $pip_quiet "$src"
"$tmp/venv/bin/python" -m pip wheel $pip_quiet --wheel-dir "$tmp/wheels" "$src"

cd "$tmp"
LD_PRELOAD=$preload "$tmp/venv/bin/python" - "$tmp" <<'PY'
import glob, os, sys, zipfile
tmp = sys.argv[1]
import allanlot
here = os.path.dirname(allanlot.__file__)
assert here.startswith(os.path.join(tmp, "venv")), "imported from %s, not the venv" % here
for name in ("py.typed", "__init__.pyi", "noise.pyi", "ci.pyi"):
    assert os.path.isfile(os.path.join(here, name)), name + " not installed"
assert "Parameters" in allanlot.deviation.__doc__ and callable(allanlot.plot)
x = allanlot.noise.white(1000)
taus, devs, errs, ns = allanlot.oadev(x)
assert len(taus) == 9, taus
wheels = glob.glob(os.path.join(tmp, "wheels", "allanlot-*.whl"))
assert len(wheels) == 1, wheels
names = zipfile.ZipFile(wheels[0]).namelist()
for need in ("allanlot/__init__.py", "allanlot/__init__.pyi", "allanlot/py.typed"):
    assert need in names, need + " not in the wheel"
assert any(n.startswith("allanlot/_allanlot") and n.endswith(".so") for n in names), names
print("pip install and pip wheel: ok (%s)" % os.path.basename(wheels[0]))
PY
