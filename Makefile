# rodkit: the library, its C / C++ / Fortran drivers, the tests, the install.
#
#   make run      build the library (release) and the drivers, then one
#                 short report per capability (tubes, rods, DNA): what each
#                 driver computed and where its CSV / VTK / SVG files went,
#                 all under OUT (default rodkit-out in the repository; works
#                 from any directory: make -C /path/to/rodkit run OUT=/tmp/x)
#   make run-drivers  the same reports on drivers already built
#   make test     every test: Rust, C, C++, Fortran, valgrind, SUNDIALS, and
#                 the quick fuzz run (fuzz-quick)
#   make fuzz     the fuzz targets of tests/fuzz/ (ASan + UBSan), longer:
#                 FUZZ_ITERS=20000 FUZZ_SEED=1 by default
#   make install  PREFIX=/usr/local (after make lib; GNU directory
#                 variables libdir, includedir, docdir, … and DESTDIR): the
#                 shared library (soname librodkit.so.<ABI>, with the usual
#                 symlinks), the static archive, the header, the pkg-config
#                 file rodkit.pc and the CMake package (libdir/cmake/rodkit:
#                 find_package(rodkit)); with gfortran (WITH_FORTRAN) the
#                 compiled module (rodkit.mod in libdir/fortran/gfortran-mod-N,
#                 librodkit_fortran.a, rodkit-fortran.pc) and its source; the
#                 physics reference, licences, citation and changelog in docdir
#   make downstream  install into a temporary prefix and build and run the
#                 C, C++ and Fortran projects of tests/downstream/ against it
#                 with CMake and with pkg-config (part of `make test`)
#
# `run` first installs the compilers it needs when missing (.ci/deps run),
# `test` everything the tests need (.ci/deps: valgrind, cmake, SUNDIALS,
# libclang for the cross-checks' bindings).

PROFILE ?= release
CARGO ?= cargo
ROOT := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
TARGET_DIR ?= $(ROOT)/target
OUTDIR := $(TARGET_DIR)/$(PROFILE)
BUILD := $(OUTDIR)/native
PREFIX ?= /usr/local
VERSION := $(shell sed -n 's/^version = "\(.*\)"/\1/p' $(ROOT)/Cargo.toml | head -n 1)
V_MAJOR := $(word 1,$(subst ., ,$(VERSION)))
V_MINOR := $(word 2,$(subst ., ,$(VERSION)))
V_PATCH := $(word 3,$(subst ., ,$(VERSION)))
# The ABI version (src/version.rs) names the shared library: soname
# librodkit.so.<ABI> (set by build.rs), installed as
# librodkit.so.<ABI>.<minor>.<patch> with librodkit.so.<ABI> and
# librodkit.so linking to it.
ABI := $(shell sed -n 's/^pub const ABI_VERSION: i32 = \([0-9]*\);/\1/p' $(ROOT)/src/version.rs)
SONAME := librodkit.so.$(ABI)
REALNAME := librodkit.so.$(ABI).$(V_MINOR).$(V_PATCH)
CARGO_PROFILE := $(if $(filter release,$(PROFILE)),--release,)

# What a static link of librodkit.a needs besides the archive itself,
# derived when the library is built: rustc's --print native-static-libs for
# a static library of the same toolchain (rodkit's dependencies add no
# native library of their own, so std's list is rodkit's; the static
# drivers and tests/downstream link with it).
STATIC_LIBS_FILE := $(OUTDIR)/rodkit-static-libs
STATIC_LIBS = $(or $(shell cat $(STATIC_LIBS_FILE) 2>/dev/null),$(error rodkit: $(STATIC_LIBS_FILE) is missing (make lib)))

CC ?= gcc
CXX ?= g++
# gfortran unless the caller names another (make's own default is f77).
ifeq ($(origin FC),default)
FC := gfortran
endif
# The compiled Fortran module is built and installed when $(FC) exists.
WITH_FORTRAN ?= $(if $(shell command -v $(FC) 2>/dev/null),yes,no)
CFLAGS := -std=c11 -O2 -g -Wall -Wextra -pedantic -Werror -I$(ROOT)/include
CXXFLAGS := -std=c++17 -O2 -g -Wall -Wextra -pedantic -Werror -I$(ROOT)/include
FFLAGS := -std=f2008 -O2 -g -Wall -Wextra -J$(BUILD)/fmod -I$(BUILD)/fmod
SHARED := -L$(OUTDIR) -lrodkit -Wl,-rpath,$(OUTDIR)
STATIC = $(OUTDIR)/librodkit.a $(STATIC_LIBS)

