#!/bin/sh
# t003-install.sh - the installed library links as README says: `make install` into a temporary
# prefix, then both README examples (C and Fortran) are built with nothing but the pkg-config line
# and run. The shared library carries a SONAME and versioned file names; the .pc file's rpath lets
# the programs find it without LD_LIBRARY_PATH. The scenes, the ABI manifest and the output reader
# module go under share/granary/.
set -eu
src=${GRAN_SOURCE_DIR:-.}
build=${GRAN_BUILD:-build}
tmp=$(mktemp -d /tmp/granary-t003-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
make -s -C "$src" BUILD="$build" OPT="${GRAN_OPT:--O3 -march=native}" SAN="${GRAN_SAN:-}" NVCC="${GRAN_NVCC:-}" \
  install prefix="$prefix" >"$tmp/install.log" 2>&1 || { cat "$tmp/install.log"; exit 1; }
ver=$(sed -n 's/^#define GRAN_VERSION_STRING "\(.*\)"/\1/p' "$src/include/granary.h")
major=$(sed -n 's/^#define GRAN_ABI_VERSION \([0-9]*\)$/\1/p' "$src/include/granary.h") # the SONAME's number
for f in "libgranary.so.$ver" "libgranary.so.$major" libgranary.so libgranary.a libgranary_fortran.a; do
  [ -e "$prefix/lib/$f" ] || { echo "FAIL: $prefix/lib/$f missing"; exit 1; }
done
soname=$(objdump -p "$prefix/lib/libgranary.so.$ver" | awk '/SONAME/ {print $2}')
[ "$soname" = "libgranary.so.$major" ] || { echo "FAIL: SONAME is '$soname', expected libgranary.so.$major"; exit 1; }
echo "ok: libgranary.so.$ver with SONAME $soname"
for f in scenes/default.toml scenes/srd/haff.toml granary.abi python/granary_h5.py; do
  [ -e "$prefix/share/granary/$f" ] || { echo "FAIL: $prefix/share/granary/$f missing"; exit 1; }
done
echo "ok: scenes, granary.abi and the reader module under share/granary"
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
# the README's lines (section "Calling granary from C / Fortran")
cc ${GRAN_SAN:-} $(pkg-config --cflags granary) "$src/bindings/examples/example.c" -o "$tmp/example-c" \
  $(pkg-config --libs granary)
gfortran ${GRAN_SAN:-} $(pkg-config --cflags granary) "$src/bindings/examples/example.f90" -o "$tmp/example-f" \
  -lgranary_fortran $(pkg-config --libs granary)
for p in example-c example-f; do
  ldd "$tmp/$p" | grep -q "$prefix/lib/libgranary.so.$major" || { echo "FAIL: $p does not load the installed library"; ldd "$tmp/$p"; exit 1; }
  (cd "$tmp" && env -u LD_LIBRARY_PATH "./$p" >"$tmp/$p.out" 2>&1) || { echo "FAIL: $p"; cat "$tmp/$p.out"; exit 1; }
  echo "ok: $p built from the pkg-config line runs against the installed library"
done
echo "1 passed, 0 failed"
