# rockfall - design checks for rockfall protection measures.
#
#   make            build build/rockfall
#   make demo       build and run the example project, then check it
#   make test       build and run the tests (ends with "N passed, N failed")
#   make test SANITIZE=1   the same under AddressSanitizer and UBSan
#   make bench      speed against error of the motion engines
#   make install    PREFIX=/usr/local

# ---- settings ---------------------------------------------------------------
CC       ?= cc
PREFIX   ?= /usr/local
PKGS     := sqlite3 gsl yaml-0.1
OPT      ?= -O2
WARN     := -Wall -Wextra -Wshadow -Wstrict-prototypes -Wmissing-prototypes \
            -Wno-missing-field-initializers -Werror
CFLAGS   += -std=c11 -D_POSIX_C_SOURCE=200809L -g $(OPT) $(WARN) -ffp-contract=off \
            -Iinclude -Isrc $(shell pkg-config --cflags $(PKGS))
LDLIBS   += $(shell pkg-config --libs $(PKGS)) -lm -lpthread
BUILD    := build
ifeq ($(SANITIZE),1)
BUILD    := build/san
CFLAGS   += -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
LDFLAGS  += -fsanitize=address,undefined
endif

# ---- objects ----------------------------------------------------------------
LIB_SRC  := $(filter-out src/main.c,$(wildcard src/*.c))
LIB_OBJ  := $(LIB_SRC:src/%.c=$(BUILD)/src/%.o)
TEST_SRC := $(wildcard tests/*.c)
TEST_OBJ := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%.o)
TOOL_SRC := $(wildcard tools/*.c)
TOOLS    := $(TOOL_SRC:tools/%.c=$(BUILD)/tools/%)

.PHONY: all demo test bench install clean deps
all: $(BUILD)/rockfall $(TOOLS)

$(BUILD)/src/%.o: src/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -MMD -MP -c $< -o $@
$(BUILD)/tests/%.o: tests/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -Itests -MMD -MP -c $< -o $@
$(BUILD)/tools/%: tools/%.c $(BUILD)/librockfall.a
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(LDFLAGS) $< $(BUILD)/librockfall.a $(LDLIBS) -o $@

$(BUILD)/librockfall.a: $(LIB_OBJ)
	$(AR) rcs $@ $^
$(BUILD)/rockfall: $(BUILD)/src/main.o $(BUILD)/librockfall.a
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@
$(BUILD)/run_tests: $(TEST_OBJ) $(BUILD)/librockfall.a
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

# Dependencies the quick start installs on Debian when they are missing.
deps:
	@pkg-config --exists $(PKGS) 2>/dev/null || { \
	  echo "installing libsqlite3-dev libgsl-dev libyaml-dev pkg-config"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
	  apt-get install -y -qq libsqlite3-dev libgsl-dev libyaml-dev pkg-config; }

demo: all
	$(BUILD)/rockfall run projects/demo/demo.yaml -o demo.db

test: $(BUILD)/rockfall $(BUILD)/run_tests $(TOOLS)
	ROCKFALL_BIN=$(BUILD)/rockfall ROCKFALL_TOOLS=$(BUILD)/tools $(BUILD)/run_tests $(T)

bench: all
	$(BUILD)/tools/bench

install: $(BUILD)/rockfall
	install -d $(DESTDIR)$(PREFIX)/bin
	install -m 755 $(BUILD)/rockfall $(DESTDIR)$(PREFIX)/bin/rockfall

clean:
	rm -rf build

-include $(LIB_OBJ:.o=.d) $(TEST_OBJ:.o=.d) $(BUILD)/src/main.d
