# granary - one non-recursive Makefile.
#   make run     build and run the default scene          make test       build and run every test
#   make all     libraries + command-line driver          make test-asan  the tests under ASan+UBSan
#   make bench   speed / accuracy-versus-cost tables      make test-gpu   GPU tests (needs a GPU)
#   make install prefix=... DESTDIR=...                   make deps       install Debian packages
#   make fuzz    libFuzzer harnesses (FUZZ_SECONDS=60)    make doc-numbers  regenerate docs/numbers.md
#   make info    show the configuration                   make clean      remove build folders
#   make docs    the HTML manual in build/docs/html
#   make help    this text                                make figures    seed figures as PNG (QUICK=1)
# Override OPT (default -O3 -march=native: tuned for the building CPU), NVCC (empty disables CUDA),
# CUDA_ARCH / CUDA_PTX (default: the visible GPU's SM, else PTX compute_80 only; all four GPUs:
# CUDA_ARCH="80 90 100 120"), BUILD (build folder), T (test patterns: T='t2* t52*').
# Builds and tests run on every core unless -jN is given (make -j1: one at a time); ccache is used
# for CC/CXX when it is installed. The Fortran raw layer, the gran_abi_query table and t901's list
# are generated from include/granary.h: after changing the header run python3 bindings/gen_raw.py
# (make fails while they are stale).
# HELP_END

# Parallel by default: -j<cores> unless the command line gives -j (GNU make 4.3 lets a command-line
# -j win; make 4.4 shows it in MAKEFLAGS). Only the top-level make adds it: sub-makes share its
# jobserver.
NPROC := $(shell nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)
ifeq ($(MAKELEVEL)$(filter -j%,$(MAKEFLAGS)),0)
MAKEFLAGS += -j$(NPROC)
endif

BUILD   ?= build
prefix  ?= /usr/local
DESTDIR ?=
# ccache in front of the C and C++ compilers when it is installed (not required).
CCACHE  := $(shell command -v ccache 2>/dev/null)
CC      := $(if $(CCACHE),ccache )gcc
CXX     := $(if $(CCACHE),ccache )g++
FC      := gfortran
OPT     ?= -O3 -march=native
SAN     ?=
# CUDA: probe nvcc on PATH, then in /usr/local/cuda/bin. `make NVCC=` builds without CUDA.
NVCC    ?= $(firstword $(shell command -v nvcc 2>/dev/null) $(wildcard /usr/local/cuda/bin/nvcc))
CUDA_HOME ?= $(patsubst %/bin/nvcc,%,$(NVCC))
# ---- CUDA block (owner: cuda backend) ----
# CUDA_ARCH: SM numbers to build cubins for (A100 = 80, H100/H200 = 90, B200 = 100, RTX PRO/50xx =
# 120); CUDA_PTX: those whose PTX is embedded for JIT on later GPUs. Default: the SM of each visible
# GPU (nvidia-smi) that this nvcc supports, with its PTX; without a visible GPU no cubin and the PTX
# of compute_80 (or the lowest this nvcc has above it), which the driver compiles at the first
# launch on any GPU from A100 on. CUDA_PTX defaults to the last of CUDA_ARCH when CUDA_ARCH is
# given. `make CUDA_ARCH="80 90 100 120"` builds the fat binary for all four.
ifeq ($(origin CUDA_ARCH),undefined)
ifneq ($(NVCC),)
CUDA_GPU_SM := $(shell timeout 20 nvidia-smi --query-gpu=compute_cap --format=csv,noheader 2>/dev/null | tr -d ' .' | grep -E '^[0-9]+$$' | sort -un)
CUDA_ARCH := $(filter $(shell $(NVCC) --list-gpu-code 2>/dev/null | sed -n 's/^sm_//p'),$(CUDA_GPU_SM))
endif
endif
CUDA_PTX_LOW := $(if $(NVCC),$(or $(firstword $(shell $(NVCC) --list-gpu-arch 2>/dev/null | sed -n 's/^compute_//p' | awk '$$1 >= 80' | sort -n)),80),80)
CUDA_PTX  ?= $(if $(strip $(CUDA_ARCH)),$(lastword $(CUDA_ARCH)),$(CUDA_PTX_LOW))
# one -gencode per virtual architecture: code=sm_A for each of CUDA_ARCH, code=compute_A for each of
# CUDA_PTX (front end run once per architecture)
comma := ,
empty :=
space := $(empty) $(empty)
CUDA_CODES = $(strip $(if $(filter $(1),$(CUDA_ARCH)),sm_$(1)) $(if $(filter $(1),$(CUDA_PTX)),compute_$(1)))
CUDA_GENCODE := $(foreach a,$(sort $(CUDA_ARCH) $(CUDA_PTX)),-gencode 'arch=compute_$(a)$(comma)code=[$(subst $(space),$(comma),$(call CUDA_CODES,$(a)))]')
CUDA_ARCH_STR := $(strip $(foreach a,$(CUDA_ARCH),sm_$(a)) $(foreach a,$(CUDA_PTX),compute_$(a)))
# cuFFT (S(k) of GSRD runs on the GPU): the toolkit ships it as a shared library only.
CUDA_FFT_LIBS = -lcufft -Wl,-rpath,$(CUDA_HOME)/lib64
# ---- end CUDA block ----

