#!/bin/sh
# t005-build-tree.sh - programs linked against the build tree start: the README's C and Fortran
# examples built with -L$(BUILD) -lgranary (and an rpath to it) run without an installation,
# because $(BUILD) holds the library under its SONAME (libgranary.so -> libgranary.so.MAJOR ->
# libgranary.so.MAJOR.MINOR.PATCH).
set -eu
src=${GRAN_SOURCE_DIR:-.}
build=${GRAN_BUILD:-build}
case "$build" in /*) ;; *) build="$src/$build" ;; esac
tmp=$(mktemp -d /tmp/granary-t005-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
ver=$(sed -n 's/^#define GRAN_VERSION_STRING "\(.*\)"/\1/p' "$src/include/granary.h")
major=$(sed -n 's/^#define GRAN_ABI_VERSION \([0-9]*\)$/\1/p' "$src/include/granary.h") # the SONAME's number
[ -f "$build/libgranary.so.$ver" ] && [ ! -L "$build/libgranary.so.$ver" ] ||
  { echo "FAIL: $build/libgranary.so.$ver is not the library file"; ls -l "$build"/libgranary.so*; exit 1; }
[ "$(readlink "$build/libgranary.so.$major")" = "libgranary.so.$ver" ] ||
  { echo "FAIL: $build/libgranary.so.$major does not link to libgranary.so.$ver"; ls -l "$build"/libgranary.so*; exit 1; }
[ "$(readlink "$build/libgranary.so")" = "libgranary.so.$major" ] ||
  { echo "FAIL: $build/libgranary.so does not link to libgranary.so.$major"; ls -l "$build"/libgranary.so*; exit 1; }
soname=$(objdump -p "$build/libgranary.so" | awk '/SONAME/ {print $2}')
[ "$soname" = "libgranary.so.$major" ] || { echo "FAIL: SONAME is '$soname', expected libgranary.so.$major"; exit 1; }
echo "ok: $build/libgranary.so -> libgranary.so.$major -> libgranary.so.$ver (SONAME $soname)"
omp=$(sed -n 's/^OMP_FLAG *?= *//p' "$src/Makefile")
cc ${GRAN_SAN:-} -I"$src/include" "$src/bindings/examples/example.c" -o "$tmp/example-c" \
  -L"$build" -lgranary -Wl,-rpath,"$build" -lm
gfortran ${GRAN_SAN:-} -I"$build/mod" "$src/bindings/examples/example.f90" -o "$tmp/example-f" \
  -L"$build" -lgranary_fortran -lgranary -Wl,-rpath,"$build" $omp
for p in example-c example-f; do
  ldd "$tmp/$p" | grep -q "libgranary.so.$major => $build/libgranary.so.$major" ||
    { echo "FAIL: $p does not load $build/libgranary.so.$major"; ldd "$tmp/$p"; exit 1; }
  (cd "$tmp" && env -u LD_LIBRARY_PATH "./$p" >"$tmp/$p.out" 2>&1) || { echo "FAIL: $p"; cat "$tmp/$p.out"; exit 1; }
  echo "ok: $p built with -L$build -lgranary runs from the build tree"
done
echo "1 passed, 0 failed"
