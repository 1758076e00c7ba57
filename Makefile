# voroprobe — plain GNU make.
#   make            core library + build/voroprobe for this machine
#   make check      build and run every test; last line "N passed, N failed, N skipped"
#   make bench      benchmarks against the anchor figures
#   make demo       a full simulated scan
#   make CROSS=aarch64-linux-gnu-   the device program for an ARM Linux board
# BUILD=dir puts every output under another directory (default build/).
# all, demo, check and bench first install the Debian packages they need (tools/install-deps.sh),
# then run make again, which reads this file anew: the hardware libraries found by pkg-config
# (libgpiod, libcamera) are then seen on the very first build. HAVE_GPIOD= HAVE_LIBCAMERA= on
# the command line build without them (tests/t_backends.sh is checked against such a build).

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
# The layers above the core (doc/architecture.md): each folder sees only the headers of the
# layers it may use (tests/t_layers.sh checks the #includes too).
#   mesh: core   sim: core mesh   port: core   host: core mesh sim port   cli: all
LAYER_CFLAGS := $(WARN) $(OPT) $(FPFLAGS) -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE $(EXTRA_CFLAGS)
INC_mesh := -Icore -Imesh
INC_sim  := -Icore -Imesh -Isim
INC_port := -Icore -Iport
INC_host := -Icore -Imesh -Isim -Iport -Ihost
INC_cli  := $(INC_host) -Icli
HOST_CFLAGS = $(LAYER_CFLAGS) $(INC_cli)
LDLIBS := -lm

# Optional hardware libraries: used when present for the build target (a cross build: when
# given, e.g. HAVE_GPIOD=1 with the target's libgpiod-dev installed).
ifeq ($(CROSS),)
HAVE_GPIOD := $(shell pkg-config --exists libgpiod 2>/dev/null && echo 1)
HAVE_LIBCAMERA := $(shell pkg-config --exists libcamera 2>/dev/null && echo 1)
HAVE_GMP := $(shell test -f /usr/include/gmp.h -o -f /usr/include/x86_64-linux-gnu/gmp.h && echo 1)
ifeq ($(shell command -v pkg-config 2>/dev/null),)
ifneq ($(wildcard /usr/include/gpiod.h /usr/include/libcamera/libcamera/camera_manager.h),)
$(warning pkg-config is missing: building without libgpiod and libcamera (make deps installs it))
endif
endif
endif
# libpng: the pictures of host/vp_render (--png); libmicrohttpd: the live view (host/vp_live,
# --serve). Without them those options say so.
HAVE_PNG := $(if $(CROSS),,$(shell pkg-config --exists libpng 2>/dev/null && echo 1))
HAVE_MHD := $(if $(CROSS),,$(shell pkg-config --exists libmicrohttpd 2>/dev/null && echo 1))
ifeq ($(HAVE_PNG),1)
LAYER_CFLAGS += -DVP_HAVE_PNG=1
LDLIBS += -lpng
endif
ifeq ($(HAVE_MHD),1)
LAYER_CFLAGS += -DVP_HAVE_MHD=1
LDLIBS += -lmicrohttpd -lpthread
endif
ifeq ($(HAVE_GPIOD),1)
LAYER_CFLAGS += -DVP_HAVE_GPIOD=1
PORT_LIBS += -lgpiod
endif
# libcamera (C++): port/*.cpp is built only when pkg-config finds it.
ifeq ($(HAVE_LIBCAMERA),1)
LAYER_CFLAGS += -DVP_HAVE_LIBCAMERA=1
PORT_CXX_SRC := $(sort $(wildcard port/*.cpp))
PORT_LIBS += $(shell pkg-config --libs libcamera) -lstdc++
endif

CORE_SRC := $(sort $(wildcard core/*.c core/planner/*.c))
MESH_SRC := $(sort $(wildcard mesh/*.c))
SIM_SRC  := $(sort $(wildcard sim/*.c))
PORT_SRC := $(sort $(wildcard port/*.c))
HOSTL_SRC := $(sort $(wildcard host/*.c))
CLI_SRC  := $(sort $(wildcard cli/*.c))
# the C tests, by the layer they exercise (tests/core, mesh, sim, port, host)
TEST_SRC := $(sort $(wildcard tests/*/test_*.c))
ifneq ($(HAVE_GMP),1)
TEST_SRC := $(filter-out tests/core/test_gmp_%,$(TEST_SRC))
endif

CORE_OBJ := $(CORE_SRC:%.c=$(BUILD)/%.o)
MESH_OBJ := $(MESH_SRC:%.c=$(BUILD)/%.o)
SIM_OBJ  := $(SIM_SRC:%.c=$(BUILD)/%.o)
PORT_OBJ := $(PORT_SRC:%.c=$(BUILD)/%.o) $(PORT_CXX_SRC:%.cpp=$(BUILD)/%.o)
HOSTL_OBJ := $(HOSTL_SRC:%.c=$(BUILD)/%.o)
# the command line (main and cmd_*): linked into the program, in no library
CLI_OBJ  := $(CLI_SRC:%.c=$(BUILD)/%.o)
TEST_BIN := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)