PKGS     := gsl fftw3 hdf5 cmocka zlib
DEB_PKGS := pkg-config zlib1g-dev libgsl-dev libfftw3-dev libhdf5-dev libcmocka-dev libtoml11-dev gfortran libopenmpi-dev openmpi-bin libfftw3-mpi-dev
DEPS_OK   = pkg-config --exists $(PKGS) 2>/dev/null && [ -f /usr/include/toml.hpp ] && command -v $(FC) >/dev/null 2>&1

# ---- configuration, cached in $(BUILD)/config.mk (installs missing packages first) ------------
CONFIG := $(BUILD)/config.mk
NOCONFIG_GOALS := clean deps info help
ifeq ($(filter $(NOCONFIG_GOALS),$(MAKECMDGOALS)),)
include $(CONFIG)
endif

# PKG_LIBS: -lhdf5_hl (HDF5's high-level library, part of libhdf5-dev) for the dimension scales of
# the output file (H5DS); it has no pkg-config file of its own in Debian. The file is rewritten
# only when its text changes: an edit of this Makefile rebuilds only what its flags change
# ($(FLAGS_STAMP) below), not everything.
$(CONFIG): Makefile
	@mkdir -p $(@D)
	@if ! ( $(DEPS_OK) ); then $(MAKE) --no-print-directory deps; fi
	@( $(DEPS_OK) ) || { echo "granary: dependencies still missing (see 'make deps')" >&2; exit 1; }
	@echo "PKG_CFLAGS := $$(pkg-config --cflags $(PKGS))" > $@.tmp
	@echo "PKG_LIBS := -lhdf5_hl $$(pkg-config --libs gsl fftw3 hdf5 zlib)" >> $@.tmp
	@echo "CMOCKA_LIBS := $$(pkg-config --libs cmocka)" >> $@.tmp
	@if cmp -s $@.tmp $@; then rm -f $@.tmp; else mv $@.tmp $@; fi

# $(call apt_install,PACKAGES,WHO,ON_FAIL): apt-get install -y as root or with password-less sudo,
# once more after an `apt-get update` when the package lists are stale; without either, print the
# command to run and do ON_FAIL (exit 1: the target needs them; exit 0: optional). One shell line.
apt_install = if [ "$$(id -u)" = 0 ]; then SUDO=; elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then SUDO=sudo; \
	  else echo "$(2) needs Debian packages it cannot install without root. Run: sudo apt-get install -y $(1)" >&2; $(3); fi; \
	  echo "$(2): installing $(1)$${SUDO:+ with sudo}"; \
	  $$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q $(1) >/dev/null || \
	  { $$SUDO apt-get update -q >/dev/null && $$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q $(1) >/dev/null; }

deps:
	@if ( $(DEPS_OK) ); then echo "deps: everything granary needs is installed"; \
	else $(call apt_install,$(DEB_PKGS),deps,exit 1); fi

# ---- flags ------------------------------------------------------------------------------------
WARN       := -Wall -Wextra
CUDA_FLAG  := $(if $(NVCC),-DGRAN_HAVE_CUDA=1,)
# The configuration `granary info` prints ("key=value; ..."), and the CUDA code generation; each is
# kept in a stamp file under $(BUILD) that is rewritten when it changes, so that the objects that use
# it are rebuilt (errors.o for the first, cuda/*.o for the second).
CXX_NAME := $(filter-out ccache %/ccache,$(CXX))
BUILD_CONFIG_STR := cxx=$(CXX_NAME) $(shell $(CXX_NAME) -dumpfullversion 2>/dev/null); opt=$(OPT)$(if $(SAN),; san=$(SAN),); \
  cuda=$(if $(NVCC),nvcc $(shell $(NVCC) --version 2>/dev/null | sed -n 's/.*release \([0-9.]*\).*/\1/p'),no)$(if $(NVCC),; cuda_arch=$(CUDA_ARCH_STR))
# $(call stamp,FILE,TEXT): write TEXT to FILE unless it holds it already (at parse time).
stamp = $(shell mkdir -p $(dir $(1)) && { [ "$$(cat $(1) 2>/dev/null)" = '$(2)' ] || printf '%s\n' '$(2)' > $(1); })
BUILD_CONFIG_STAMP := $(BUILD)/stamp/build-config
CUDA_STAMP := $(BUILD)/stamp/cuda-gencode
ifeq ($(filter $(NOCONFIG_GOALS),$(MAKECMDGOALS)),)
$(call stamp,$(BUILD_CONFIG_STAMP),$(BUILD_CONFIG_STR))
$(call stamp,$(CUDA_STAMP),$(CUDA_GENCODE))
endif
CPPFLAGS   := -Iinclude -Isrc $(CUDA_FLAG)
CXXFLAGS   := -std=c++17 $(OPT) $(SAN) $(WARN) -fPIC -fvisibility=hidden -MMD -MP
CFLAGS     := -std=c99 $(OPT) $(SAN) $(WARN) -MMD -MP
FFLAGS     := -std=f2008 $(OPT) $(SAN) -Wall -Wextra -Wno-compare-reals -J$(BUILD)/mod -I$(BUILD)/mod
NVCCFLAGS  := -std=c++17 -O3 $(CUDA_GENCODE) -Xcompiler -fPIC,-fvisibility=hidden,-Wall,-Wextra
CUDA_LIBS  := $(if $(NVCC),-L$(CUDA_HOME)/lib64 $(CUDA_FFT_LIBS) -lcudart_static -ldl -lrt -lpthread,)
LDLIBS      = $(PKG_LIBS) $(CUDA_LIBS) -lstdc++ -lm -lpthread
# OpenMP: the replicas of the run driver (src/io/run.cpp) and the GSRD engine (src/srd/).
# `make OMP_FLAG=` builds without (one thread).
OMP_FLAG   ?= -fopenmp
CXXFLAGS   += $(OMP_FLAG)
LDLIBS     += $(OMP_FLAG)
# The compilers and flags every object is built with, in a stamp rewritten when they change (the
# objects depend on it, so a changed flag rebuilds them and an unrelated Makefile edit does not).
SCENE_OPT  ?= $(if $(filter -O2 -O3,$(OPT)),-O1,)
FLAGS_STAMP := $(BUILD)/stamp/flags
ifeq ($(filter $(NOCONFIG_GOALS),$(MAKECMDGOALS)),)
$(call stamp,$(FLAGS_STAMP),$(CXX_NAME) $(CPPFLAGS) $(CXXFLAGS) [scenes $(SCENE_OPT)]; $(CC) $(CFLAGS); $(FC) $(FFLAGS); $(NVCC) $(NVCCFLAGS); $(LDLIBS))
endif

