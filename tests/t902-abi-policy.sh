#!/bin/sh
# t902-abi-policy.sh - the ABI rule of docs/developers/abi.md is enforced by bindings/gen_raw.py:
# in a copy of the header and the script, with the ABI marked released (--release), a change that
# can break a program built against the old header (a struct field added, a function's parameter
# changed, a constant's value changed, a function removed) under the same GRAN_ABI_VERSION is
# refused and nothing is written; the same change with GRAN_ABI_VERSION raised is accepted (and
# the new ABI is unreleased); an added function is accepted as it is; before the release a breaking
# change passes; a lower number is refused. The committed include/granary.abi is what the header
# gives, and names the SONAME's number.
set -eu
src=${GRAN_SOURCE_DIR:-.}
command -v python3 >/dev/null 2>&1 || { echo "skip: python3 not found"; exit 0; }
tmp=$(mktemp -d /tmp/granary-t902-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
abi=$(sed -n 's/^#define GRAN_ABI_VERSION \([0-9]*\)$/\1/p' "$src/include/granary.h")
[ -n "$abi" ] || { echo "FAIL: include/granary.h defines no GRAN_ABI_VERSION"; exit 1; }
grep -Eqx "abi $abi (un)?released" "$src/include/granary.abi" || { echo "FAIL: include/granary.abi does not record abi $abi"; exit 1; }
python3 "$src/bindings/gen_raw.py" --check || { echo "FAIL: the generated files are not current"; exit 1; }

fresh() { # a copy of the tree's header, script, manifest and generated files
  rm -rf "$tmp/t"; mkdir -p "$tmp/t/include" "$tmp/t/bindings" "$tmp/t/src/core" "$tmp/t/tests"
  cp "$src/include/granary.h" "$src/include/granary.abi" "$tmp/t/include/"
  cp "$src/bindings/gen_raw.py" "$src/bindings/granary_raw.inc" "$src/bindings/granary.f90" "$tmp/t/bindings/"
  cp "$src/src/core/abi_table.inc" "$tmp/t/src/core/"
  cp "$src/tests/t901-layout-f.inc" "$tmp/t/tests/"
  python3 "$tmp/t/bindings/gen_raw.py" --release > /dev/null
  grep -qx "abi $abi released" "$tmp/t/include/granary.abi" || { echo "FAIL: --release did not mark abi $abi released"; exit 1; }
  cp "$tmp/t/include/granary.abi" "$tmp/released.abi"
}
refused() { # $1: what was changed; the sed program in $2 applied to the header
  fresh
  sed -i "$2" "$tmp/t/include/granary.h"
  cmp -s "$src/include/granary.h" "$tmp/t/include/granary.h" && { echo "FAIL: the edit '$1' changed nothing"; exit 1; }
  if python3 "$tmp/t/bindings/gen_raw.py" > "$tmp/out" 2>&1; then
    echo "FAIL: $1 under GRAN_ABI_VERSION $abi was accepted"; cat "$tmp/out"; exit 1
  fi
  grep -q "raise GRAN_ABI_VERSION" "$tmp/out" || { echo "FAIL: $1: message does not say what to do"; cat "$tmp/out"; exit 1; }
  cmp -s "$tmp/released.abi" "$tmp/t/include/granary.abi" || { echo "FAIL: $1: the manifest was written"; exit 1; }
  cmp -s "$src/bindings/granary_raw.inc" "$tmp/t/bindings/granary_raw.inc" || { echo "FAIL: $1: granary_raw.inc was written"; exit 1; }
  # raised: accepted, and the new manifest names the new number
  sed -i "s/^#define GRAN_ABI_VERSION $abi\$/#define GRAN_ABI_VERSION $((abi + 1))/" "$tmp/t/include/granary.h"
  python3 "$tmp/t/bindings/gen_raw.py" > "$tmp/out" 2>&1 || { echo "FAIL: $1 with GRAN_ABI_VERSION raised was refused"; cat "$tmp/out"; exit 1; }
  grep -qx "abi $((abi + 1)) unreleased" "$tmp/t/include/granary.abi" || { echo "FAIL: $1: the manifest does not say abi $((abi + 1)) unreleased"; exit 1; }
  echo "ok: $1: refused under ABI $abi, accepted under $((abi + 1))"
}
refused "a field added to gran_srd_options" 's/^\(  int32_t dim;\)/\1 int32_t added_;/'
refused "a parameter of gran_rng_seed changed" 's/^GRAN_EXTERN int gran_rng_seed(gran_rng \*rng, uint64_t seed);/GRAN_EXTERN int gran_rng_seed(gran_rng *rng, int64_t seed);/'
refused "GRAN_ERR_ARG's value changed" 's/X(GRAN_ERR_ARG, -1,/X(GRAN_ERR_ARG, -101,/'
refused "gran_clear_error removed" '/^GRAN_EXTERN int gran_clear_error(/d'

fresh
sed -i 's/^\(GRAN_EXTERN int gran_get_version(int \*major, int \*minor, int \*patch);\)/\1\nGRAN_EXTERN int gran_added_for_t902(int x);/' "$tmp/t/include/granary.h"
python3 "$tmp/t/bindings/gen_raw.py" > "$tmp/out" 2>&1 || { echo "FAIL: an added function was refused"; cat "$tmp/out"; exit 1; }
grep -q "^function int gran_added_for_t902(int x)$" "$tmp/t/include/granary.abi" || { echo "FAIL: the added function is not in the manifest"; exit 1; }
grep -qx "abi $abi released" "$tmp/t/include/granary.abi" || { echo "FAIL: an addition changed the ABI number"; exit 1; }
echo "ok: an added function is accepted under the released ABI $abi"

fresh # before the release: a breaking change under an unreleased number passes
sed -i "s/^abi $abi released\$/abi $abi unreleased/" "$tmp/t/include/granary.abi"
sed -i 's/^\(  int32_t dim;\)/\1 int32_t added_;/' "$tmp/t/include/granary.h"
python3 "$tmp/t/bindings/gen_raw.py" > "$tmp/out" 2>&1 || { echo "FAIL: a change under the unreleased ABI $abi was refused"; cat "$tmp/out"; exit 1; }
echo "ok: a breaking change under the unreleased ABI $abi is accepted"

fresh # a lower number than the manifest's
sed -i "s/^#define GRAN_ABI_VERSION $abi\$/#define GRAN_ABI_VERSION $((abi - 1))/" "$tmp/t/include/granary.h"
if python3 "$tmp/t/bindings/gen_raw.py" > "$tmp/out" 2>&1; then echo "FAIL: a lower ABI number was accepted"; exit 1; fi
grep -q "is lower than" "$tmp/out" || { echo "FAIL: the lower number's message"; cat "$tmp/out"; exit 1; }
echo "ok: a lower ABI number is refused"
