# lanray - one Makefile for everything.
#   make            build bin/lanray-render and bin/obj2tmd (float build)
#   make deps       install the Debian packages the build needs (idempotent)
#   make demo       server + two local clients: a window, or frames in demo-frames/
#   make check      unit + CLI tests (after installing deps)
#   make check-asan the same tests under AddressSanitizer + UBSan
#   make check-tsan the thread pool, client and server under ThreadSanitizer
#   make fuzz       libFuzzer on every parser of outside bytes (FUZZ_SECONDS each)
#   make bench      renderer benchmark against Embree (prints ratios)
#   make tradeoff   quality knobs: time and error against a reference (docs/tradeoff.*)
#   make bench-compress  compressed pixels: ratios, the server's CPU a packet, fps behind slow links
#   make bench-pipeline  pipelined frames against serial ones, measured and simulated
#   make bench-path      the path integrator against the book's renderer (tools/bench/rtweekend)
#   make bench-cycles    the path integrator against Blender's Cycles at equal error (installs blender)
#   make bench-scaling  clients x segment size x tail rule, with schedsim (docs/scaling*)
#   make loadtest   64 clients joining and leaving for 5 minutes, every frame verified
#   make install    programs, docs, the client's systemd unit, the Avahi file (PREFIX, DESTDIR)
#   make deb        a Debian package of the tree in build/, checked by lintian
#   make tools-doc  docs/tools.md from every tool's --help
#   make architecture  docs/architecture.dot and .svg from the #include graph (graphviz)
#   make scene-doc  docs/scene.md's tables of keys from the scene's field tables
#   make PRECISION=double ...   double-precision build in build/double, bin/double
PRECISION ?= float
SAN ?=
CC ?= gcc

ifeq ($(PRECISION),double)
  PFLAGS := -DLANRAY_DOUBLE
  BIN := bin/double
else ifeq ($(PRECISION),float)
  PFLAGS :=
  BIN := bin
else
  $(error PRECISION must be float or double)
endif

ifeq ($(SAN),asan)
  SANFLAGS := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
  OPT := -O1
  BIN := $(BIN)/asan
else ifeq ($(SAN),tsan)
  SANFLAGS := -fsanitize=thread
  OPT := -O1
  BIN := $(BIN)/tsan
else
  SANFLAGS :=
  OPT := -O2
endif

# FEATURES=minimal: every optional feature compiled out (for the feature-cost benchmark)
ifeq ($(FEATURES),minimal)
  PFLAGS += -DLANRAY_MINIMAL
  BIN := $(BIN)/minimal
endif

BUILD := build/$(PRECISION)$(if $(SAN),-$(SAN))$(if $(FEATURES),-$(FEATURES))
CFLAGS ?= $(OPT) -g
CPPFLAGS := -D_POSIX_C_SOURCE=200809L $(PFLAGS) -Icommon -Iserver -Iclient
# -ffp-contract=off: the same rounding on every SIMD path and compiler (one
# frame, one picture).  -fno-trapping-math: lanray reads no floating-point
# exception flags, and without it GCC keeps a lane loop with two selects
# (a ? x : y) scalar, lest the select's unused side trap (the round lamp's
# points, scene/shade.c sphere_dirs); the values are IEEE's either way.
ALL_CFLAGS := -std=c17 -ffp-contract=off -fno-math-errno -fno-trapping-math -Wall -Wextra -Wshadow -Wdouble-promotion -Wmissing-prototypes -Werror -pthread -MMD -MP $(SANFLAGS) $(CPPFLAGS) $(CFLAGS)
LDLIBS := -lassimp -ljson-c -lsodium -lnetpbm -lpng -ljpeg -lzstd -llz4 -lavahi-client -lavahi-common -lz -lm -pthread
LDFLAGS := $(SANFLAGS)