# ---- sources ----------------------------------------------------------------------------------
LIB_SRC  := $(sort $(wildcard src/core/*.cpp src/theory/*.cpp src/dsmc/*.cpp src/analysis/*.cpp src/io/*.cpp src/srd/*.cpp))
CLI_SRC  := $(sort $(wildcard src/cli/*.cpp))
CU_SRC   := $(if $(NVCC),$(sort $(wildcard cuda/*.cu)),cuda/stub.cpp)
# Built longest first (the CUDA objects, then the sources by size), so that a parallel build does not
# end on one long compile while the other cores idle; the order of the archive does not matter.
LIB_OBJ  := $(patsubst %,$(BUILD)/obj/%.o,$(basename $(shell ls -S $(CU_SRC)))) \
            $(patsubst %.cpp,$(BUILD)/obj/%.o,$(shell ls -S $(LIB_SRC)))
CLI_OBJ  := $(CLI_SRC:%.cpp=$(BUILD)/obj/%.o)
FMOD_SRC := bindings/granary.f90
FMOD_OBJ := $(BUILD)/obj/bindings/granary.o
# The raw layer of the Fortran module (constants, bind(C) types, interfaces), the gran_abi_query
# table and t901-layout-f's list, generated from include/granary.h by bindings/gen_raw.py.
GEN_RAW     := bindings/gen_raw.py
GEN_RAW_OUT := bindings/granary_raw.inc src/core/abi_table.inc tests/t901-layout-f.inc include/granary.abi
# the module the Fortran tests share (expect, require, test_finish)
FTEST_OBJ := $(BUILD)/obj/tests/granary_test_f.o

LIB_A    := $(BUILD)/libgranary.a
# Shared library: SONAME libgranary.so.ABI (GRAN_ABI_VERSION: the rules in docs/developers/abi.md),
# file libgranary.so.MAJOR.MINOR.PATCH (the release), and the links libgranary.so ->
# libgranary.so.ABI -> the file (ldconfig style), in $(BUILD) as in the installation, so that a
# program linked with -L$(BUILD) -lgranary finds its SONAME there.
VERSION  := $(shell sed -n 's/^\#define GRAN_VERSION_STRING "\(.*\)"/\1/p' include/granary.h)
SOMAJOR  := $(shell sed -n 's/^\#define GRAN_ABI_VERSION \([0-9]*\)$$/\1/p' include/granary.h)
SONAME   := libgranary.so.$(SOMAJOR)
LIB_SO   := $(BUILD)/libgranary.so
LIB_SO_FILE := $(BUILD)/libgranary.so.$(VERSION)
LIBF_A   := $(BUILD)/libgranary_fortran.a
CLI      := $(BUILD)/granary

# T selects tests by pattern: `make test T='t4*'` builds and runs only tests/t4*.
T        ?= t*
TEST_C   := $(sort $(wildcard $(patsubst %,tests/%.c,$(T))))
TEST_F   := $(sort $(filter %-f.f90,$(wildcard $(patsubst %,tests/%.f90,$(T)))))
EXAMPLES := $(if $(filter t*,$(T)),$(if $(filter-out t*,$(T)),,$(sort $(wildcard bindings/examples/*.c bindings/examples/*.f90))),)
TEST_BIN := $(TEST_C:tests/%.c=$(BUILD)/tests/%) $(TEST_F:tests/%.f90=$(BUILD)/tests/%) \
            $(patsubst bindings/examples/%.c,$(BUILD)/tests/example-c-%,$(filter %.c,$(EXAMPLES))) \
            $(patsubst bindings/examples/%.f90,$(BUILD)/tests/example-f-%,$(filter %.f90,$(EXAMPLES)))
BENCH_C  := $(sort $(wildcard bench/b*.c))
BENCH_BIN:= $(BENCH_C:bench/%.c=$(BUILD)/bench/%)
GPU_TEST_C := $(sort $(wildcard tests/gpu/t*.c))
GPU_TEST_BIN := $(GPU_TEST_C:tests/gpu/%.c=$(BUILD)/tests/gpu/%)

.PHONY: all lib so-links run test test-asan test-gpu bench-gpu bench install deps info clean help check-header fuzz doc-numbers \
        check-generated
.DEFAULT_GOAL := all

all: $(LIB_A) $(LIB_SO) $(LIBF_A) $(CLI) check-header check-generated

# ---- compile ----------------------------------------------------------------------------------
$(BUILD)/obj/%.o: %.cpp $(CONFIG) $(FLAGS_STAMP)
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(PKG_CFLAGS) $(CXXFLAGS) -c $< -o $@

# The scene parsers (toml11's templates, run once per scene) are on no hot path: at -O1 they build
# in half the time of -O3 (the largest objects of the library); `make SCENE_OPT=` keeps $(OPT).
SCENE_OBJ := $(BUILD)/obj/src/io/scene.o $(BUILD)/obj/src/dsmc/scene_dsmc.o $(BUILD)/obj/src/srd/scene_srd.o
$(SCENE_OBJ): CXXFLAGS += $(SCENE_OPT)

$(BUILD)/obj/src/core/errors.o: CPPFLAGS += -DGRAN_BUILD_CONFIG='"$(BUILD_CONFIG_STR)"'
$(BUILD)/obj/src/core/errors.o: $(BUILD_CONFIG_STAMP)

$(BUILD)/obj/cuda/%.o: cuda/%.cu $(CONFIG) $(FLAGS_STAMP) $(CUDA_STAMP) include/granary.h src/granary_impl.h src/core/xoshiro.h $(wildcard cuda/*.h src/srd/*.h)
	@mkdir -p $(@D)
	$(NVCC) $(CPPFLAGS) $(NVCCFLAGS) -c $< -o $@

$(FMOD_OBJ): $(FMOD_SRC) bindings/granary_raw.inc $(CONFIG) $(FLAGS_STAMP)
	@mkdir -p $(@D) $(BUILD)/mod
	$(FC) $(FFLAGS) -c $< -o $@

$(LIB_A): $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(LIB_SO_FILE): $(LIB_OBJ)
	$(CXX) -shared $(SAN) -Wl,-soname,$(SONAME) -o $@ $^ $(LDLIBS)

# The links are checked on every make, not only when the library file is relinked: a build folder
# that holds links of another version (or none) gets them right without a relink.
$(LIB_SO): $(LIB_SO_FILE) so-links
so-links: $(LIB_SO_FILE)
	@[ "$$(readlink $(BUILD)/$(SONAME))" = "$(notdir $(LIB_SO_FILE))" ] || ln -sfn $(notdir $(LIB_SO_FILE)) $(BUILD)/$(SONAME)
	@[ "$$(readlink $(LIB_SO))" = "$(SONAME)" ] || ln -sfn $(SONAME) $(LIB_SO)

$(LIBF_A): $(FMOD_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(CLI): $(CLI_OBJ) $(LIB_A)
	$(CXX) $(SAN) -o $@ $(CLI_OBJ) $(LIB_A) $(LDLIBS)

# The public header must be valid C99 on its own (and C++17: every src/ file includes it).
check-header: $(BUILD)/check/header-c99.o
$(BUILD)/check/header-c99.o: include/granary.h $(CONFIG) $(FLAGS_STAMP)
	@mkdir -p $(@D)
	$(CC) -std=c99 -pedantic-errors $(WARN) -Iinclude -x c -c $< -o $@

# The generated files must be what bindings/gen_raw.py makes of the current header (checked when
# the header, the script or a generated file changes; skipped with a note without python3).
check-generated: $(BUILD)/stamp/generated-current
$(BUILD)/stamp/generated-current: include/granary.h $(GEN_RAW) $(GEN_RAW_OUT) bindings/granary.f90
	@mkdir -p $(@D)
	@if command -v python3 >/dev/null 2>&1; then \
	  python3 $(GEN_RAW) --check || { echo "make: the generated files are stale; run: python3 $(GEN_RAW)" >&2; exit 1; }; \
	else echo "note: python3 not found; not checking that $(GEN_RAW_OUT) are current"; fi
	@touch $@

# ---- tests ------------------------------------------------------------------------------------
$(BUILD)/tests/%: tests/%.c tests/granary_test.h $(LIB_A)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(PKG_CFLAGS) -Itests -Icuda $(CFLAGS) -o $@ $< $(LIB_A) $(CMOCKA_LIBS) $(LDLIBS)

$(FTEST_OBJ): tests/granary_test_f.f90 $(CONFIG) $(FLAGS_STAMP)
	@mkdir -p $(@D) $(BUILD)/mod
	$(FC) $(FFLAGS) -c $< -o $@

$(BUILD)/tests/%-f: tests/%-f.f90 $(FTEST_OBJ) $(LIBF_A) $(LIB_A)
	@mkdir -p $(@D)
	$(FC) $(FFLAGS) -o $@ $< $(FTEST_OBJ) $(LIBF_A) $(LIB_A) $(LDLIBS)

$(BUILD)/tests/t901-layout-f: tests/t901-layout-f.inc

$(BUILD)/tests/example-c-%: bindings/examples/%.c $(LIB_A)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -o $@ $< $(LIB_A) $(LDLIBS)

$(BUILD)/tests/example-f-%: bindings/examples/%.f90 $(LIBF_A) $(LIB_A)
	@mkdir -p $(@D)
	$(FC) $(FFLAGS) -o $@ $< $(LIBF_A) $(LIB_A) $(LDLIBS)

$(BUILD)/tests/gpu/%: tests/gpu/%.c tests/granary_test.h $(LIB_A)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(PKG_CFLAGS) -Itests -Icuda $(CFLAGS) -o $@ $< $(LIB_A) $(CMOCKA_LIBS) $(LDLIBS)

# Script tests (tests/tNNN-*.sh) run beside the programs: the install test builds the README's
# examples against a temporary installation, through pkg-config.
TEST_SH  := $(sort $(wildcard $(patsubst %,tests/%.sh,$(T))))

# The runner runs as many tests at once as make runs jobs (-jN; default and plain -j: the cores).
test: $(TEST_BIN) $(CLI) check-header check-generated $(LIB_SO) $(LIBF_A)
	@GRAN_TEST_JOBS=$(or $(patsubst -j%,%,$(filter -j%,$(MAKEFLAGS))),$(NPROC)) GRAN_SOURCE_DIR=$(CURDIR) GRAN_BUILD=$(BUILD) GRAN_SAN="$(SAN)" GRAN_OPT="$(OPT)" GRAN_NVCC="$(NVCC)" \
	  GRAN_CLI=$(CURDIR)/$(CLI) sh tests/run-tests.sh $(TEST_BIN) $(TEST_SH)

# The same tests under AddressSanitizer + UndefinedBehaviorSanitizer, in their own build folder
# (CUDA off: the CUDA runtime is not built for the sanitizers).
test-asan:
	@$(MAKE) --no-print-directory BUILD=build-asan NVCC= OPT="-O1 -g -fno-omit-frame-pointer" \
	  SAN="-fsanitize=address,undefined -fno-sanitize-recover=all" test

# test-gpu / bench-gpu (CUDA block): one command each; output also in $(BUILD)/gpu-results/*.txt.
test-gpu: $(GPU_TEST_BIN) $(CLI)
	@mkdir -p $(BUILD)/gpu-results; n=0; [ -x $(CLI) ] && n=$$($(CLI) info --gpu-count 2>/dev/null || echo 0); \
	if [ "$(NVCC)" = "" ]; then echo "test-gpu: CUDA was not compiled (no nvcc); nothing to run" | tee $(BUILD)/gpu-results/test-gpu.txt; \
	elif [ "$$n" = "0" ]; then echo "test-gpu: no GPU visible on this machine; nothing to run" | tee $(BUILD)/gpu-results/test-gpu.txt; \
	else GRAN_SOURCE_DIR=$(CURDIR) sh tests/run-tests.sh $(GPU_TEST_BIN) > $(BUILD)/gpu-results/test-gpu.txt 2>&1; rc=$$?; \
	  cat $(BUILD)/gpu-results/test-gpu.txt; exit $$rc; fi

GPU_BENCH_C   := $(sort $(wildcard bench/gpu/b*.c))
GPU_BENCH_BIN := $(GPU_BENCH_C:bench/gpu/%.c=$(BUILD)/bench/gpu/%)
$(BUILD)/bench/gpu/%: bench/gpu/%.c bench/bench_util.h $(LIB_A)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(PKG_CFLAGS) -Ibench -Icuda $(CFLAGS) -o $@ $< $(LIB_A) $(LDLIBS)

bench-gpu: $(GPU_BENCH_BIN) $(CLI)
	@mkdir -p $(BUILD)/gpu-results; n=0; [ -x $(CLI) ] && n=$$($(CLI) info --gpu-count 2>/dev/null || echo 0); \
	if [ "$(NVCC)" = "" ]; then echo "bench-gpu: CUDA was not compiled (no nvcc); nothing to run" | tee $(BUILD)/gpu-results/bench-gpu.txt; \
	elif [ "$$n" = "0" ]; then echo "bench-gpu: no GPU visible on this machine; nothing to run" | tee $(BUILD)/gpu-results/bench-gpu.txt; \
	else rc=0; for b in $(GPU_BENCH_BIN); do echo "== $$b"; GRAN_SOURCE_DIR=$(CURDIR) $$b || { rc=1; break; }; done \
	  > $(BUILD)/gpu-results/bench-gpu.txt 2>&1; cat $(BUILD)/gpu-results/bench-gpu.txt; exit $$rc; fi

# ---- bench ------------------------------------------------------------------------------------
$(BUILD)/bench/%: bench/%.c bench/bench_util.h $(LIB_A)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(PKG_CFLAGS) -Ibench $(CFLAGS) -o $@ $< $(LIB_A) $(LDLIBS)

bench: $(BENCH_BIN) $(CLI)
	@for b in $(BENCH_BIN); do echo "== $$b"; GRAN_SOURCE_DIR=$(CURDIR) $$b || exit 1; done

# ---- fuzz -------------------------------------------------------------------------------------
# libFuzzer harnesses (fuzz/fuzz_NAME.c or .cc): the scene parser and the file readers (scene,
# resume) and the engines (run_scene: every engine run a few steps; checkpoint: checkpoints edited
# value by value with their checksums recomputed; options: the option structs of gran_srd_create
# and gran_dsmc_create_cell/_agg), built with clang (Debian's clang and libclang-rt-dev) under
# ASan+UBSan in build-fuzz/; each runs for FUZZ_SECONDS (FUZZ_ONLY=NAME: that one only) from the
# seed corpus in fuzz/corpus/NAME (and the dictionary fuzz/NAME.dict where there is one) plus, for
# scene and run_scene, every scene of scenes/ (new inputs
# go to build-fuzz/corpus/NAME, crashes to build-fuzz/artifacts/NAME-*; fuzz/lsan.supp: libomp's
# thread pool, which lives until exit). FUZZ_ARGS: more libFuzzer
# options (e.g. -fork=1 -ignore_crashes=1 to go on after a finding).
FUZZ_SECONDS ?= 60
FUZZ_ONLY    ?=
FUZZ_ARGS    ?=
FUZZ_DEB_PKGS := clang libclang-rt-dev
FUZZ_BUILD   := build-fuzz
FUZZ_SAN     := -fsanitize=address,undefined -fno-sanitize-recover=all
FUZZ_NAMES   := $(sort $(patsubst fuzz/fuzz_%.c,%,$(wildcard fuzz/fuzz_*.c)) $(patsubst fuzz/fuzz_%.cc,%,$(wildcard fuzz/fuzz_*.cc)))
FUZZ_RUN     := $(or $(FUZZ_ONLY),$(FUZZ_NAMES))
FUZZ_SCENES  := $(wildcard scenes/*.toml scenes/*/*.toml)

fuzz:
	@for n in $(FUZZ_RUN); do case " $(FUZZ_NAMES) " in *" $$n "*) ;; \
	  *) echo "make fuzz: FUZZ_ONLY=$$n: no fuzz/fuzz_$$n.c(c) (harnesses: $(FUZZ_NAMES))" >&2; exit 1;; esac; done
	@if ! command -v clang >/dev/null 2>&1; then $(call apt_install,$(FUZZ_DEB_PKGS),fuzz,exit 1); fi
	@command -v clang >/dev/null 2>&1 || { echo "make fuzz: clang still missing ($(FUZZ_DEB_PKGS))" >&2; exit 1; }
	@$(MAKE) --no-print-directory BUILD=$(FUZZ_BUILD) NVCC= CC=clang CXX=clang++ OPT="-O1 -g" \
	  SAN="$(FUZZ_SAN) -fsanitize=fuzzer-no-link" $(FUZZ_BUILD)/libgranary.a
	@mkdir -p $(FUZZ_BUILD)/artifacts
	@set -e; libs="$$(sed -n 's/^PKG_LIBS := //p' $(FUZZ_BUILD)/config.mk)"; \
	cflags="$$(sed -n 's/^PKG_CFLAGS := //p' $(FUZZ_BUILD)/config.mk)"; \
	for n in $(FUZZ_RUN); do \
	  if [ -f fuzz/fuzz_$$n.cc ]; then \
	    clang++ -std=c++17 -Iinclude -Isrc $$cflags -Wall -Wextra $(FUZZ_SAN) -fsanitize=fuzzer -fopenmp -g -O1 \
	      -c fuzz/fuzz_$$n.cc -o $(FUZZ_BUILD)/fuzz_$$n.o; \
	  else \
	    clang -Iinclude -Wall -Wextra $(FUZZ_SAN) -fsanitize=fuzzer -g -O1 -c fuzz/fuzz_$$n.c -o $(FUZZ_BUILD)/fuzz_$$n.o; \
	  fi; \
	  clang++ $(FUZZ_SAN) -fsanitize=fuzzer -fopenmp $(FUZZ_BUILD)/fuzz_$$n.o $(FUZZ_BUILD)/libgranary.a \
	    $$libs -lm -lpthread -o $(FUZZ_BUILD)/fuzz_$$n; \
	  mkdir -p $(FUZZ_BUILD)/corpus/$$n fuzz/corpus/$$n; \
	  case $$n in scene|run_scene) for f in $(FUZZ_SCENES); do \
	    cp -p $$f $(FUZZ_BUILD)/corpus/$$n/$$(echo $$f | tr / -); done;; esac; \
	  dict=; if [ -f fuzz/$$n.dict ]; then dict=-dict=fuzz/$$n.dict; fi; \
	  echo "== fuzz_$$n for $(FUZZ_SECONDS) s"; \
	  OMP_NUM_THREADS=1 LSAN_OPTIONS=suppressions=$(CURDIR)/fuzz/lsan.supp $(FUZZ_BUILD)/fuzz_$$n -max_total_time=$(FUZZ_SECONDS) -timeout=30 -rss_limit_mb=4096 \
	    -max_len=65536 -artifact_prefix=$(FUZZ_BUILD)/artifacts/$$n- -print_final_stats=1 $$dict $(FUZZ_ARGS) \
	    $(FUZZ_BUILD)/corpus/$$n fuzz/corpus/$$n 2>&1 | tail -n 25; \
	done

