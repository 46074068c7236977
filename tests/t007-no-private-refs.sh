#!/bin/sh
# t007-no-private-refs.sh - the shipped tree cites what its users can read: code comments, strings,
# scenes and the manual name the papers (author, year, equation) and the sections of docs/physics.md,
# never the project's private notes ("PHYSICS-NOTES"), the private names of the source documents
# ("seed 000", "seed-002", ...) or tracker numbers ("issue 11"). History lives in CHANGELOG.md and
# docs/developers/, which are not searched (nor is this script). Fails listing every hit as
# file:line: text.
set -eu
src=${GRAN_SOURCE_DIR:-.}
cd "$src"
pattern='PHYSICS-NOTES|seed[ -]00[0-9]|\bissues? #?[0-9]'
dirs="src include cuda bindings docs scenes tests bench figures fuzz"
present=
for d in $dirs README.md Makefile; do [ -e "$d" ] && present="$present $d"; done
[ -n "$present" ] || { echo "FAIL: none of $dirs README.md Makefile under $src"; exit 1; }
# -I: binary files (fuzz inputs, caches) are skipped; -i: "Seed 002", "Issue 9" count too.
# shellcheck disable=SC2086
hits=$(grep -rnIiE "$pattern" $present --exclude-dir=developers --exclude=CHANGELOG.md \
  --exclude=t007-no-private-refs.sh --exclude-dir=__pycache__ || true)
# The pattern must find what it is meant to find (a grep without -E, or a broken pattern, would
# pass every tree).
for probe in "see PHYSICS-NOTES Sec. 3" "seed 000 Eq. 24" "Seed 002 Fig. 1" "the seed-000 numbers" "(issue 11)" "issues 9"; do
  echo "$probe" | grep -qiE "$pattern" || { echo "FAIL: the pattern misses '$probe'"; exit 1; }
done
for probe in "scenes/seed002/fig1-2.toml" "t525-seed002-scenes" "tissue 3" "rng seed 7"; do
  if echo "$probe" | grep -qiE "$pattern"; then echo "FAIL: the pattern matches '$probe'"; exit 1; fi
done
if [ -n "$hits" ]; then
  n=$(printf '%s\n' "$hits" | wc -l)
  echo "FAIL: $n private reference(s) in the shipped tree (cite the paper and docs/physics.md instead):"
  printf '%s\n' "$hits"
  exit 1
fi
echo "ok: no PHYSICS-NOTES, seed 00N or issue N in$present"
echo "1 passed, 0 failed"