C_DRIVERS := tube_stiffness bad_input artery dna_tube rod_buckling dna_supercoil dna_supercoil_resume dna_map dna_tweezers
F_DRIVERS := tube_stiffness stretch_sweep follower_cantilever greenhill charged_curve dna_supercoil dna_tweezers
# The SUNDIALS driver only where SUNDIALS is installed (libsundials-dev).
HAVE_SUNDIALS := $(wildcard /usr/include/kinsol/kinsol.h)
SUNDIALS_DRIVER := $(if $(HAVE_SUNDIALS),c_rod_sundials_shared)
EXES := $(foreach d,$(C_DRIVERS),$(BUILD)/c_$(d)_shared $(BUILD)/c_$(d)_static) \
        $(BUILD)/cpp_tube_stiffness $(BUILD)/cpp_fe_beam $(addprefix $(BUILD)/,$(SUNDIALS_DRIVER)) \
        $(foreach d,$(F_DRIVERS),$(BUILD)/f_$(d)_shared $(BUILD)/f_$(d)_static)
LIBS := $(OUTDIR)/librodkit.so $(OUTDIR)/librodkit.a $(OUTDIR)/$(SONAME) $(STATIC_LIBS_FILE)
HEADER := $(ROOT)/include/rodkit.h

.PHONY: all deps lib drivers run run-drivers test install downstream clean-native fuzz fuzz-quick fuzz-build
all: lib drivers

deps:
	@bash $(ROOT)/.ci/deps

lib:
	cd $(ROOT) && $(CARGO) build --lib $(CARGO_PROFILE)
	@$(MAKE) --no-print-directory -s $(OUTDIR)/$(SONAME) $(STATIC_LIBS_FILE)

# Programs linked against the build's librodkit.so record its soname: the
# link lets them load it from the build directory.
$(OUTDIR)/$(SONAME): $(OUTDIR)/librodkit.so
	ln -sf librodkit.so $@

$(STATIC_LIBS_FILE): $(OUTDIR)/librodkit.a
	@tmp=$$(mktemp -d) && : > $$tmp/probe.rs && \
	  $${RUSTC:-rustc} --crate-type staticlib --crate-name probe --print native-static-libs \
	    -o $$tmp/libprobe.a $$tmp/probe.rs 2>&1 | sed -n 's/^note: native-static-libs: //p' > $$tmp/libs && \
	  test -s $$tmp/libs && mv $$tmp/libs $@; status=$$?; rm -rf $$tmp; \
	  test $$status -eq 0 || { echo "rodkit: rustc --print native-static-libs gave nothing" >&2; exit 1; }

drivers: $(EXES)

$(BUILD)/c_%_shared: $(ROOT)/c_examples/%.c $(HEADER) $(LIBS)
	@mkdir -p $(BUILD)
	$(CC) $(CFLAGS) $< $(SHARED) -lm -o $@

$(BUILD)/c_%_static: $(ROOT)/c_examples/%.c $(HEADER) $(LIBS)
	@mkdir -p $(BUILD)
	$(CC) $(CFLAGS) $< $(STATIC) -o $@

# The SUNDIALS driver links Debian's SUNDIALS (libsundials-dev) too.
SUNDIALS_LIBS := -lsundials_kinsol -lsundials_ida -lsundials_nvecserial -lsundials_sunmatrixdense \
                 -lsundials_sunlinsoldense -lm
$(BUILD)/c_rod_sundials_shared: $(ROOT)/c_examples/rod_sundials.c $(HEADER) $(LIBS)
	@mkdir -p $(BUILD)
	$(CC) $(CFLAGS) $< $(SHARED) $(SUNDIALS_LIBS) -o $@