# The measured numbers README and the scene comments quote: docs/numbers.md, from one command.
doc-numbers: all
	@GRAN_CLI=$(CLI) sh bench/doc-numbers.sh docs/numbers.md

# ---- docs -------------------------------------------------------------------------------------
# `make docs` builds the HTML manual in $(BUILD)/docs/html from docs/ (Sphinx with MyST Markdown)
# and include/granary.h (Doxygen XML read by Breathe, through docs/tools/header_filter.py); every
# warning is an error (-W). The scene-key page is generated into the build copy of docs/ from
# `granary keys --format markdown` (docs/tools/scene-keys.sh), the Fortran procedure list from
# bindings/granary.f90 (docs/tools/fortran_ref.py). Missing Debian packages
# (DOCS_DEB_PKGS) are installed as `make deps` does. Debian's /usr/bin/python3 runs Sphinx.
DOCS_DEB_PKGS := python3-sphinx python3-myst-parser python3-breathe doxygen
DOCS_PYTHON   ?= /usr/bin/python3
DOCS_OUT      := $(BUILD)/docs
DOCS_OK        = $(DOCS_PYTHON) -c 'import sphinx, myst_parser, breathe' >/dev/null 2>&1 && command -v doxygen >/dev/null 2>&1

.PHONY: docs
docs: $(CLI)
	@if ! ( $(DOCS_OK) ); then $(call apt_install,$(DOCS_DEB_PKGS),docs,exit 1); fi
	@( $(DOCS_OK) ) || { echo "docs: $(DOCS_PYTHON) cannot import sphinx, myst_parser, breathe or doxygen is missing ($(DOCS_DEB_PKGS))" >&2; exit 1; }
	@rm -rf $(DOCS_OUT)/src $(DOCS_OUT)/xml && mkdir -p $(DOCS_OUT)
	@cp -R docs $(DOCS_OUT)/src
	@mkdir -p $(DOCS_OUT)/src/_examples && cp bindings/examples/example.c bindings/examples/example.f90 $(DOCS_OUT)/src/_examples/
	@sh docs/tools/scene-keys.sh $(CLI) > $(DOCS_OUT)/src/reference/scene-keys.md
	@$(DOCS_PYTHON) docs/tools/fortran_ref.py $(FMOD_SRC) > $(DOCS_OUT)/src/reference/fortran-procedures.md
	@( cat docs/Doxyfile; echo "OUTPUT_DIRECTORY = $(DOCS_OUT)" ) | doxygen -
	@GRAN_SOURCE_DIR=$(CURDIR) GRAN_DOXYGEN_XML=$(CURDIR)/$(DOCS_OUT)/xml \
	  $(DOCS_PYTHON) -m sphinx -W --keep-going -q -b html $(DOCS_OUT)/src $(DOCS_OUT)/html
	@echo "docs: $(DOCS_OUT)/html/index.html"