LIBCORE := $(BUILD)/libvpcore.a
LIBMESH := $(BUILD)/libvpmesh.a
LIBSIM  := $(BUILD)/libvpsim.a
LIBPORT := $(BUILD)/libvpport.a
LIBHOST := $(BUILD)/libvphost.a
# one archive per layer, in link order (a layer before the layers it uses)
LIBS    := $(LIBHOST) $(LIBSIM) $(LIBPORT) $(LIBMESH) $(LIBCORE)
PROG    := $(BUILD)/voroprobe
CXXFLAGS_PORT := -std=c++17 $(OPT) -Wall -Wextra -Werror $(if $(PORT_CXX_SRC),$(shell pkg-config --cflags libcamera)) -Icore -Iport

# $(BUILD)/config.mk: what this build was configured with. Rewritten only when it changes, and
# every object and program depends on it, so a build directory made before libgpiod-dev or
# libcamera-dev was installed (or with other flags) is rebuilt with them.
CONFIG := $(BUILD)/config.mk
define CONFIG_TEXT
# written by the Makefile: the configuration of $(BUILD); a change rebuilds everything in it
CROSS = $(CROSS)
CC = $(CC)
CXX = $(CXX)
HAVE_GPIOD = $(HAVE_GPIOD)
HAVE_LIBCAMERA = $(HAVE_LIBCAMERA)
CORE_CFLAGS = $(CORE_CFLAGS)
LAYER_CFLAGS = $(LAYER_CFLAGS)
CXXFLAGS_PORT = $(CXXFLAGS_PORT)
PORT_LIBS = $(PORT_LIBS)
LDLIBS = $(LDLIBS)
endef

.PHONY: all tests test-programs check bench demo clean deps deps-build deps-bench fuzz FORCE
# The targets a user types install the packages first, then make again (re-reading this file).
ifeq ($(CROSS),)
all: deps-build
	@$(MAKE) --no-print-directory $(PROG)
else
all: $(PROG)
endif

$(CONFIG): FORCE
	$(shell mkdir -p $(@D))$(file >$@.new,$(CONFIG_TEXT))
	@if cmp -s $@.new $@; then rm -f $@.new; else mv -f $@.new $@; \
	  echo "$(BUILD): GPIO libgpiod $(if $(HAVE_GPIOD),yes,no), camera libcamera $(if $(HAVE_LIBCAMERA),yes,no) (configuration in $@)"; fi

$(BUILD)/core/%.o: core/%.c $(wildcard core/*.h core/planner/*.h) Makefile $(CONFIG)
	@mkdir -p $(@D)
	$(CC) $(CORE_CFLAGS) -c $< -o $@

$(BUILD)/mesh/%.o: mesh/%.c $(wildcard core/*.h mesh/*.h) Makefile $(CONFIG)
	@mkdir -p $(@D)
	$(CC) $(LAYER_CFLAGS) $(INC_mesh) -c $< -o $@

$(BUILD)/sim/%.o: sim/%.c $(wildcard core/*.h mesh/*.h sim/*.h) Makefile $(CONFIG)
	@mkdir -p $(@D)
	$(CC) $(LAYER_CFLAGS) $(INC_sim) -c $< -o $@

$(BUILD)/port/%.o: port/%.c $(wildcard core/*.h port/*.h) Makefile $(CONFIG)
	@mkdir -p $(@D)
	$(CC) $(LAYER_CFLAGS) $(INC_port) -c $< -o $@

$(BUILD)/host/%.o: host/%.c $(wildcard core/*.h mesh/*.h sim/*.h port/*.h host/*.h) Makefile $(CONFIG)
	@mkdir -p $(@D)
	$(CC) $(LAYER_CFLAGS) $(INC_host) -c $< -o $@

$(BUILD)/cli/%.o: cli/%.c $(wildcard core/*.h mesh/*.h sim/*.h port/*.h host/*.h cli/*.h) Makefile $(CONFIG)
	@mkdir -p $(@D)
	$(CC) $(LAYER_CFLAGS) $(INC_cli) -c $< -o $@

$(BUILD)/port/%.o: port/%.cpp $(wildcard core/*.h port/*.h) Makefile $(CONFIG)
	@mkdir -p $(@D)
	$(CXX) $(CXXFLAGS_PORT) -c $< -o $@

$(LIBCORE): $(CORE_OBJ)
	@rm -f $@
	$(AR) rcs $@ $^

$(LIBMESH): $(MESH_OBJ)
	@rm -f $@
	$(AR) rcs $@ $^

$(LIBSIM): $(SIM_OBJ)
	@rm -f $@
	$(AR) rcs $@ $^

$(LIBPORT): $(PORT_OBJ)
	@rm -f $@
	$(AR) rcs $@ $^

$(LIBHOST): $(HOSTL_OBJ)
	@rm -f $@
	$(AR) rcs $@ $^

$(PROG): $(CLI_OBJ) $(LIBS) $(CONFIG)
	$(CC) $(OPT) -o $@ $(CLI_OBJ) $(LIBS) $(PORT_LIBS) $(LDLIBS)

# the pages of the report and of the live view (host/report/NAME.html) as C arrays
# vp_NAME_page[] linked into the program (od, awk)
CLI_OBJ += $(BUILD)/cli/vp_report_page.o
$(PROG): $(BUILD)/cli/vp_report_page.o
$(BUILD)/cli/vp_report_page.c: host/report/viewer.html host/report/live.html Makefile
	@mkdir -p $(@D)
	@{ echo '/* generated from host/report/viewer.html and live.html by the Makefile */'; echo '#include <stddef.h>'; \
	  for f in viewer live; do a=vp_$${f}_page; \
	  echo "extern const unsigned char $$a[]; extern const size_t $${a}_len;"; echo "const unsigned char $$a[] = {"; \
	  od -An -v -tu1 host/report/$$f.html | awk '{ for (i = 1; i <= NF; i++) printf "%s,", $$i; print "" }'; \
	  echo '0 };'; echo "const size_t $${a}_len = sizeof $$a - 1;"; done; } > $@
