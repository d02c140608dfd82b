# rockfall - design checks for rockfall protection measures.
#
#   make            build build/rockfall
#   make demo       build and run the example project (projects/noto) into noto.gpkg, report/
#   make test       build and run the tests (ends with "N passed, N failed")
#   make test SANITIZE=1   the same under AddressSanitizer and UBSan
#   make bench      speed against error of the motion engines, and of a grid made a TIN;
#                   with RF_ROCKGIS=/path/to/RockGIS_Linux also against RockGIS
#   make validate   the engine against the Authume quarry's measured stop points
#   make report-check   the demo report, its maps and a comparison of variants rendered by headless chromium (PNGs to look at)
#   make layers     the layer rule of src/ (docs/architecture.md), on sources and objects
#   make bench-memory   peak memory of a run at 2 000 and 200 000 trajectories (flat)
#   make bench-load the project loader on large inputs (times, not tests)
#   make fuzz       libFuzzer on every loader (clang, installed when missing), FUZZ_SECONDS each
#   make mpi        build/mpi/rockfall with OpenMPI (mpicc), for mpirun (docs/scaling.md)
#   make install    PREFIX=/usr/local

# ---- settings ---------------------------------------------------------------
CC       ?= cc
PREFIX   ?= /usr/local
PKGS     := sqlite3 gsl yaml-0.1 proj
OPT      ?= -O2
WARN     := -Wall -Wextra -Wshadow -Wstrict-prototypes -Wmissing-prototypes \
            -Wno-missing-field-initializers -Werror
CFLAGS   += -std=c11 -D_DEFAULT_SOURCE -D_POSIX_C_SOURCE=200809L -g $(OPT) $(WARN) -ffp-contract=off \
            -Iinclude -Isrc $(shell pkg-config --cflags $(PKGS))
LDLIBS   += $(shell pkg-config --libs $(PKGS)) -lm -lpthread
BUILD    ?= build
ifeq ($(SANITIZE),1)
BUILD    := build/san
CFLAGS   += -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
LDFLAGS  += -fsanitize=address,undefined
endif
# The libFuzzer build (`make fuzz`): clang, every object instrumented for coverage and
# under ASan and UBSan.  The default build needs none of it.
ifeq ($(FUZZ),1)
CC       := clang
BUILD    := build/fuzz
CFLAGS   += -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer \
            -fno-sanitize-recover=undefined
LDFLAGS  += -fsanitize=address,undefined
endif