# The serial DNA map shares its curve, CSV and plot code with the MPI map
# (c_examples/dna_map_common.c).
DNA_MAP_COMMON := $(ROOT)/c_examples/dna_map_common.c
$(BUILD)/c_dna_map_shared: $(ROOT)/c_examples/dna_map.c $(DNA_MAP_COMMON) $(ROOT)/c_examples/dna_map_common.h $(HEADER) $(LIBS)
	@mkdir -p $(BUILD)
	$(CC) $(CFLAGS) $< $(DNA_MAP_COMMON) $(SHARED) -lm -o $@

$(BUILD)/c_dna_map_static: $(ROOT)/c_examples/dna_map.c $(DNA_MAP_COMMON) $(ROOT)/c_examples/dna_map_common.h $(HEADER) $(LIBS)
	@mkdir -p $(BUILD)
	$(CC) $(CFLAGS) $< $(DNA_MAP_COMMON) $(STATIC) -o $@

# The tweezers driver borrows the map's atomic file writes and clock; its
# family runs on two threads of its own (--threads).
$(BUILD)/c_dna_tweezers_shared: $(ROOT)/c_examples/dna_tweezers.c $(DNA_MAP_COMMON) $(ROOT)/c_examples/dna_map_common.h $(HEADER) $(LIBS)
	@mkdir -p $(BUILD)
	$(CC) $(CFLAGS) -pthread $< $(DNA_MAP_COMMON) $(SHARED) -lm -o $@

$(BUILD)/c_dna_tweezers_static: $(ROOT)/c_examples/dna_tweezers.c $(DNA_MAP_COMMON) $(ROOT)/c_examples/dna_map_common.h $(HEADER) $(LIBS)
	@mkdir -p $(BUILD)
	$(CC) $(CFLAGS) -pthread $< $(DNA_MAP_COMMON) $(STATIC) -o $@

# ---- MPI drivers (issue 21) ----------------------------------------------
# Built by `make drivers` only where an MPI C compiler exists (OpenMPI:
# libopenmpi-dev, openmpi-bin; .ci/deps installs them for the tests).
# MPI_CC names the wrapper; HAVE_MPI is empty without one. Run them with
# mpirun (tests/mpi.rs; doc/cluster.md).
MPI_CC ?= mpicc
HAVE_MPI := $(if $(shell command -v $(MPI_CC) 2>/dev/null),yes,)
#   mpi_dna_map: the DNA length x force x salt map (c_examples/mpi_dna_map.c).
MPI_DNA_EXES := $(if $(HAVE_MPI),$(BUILD)/mpi_dna_map_shared)
.PHONY: mpi-dna
drivers: $(MPI_DNA_EXES)
# What tests/mpi.rs needs: the MPI map and the serial map it is checked with.
mpi-dna: $(MPI_DNA_EXES) $(BUILD)/c_dna_map_shared
$(BUILD)/mpi_dna_map_shared: $(ROOT)/c_examples/mpi_dna_map.c $(DNA_MAP_COMMON) $(ROOT)/c_examples/dna_map_common.h \
                             $(HEADER) $(LIBS)
	@mkdir -p $(BUILD)
	$(MPI_CC) $(CFLAGS) $< $(DNA_MAP_COMMON) $(SHARED) -lm -o $@
# ---- end of the MPI drivers ----------------------------------------------

$(BUILD)/cpp_%: $(ROOT)/c_examples/%.cpp $(HEADER) $(LIBS)
	@mkdir -p $(BUILD)
	$(CXX) $(CXXFLAGS) $< $(SHARED) -o $@

$(BUILD)/rodkit_mod.o: $(ROOT)/include/rodkit.f90
	@mkdir -p $(BUILD)/fmod
	$(FC) $(FFLAGS) -fPIC -c $< -o $@

# The compiled Fortran module for installation: rodkit.mod (in
# $(BUILD)/fmod) and its procedures' archive.
$(BUILD)/librodkit_fortran.a: $(BUILD)/rodkit_mod.o
	ar rcs $@ $<

$(BUILD)/f_%_shared: $(ROOT)/fortran_examples/%.f90 $(BUILD)/rodkit_mod.o $(LIBS)
	$(FC) $(FFLAGS) $< $(BUILD)/rodkit_mod.o $(SHARED) -o $@