# make install copies the HTML manual to $(prefix)/share/granary/doc/html when `make docs` has built it.
.PHONY: install-docs
install: install-docs
install-docs:
	@if [ -f $(DOCS_OUT)/html/index.html ]; then install -d $(DESTDIR)$(prefix)/share/granary/doc/html && \
	  cp -R $(DOCS_OUT)/html/. $(DESTDIR)$(prefix)/share/granary/doc/html/ && \
	  echo "install: the manual in $(DESTDIR)$(prefix)/share/granary/doc/html"; \
	else echo "install: no HTML manual in $(DOCS_OUT)/html (make docs builds it); not installed"; fi

# ---- figures ----------------------------------------------------------------------------------
# `make figures` regenerates Figs. 1-8 and Table I of Bodrova & Osinsky (2024) as PNG in
# build/figures/ (QUICK=1: the reduced scenes of scenes/quick/, a few minutes). Plotting needs
# Debian's python3-matplotlib and python3-h5py (FIG_DEB_PKGS, installed by `make deps` when
# possible and by `make figures`); they are not needed to build or test granary (the reader test
# skips without h5py). Debian's /usr/bin/python3 is used on purpose: another python3 on PATH may
# lack Debian's modules.
FIG_DEB_PKGS := python3-matplotlib python3-h5py python3-numpy
FIG_PYTHON   ?= /usr/bin/python3
FIG_OUT      ?= $(BUILD)/figures
FIG_OK        = $(FIG_PYTHON) -c 'import matplotlib, h5py, numpy' >/dev/null 2>&1
FIG_INSTALL   = $(call apt_install,$(FIG_DEB_PKGS),figures,exit 1)

