# voroprobe — plain GNU make.
#   make            core library + build/voroprobe for this machine
#   make check      build and run every test; last line "N passed, N failed, N skipped"
#   make bench      benchmarks against the anchor figures
#   make demo       a full simulated scan
#   make CROSS=aarch64-linux-gnu-   the device program for an ARM Linux board
# BUILD=dir puts every output under another directory (default build/).

BUILD ?= build
CROSS ?=
CC := $(if $(CROSS),$(CROSS)gcc,$(if $(filter default,$(origin CC)),gcc,$(CC)))
AR := $(if $(CROSS),$(CROSS)ar,ar)
CXX := $(if $(CROSS),$(CROSS)g++,g++)
OPT ?= -O2

WARN := -std=c99 -pedantic -Wall -Wextra -Werror -Wmissing-prototypes -Wshadow
# -ffp-contract=off: no fused multiply-add, so x86-64 and ARM round the same way.
FPFLAGS := -ffp-contract=off -fno-math-errno
CORE_CFLAGS := $(WARN) $(OPT) $(FPFLAGS) -Icore $(EXTRA_CFLAGS)
HOST_CFLAGS := $(WARN) $(OPT) $(FPFLAGS) -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE \
               -Icore -Ihost-sim -Iport -Itools $(EXTRA_CFLAGS)
LDLIBS := -lm

# Optional hardware libraries: used when present for the build target.
ifeq ($(CROSS),)
HAVE_GPIOD := $(shell pkg-config --exists libgpiod 2>/dev/null && echo 1)
HAVE_LIBCAMERA := $(shell pkg-config --exists libcamera 2>/dev/null && echo 1)
HAVE_GMP := $(shell test -f /usr/include/gmp.h -o -f /usr/include/x86_64-linux-gnu/gmp.h && echo 1)
endif
ifeq ($(HAVE_GPIOD),1)
HOST_CFLAGS += -DVP_HAVE_GPIOD=1
PORT_LIBS += -lgpiod
endif
# libcamera (C++): port/*.cpp is built only when pkg-config finds it.
ifeq ($(HAVE_LIBCAMERA),1)
HOST_CFLAGS += -DVP_HAVE_LIBCAMERA=1
PORT_CXX_SRC := $(sort $(wildcard port/*.cpp))
PORT_LIBS += $(shell pkg-config --libs libcamera) -lstdc++
endif

CORE_SRC := $(sort $(wildcard core/*.c))
SIM_SRC  := $(sort $(wildcard host-sim/*.c))
PORT_SRC := $(sort $(wildcard port/*.c))
TOOL_SRC := $(sort $(filter-out tools/main.c,$(wildcard tools/*.c)))
TEST_SRC := $(sort $(wildcard tests/test_*.c))
ifneq ($(HAVE_GMP),1)
TEST_SRC := $(filter-out tests/test_gmp_%,$(TEST_SRC))
endif

CORE_OBJ := $(CORE_SRC:%.c=$(BUILD)/%.o)
SIM_OBJ  := $(SIM_SRC:%.c=$(BUILD)/%.o)
PORT_OBJ := $(PORT_SRC:%.c=$(BUILD)/%.o) $(PORT_CXX_SRC:%.cpp=$(BUILD)/%.o)
TOOL_OBJ := $(TOOL_SRC:%.c=$(BUILD)/%.o)
TEST_BIN := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)

LIBCORE := $(BUILD)/libvpcore.a
LIBHOST := $(BUILD)/libvphost.a
PROG    := $(BUILD)/voroprobe

.PHONY: all tests check bench demo clean deps fuzz
all: $(PROG)

$(BUILD)/core/%.o: core/%.c $(wildcard core/*.h) Makefile
	@mkdir -p $(@D)
	$(CC) $(CORE_CFLAGS) -c $< -o $@

$(BUILD)/%.o: %.c $(wildcard core/*.h host-sim/*.h port/*.h tools/*.h) Makefile
	@mkdir -p $(@D)
	$(CC) $(HOST_CFLAGS) -c $< -o $@

$(BUILD)/port/%.o: port/%.cpp $(wildcard core/*.h port/*.h) Makefile
	@mkdir -p $(@D)
	$(CXX) -std=c++17 $(OPT) -Wall -Wextra -Werror $(shell pkg-config --cflags libcamera) -Icore -Iport -c $< -o $@

$(LIBCORE): $(CORE_OBJ)
	@rm -f $@
	$(AR) rcs $@ $^

$(LIBHOST): $(SIM_OBJ) $(PORT_OBJ) $(TOOL_OBJ)
	@rm -f $@
	$(AR) rcs $@ $^

$(PROG): $(BUILD)/tools/main.o $(LIBHOST) $(LIBCORE)
	$(CC) $(OPT) -o $@ $< $(LIBHOST) $(LIBCORE) $(PORT_LIBS) $(LDLIBS)

$(BUILD)/tests/test_gmp_%: tests/test_gmp_%.c tests/vp_test.h $(LIBHOST) $(LIBCORE)
	@mkdir -p $(@D)
	$(CC) $(HOST_CFLAGS) -Itests -o $@ $< $(LIBHOST) $(LIBCORE) $(PORT_LIBS) -lgmp $(LDLIBS)

$(BUILD)/tests/%: tests/%.c tests/vp_test.h $(LIBHOST) $(LIBCORE)
	@mkdir -p $(@D)
	$(CC) $(HOST_CFLAGS) -Itests -o $@ $< $(LIBHOST) $(LIBCORE) $(PORT_LIBS) $(LDLIBS)

tests: $(PROG) $(TEST_BIN)

deps:
	@sh tools/install-deps.sh

check: deps
	@$(MAKE) --no-print-directory tests
	@sh tests/run.sh $(BUILD)

bench: deps
	@$(MAKE) --no-print-directory $(PROG)
	@sh bench/run.sh $(BUILD)

demo: $(PROG)
	@sh tools/demo.sh $(BUILD)

clean:
	rm -rf $(BUILD) build-*

# ---- fuzzing: libFuzzer targets tests/fuzz/fuzz_*.c (clang, Debian's libclang-rt-14-dev) ----
#   make fuzz [FUZZ_TIME=60]   builds BUILD/fuzz/fuzz_* and runs each for FUZZ_TIME seconds
FUZZ_CC ?= clang
FUZZ_TIME ?= 60
FUZZ_CFLAGS := -std=c99 -g -O1 $(FPFLAGS) -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -Icore -Ihost-sim \
               -Iport -Itools -fno-sanitize-recover=undefined
FUZZ_SRC := $(CORE_SRC) $(SIM_SRC) $(TOOL_SRC) $(PORT_SRC)
FUZZ_OBJ := $(FUZZ_SRC:%.c=$(BUILD)/fuzz/obj/%.o)
FUZZ_BIN := $(patsubst tests/fuzz/%.c,$(BUILD)/fuzz/%,$(wildcard tests/fuzz/fuzz_*.c))
.SECONDARY: $(FUZZ_OBJ)
$(BUILD)/fuzz/obj/%.o: %.c $(wildcard core/*.h host-sim/*.h port/*.h tools/*.h) Makefile
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link,address,undefined -c $< -o $@
$(BUILD)/fuzz/%: tests/fuzz/%.c $(FUZZ_OBJ)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer,address,undefined -o $@ $< $(FUZZ_OBJ) -lm
fuzz: $(PROG) $(FUZZ_BIN)
	@sh tests/fuzz/run.sh $(BUILD) $(FUZZ_TIME)