$(BUILD)/f_%_static: $(ROOT)/fortran_examples/%.f90 $(BUILD)/rodkit_mod.o $(LIBS)
	$(FC) $(FFLAGS) $< $(BUILD)/rodkit_mod.o $(STATIC) -o $@

# ---- MPI, Fortran (issue 21): the tube material search over MPI ranks ------
# fortran_examples/mpi_tube_search.f90, built with $(MPIF90) (OpenMPI's
# wrapper around gfortran; Debian: libopenmpi-dev, openmpi-bin) only when it
# exists, as part of `drivers`; the generated module rodkit_mod.o comes from
# gfortran above (the wrapper must wrap the same gfortran). OpenMPI 4.1's
# mpi_f08 compiles clean with -std=f2008. Its own modules go to fmod-mpi, not
# to the installed fmod. Run: mpirun -np P $(BUILD)/f_mpi_tube_search OUTDIR
# (tests/mpi_tube_search.rs).
MPIF90 ?= mpif90
HAVE_MPIF90 := $(if $(shell command -v $(MPIF90) 2>/dev/null),yes,)
MPI_FFLAGS := -std=f2008 -O2 -g -Wall -Wextra -J$(BUILD)/fmod-mpi -I$(BUILD)/fmod
drivers: $(if $(HAVE_MPIF90),$(BUILD)/f_mpi_tube_search)

$(BUILD)/f_mpi_tube_search: $(ROOT)/fortran_examples/mpi_tube_search.f90 $(BUILD)/rodkit_mod.o $(LIBS)
	@mkdir -p $(BUILD)/fmod-mpi
	$(MPIF90) $(MPI_FFLAGS) $< $(BUILD)/rodkit_mod.o $(SHARED) -o $@
# ---- end of MPI, Fortran ----------------------------------------------------

# The main job: one short report per capability (tubes, rods, DNA), each
# driver once on its bundled input, saying what it computed and where its
# files went. Every file goes under one folder, OUT (default rodkit-out in
# the repository; a relative OUT is taken from the directory make runs in,
# which `make -C <repo>` makes the repository): tubes/, rods/, dna/ and
# dna/map. The drivers get absolute input and output paths, so `make -C
# /path/to/rodkit run` works from any directory and writes nothing outside
# OUT (besides the build in target/). The DNA force x salt map
# (c_examples/dna_map.c) runs twice: with the full zero-temperature rod (the
# reference, --model full-rod) on a small subset: 300 bp, 1 and 2 pN x 0.05
# and 0.1 M, to 2.2 turns (~31 s on the 2-core machine; the full map, 1
# kbp, 3 forces x 4 salts, to 12 turns, is `c_dna_map_shared --model
# full-rod`, doc/dna.md: "The force × salt map"), and with the thermal
# two-phase model (its default) at 10 kbp over 0.25-4 pN x 0.01, 0.1 M,
# whose plateau torque vs force is set beside the tweezers data of
# tests/data/tweezers/buckling_torque.csv (plateau_torque_vs_force.svg and
# a "model vs data" table; ~0.3 s; with the tweezers family ~1 s in all).
# Each driver's `--values` adds the name = value lines the tests read.
OUT ?= $(ROOT)/rodkit-out
RUN_OUT := $(abspath $(OUT))
DNA_MAP_SUBSET ?= --bp 300 --forces 1,2 --salts 0.05,0.1 --turns 2.2 --elements 40 --steps 300
DNA_MAP_OUT ?= $(RUN_OUT)/dna/map
# The supercoiling run: continuation steps, then elements and base pairs.
DNA_SUPERCOIL_STEPS ?= 90
DNA_SUPERCOIL_SCENE ?= 51 300
# The tweezers family at 25 C (c_examples/dna_tweezers.c --family: 4 forces
# x 2 salts x 2 lengths, on two threads: ~0.3 s) and where its
# files go.
DNA_TWEEZERS_FAMILY ?= --family
DNA_TWEEZERS_OUT ?= $(RUN_OUT)/dna/tweezers
# The thermal map of the plateau torque vs force beside the tweezers data.
DNA_PLATEAU_MAP ?= --bp 10000 --forces 0.25,0.5,1,2,3,4 --salts 0.01,0.1 --turns auto --points 100
DNA_PLATEAU_DATA ?= $(ROOT)/tests/data/tweezers/buckling_torque.csv
DNA_PLATEAU_OUT ?= $(RUN_OUT)/dna/plateau
# Each driver once (the static and C++ link modes are `make test`'s).
run:
	@bash $(ROOT)/.ci/deps run
	@$(MAKE) --no-print-directory -s lib
	@$(MAKE) --no-print-directory -s drivers
	@$(MAKE) --no-print-directory -s run-drivers