.PHONY: figures figures-deps figures-deps-soft
figures: figures-deps all
	$(FIG_PYTHON) figures/make_figures.py $(if $(QUICK),--quick) --granary $(CLI) --out $(FIG_OUT)
	$(FIG_PYTHON) figures/make_srd_figures.py $(if $(QUICK),--quick) --granary $(CLI) --out $(FIG_OUT)

figures-deps:
	@if ! ( $(FIG_OK) ); then $(FIG_INSTALL); fi
	@( $(FIG_OK) ) || { echo "figures: $(FIG_PYTHON) cannot import matplotlib, h5py, numpy ($(FIG_DEB_PKGS))" >&2; exit 1; }

# `make deps` also tries the plotting packages, without failing when it cannot install them.
deps: figures-deps-soft
figures-deps-soft:
	@if ! ( $(FIG_OK) ); then ( $(FIG_INSTALL) ) || echo "deps: plotting packages not installed (only make figures needs them)"; fi

# ---- MPI block (owner: replicas over MPI) ------------------------------------------------------
# build/granary-mpi: the same driver compiled by mpicxx with -DGRAN_MPI (src/cli/mpi.cpp), built
# when an MPI compiler wrapper is found (Debian: libopenmpi-dev openmpi-bin; `make deps` tries
# them). `mpirun -n P build/granary-mpi run SCENE` spreads the replicas over P processes. The
# libraries and build/granary never link MPI (src/io/run_comm.h says how). `make MPICXX=` skips it.
# FFTW's MPI interface (Debian libfftw3-mpi-dev) gives `granary decompose --sk` its distributed
# transform; without it build/granary-mpi refuses S(k) of a gas split over processes.
MPI_DEB_PKGS := libopenmpi-dev openmpi-bin libfftw3-mpi-dev
MPICXX   ?= $(shell command -v mpicxx 2>/dev/null)
CLI_MPI  := $(if $(MPICXX),$(BUILD)/granary-mpi,)
CLI_MPI_OBJ := $(CLI_SRC:%.cpp=$(BUILD)/obj-mpi/%.o)
FFTW_MPI := $(if $(MPICXX),$(shell printf '\043include <fftw3-mpi.h>\n' | $(MPICXX) -E -x c++ - >/dev/null 2>&1 && echo 1),)
CLI_MPI_DEFS := $(if $(FFTW_MPI),-DGRAN_HAVE_FFTW_MPI,)
CLI_MPI_LIBS := $(if $(FFTW_MPI),-lfftw3_mpi,)
MPI_STAMP := $(BUILD)/stamp/mpi
ifeq ($(filter $(NOCONFIG_GOALS),$(MAKECMDGOALS)),)
$(if $(MPICXX),$(call stamp,$(MPI_STAMP),$(MPICXX) $(CLI_MPI_DEFS) $(CLI_MPI_LIBS)))
endif
$(BUILD)/obj-mpi/%.o: %.cpp $(CONFIG) $(FLAGS_STAMP) $(MPI_STAMP)
	@mkdir -p $(@D)
	$(MPICXX) -DGRAN_MPI $(CLI_MPI_DEFS) -DOMPI_SKIP_MPICXX=1 -DMPICH_SKIP_MPICXX=1 $(CPPFLAGS) $(PKG_CFLAGS) $(CXXFLAGS) -c $< -o $@
