# evo — top-level build. `make help` lists the targets.
#
# Layout of the output (BUILD, default build/):
#   BUILD/evo                the evo command
#   BUILD/libevocore.a       core/ (freestanding C11)
#   BUILD/libevohost.a       sim/ (host side)
#   BUILD/tests/...          one test binary per tests/**/test_*.c
# `make test` builds and runs every test plainly (build/), under
# AddressSanitizer + UndefinedBehaviorSanitizer (build/asan/), and the
# threaded ones under ThreadSanitizer (build/tsan/).

BUILD ?= build
CC ?= cc
CXX ?= c++
CLANG ?= clang
ARM_CC ?= arm-none-eabi-gcc
ARM_SIZE ?= arm-none-eabi-size
ARM_NM ?= arm-none-eabi-nm
PREFIX ?= /usr/local
FUZZ_SECONDS ?= 20
TEST_FUZZ_SECONDS ?= 5
SAN ?=

WARN := -Wall -Wextra -Werror -Wpedantic -Wshadow -Wstrict-prototypes \
	-Wmissing-prototypes -Wpointer-arith -Wvla
OPT ?= -O2 -g
# Lua and SDL2 headers are system headers: their own warnings are not ours.
LUA_CFLAGS := -isystem /usr/include/lua5.4
SDL_CFLAGS := $(patsubst -I%,-isystem %,$(shell pkg-config --cflags sdl2 2>/dev/null))
# sim/, core/ and bench/ see no test headers (-Itests is the tests' alone),
# so neither the host side nor a benchmark can include test code.
CFLAGS_HOST := -std=c11 $(OPT) $(WARN) -Icore/include -Isim $(LUA_CFLAGS) $(SDL_CFLAGS) $(SAN) $(CFLAGS)
CFLAGS_ALL := $(CFLAGS_HOST) -Itests
LDFLAGS_ALL := $(SAN) $(LDFLAGS)
LIBS := -llua5.4 $(shell pkg-config --libs sdl2 2>/dev/null || echo -lSDL2) -lbox2d -lz -lstdc++ -lm
CXXFLAGS_ALL := -std=c++17 $(OPT) -Wall -Wextra -Werror -Wshadow -Isim $(SAN) $(CXXFLAGS)

