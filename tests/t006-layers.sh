#!/bin/sh
# t006-layers.sh - the layer rules of docs/developers/ARCHITECTURE.md, checked on every #include of
# src/ and cuda/: each folder includes only the folders below it and the interfaces named here, and
# the dependencies (HDF5, toml11, GSL, FFTW, MPI) stay in the layers that own them. A failure names
# the file, the include and the rule.
set -eu
src=${GRAN_SOURCE_DIR:-.}
cd "$src"
fail=0
# folder -> the project headers it may include (prefixes; granary.h, granary_impl.h and its own
# folder are always allowed)
allowed() {
  case "$1" in
    src) echo "core/" ;;
    src/core) echo "" ;;
    src/theory) echo "core/" ;;
    src/analysis) echo "core/" ;;
    src/dsmc) echo "core/ theory/ io/state.h io/scene_impl.h io/engine.h io/io_impl.h" ;;
    src/srd) echo "core/ io/state.h io/scene_impl.h io/engine.h io/io_impl.h ../cuda/srd_cuda.h" ;;
    src/io) echo "core/ srd/fields.h srd/srd_theory.h srd/bricks.h" ;;
    src/cli) echo "core/ io/engine.h io/io_impl.h io/run_comm.h srd/srd_theory.h srd/bricks.h" ;;
    cuda) echo "core/xoshiro.h srd/rules.h srd/srd_kernels.h srd/device_cuda.h" ;;
    *) echo "?" ;;
  esac
}
# external header -> the folders that may include it
ext_ok() { # $1 folder, $2 file, $3 header
  case "$3" in
    hdf5.h|H5*.h) case "$1" in src/io) return 0 ;; esac; [ "$2" = src/cli/run.cpp ] && return 0; return 1 ;;
    toml.hpp) case "$2" in src/io/scene_impl.h|src/io/scene.cpp) return 0 ;; esac; return 1 ;;
    gsl/*) [ "$1" = src/theory ] && return 0 # the keyed multinomial split (GSRD and cell-DSMC creation): gsl_ran_binomial
      case "$2" in src/core/keyed.h|src/core/keyed.cpp) return 0 ;; esac; return 1 ;;
    fftw3.h) case "$1" in src/analysis|src/srd) return 0 ;; esac; return 1 ;;
    fftw3-mpi.h) [ "$2" = src/cli/mpi.cpp ] ;; # with MPI: the distributed transform of a split gas's S(k)
    mpi.h) [ "$2" = src/cli/mpi.cpp ] ;;
    cuda*.h|cufft*.h|curand*.h) [ "$1" = cuda ] ;;
    *) return 0 ;;
  esac
}
n=0
for f in $(find src cuda -type f \( -name '*.cpp' -o -name '*.h' -o -name '*.cu' -o -name '*.inc' \) | sort); do
  dir=$(dirname "$f")
  rules=$(allowed "$dir")
  if [ "$rules" = "?" ]; then echo "FAIL: $f: folder $dir has no layer rule (add it to t006 and ARCHITECTURE.md)"; fail=1; continue; fi
  own=${dir#src/}/
  [ "$dir" = cuda ] && own=../cuda/
  grep -o '^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"][^>"]*[>"]' "$f" | sed 's/.*include[[:space:]]*//' > /tmp/t006.$$ || true
  while read -r inc; do
    n=$((n + 1))
    name=$(echo "$inc" | sed 's/^[<"]//; s/[>"]$//')
    case "$inc" in
      \"*)
        case "$name" in granary.h|granary_impl.h|"$own"*) continue ;; esac
        case "$name" in */*) ;; *) continue ;; esac # a header beside the file (cuda/srd_cuda.h, ...)
        ok=0
        for r in $rules; do case "$name" in "$r"*) ok=1 ;; esac; done
        [ $ok = 1 ] || { echo "FAIL: $f includes \"$name\": $dir may include only: ${rules:-(its own folder)}"; fail=1; } ;;
      *)
        ext_ok "$dir" "$f" "$name" || { echo "FAIL: $f includes <$name>: that dependency belongs to another layer"; fail=1; } ;;
    esac
  done < /tmp/t006.$$
  rm -f /tmp/t006.$$
done
[ $fail = 0 ] || exit 1
echo "ok: $n includes of src/ and cuda/ follow the layer rules"