# one archive per layer of programs: the library every program shares
# (common/), the server's loop, scheduler and measurements, the client's
# session.  The server's SDL window is in none of them, so no test links
# SDL, and a test links the server's or the client's archive only when it
# tests them.
# (with them the scene shown replaced, livescene.c, which calls the window:
# in an archive of the server's loop it broke the fuzz harnesses' link)
DISPLAY_SRC := server/display.c server/window.c server/livescene.c
COMMON_SRC := $(wildcard common/*/*.c)
SERVER_SRC := $(filter-out server/main.c $(DISPLAY_SRC),$(wildcard server/*.c))
CLIENT_SRC := $(filter-out client/main.c,$(wildcard client/*.c))
LIB := $(BUILD)/liblanray.a
SERVER_LIB := $(BUILD)/liblanray-server.a
CLIENT_LIB := $(BUILD)/liblanray-client.a
# a link line: the objects, the archives above the shared library, then it
# (a static archive only serves the ones named before it)
LINK_INPUTS = $(filter %.o,$^) $(filter-out $(LIB),$(filter %.a,$^)) $(LIB)
TOOLS := $(BIN)/lanray-render $(BIN)/obj2tmd $(BIN)/lanray-imgdiff $(BIN)/lanray-server $(BIN)/lanray-client $(BIN)/schedsim
TEST_SRC := $(wildcard tests/test_*.c tests/stability/test_*.c)
TESTS := $(TEST_SRC:%.c=$(BUILD)/%)
# fuzz harnesses (tests/fuzz/fuzz_NAME.c): replayed over their corpus by make check
FUZZ_NAMES := $(patsubst tests/fuzz/fuzz_%.c,%,$(wildcard tests/fuzz/fuzz_*.c))
REPLAYS := $(FUZZ_NAMES:%=$(BUILD)/fuzz/replay_%)

DEB_PACKAGES := gcc make pkg-config libjson-c-dev libsdl2-dev libsdl2-ttf-dev fonts-dejavu-core xdotool libnetpbm-dev libpng-dev libjpeg62-turbo-dev zlib1g-dev libassimp-dev libcmocka-dev libembree-dev libsodium-dev libzstd-dev liblz4-dev libavahi-client-dev avahi-daemon avahi-utils dbus dpkg-dev help2man xvfb x11-apps jwm python3 clang libclang-rt-14-dev povray

.PHONY: all deps check check-asan bench demo clean tradeoff bench-scaling bench-realtime bench-ahead bench-compress bench-pipeline bench-path bench-cycles install uninstall deb fuzz loadtest tools-doc architecture scene-doc
.SECONDARY:
all: $(TOOLS)

deps:
	@missing=""; for p in $(DEB_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "make deps: installing$$missing"; \
	  SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing >/dev/null; \
	else echo "make deps: all packages present"; fi

# Before anything compiles: the libraries' headers are there, or one line
# says what to do (instead of a compiler error per file).  The targets that
# run `make deps` first are not held back by it.
LIB_HEADERS ?= /usr/include/json-c/json.h /usr/include/SDL2/SDL.h /usr/include/SDL2/SDL_ttf.h /usr/include/netpbm/pam.h /usr/include/png.h /usr/include/zlib.h /usr/include/sodium.h /usr/include/zstd.h /usr/include/lz4.h /usr/include/avahi-client/client.h /usr/include/cmocka.h /usr/include/assimp/cimport.h /usr/include/jpeglib.h
INSTALLING_GOALS := deps check check-asan check-tsan demo bench tradeoff bench-scaling bench-compress bench-pipeline bench-path bench-cycles bench-realtime fuzz loadtest clean architecture deb
ifeq ($(filter $(INSTALLING_GOALS),$(MAKECMDGOALS)),)
  MISSING_HEADERS := $(filter-out $(wildcard $(LIB_HEADERS)),$(LIB_HEADERS))
  ifneq ($(MISSING_HEADERS),)
    $(error lanray: the libraries are not installed (no $(MISSING_HEADERS)): run 'make deps' first)
  endif
endif

# The compiler and flags the objects were made with: a change to them (an
# option here, CFLAGS on the command line) compiles every object again.
# The stamp is written only when its contents change, so that an unchanged
# build stays up to date.
FLAGS_STAMP := $(BUILD)/cflags
$(FLAGS_STAMP): FORCE
	@mkdir -p $(dir $@)
	@echo '$(CC) $(ALL_CFLAGS)' | cmp -s - $@ || echo '$(CC) $(ALL_CFLAGS)' >$@
.PHONY: FORCE
FORCE:

$(BUILD)/%.o: %.c $(FLAGS_STAMP)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -c $< -o $@

$(LIB): $(COMMON_SRC:%.c=$(BUILD)/%.o)
	@rm -f $@
	ar rcs $@ $^
$(SERVER_LIB): $(SERVER_SRC:%.c=$(BUILD)/%.o)
	@rm -f $@
	ar rcs $@ $^
$(CLIENT_LIB): $(CLIENT_SRC:%.c=$(BUILD)/%.o)
	@rm -f $@
	ar rcs $@ $^

$(BIN)/lanray-render: $(BUILD)/tools/lanray_render.o $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(BIN)/obj2tmd: $(BUILD)/tools/obj2tmd.o $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(BIN)/lanray-server: $(BUILD)/server/main.o $(DISPLAY_SRC:%.c=$(BUILD)/%.o) $(SERVER_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) -o $@ $(LINK_INPUTS) -lSDL2_ttf -lSDL2 $(LDLIBS)

$(BIN)/lanray-client: $(BUILD)/client/main.o $(CLIENT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) -o $@ $(LINK_INPUTS) $(LDLIBS)

$(BIN)/schedsim: $(BUILD)/tools/schedsim.o $(SERVER_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) -o $@ $(LINK_INPUTS) $(LDLIBS)

$(BIN)/lanray-imgdiff: $(BUILD)/tools/imgdiff.o $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(BUILD)/tests/%: $(BUILD)/tests/%.o $(LIB)
	$(CC) $(LDFLAGS) -o $@ $(LINK_INPUTS) -lcmocka $(LDLIBS)
# the tests of the server's scheduler and measurements, and the packet
# handlers' fuzz harnesses, link the archive they test
$(BUILD)/tests/test_sched $(BUILD)/tests/test_measure $(BUILD)/tests/test_pace $(BUILD)/tests/test_framerate $(BUILD)/tests/test_upscale $(BUILD)/tests/test_framewriter $(BUILD)/tests/test_controls $(BUILD)/fuzz/replay_server: $(SERVER_LIB)
$(BUILD)/fuzz/replay_client: $(CLIENT_LIB)
# the assets' way from the server's uploads to the client's cache: both sides
$(BUILD)/tests/test_upload: $(SERVER_LIB) $(CLIENT_LIB)

# docs/scene.md's tables of keys, printed from the field tables that the
# parser, the wire and the checks read (test_fields fails where they differ)
scene-doc: $(BUILD)/tests/test_fields
	$(BUILD)/tests/test_fields --write

# The unit tests, then the command-line tests against the built tools.
# What they need is built first on every core (CI's machines have two:
# built one file at a time, the three configurations took about four of
# its fifteen minutes), unless make already runs with -j (a jobserver).
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
PARALLEL := $(if $(findstring jobserver,$(MAKEFLAGS)),,-j$(JOBS))
check: deps
	@$(MAKE) --no-print-directory $(PARALLEL) test-build
	@$(MAKE) --no-print-directory test-run
check-asan: deps
	@$(MAKE) --no-print-directory $(PARALLEL) test-build SAN=asan
	@$(MAKE) --no-print-directory test-run SAN=asan

# ThreadSanitizer on what runs threads: the render pool (render, wire and
# stability tests render with it), the builders' workers (bvh), the
# server's frame writer, and the client's render thread against the server
# (the integration test, whose server writes its frames on the writer's
# thread; and denoising's and the Whitted history's, whose server filters
# or adds up frames on a thread of its own; and edits', whose scenes the
# server reads on a thread of its own)
TSAN_TESTS := build/float-tsan/tests/test_render build/float-tsan/tests/test_bvh build/float-tsan/tests/test_wire build/float-tsan/tests/test_framewriter build/float-tsan/tests/test_upload
TSAN_BUILD := $(TSAN_TESTS) bin/tsan/lanray-render bin/tsan/lanray-server bin/tsan/lanray-client bin/tsan/lanray-imgdiff
tsan-build:
	@$(MAKE) --no-print-directory SAN=tsan $(TSAN_BUILD)
# (two at a time, as make check runs its tests: one after another they
# took over two minutes of CI's fifteen; the slowest first)
check-tsan: deps
	@$(MAKE) --no-print-directory $(PARALLEL) tsan-build
	@rm -f build/float-tsan/report.*
	@TSAN_OPTIONS="halt_on_error=1 exitcode=66 log_path=$(CURDIR)/build/float-tsan/report" BIN=bin/tsan \
	    CLI_TESTS="history denoise distributed edit" bash tests/run.sh $(TSAN_TESTS)
	@# a report from a client running in the background lands in a file: any file fails the run
	@if ls build/float-tsan/report.* >/dev/null 2>&1; then cat build/float-tsan/report.*; exit 1; fi
	@echo "[       OK ] test_render, test_bvh, test_wire, test_framewriter, test_upload, distributed.sh, denoise.sh, history.sh and edit.sh under ThreadSanitizer, no reports"

.PHONY: test-run test-build check-tsan tsan-build
test-run: test-build
	@BUILD=$(BUILD) BIN=$(BIN) bash tests/run.sh $(TESTS)
# every benchmark program is built with the tests, so that a change that
# breaks one (view_bench's own assets_free met asset.h's) fails make check
# rather than a later make bench
BENCH_PROGRAMS := $(patsubst tools/bench/%.c,$(BUILD)/tools/bench/%,$(wildcard tools/bench/*.c))
test-build: $(TESTS) $(TOOLS) $(REPLAYS) $(BENCH_PROGRAMS)

$(BUILD)/fuzz/replay_%: tests/fuzz/fuzz_%.c tests/fuzz/replay.c $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -Itests/fuzz -o $@ tests/fuzz/fuzz_$*.c tests/fuzz/replay.c $(filter-out $(LIB),$(filter %.a,$^)) $(LIB) $(LDLIBS)

# make fuzz [FUZZ_SECONDS=600] [FUZZ_JOBS=2] [FUZZ_NAMES="server client"]: libFuzzer with ASan+UBSan (clang),
# each harness for FUZZ_SECONDS, seeded from tests/fuzz/corpus/NAME; new
# inputs go to build/fuzz-corpus/NAME, crashes to tests/fuzz/crashes/NAME-*
# (commit them: make check replays them).
FUZZ_SECONDS ?= 60
FUZZ_JOBS ?= 2
FUZZ_CFLAGS := -std=c17 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined $(CPPFLAGS) -Itests/fuzz
FUZZERS := $(FUZZ_NAMES:%=build/fuzz/fuzz_%)
# (the headers too: a kernel in a header changed, the harnesses must be built again)
build/fuzz/fuzz_%: tests/fuzz/fuzz_%.c $(COMMON_SRC) $(SERVER_SRC) $(CLIENT_SRC) $(wildcard common/*/*.h server/*.h client/*.h tests/fuzz/*.h)
	@mkdir -p $(dir $@)
	clang $(FUZZ_CFLAGS) -o $@ $< $(COMMON_SRC) $(SERVER_SRC) $(CLIENT_SRC) $(LDLIBS)
fuzz: deps $(FUZZERS)
	@BUILD_FUZZ=build/fuzz FUZZ_SECONDS=$(FUZZ_SECONDS) FUZZ_JOBS=$(FUZZ_JOBS) bash tests/fuzz/run-fuzzers $(FUZZ_NAMES)

$(BUILD)/tools/bench/embree_ref: tools/bench/embree_ref.c $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -o $@ $< $(LIB) -lembree3 $(LDLIBS)
$(BUILD)/tools/bench/rayclass: tools/bench/rayclass.c $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -o $@ $< $(LIB) -lembree3 $(LDLIBS)

# the benchmark drivers that need no more than the library (embree_ref, above, links Embree too)
$(BUILD)/tools/bench/%: tools/bench/%.c $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -o $@ $< $(LIB) $(LDLIBS)

bench: deps $(TOOLS) $(BUILD)/tools/bench/embree_ref $(BUILD)/tools/bench/import_bench $(BUILD)/tools/bench/build_bench $(BUILD)/tools/bench/view_bench $(BUILD)/tools/bench/rayclass $(BUILD)/tools/bench/scene2pov
	@$(MAKE) --no-print-directory FEATURES=minimal $(BIN)/minimal/lanray-render
	@BIN=$(BIN) EMBREE_REF=$(BUILD)/tools/bench/embree_ref BUILD_BENCH=$(BUILD)/tools/bench/build_bench bash tools/bench/bench-render
	@BIN=$(BIN) RAYCLASS=$(BUILD)/tools/bench/rayclass bash tools/bench/bench-rayclass
	@BIN=$(BIN) bash tools/bench/bench-features
	@IMPORT_BENCH=$(BUILD)/tools/bench/import_bench bash tools/bench/bench-import
	@VIEW_BENCH=$(BUILD)/tools/bench/view_bench bash tools/bench/bench-view
	@BIN=$(BIN) bash tools/bench/bench-frame
	@BIN=$(BIN) SCENE2POV=$(BUILD)/tools/bench/scene2pov bash tools/bench/bench-pov

# make install [PREFIX=/usr/local] [DESTDIR=]: the programs, the docs, the
# client's systemd unit and its settings file, the server's Avahi service
# file (settings files kept where they are there already: a farm's own);
# make uninstall takes them away again (the settings files stay)
PREFIX ?= /usr/local
DESTDIR ?=
SYSCONFDIR ?= $(if $(filter /usr,$(PREFIX)),/etc,$(PREFIX)/etc)
UNITDIR ?= $(if $(filter /usr,$(PREFIX)),/lib/systemd/system,$(PREFIX)/lib/systemd/system)
INSTALL_PROGRAMS := lanray-server lanray-client lanray-render obj2tmd lanray-imgdiff
INSTALL_DOCS := README.md docs/farm.md docs/getting-started.md docs/scene.md docs/protocol.md docs/tools.md docs/tmd.md
DOCDIR := $(PREFIX)/share/doc/lanray
PROTO_VERSION = $(shell sed -n 's/^#define PROTO_VERSION \([0-9]*\)u.*/\1/p' common/net/msg.h)
DIST_SED = sed -e 's|@BINDIR@|$(PREFIX)/bin|g' -e 's|@DOCDIR@|$(DOCDIR)|g' -e 's|@SYSCONFDIR@|$(SYSCONFDIR)|g' \
	-e 's|@PROTO@|$(PROTO_VERSION)|g'
install: $(TOOLS)
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(DOCDIR) $(DESTDIR)$(UNITDIR) $(DESTDIR)$(SYSCONFDIR)/default \
	  $(DESTDIR)$(SYSCONFDIR)/avahi/services
	install -m 755 $(addprefix $(BIN)/,$(INSTALL_PROGRAMS)) $(DESTDIR)$(PREFIX)/bin/
	install -m 644 $(INSTALL_DOCS) $(DESTDIR)$(DOCDIR)/
	$(DIST_SED) tools/dist/lanray-client.service.in >$(DESTDIR)$(UNITDIR)/lanray-client.service
	$(DIST_SED) tools/dist/lanray.avahi.service.in >$(DESTDIR)$(SYSCONFDIR)/avahi/services/lanray.service
	chmod 644 $(DESTDIR)$(UNITDIR)/lanray-client.service $(DESTDIR)$(SYSCONFDIR)/avahi/services/lanray.service
	[ -e $(DESTDIR)$(SYSCONFDIR)/default/lanray-client ] || \
	  install -m 644 tools/dist/lanray-client.default $(DESTDIR)$(SYSCONFDIR)/default/lanray-client

uninstall:
	rm -f $(addprefix $(DESTDIR)$(PREFIX)/bin/,$(INSTALL_PROGRAMS)) $(DESTDIR)$(UNITDIR)/lanray-client.service \
	  $(DESTDIR)$(SYSCONFDIR)/avahi/services/lanray.service
	rm -rf $(DESTDIR)$(DOCDIR)

# make deb: a Debian package of the tree (build/lanray_VERSION_ARCH.deb),
# checked by lintian
deb: deps $(TOOLS)
	@$(MAKE) --no-print-directory DEB_PACKAGES="dpkg-dev lintian help2man" deps
	@BIN=$(BIN) bash tools/dist/make-deb

# compressed pixels: codings of rendered segments, the server's CPU a DATA
# packet (datagen), frames a second through rate-limited links (root)
bench-compress: deps $(TOOLS) $(BUILD)/tools/bench/codec_bench $(BUILD)/tools/bench/datagen
	@$(MAKE) --no-print-directory DEB_PACKAGES=iproute2 deps
	@BIN=$(BIN) DATAGEN=$(BUILD)/tools/bench/datagen CODEC_BENCH=$(BUILD)/tools/bench/codec_bench bash tools/bench/bench-compress

bench-pipeline: deps $(TOOLS)
	@BIN=$(BIN) bash tools/bench/bench-pipeline

bench-path: deps $(TOOLS) $(BUILD)/tools/bench/rtweekend
	@$(MAKE) --no-print-directory DEB_PACKAGES=gnuplot deps
	@BIN=$(BIN) RTWEEKEND=$(BUILD)/tools/bench/rtweekend bash tools/bench/bench-path docs

# Blender (Cycles) is large: installed here, not by make deps
bench-cycles: deps $(TOOLS) $(BUILD)/tools/bench/rtweekend
	@$(MAKE) --no-print-directory DEB_PACKAGES="blender gnuplot" deps
	@BIN=$(BIN) RTWEEKEND=$(BUILD)/tools/bench/rtweekend bash tools/bench/bench-cycles docs

# the trade-off study: CSV and plot into docs/ (needs gnuplot, installed here)
tradeoff: deps $(TOOLS)
	@$(MAKE) --no-print-directory DEB_PACKAGES=gnuplot-nox deps
	@$(MAKE) --no-print-directory PRECISION=double bin/double/lanray-render
	@BIN=$(BIN) bash tools/bench/tradeoff docs

# scaling by clients, segment size and tail rule, and the simulator beside it;
# docs/scaling-runs.csv keeps one row per run, which REPLAY=docs/scaling-runs.csv
# tools/bench/bench-scaling analyses again after a simulator change
bench-scaling: deps $(TOOLS)
	@$(MAKE) --no-print-directory DEB_PACKAGES="gnuplot-nox iproute2" deps
	@BIN=$(BIN) tools/bench/bench-scaling docs

# the real-time viewer: make demo's flight at a frame-rate target, its error
# and its time to converge against lanray-render (docs/realtime.md)
# frames while a large model edited into the scene reaches the clients
# (docs/protocol.md); links of 100 Mbit/s and 1 Gbit/s as root
bench-ahead: deps $(TOOLS)
	@$(MAKE) --no-print-directory DEB_PACKAGES=iproute2 deps
	@BIN=$(BIN) bash tools/bench/bench-ahead

bench-realtime: deps $(TOOLS)
	@$(MAKE) --no-print-directory DEB_PACKAGES=gnuplot-nox deps
	@BIN=$(BIN) bash tools/bench/bench-realtime docs

# make loadtest [LOAD_SECONDS=300] [LOAD_CLIENTS=64]: one server, many clients
# joining and leaving, every frame verified; server RSS and CPU in docs/loadtest.csv
LOAD_SECONDS ?= 300
LOAD_CLIENTS ?= 64
loadtest: deps $(TOOLS)
	@BIN=$(BIN) DURATION=$(LOAD_SECONDS) CLIENTS=$(LOAD_CLIENTS) bash tools/bench/loadtest docs

# docs/tools.md from the tools' --help (tests/cli/docs.sh checks they agree)
tools-doc: $(TOOLS)
	@bash tools/tools-doc $(BIN)

demo: deps $(TOOLS)
	@BIN=$(BIN) bash tools/demo

clean:
	rm -rf build bin

-include $(shell find build -name '*.d' 2>/dev/null)

# the layers as a picture, made from the code's #include lines (tests/tools/layers.py;
# tests/cli/layers.sh checks that docs/architecture.dot is current)
architecture: deps
	@$(MAKE) --no-print-directory DEB_PACKAGES=graphviz deps
	@python3 tests/tools/layers.py --dot > docs/architecture.dot.tmp && mv docs/architecture.dot.tmp docs/architecture.dot
	@tred docs/architecture.dot | dot -Tsvg -o docs/architecture.svg.tmp && mv docs/architecture.svg.tmp docs/architecture.svg
	@echo "docs/architecture.dot, docs/architecture.svg"