$(BUILD)/granary-mpi: $(CLI_MPI_OBJ) $(LIB_A) $(MPI_STAMP)
	$(MPICXX) $(SAN) -o $@ $(CLI_MPI_OBJ) $(LIB_A) $(CLI_MPI_LIBS) $(LDLIBS)
all: $(CLI_MPI)
test: $(CLI_MPI)
bench: $(CLI_MPI)
bench: export GRAN_MPI_CLI := $(if $(CLI_MPI),$(CURDIR)/$(CLI_MPI),)
install: install-mpi
.PHONY: install-mpi mpi-deps-soft
install-mpi: all
	$(if $(CLI_MPI),install -d $(DESTDIR)$(prefix)/bin && install -m 755 $(CLI_MPI) $(DESTDIR)$(prefix)/bin/,@true)
deps: mpi-deps-soft
mpi-deps-soft:
	@if ! command -v mpicxx >/dev/null 2>&1 || [ ! -f /usr/include/fftw3-mpi.h ]; then \
	  ( $(call apt_install,$(MPI_DEB_PKGS),deps (MPI: only build/granary-mpi needs it),exit 0) ) || \
	  echo "deps: MPI not installed (only build/granary-mpi needs it)"; fi
-include $(shell find $(BUILD)/obj-mpi -name "*.d" 2>/dev/null)
# ---- end MPI block ----