CORE_SRCS := $(sort $(wildcard core/src/*.c))
# What a robot's firmware carries: the tick, networks, variables, hard-coded
# skills and the image loader. Parsers, the image writer and the network
# compiler are core too (freestanding) but run only on the host, and so do
# the status messages (status.c): a firmware reports a status by its code.
CORE_RUNTIME := mind variables hardcoded hash net table
HOST_SRCS := $(filter-out sim/cmd/evo_main.c,$(sort $(wildcard sim/*/*.c)))
# The Box2D shim is the only C++ in evo.
HOST_CXX_SRCS := $(sort $(wildcard sim/*/*.cpp))
TEST_SUPPORT := $(filter-out tests/support/net_dump_main.c,$(sort $(wildcard tests/support/*.c)))
TEST_SRCS := $(sort $(wildcard tests/*/test_*.c tests/sim/*/test_*.c))
TEST_BINS := $(patsubst tests/%.c,$(BUILD)/tests/%,$(TEST_SRCS))
FUZZ_SRCS := $(sort $(wildcard tests/fuzz/fuzz_*.c))

CORE_OBJS := $(patsubst %.c,$(BUILD)/obj/%.o,$(CORE_SRCS))
HOST_OBJS := $(patsubst %.c,$(BUILD)/obj/%.o,$(HOST_SRCS)) \
	$(patsubst %.cpp,$(BUILD)/obj/%.o,$(HOST_CXX_SRCS))
SUPPORT_OBJS := $(patsubst %.c,$(BUILD)/obj/%.o,$(TEST_SUPPORT))

.PHONY: all help deps test test-plain test-asan run install core-check fuzz \
	format clean bench bench-compare firmware-test
.DEFAULT_GOAL := all
# Keep objects make would otherwise treat as intermediate and delete.
.SECONDARY:

all: $(BUILD)/evo $(BUILD)/libevocore.a $(BUILD)/libevohost.a

help:
	@echo "make            build build/evo and the libraries"
	@echo "make deps       install the Debian packages evo needs (as root)"
	@echo "make test       deps, build, run every test plainly, under ASan+UBSan and TSan"
	@echo "make test-tsan  the threaded tests and headless runs under ThreadSanitizer"
	@echo "make run        deps, build, run the main job on a shipped example"
	@echo "make core-check compile core/ for Cortex-M0+ and check what it links"
	@echo "make fuzz       run each parser's fuzz target for FUZZ_SECONDS"
	@echo "make bench      benchmarks, each beside its baseline in the same run"
	@echo "make bench-compare BASE=REV  bench_world and bench_evaluate of REV beside this tree's"
	@echo "make install    install evo and lua/ under PREFIX ($(PREFIX))"
	@echo "make format     apply .clang-format to the C sources"

deps:
	@sh .ci/deps

$(BUILD)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) -MMD -MP -c $< -o $@

# A module's own tests may use its private headers (core's tests, core/src);
# no other code may.
$(BUILD)/obj/tests/core/%.o: CFLAGS_ALL += -Icore/src
$(BUILD)/obj/sim/%.o $(BUILD)/obj/core/%.o $(BUILD)/obj/bench/%.o: CFLAGS_ALL = $(CFLAGS_HOST)

$(BUILD)/obj/%.o: %.cpp
	@mkdir -p $(dir $@)
	$(CXX) $(CXXFLAGS_ALL) -MMD -MP -c $< -o $@

$(BUILD)/libevocore.a: $(CORE_OBJS)
	@rm -f $@
	ar rcs $@ $^

$(BUILD)/libevohost.a: $(HOST_OBJS)
	@rm -f $@
	ar rcs $@ $^

$(BUILD)/evo: $(BUILD)/obj/sim/cmd/evo_main.o $(BUILD)/libevohost.a $(BUILD)/libevocore.a
	$(CC) $(LDFLAGS_ALL) -o $@ $^ $(LIBS)

$(BUILD)/tests/%: $(BUILD)/obj/tests/%.o $(SUPPORT_OBJS) $(BUILD)/libevohost.a $(BUILD)/libevocore.a
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_ALL) -o $@ $^ $(LIBS)

# Networks compiled at -O0 and at -O2 must give bit-identical outputs:
# tests/core/test_net_opt runs these two and compares what they print.
NET_DUMP_SRCS := tests/support/net_dump_main.c $(CORE_SRCS)
$(BUILD)/tests/net_dump_O0 $(BUILD)/tests/net_dump_O2: $(NET_DUMP_SRCS)
	@mkdir -p $(dir $@)
	$(CC) -std=c11 $(subst $(BUILD)/tests/net_dump_,-,$@) $(WARN) -Icore/include -Itests $(SAN) -o $@ $^ -lm

# Benchmarks: each prints its figure beside a baseline measured in the
# same run (timings on a shared machine are noisy; ratios hold).
BENCH_SRCS := $(sort $(wildcard bench/bench_*.c))
BENCH_BINS := $(patsubst bench/%.c,$(BUILD)/bench/%,$(BENCH_SRCS))

$(BUILD)/bench/%: $(BUILD)/obj/bench/%.o $(BUILD)/libevohost.a $(BUILD)/libevocore.a
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_ALL) -o $@ $^ $(LIBS)

bench: deps $(BENCH_BINS)
	@rc=0; for b in $(BENCH_BINS); do echo "== $$b"; $$b || rc=1; done; exit $$rc

# bench_world and bench_evaluate of commit BASE beside this tree's, in turns
# in the same run (bench/compare.sh): a change that should cost nothing is
# checked against the commit before it.
BASE ?= HEAD
ROUNDS ?= 3
bench-compare: deps
	@sh bench/compare.sh $(BASE) $(ROUNDS)

test-bins: $(TEST_BINS) $(BUILD)/evo $(BUILD)/tests/net_dump_O0 $(BUILD)/tests/net_dump_O2

# Runs every test binary; a failing one fails the target after all have run.
# tests/run.sh sums their counts into one closing line.
test-plain: test-bins
	@EVO_BUILD=$(BUILD) sh tests/run.sh $(TEST_BINS) tests/test_layout.sh \
		tests/test_docs.sh

# X11 and Mesa leak at exit inside SDL's viewer; tests/lsan.supp names only
# those libraries, so leaks in evo's own code still fail the run.
test-asan:
	@LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0 \
	$(MAKE) --no-print-directory BUILD=build/asan OPT="-O1 -g" \
		SAN="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer" \
		test-plain

# ThreadSanitizer over the tests that start threads (the evaluator's pool,
# the learning loop) and the viewer-free `evo run --headless` runs, whose
# evo is build/tsan/evo. A report makes its process exit 66 at once
# (halt_on_error), which tests/run.sh counts as a failure; as an evo that
# a test expects to fail could hide its exit status, every report also
# goes to a file under TSAN_REPORTS, and any such file fails the target.
# tests/tsan.supp names only Box2D's own unlocked global counters.
TSAN_SRCS := tests/sim/learn/test_evaluate.c tests/sim/learn/test_learn.c \
	tests/sim/learn/test_literature.c tests/sim/cmd/test_run.c \
	tests/sim/cmd/test_golden.c
TSAN_BINS := $(patsubst tests/%.c,build/tsan/tests/%,$(TSAN_SRCS))
TSAN_REPORTS := build/tsan/reports
TSAN_OPTIONS_ALL := suppressions=$(CURDIR)/tests/tsan.supp halt_on_error=1 \
	exitcode=66 print_suppressions=0 second_deadlock_stack=1 \
	log_path=$(CURDIR)/$(TSAN_REPORTS)/tsan

.PHONY: test-tsan
test-tsan:
	@$(MAKE) --no-print-directory BUILD=build/tsan OPT="-O1 -g" \
		SAN="-fsanitize=thread -fno-omit-frame-pointer" \
		build/tsan/evo $(TSAN_BINS)
	@rm -rf $(TSAN_REPORTS) && mkdir -p $(TSAN_REPORTS)
	@TSAN_OPTIONS="$(TSAN_OPTIONS_ALL)" EVO_BUILD=build/tsan \
		sh tests/run.sh $(TSAN_BINS); rc=$$?; \
	for f in $(TSAN_REPORTS)/tsan.*; do \
		[ -e "$$f" ] || continue; rc=1; \
		echo "== ThreadSanitizer report $$f"; cat "$$f"; \
	done; \
	[ $$rc -eq 0 ] || echo "test-tsan: FAILED (see the tests and reports above)"; \
	exit $$rc

test: deps
	@$(MAKE) --no-print-directory core-check
	@$(MAKE) --no-print-directory fuzz FUZZ_SECONDS=$(TEST_FUZZ_SECONDS)
	@$(MAKE) --no-print-directory test-plain
	@$(MAKE) --no-print-directory test-asan
	@$(MAKE) --no-print-directory test-tsan
	@$(MAKE) --no-print-directory firmware-test

# The main job: train the Avoid example with NEAT on a copy of its folder
# (so minds/ keeps its shipped network), then replay the champion headless.
RUN_DIR := $(BUILD)/run
run: deps all
	rm -rf $(RUN_DIR) && mkdir -p $(RUN_DIR) && cp -r minds/Avoid $(RUN_DIR)/
	$(BUILD)/evo run $(RUN_DIR)/Avoid/Tasks/Avoid-NEAT.simbatch --seed 1 \
		--run $(RUN_DIR)/avoid-neat
	$(BUILD)/evo run $(RUN_DIR)/Avoid/Tasks/Avoid-DEMO.simbatch --headless \
		--seed 2 --episodes 3 --ticks 3000
	@echo "run folder: $(RUN_DIR)/avoid-neat (log.csv, champion.net, curve.png); trained mind: $(RUN_DIR)/Avoid"

install: all
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/share/evo
	install -m 755 $(BUILD)/evo $(DESTDIR)$(PREFIX)/bin/evo
	[ ! -d lua ] || cp -r lua $(DESTDIR)$(PREFIX)/share/evo/

# ---- core on a Cortex-M0+ ------------------------------------------------
ARM_FLAGS := -mcpu=cortex-m0plus -mthumb -std=c11 -Os -ffreestanding \
	-fno-builtin -ffunction-sections -fdata-sections -DEVO_FREESTANDING \
	$(WARN) -Icore/include
ARM_OBJS := $(patsubst core/src/%.c,$(BUILD)/arm/%.o,$(CORE_SRCS))
ARM_RUNTIME_OBJS := $(patsubst %,$(BUILD)/arm/%.o,$(CORE_RUNTIME))

$(BUILD)/arm/%.o: core/src/%.c
	@mkdir -p $(dir $@)
	$(ARM_CC) $(ARM_FLAGS) -MMD -MP -c $< -o $@

$(BUILD)/arm/runtime.elf: $(ARM_RUNTIME_OBJS) tests/core_check_entry.c
	$(ARM_CC) $(ARM_FLAGS) -nostdlib -nostartfiles -Wl,--gc-sections \
		-Wl,-e,evo_core_check_entry -o $@ tests/core_check_entry.c \
		$(ARM_RUNTIME_OBJS) -lgcc

# The bars of issue 5: the runtime's flash (text + data) on the M0+, and the
# state the Collect example needs there. evo reports the state size on this
# host; a 64-bit host's evo_state header holds 8-byte pointers, so the M0+
# figure swaps in the header's size there, which both compilers give as the
# size of evo_core_check_state_header in tests/core_check_entry.c.
CORE_FLASH_MAX := 4096
CORE_STATE_MAX := 512
CORE_STATE_MIND := minds/Collect

$(BUILD)/arm/core_check_entry.o: tests/core_check_entry.c
	@mkdir -p $(dir $@)
	$(ARM_CC) $(ARM_FLAGS) -c $< -o $@

$(BUILD)/obj/tests/core_check_entry_host.o: tests/core_check_entry.c
	@mkdir -p $(dir $@)
	$(CC) -std=c11 $(WARN) -Icore/include -c $< -o $@

core-check: deps $(ARM_OBJS) $(BUILD)/arm/runtime.elf $(BUILD)/evo \
		$(BUILD)/libevocore.a \
		$(BUILD)/arm/core_check_entry.o $(BUILD)/obj/tests/core_check_entry_host.o
	@syms=$$(nm -A -g --defined-only $(BUILD)/libevocore.a) || { echo "core-check: FAIL: cannot list the symbols of $(BUILD)/libevocore.a"; exit 1; }; \
	bad=$$(printf '%s\n' "$$syms" | awk 'NF == 3 && $$3 !~ /^evo_/ { n = split($$1, p, ":"); print "  " $$3 " (" p[n - 1] ")" }' | sort -u); \
	if [ -n "$$bad" ]; then echo "core-check: FAIL: $(BUILD)/libevocore.a exports global symbols without the evo_ prefix (a firmware linking core beside other code could clash on them):"; echo "$$bad"; exit 1; fi; \
	echo "core-check: every global symbol of $(BUILD)/libevocore.a starts with evo_"
	@bad=$$($(ARM_NM) -u $(ARM_OBJS) $(BUILD)/arm/runtime.elf | \
		grep -E ' (malloc|calloc|realloc|free|printf|fprintf|sprintf|snprintf|puts|putchar|__aeabi_f[a-z0-9_]*|__aeabi_d[a-z0-9_]*|__aeabi_[ui]?[lf]2[fd]|__(add|sub|mul|div)[sd]f3)$$' | sort -u); \
	if [ -n "$$bad" ]; then echo "core-check: core/ references forbidden symbols:"; echo "$$bad"; exit 1; fi
	@echo "core-check: core/ builds freestanding for Cortex-M0+ at -Os; no malloc, free, printf or soft-float"
	@echo "MIND runtime ($(CORE_RUNTIME)), linked with --gc-sections:"
	@$(ARM_SIZE) $(BUILD)/arm/runtime.elf
	@flash=$$($(ARM_SIZE) $(BUILD)/arm/runtime.elf | awk 'NR == 2 {print $$1 + $$2}'); \
	if [ -z "$$flash" ] || [ "$$flash" -gt $(CORE_FLASH_MAX) ]; then \
		echo "core-check: FAIL: the MIND runtime takes $$flash bytes of flash on Cortex-M0+, over the bar of $(CORE_FLASH_MAX)"; exit 1; fi; \
	echo "core-check: MIND runtime flash on Cortex-M0+: $$flash bytes (text + data; bar $(CORE_FLASH_MAX))"
	@host=$$($(BUILD)/evo info $(CORE_STATE_MIND) | sed -n 's/.*mind state: \([0-9]*\) bytes.*/\1/p'); \
	hh=$$(nm -S $(BUILD)/obj/tests/core_check_entry_host.o | awk '$$4 == "evo_core_check_state_header" {print $$2}'); \
	ah=$$($(ARM_NM) -S $(BUILD)/arm/core_check_entry.o | awk '$$4 == "evo_core_check_state_header" {print $$2}'); \
	if [ -z "$$host" ] || [ -z "$$hh" ] || [ -z "$$ah" ]; then \
		echo "core-check: FAIL: cannot measure the state of $(CORE_STATE_MIND)"; exit 1; fi; \
	m0=$$(( host - (0x$$hh + 7) / 8 * 8 + (0x$$ah + 7) / 8 * 8 )); \
	if [ "$$m0" -gt $(CORE_STATE_MAX) ]; then \
		echo "core-check: FAIL: the mind state of $(CORE_STATE_MIND) takes $$m0 bytes of RAM on Cortex-M0+, over the bar of $(CORE_STATE_MAX)"; exit 1; fi; \
	echo "core-check: mind state of $(CORE_STATE_MIND) on Cortex-M0+: $$m0 bytes of RAM (bar $(CORE_STATE_MAX); $$host on this host)"

# ---- fuzzing --------------------------------------------------------------
FUZZ_BINS := $(patsubst tests/fuzz/%.c,$(BUILD)/fuzz/%,$(FUZZ_SRCS))
$(BUILD)/fuzz/%: tests/fuzz/%.c $(CORE_SRCS)
	@mkdir -p $(dir $@)
	$(CLANG) -std=c11 -O1 -g $(WARN) -Icore/include -Itests \
		-fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
		-o $@ $< $(CORE_SRCS)

fuzz: deps $(FUZZ_BINS)
	@for f in $(FUZZ_BINS); do \
		name=$$(basename $$f); corpus=$(BUILD)/fuzz/corpus-$$name; \
		mkdir -p $$corpus; \
		echo "== $$name ($(FUZZ_SECONDS)s)"; \
		$$f -max_total_time=$(FUZZ_SECONDS) -timeout=5 -rss_limit_mb=1024 \
			$$corpus tests/data > $(BUILD)/fuzz/$$name.log 2>&1; rc=$$?; \
		tail -n 3 $(BUILD)/fuzz/$$name.log; \
		[ $$rc -eq 0 ] || { echo "fuzz: $$name failed, see $(BUILD)/fuzz/$$name.log"; exit 1; }; \
	done; echo "fuzz: every target ran $(FUZZ_SECONDS)s without a crash, hang or sanitizer report"

include firmware/firmware.mk

format:
	clang-format -i $$(find core sim tests firmware -name '*.[ch]' 2>/dev/null)

clean:
	rm -rf build

-include $(shell find $(BUILD)/obj $(BUILD)/arm -name '*.d' 2>/dev/null)
