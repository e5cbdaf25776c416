#!/usr/bin/env bash
# Installs the build into a temporary prefix (`cmake --install`), runs the installed binary on a
# small simulated recording, checks what docs/install.md promises is in place (Slurm scripts
# that find the installed binary, docs, the man page), then builds the .deb with CPack and checks
# its name, its Debian dependencies and its contents.
#
# usage: test_install.sh BUILD_DIR SCRATCH_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
scratch=$2
rm -rf "$scratch"
mkdir -p "$scratch"
prefix="$scratch/prefix"

fail() {
  echo "install test: $*" >&2
  exit 1
}

cmake --install "$build" --prefix "$prefix" >"$scratch/install.log"

# The installed binary runs from its new place and analyses a recording.
bin="$prefix/bin/allanlot"
[ -x "$bin" ] || fail "$bin is not installed"
"$bin" --version | grep -Eq '^allanlot [0-9]+\.[0-9]+\.[0-9]+' || fail "$bin --version"
"$bin" simulate --duration 120 --seed 3 -q -o "$scratch/unit.h5"
"$bin" analyze -q --no-psd --taus octave -o "$scratch/results" "$scratch/unit.h5"
[ -s "$scratch/results/lot_summary.csv" ] || fail "the installed binary wrote no lot summary"

# The Slurm scripts, executable, and submit-lot finds the installed binary beside its prefix
# (not build/ of a checkout, not PATH).
slurm="$prefix/share/allanlot/slurm"
for s in submit-lot lot-status lot-task.sbatch lot-merge.sbatch; do
  [ -x "$slurm/$s" ] || fail "$slurm/$s is missing or not executable"
done
echo "$scratch/unit.h5" >"$scratch/manifest.txt"
PATH=/usr/bin:/bin "$slurm/submit-lot" --dry-run "$scratch/manifest.txt" "$scratch/slurm-out" \
  >"$scratch/dry-run.txt"
grep -q -- "$bin" "$scratch/dry-run.txt" || fail "submit-lot did not pick $bin: $(cat "$scratch/dry-run.txt")"

# The docs keep their relative links: README.md beside docs/.
doc="$prefix/share/doc/allanlot"
for f in README.md LICENSE copyright CHANGELOG.md CITATION.cff docs/cli.md docs/formats.md; do
  [ -s "$doc/$f" ] || fail "$doc/$f is missing"
done

# The man page, compressed as Debian does, documents every command.
man="$prefix/share/man/man1/allanlot.1.gz"
[ -s "$man" ] || fail "$man is missing"
for section in 'COMMAND: ANALYZE' 'COMMAND: DIAGNOSE' 'EXIT STATUS'; do
  gzip -dc "$man" | grep -q "^\.SH \"$section\"" || fail "the man page has no section $section"
done

# The Python package, where Debian's Python looks for it (docs/python.md), when it was built.
if [ -f "$build/python/allanlot/__init__.py" ]; then
  ls "$prefix"/lib/python3*/dist-packages/allanlot/__init__.py >/dev/null 2>&1 ||
    fail "the Python package allanlot is not installed under $prefix/lib/python3*/dist-packages"
  ls "$prefix"/lib/python3*/dist-packages/allanlot/_allanlot*.so >/dev/null 2>&1 ||
    fail "the extension module _allanlot is not installed"
fi

# The .deb: Debian's file name, runtime dependencies from dpkg-shlibdeps, the installed tree.
(cd "$scratch" && cpack --config "$build/CPackConfig.cmake" -G DEB -B "$scratch/deb" \
  >"$scratch/cpack.log") || fail "cpack failed: $(tail -5 "$scratch/cpack.log")"
version=$("$bin" --version | awk '{print $2}')
deb="$scratch/deb/allanlot_${version}_$(dpkg --print-architecture).deb"
[ -s "$deb" ] || fail "no $deb ($(ls "$scratch/deb"))"
depends=$(dpkg-deb -f "$deb" Depends)
for lib in libhdf5 libfftw3 libgomp1 libstdc++6 libc6; do
  grep -q "$lib" <<<"$depends" || fail "the .deb does not depend on $lib: $depends"
done
contents=$(dpkg-deb -c "$deb")
for f in ./usr/bin/allanlot ./usr/share/allanlot/slurm/submit-lot \
  ./usr/share/man/man1/allanlot.1.gz ./usr/share/doc/allanlot/copyright; do
  grep -q " $f\$" <<<"$contents" || fail "the .deb has no $f"
done
if [ -f "$build/python/allanlot/__init__.py" ]; then
  grep -q " ./usr/lib/python3/dist-packages/allanlot/__init__.py\$" <<<"$contents" ||
    fail "the .deb has no Python package in /usr/lib/python3/dist-packages"
fi
echo "install test: prefix install, Slurm scripts, docs, man page and $(basename "$deb") checked"