# The reports alone, on drivers already built (`make run` builds them).
run-drivers:
	@mkdir -p $(RUN_OUT)/tubes $(RUN_OUT)/rods $(RUN_OUT)/dna
	@echo "rodkit $(VERSION): each driver once on its bundled input; files under $(RUN_OUT)/"
	@echo
	@echo "== Tubes: helically reinforced tubes, thin and thick walls (C, Fortran)"
	@$(BUILD)/c_tube_stiffness_shared $(ROOT)/c_examples/data/dna_tube.txt
	@$(BUILD)/c_dna_tube_shared $(RUN_OUT)/tubes/dna_tube_stretch.csv
	@$(BUILD)/f_stretch_sweep_shared $(RUN_OUT)/tubes/dna_wall_stretch.csv
	@$(BUILD)/c_artery_shared $(RUN_OUT)/tubes/artery_stretch.csv
	@echo
	@echo "== Rods: Cosserat rods continued by the asymptotic numerical method (C, Fortran, C++)"
	@$(BUILD)/c_rod_buckling_shared $(RUN_OUT)/rods/buckling.csv $(RUN_OUT)/rods/buckling.vtk
	@$(BUILD)/f_follower_cantilever_shared $(RUN_OUT)/rods/follower.vtk $(RUN_OUT)/rods/follower_samples.csv
	@$(BUILD)/f_greenhill_shared
	$(if $(SUNDIALS_DRIVER),@$(BUILD)/$(SUNDIALS_DRIVER))
	@$(BUILD)/cpp_fe_beam
	@echo
	@echo "== DNA: charged rods and supercoiling, at zero and at finite temperature (Fortran, C)"
	@$(BUILD)/f_charged_curve_shared
	@$(BUILD)/c_dna_supercoil_shared 0.1 $(DNA_SUPERCOIL_STEPS) $(RUN_OUT)/dna/supercoil.csv \
	  $(RUN_OUT)/dna/supercoil.vtk $(DNA_SUPERCOIL_SCENE)
	@echo "A force x salt map of supercoiling curves, the full rod at zero temperature ($(DNA_MAP_SUBSET)):"
	@$(BUILD)/c_dna_map_shared --model full-rod $(DNA_MAP_SUBSET) $(DNA_MAP_OUT)
	@$(BUILD)/c_dna_tweezers_shared $(DNA_TWEEZERS_FAMILY) --out $(DNA_TWEEZERS_OUT)
	@echo "The thermal model's plateau torque vs force beside tweezers data ($(DNA_PLATEAU_MAP)):"
	@$(BUILD)/c_dna_map_shared --model thermal $(DNA_PLATEAU_MAP) --data $(DNA_PLATEAU_DATA) $(DNA_PLATEAU_OUT)
	@echo
	@echo "== Errors: what a bad call returns (C)"
	@$(BUILD)/c_bad_input_shared

# All tests: one cargo invocation for the Rust suites, the drivers (built here
# by tests/native.rs through this Makefile, compared with the Rust results,
# run under valgrind) and the SUNDIALS cross-checks; then the downstream
# projects against an installed prefix (CMake, pkg-config); then the quick
# fuzz run.
test: deps
	cd $(ROOT) && $(CARGO) test --release --features sundials
	@$(MAKE) --no-print-directory downstream
	@$(MAKE) --no-print-directory fuzz-quick