# ---- objects ----------------------------------------------------------------
# src/ is one folder per layer (docs/architecture.md); tests/fixtures/ holds the scenes
# and field tests that the tests and tools share, outside the library.
LIB_SRC  := $(filter-out src/cli/% src/run/mpi%.c,$(wildcard src/*/*.c))
# The MPI build (`make mpi`): mpicc, src/run/mpi*.c and RF_MPI in build/mpi; the default
# build needs no MPI.
ifeq ($(MPI),1)
CC       := mpicc
BUILD    := build/mpi
CFLAGS   += -DRF_MPI
LIB_SRC  += $(wildcard src/run/mpi*.c)
endif
LIB_OBJ  := $(LIB_SRC:src/%.c=$(BUILD)/src/%.o)
CLI_OBJ  := $(patsubst src/%.c,$(BUILD)/src/%.o,$(wildcard src/cli/*.c))
FIX_SRC  := $(wildcard tests/fixtures/*.c)
FIX_OBJ  := $(FIX_SRC:tests/%.c=$(BUILD)/tests/%.o)
TEST_SRC := $(wildcard tests/*.c)
TEST_OBJ := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%.o)
TOOL_SRC := $(wildcard tools/*.c)
TOOLS    := $(TOOL_SRC:tools/%.c=$(BUILD)/tools/%)

.PHONY: regional mpi mpi-deps all demo test bench validate install clean deps report-check layers bench-memory bench-load fuzz fuzz-deps
all: $(BUILD)/rockfall $(TOOLS)

$(BUILD)/src/%.o: src/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -MMD -MP -c $< -o $@
$(BUILD)/tests/%.o: tests/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -Itests -MMD -MP -c $< -o $@
$(BUILD)/tools/%: tools/%.c $(BUILD)/libfixtures.a $(BUILD)/librockfall.a
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -Itests $(LDFLAGS) $< $(BUILD)/libfixtures.a $(BUILD)/librockfall.a $(LDLIBS) -o $@

$(BUILD)/librockfall.a: $(LIB_OBJ)
	rm -f $@
	$(AR) rcs $@ $^
$(BUILD)/libfixtures.a: $(FIX_OBJ)
	rm -f $@
	$(AR) rcs $@ $^
$(BUILD)/rockfall: $(CLI_OBJ) $(BUILD)/librockfall.a
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@
$(BUILD)/run_tests: $(TEST_OBJ) $(BUILD)/libfixtures.a $(BUILD)/librockfall.a
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

# Debian packages the build needs, installed when they are missing.
DEBS := libsqlite3-dev libgsl-dev libyaml-dev libproj-dev pkg-config
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
deps:
	@pkg-config --exists $(PKGS) 2>/dev/null || { \
	  echo "installing $(DEBS)"; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
	  $(SUDO) apt-get install -y -qq $(DEBS); }

# demo and test install the dependencies first, then build in a fresh make (so that
# pkg-config is asked again once the packages are there).
demo:
	@$(MAKE) --no-print-directory deps
	@$(MAKE) --no-print-directory all
	rm -f noto.gpkg noto.gpkg-wal noto.gpkg-shm
	$(BUILD)/rockfall run projects/noto/noto-3.1-no-trees.yaml -o noto.gpkg
	$(BUILD)/rockfall run projects/noto/noto-3.1-trees.yaml -o noto.gpkg
	$(BUILD)/rockfall run projects/noto/noto-3.2.yaml -o noto.gpkg
	$(BUILD)/rockfall run projects/noto/noto-3.3.yaml -o noto.gpkg
	$(BUILD)/rockfall report noto.gpkg --out report

test:
	@$(MAKE) --no-print-directory deps
	@$(MAKE) --no-print-directory $(BUILD)/rockfall $(BUILD)/run_tests $(TOOLS) $(ROLL_DEMS)
	@$(MAKE) --no-print-directory regional
	@if command -v mpicc >/dev/null && command -v mpirun >/dev/null; then \
	  $(MAKE) --no-print-directory MPI=1 SANITIZE= FUZZ= build/mpi/rockfall; fi
	ROCKFALL_BIN=$(BUILD)/rockfall ROCKFALL_TOOLS=$(BUILD)/tools ROCKFALL_MPI_BIN=build/mpi/rockfall \
	  $(BUILD)/run_tests $(T)

# build/mpi/rockfall: the same command, its runs shared among MPI ranks (mpirun -n N
# build/mpi/rockfall run ...; docs/scaling.md).  OpenMPI installed when missing.
MPI_DEBS := libopenmpi-dev openmpi-bin
mpi-deps:
	@command -v mpicc >/dev/null && command -v mpirun >/dev/null || { \
	  echo "installing $(MPI_DEBS)"; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
	  $(SUDO) apt-get install -y -qq $(MPI_DEBS); }
mpi:
	@$(MAKE) --no-print-directory deps
	@$(MAKE) --no-print-directory mpi-deps
	@$(MAKE) --no-print-directory MPI=1 SANITIZE= FUZZ= build/mpi/rockfall

# The regional example's generated files (projects/regional, 30 MB, not stored): the
# valley's DEM and its source cells, written by tools/mkvalley.c.
REGIONAL := projects/regional
regional: $(REGIONAL)/valley.asc
$(REGIONAL)/valley.asc $(REGIONAL)/sources.asc &: tools/mkvalley.c
	@$(MAKE) --no-print-directory deps
	@$(MAKE) --no-print-directory $(BUILD)/tools/mkvalley
	$(BUILD)/tools/mkvalley $(REGIONAL)

# A file includes and calls only its own layer and those below; the engine's files
# depend on each other without a cycle (tools/layers.sh, docs/architecture.md).
layers: $(LIB_OBJ) $(CLI_OBJ)
	sh tools/layers.sh . $(BUILD)

# The fastest build (link-time optimisation across the engine's files, 4 to 10 %; libm
# without errno, 1 to 2 %; results identical; about 10 % faster than the default -O2 in
# all).
FAST := OPT="-O3 -march=native -flto=auto -fno-math-errno" AR=gcc-ar
bench:
	@$(MAKE) --no-print-directory $(FAST) BUILD=build/bench build/bench/tools/bench
	@$(MAKE) --no-print-directory $(ROLL_DEMS)
	build/bench/tools/bench
	@$(MAKE) --no-print-directory $(FAST) BUILD=build/bench build/bench/tools/bench_tin build/bench/rockfall
	build/bench/tools/bench_tin
	@$(MAKE) --no-print-directory $(FAST) BUILD=build/bench build/bench/tools/bench_threads
	build/bench/tools/bench_threads
	@if [ -n "$$RF_ROCKGIS" ]; then RF_ROCKFALL=build/bench/rockfall RF_APRON=400 RF_APRON_DEG=14 sh tools/rockgis_bench.sh projects/bench/roll-1m.asc 50 253 2000; fi
	@if [ -n "$$RF_ROCKGIS" ]; then RF_ROCKFALL=build/bench/rockfall RF_APRON=250 RF_APRON_DEG=25 sh tools/rockgis_bench.sh projects/noto/terrain.asc 170 204 2000; fi

# The rolling bench slope's grids at 2, 1 and 0.5 m (tools/mkroll.c; not kept in git).
ROLL_DEMS := projects/bench/roll-2m.asc projects/bench/roll-1m.asc projects/bench/roll-05m.asc
projects/bench/roll-%m.asc: $(BUILD)/tools/mkroll
	$(BUILD)/tools/mkroll $(subst 05,0.5,$*) > $@.tmp && mv $@.tmp $@

# Peak memory of a run (a child process's ru_maxrss) at two counts: within 10 % of each
# other, since nothing a run keeps grows with its trajectories (docs/database.md).
bench-memory:
	@$(MAKE) --no-print-directory deps
	@$(MAKE) --no-print-directory $(BUILD)/rockfall $(BUILD)/tools/bench_memory
	$(BUILD)/tools/bench_memory $(BUILD)/rockfall

# The project loader's time on the inputs that once made it quadratic or unbounded
# (100 000 rocks, a 30 000-vertex zone, an alias of a long line used 1 000 times).
bench-load:
	@$(MAKE) --no-print-directory deps
	@$(MAKE) --no-print-directory $(BUILD)/tools/bench_load
	$(BUILD)/tools/bench_load

# libFuzzer on every loader (tests/fuzz/README.md): FUZZ_SECONDS each, one after the
# other, clang and its fuzzer runtime installed when missing.
FUZZ_SECONDS ?= 300
FUZZ_TARGETS ?= yaml project rules grid stl obj points layout
FUZZ_BINS := $(FUZZ_TARGETS:%=build/fuzz/fuzz/fuzz_%)
build/fuzz/fuzz/fuzz_%: tests/fuzz/fuzz_%.c tests/fuzz/fuzz_util.h build/fuzz/librockfall.a
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -Itests/fuzz -DRF_FUZZ_DATA='"$(abspath tests/data/project)"' \
	  -fsanitize=fuzzer $< build/fuzz/librockfall.a $(LDFLAGS) $(LDLIBS) -o $@
fuzz-deps:
	@printf 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n)\n{ (void)d; (void)n; return 0; }\n' \
	  > /tmp/rf_fuzz_probe.c; \
	clang -fsanitize=fuzzer /tmp/rf_fuzz_probe.c -o /tmp/rf_fuzz_probe 2>/dev/null || { \
	  echo "installing clang and its fuzzer runtime"; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
	  $(SUDO) apt-get install -y -qq clang libclang-rt-dev; }; \
	rm -f /tmp/rf_fuzz_probe /tmp/rf_fuzz_probe.c
fuzz:
	@$(MAKE) --no-print-directory deps
	@$(MAKE) --no-print-directory fuzz-deps
	@$(MAKE) --no-print-directory FUZZ=1 $(FUZZ_BINS)
	FUZZ_FLAGS='$(FUZZ_FLAGS)' sh tools/fuzz.sh build/fuzz $(FUZZ_SECONDS) $(FUZZ_TARGETS)

# The engine against real rockfalls (../shared/validation/authume, docs/validation.md).
validate:
	@$(MAKE) --no-print-directory deps
	@$(MAKE) --no-print-directory $(BUILD)/tools/validate
	$(BUILD)/tools/validate

# The report in a real browser: the demo's report, its hazard maps and passing-height
# figures one by one, and the comparison of runs 3 and 4, rendered by Debian's headless
# chromium (installed when missing) to PNGs (tools/report_check.sh).  Look at them.
report-check:
	@$(MAKE) --no-print-directory demo
	@[ -x /usr/bin/chromium ] || { echo "installing chromium"; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
	  $(SUDO) apt-get install -y -qq chromium; }
	sh tools/report_check.sh $(BUILD) noto.gpkg

install: $(BUILD)/rockfall
	install -d $(DESTDIR)$(PREFIX)/bin
	install -m 755 $(BUILD)/rockfall $(DESTDIR)$(PREFIX)/bin/rockfall

clean:
	rm -rf build

-include $(LIB_OBJ:.o=.d) $(CLI_OBJ:.o=.d) $(FIX_OBJ:.o=.d) $(TEST_OBJ:.o=.d)