$(BUILD)/cli/vp_report_page.o: $(BUILD)/cli/vp_report_page.c $(CONFIG)
	$(CC) $(LAYER_CFLAGS) -c $< -o $@

$(BUILD)/tests/core/test_gmp_%: tests/core/test_gmp_%.c tests/vp_test.h $(LIBS) $(CONFIG)
	@mkdir -p $(@D)
	$(CC) $(HOST_CFLAGS) -Itests -o $@ $< $(LIBS) $(PORT_LIBS) -lgmp $(LDLIBS)

$(BUILD)/tests/%: tests/%.c $(wildcard tests/*.h) $(LIBS) $(CONFIG)
	@mkdir -p $(@D)
	$(CC) $(HOST_CFLAGS) -Itests -o $@ $< $(LIBS) $(PORT_LIBS) $(LDLIBS)

# after `all` (which may make itself again once packages are installed), never beside it: two
# makes writing one build directory at once (`make -j2 all tests`) link half-written libraries
tests: all
	@$(MAKE) --no-print-directory test-programs
test-programs: $(PROG) $(TEST_BIN)

# tools/install-deps.sh GROUP: build (compiler, pkg-config, libgpiod-dev, libcamera-dev),
# check (build + every tool a test calls), bench (check + CGAL).
deps:
	@sh tools/install-deps.sh check
deps-build:
	@sh tools/install-deps.sh build
deps-bench:
	@sh tools/install-deps.sh bench

check: deps
	@$(MAKE) --no-print-directory tests
	@sh tests/run.sh $(BUILD)

bench: deps-bench
	@$(MAKE) --no-print-directory $(PROG)
	@sh bench/run.sh $(BUILD)

demo: deps-build
	@$(MAKE) --no-print-directory $(PROG)
	@sh tools/demo.sh $(BUILD)

clean:
	rm -rf $(BUILD) build-*

# ---- fuzzing: libFuzzer targets tests/fuzz/fuzz_*.c (clang, Debian's libclang-rt-14-dev) ----
#   make fuzz [FUZZ_TIME=60]   builds BUILD/fuzz/fuzz_* and runs each for FUZZ_TIME seconds
FUZZ_CC ?= clang
FUZZ_TIME ?= 60
FUZZ_CFLAGS := -std=c99 -g -O1 $(FPFLAGS) -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE $(INC_host) \
               -fno-sanitize-recover=undefined
FUZZ_SRC := $(CORE_SRC) $(MESH_SRC) $(SIM_SRC) $(PORT_SRC) $(HOSTL_SRC)
FUZZ_OBJ := $(FUZZ_SRC:%.c=$(BUILD)/fuzz/obj/%.o)
FUZZ_BIN := $(patsubst tests/fuzz/%.c,$(BUILD)/fuzz/%,$(wildcard tests/fuzz/fuzz_*.c))
.SECONDARY: $(FUZZ_OBJ)
$(BUILD)/fuzz/obj/%.o: %.c $(wildcard core/*.h mesh/*.h sim/*.h port/*.h host/*.h) Makefile
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link,address,undefined -c $< -o $@
$(BUILD)/fuzz/%: tests/fuzz/%.c $(FUZZ_OBJ)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer,address,undefined -o $@ $< $(FUZZ_OBJ) -lm
fuzz: $(PROG) $(FUZZ_BIN)
	@sh tests/fuzz/run.sh $(BUILD) $(FUZZ_TIME)