# Fuzz targets (issue 17; tests/fuzz/fuzz.h says what they check): one C
# program per entry-point group, built with AddressSanitizer and UBSan
# against the shared library (not sanitized itself). Violations listed in
# tests/fuzz/known.txt are reported, not failed (the list is empty: see it).
FUZZ_TARGETS := tube thin_tube rod curve supercoil dna_fit
FUZZ_ITERS ?= 20000
FUZZ_SEED ?= 1
FUZZ_CFLAGS := -std=c11 -O1 -g -Wall -Wextra -Werror -fsanitize=address,undefined -fno-omit-frame-pointer \
               -fno-sanitize-recover=undefined -I$(ROOT)/include
# An allocation above 2 GiB is reported as a crash (a runaway size), not
# left to take the machine's memory.
FUZZ_ENV := ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:max_allocation_size_mb=2048 UBSAN_OPTIONS=print_stacktrace=1 \
            RODKIT_FUZZ_KNOWN=$(ROOT)/tests/fuzz/known.txt
# Iterations of `fuzz-quick` per target (the tube and supercoil calls solve
# problems; the others are algebraic or cheap): about 35 s in all on one core.
FUZZ_QUICK := tube:500 thin_tube:20000 rod:5000 curve:2000 supercoil:100 dna_fit:20000

$(BUILD)/fuzz_%: $(ROOT)/tests/fuzz/fuzz_%.c $(ROOT)/tests/fuzz/fuzz.h $(HEADER) $(LIBS)
	@mkdir -p $(BUILD)
	$(CC) $(FUZZ_CFLAGS) $< $(SHARED) -lm -o $@

fuzz-build: lib
	@$(MAKE) --no-print-directory $(foreach t,$(FUZZ_TARGETS),$(BUILD)/fuzz_$(t))