# ---- run --------------------------------------------------------------------------------------
# `make run` builds what the default scene needs (the library and build/granary), not the Fortran
# module, the shared library or build/granary-mpi (`make` builds those).
run: $(CLI)
	@if [ -f scenes/default.toml ] && $(CLI) --help 2>&1 | grep -q '^ *run '; then \
	  $(CLI) run scenes/default.toml --force; else $(CLI) info; fi

# ---- install ----------------------------------------------------------------------------------
install: all
	install -d $(DESTDIR)$(prefix)/include $(DESTDIR)$(prefix)/lib/pkgconfig $(DESTDIR)$(prefix)/bin \
	  $(DESTDIR)$(prefix)/include/granary
	install -m 644 include/granary.h $(DESTDIR)$(prefix)/include/
	install -m 644 $(LIB_A) $(LIBF_A) $(DESTDIR)$(prefix)/lib/
	install -m 755 $(LIB_SO_FILE) $(DESTDIR)$(prefix)/lib/libgranary.so.$(VERSION)
	ln -sf libgranary.so.$(VERSION) $(DESTDIR)$(prefix)/lib/$(SONAME)
	ln -sf $(SONAME) $(DESTDIR)$(prefix)/lib/libgranary.so
	install -m 644 $(BUILD)/mod/granary.mod $(DESTDIR)$(prefix)/include/granary/
	install -m 755 $(CLI) $(DESTDIR)$(prefix)/bin/
	install -d $(DESTDIR)$(prefix)/share/granary/python
	cp -R scenes $(DESTDIR)$(prefix)/share/granary/
	install -m 644 include/granary.abi $(DESTDIR)$(prefix)/share/granary/
	install -m 644 figures/granary_h5.py $(DESTDIR)$(prefix)/share/granary/python/
	sed -e 's|@prefix@|$(prefix)|' -e 's|@version@|$(VERSION)|' \
	  -e 's|@libs@|$(PKG_LIBS) $(CUDA_LIBS) $(OMP_FLAG)|' granary.pc.in > $(DESTDIR)$(prefix)/lib/pkgconfig/granary.pc

info:
	@echo "granary build configuration"
	@echo "  CC=$(CC) CXX=$(CXX) FC=$(FC)"
	@echo "  OPT=$(OPT) SAN=$(SAN)"
	@echo "  NVCC=$(if $(NVCC),$(NVCC),(none: CUDA backend is a stub))"
	@echo "  CUDA_ARCH=$(CUDA_ARCH) CUDA_PTX=$(CUDA_PTX)$(if $(NVCC),: $(CUDA_ARCH_STR))"
	@echo "  jobs: $(NPROC) cores$(if $(CCACHE),; ccache $(CCACHE),)"
	@echo "  packages: $$(for p in $(PKGS); do printf '%s=%s ' $$p $$(pkg-config --modversion $$p 2>/dev/null || echo missing); done)"
	@echo "  toml11: $$([ -f /usr/include/toml.hpp ] && echo found || echo missing)"
	@echo "  sources: $(words $(LIB_SRC)) library, $(words $(CU_SRC)) cuda, $(words $(TEST_C) $(TEST_F)) tests, $(words $(BENCH_C)) benches"

help:
	@sed -n '2,/^# HELP_END/p' Makefile | grep -v HELP_END

clean:
	rm -rf build build-asan build-fuzz

-include $(shell find $(BUILD)/obj $(BUILD)/tests $(BUILD)/bench -name "*.d" 2>/dev/null)