fuzz-quick: fuzz-build
	@for tn in $(FUZZ_QUICK); do t=$${tn%%:*}; n=$${tn##*:}; \
	  $(FUZZ_ENV) $(BUILD)/fuzz_$$t $$n $(FUZZ_SEED) || exit 1; done

fuzz: fuzz-build
	@for t in $(FUZZ_TARGETS); do $(FUZZ_ENV) $(BUILD)/fuzz_$$t $(FUZZ_ITERS) $(FUZZ_SEED) || exit 1; done

# Installation directories, GNU names (override any, e.g. make install
# libdir=/usr/lib/x86_64-linux-gnu); DESTDIR stages them. The Fortran
# module goes where Debian keeps gfortran modules, by its format version
# (read from rodkit.mod itself), its source to share/.
empty :=
space := $(empty) $(empty)
libdir ?= $(PREFIX)/lib
includedir ?= $(PREFIX)/include
docdir ?= $(PREFIX)/share/doc/rodkit
pkgconfigdir ?= $(libdir)/pkgconfig
cmakedir ?= $(libdir)/cmake/rodkit
fortransrcdir ?= $(PREFIX)/share/rodkit/fortran
GFORTRAN_VERSION = $(shell $(FC) -dumpfullversion 2>/dev/null)
GFORTRAN_MOD = $(shell gzip -dc $(BUILD)/fmod/rodkit.mod 2>/dev/null | sed -n "1s/^GFORTRAN module version '\([0-9]*\)'.*/\1/p")
fortrandir ?= $(libdir)/fortran/gfortran-mod-$(GFORTRAN_MOD)
# The CMake package finds everything relative to its own place.
rel = $(shell realpath -m --relative-to=$(1) $(2))

# The library and archive are built by `make lib` (install does not build:
# `sudo make install` would build as root).
$(OUTDIR)/librodkit.so $(OUTDIR)/librodkit.a:
	@echo "rodkit: $@ is missing: build it first (make lib)" >&2; exit 1

install: $(LIBS) $(if $(filter yes,$(WITH_FORTRAN)),$(BUILD)/librodkit_fortran.a)
	install -d $(DESTDIR)$(libdir) $(DESTDIR)$(includedir) $(DESTDIR)$(pkgconfigdir) $(DESTDIR)$(cmakedir) \
	  $(DESTDIR)$(docdir)
	rm -f $(DESTDIR)$(libdir)/librodkit.so.$(ABI).*
	install -m 755 $(OUTDIR)/librodkit.so $(DESTDIR)$(libdir)/$(REALNAME)
	ln -sf $(REALNAME) $(DESTDIR)$(libdir)/$(SONAME)
	ln -sf $(SONAME) $(DESTDIR)$(libdir)/librodkit.so
	install -m 644 $(OUTDIR)/librodkit.a $(DESTDIR)$(libdir)/
	install -m 644 $(ROOT)/include/rodkit.h $(DESTDIR)$(includedir)/
	install -m 644 $(DOCS) $(DESTDIR)$(docdir)/
	printf '%s\n' 'prefix=$(PREFIX)' 'libdir=$(libdir)' 'includedir=$(includedir)' '' \
	  'Name: rodkit' 'Description: Mechanics of elastic tubes and rods (C ABI)' 'Version: $(VERSION)' \
	  'Libs: -L$${libdir} -lrodkit' 'Libs.private: $(STATIC_LIBS)' 'Cflags: -I$${includedir}' \
	  > $(DESTDIR)$(pkgconfigdir)/rodkit.pc
	sed -e 's|@VERSION@|$(VERSION)|g' -e 's|@ABI@|$(ABI)|g' -e 's|@MINOR@|$(V_MINOR)|g' -e 's|@PATCH@|$(V_PATCH)|g' \
	  -e 's|@TO_PREFIX@|$(call rel,$(cmakedir),$(PREFIX))|g' -e 's|@LIB@|$(call rel,$(PREFIX),$(libdir))|g' \
	  -e 's|@INCLUDE@|$(call rel,$(PREFIX),$(includedir))|g' -e 's|@STATIC_LIBS@|$(subst $(space),;,$(STATIC_LIBS))|g' \
	  -e 's|@FMOD@|$(call rel,$(PREFIX),$(fortrandir))|g' -e 's|@GFORTRAN@|$(GFORTRAN_VERSION)|g' \
	  -e 's|@FORTRAN_SOURCE@|$(call rel,$(PREFIX),$(fortransrcdir))|g' \
	  $(ROOT)/cmake/rodkitConfig.cmake.in > $(DESTDIR)$(cmakedir)/rodkitConfig.cmake
	sed -e 's|@VERSION@|$(VERSION)|g' -e 's|@MAJOR@|$(V_MAJOR)|g' -e 's|@MINOR@|$(V_MINOR)|g' \
	  $(ROOT)/cmake/rodkitConfigVersion.cmake.in > $(DESTDIR)$(cmakedir)/rodkitConfigVersion.cmake
ifeq ($(WITH_FORTRAN),yes)
	install -d $(DESTDIR)$(fortrandir) $(DESTDIR)$(fortransrcdir)
	install -m 644 $(BUILD)/librodkit_fortran.a $(DESTDIR)$(libdir)/
	install -m 644 $(BUILD)/fmod/rodkit.mod $(DESTDIR)$(fortrandir)/
	install -m 644 $(ROOT)/include/rodkit.f90 $(DESTDIR)$(fortransrcdir)/
	printf '%s\n' 'prefix=$(PREFIX)' 'libdir=$(libdir)' 'fmoddir=$(fortrandir)' '' \
	  'Name: rodkit-fortran' 'Description: Fortran 2008 module of rodkit (rodkit.mod of gfortran $(GFORTRAN_VERSION))' \
	  'Version: $(VERSION)' 'Requires: rodkit = $(VERSION)' 'Libs: -L$${libdir} -lrodkit_fortran' \
	  'Cflags: -I$${fmoddir}' > $(DESTDIR)$(pkgconfigdir)/rodkit-fortran.pc
endif

# What goes to docdir (a distribution that ships licences elsewhere sets DOCS).
DOCS ?= $(wildcard $(ROOT)/doc/*.md) $(ROOT)/README.md $(ROOT)/CHANGELOG.md $(ROOT)/CITATION.cff \
        $(ROOT)/LICENSE-MIT $(ROOT)/LICENSE-APACHE

# Downstream projects (tests/downstream/: C, C++, Fortran) built against an
# installed rodkit with CMake and with pkg-config; the soname checked.
downstream: lib
	@bash $(ROOT)/tests/downstream/run.sh

clean-native:
	rm -rf $(BUILD)
