# evo's firmware: a Cortex-M0(+) build for QEMU's microbit and a Cortex-M3
# build for QEMU's mps2-an385, each running the mind of FW_MIND with the
# robot's names of firmware/bots/$(FW_BOT).h. Included from the Makefile.
# docs/firmware.md describes what is built and how to run it.
#
#   make firmware        BUILD/firmware/evo-m0.elf, evo-m3.elf (+ .bin)
#   make firmware-test   replay a trace through both under QEMU, and more
#   make firmware-size   text/data/bss of each firmware and of the runtime
#   make firmware-run    the M3 firmware under QEMU on two slcan ptys, for
#                        evo flash and evo serve --robot to reach it
#
# Outputs go to BUILD/firmware/: per core m0/ and m3/ (objects, the two
# core archives), mind/ (the exported images), the test driver, the plugin.

FW_BUILD := $(BUILD)/firmware
FW_MIND ?= minds/Collect
FW_BOT ?= Collect
FW_TASK ?= $(FW_MIND)/Tasks/Collect-DEMO.simbatch
FW_TRACE_TICKS ?= 10000
# Another mind folder, for the image built for another botdesc.
FW_OTHER_MIND ?= minds/Avoid
# The evo that exports images and records the trace.
FW_EVO ?= $(BUILD)/evo
QEMU_ARM ?= qemu-system-arm
ARM_OBJCOPY ?= arm-none-eabi-objcopy
ARM_AR ?= arm-none-eabi-ar
# Seconds the whole firmware-test may take before it is stopped: a guard
# against a hang, well above the few minutes a host with slow system calls
# needs (docs/firmware.md).
FW_TEST_TIMEOUT ?= 900

FW_CORES := m0 m3
FW_CPU_m0 := -mcpu=cortex-m0plus
FW_CPU_m3 := -mcpu=cortex-m3
FW_BOARD_m0 := microbit
FW_BOARD_m3 := mps2_an385
FW_MACHINE_m0 := microbit
FW_MACHINE_m3 := mps2-an385

FW_CFLAGS := -mthumb -std=c11 -Os -g -ffreestanding -fno-builtin \
	-fno-tree-loop-distribute-patterns -ffunction-sections \
	-fdata-sections -DEVO_FREESTANDING $(WARN) -Icore/include -Ifirmware \
	-I$(FW_BUILD)/mind -I$(FW_BUILD)/key '-DFW_BOT="bots/$(FW_BOT).h"' \
	$(FW_CFLAGS_EXTRA)
FW_LDFLAGS := -nostdlib -nostartfiles -Wl,--gc-sections -Lfirmware

# What the firmware carries of core/, in two archives. libevoruntime.a is
# the MIND runtime (CORE_RUNTIME) and nothing else: sections.ld keeps its
# code apart, and make bench counts the instructions a tick runs there.
# libevolink.a is the rest, what the firmware's link to the host uses:
# status.c for the message that says why an image was refused, wire.c, the
# CAN frames and slcan lines it speaks (the host speaks them with the same
# code), and flash.c, the receiver of evo flash.
FW_RUNTIME_NAMES := $(sort $(CORE_RUNTIME))
FW_LINK_NAMES := $(sort status wire flash mac)
FW_SRCS := main cortex_m mind_slot

fw_core_objs = $(patsubst %,$(FW_BUILD)/$(1)/core/%.o,$(2))
fw_libs = $(FW_BUILD)/$(1)/libevoruntime.a $(FW_BUILD)/$(1)/libevolink.a
fw_objs = $(patsubst %,$(FW_BUILD)/$(1)/%.o,$(FW_SRCS) board_$(FW_BOARD_$(1)))

.PHONY: firmware firmware-test firmware-size

firmware: $(foreach c,$(FW_CORES),$(FW_BUILD)/evo-$(c).elf $(FW_BUILD)/evo-$(c).bin)

# ---- what the build is made for ----------------------------------------
# The firmware is built for one mind and one robot: config.stamp holds
# FW_MIND, FW_BOT, FW_TASK and FW_OTHER_MIND, and is rewritten only when
# one of them changed; everything built from them depends on it, so `make
# firmware FW_MIND=... FW_BOT=...` builds the images, the trace and the
# objects again instead of leaving a firmware of the earlier mind (or
# half of each).
FW_CONFIG := $(FW_BUILD)/config.stamp
.PHONY: fw-config-force
$(FW_CONFIG): fw-config-force
	@mkdir -p $(dir $@)
	@printf 'FW_MIND=%s\nFW_BOT=%s\nFW_TASK=%s\nFW_OTHER_MIND=%s\n' \
		'$(FW_MIND)' '$(FW_BOT)' '$(FW_TASK)' '$(FW_OTHER_MIND)' > $@.tmp
	@if cmp -s $@.tmp $@; then rm -f $@.tmp; else mv $@.tmp $@; fi

# ---- the images the firmware carries or is tested with -----------------
FW_MIND_FILES := $(shell find $(FW_MIND) -name '*.botdesc' -o -name '*.vardesc' -o -name '*.ades' -o -name '*.net' 2>/dev/null)
FW_OTHER_FILES := $(shell find $(FW_OTHER_MIND) -name '*.botdesc' -o -name '*.vardesc' -o -name '*.ades' -o -name '*.net' 2>/dev/null)

$(FW_BUILD)/mind/mind.h: $(FW_EVO) $(FW_MIND_FILES) $(FW_CONFIG)
	@mkdir -p $(dir $@)
	$(FW_EVO) export $(FW_MIND) --format c -o $@

$(FW_BUILD)/mind/mind.bin: $(FW_EVO) $(FW_MIND_FILES) $(FW_CONFIG)
	@mkdir -p $(dir $@)
	$(FW_EVO) export $(FW_MIND) -o $@

$(FW_BUILD)/mind/other.bin: $(FW_EVO) $(FW_OTHER_FILES) $(FW_CONFIG)
	@mkdir -p $(dir $@)
	$(FW_EVO) export $(FW_OTHER_MIND) -o $@

# A newly trained mind for the same robot, which the firmware test sends
# to the running firmware with evo flash: the mind folder copied, and its
# NEAT task run for two short generations (a few seconds), which saves a
# champion into the copy. Its own trace is what the firmware must give
# from the switch on.
FW_NEW := $(FW_BUILD)/mind/new
FW_NEW_MIND := $(FW_NEW)/$(notdir $(FW_MIND))
FW_NEW_TASK ?= $(FW_MIND)/Tasks/Collect-NEAT.simbatch
FW_NEW_TRACE_TICKS ?= 600
$(FW_NEW)/stamp: $(FW_EVO) $(FW_MIND_FILES) $(FW_NEW_TASK) $(FW_CONFIG)
	rm -rf $(FW_NEW) && mkdir -p $(FW_NEW) && cp -r $(FW_MIND) $(FW_NEW_MIND)
	sed 's/^NUMGEN:.*/NUMGEN:2 EVALREP:1 TICKLIM:300 POPSIZE:30/' $(FW_NEW_TASK) \
		> $(FW_NEW_MIND)/Tasks/flash-train.simbatch
	$(FW_EVO) run $(FW_NEW_MIND)/Tasks/flash-train.simbatch --seed 5 \
		--run $(FW_NEW)/run > $(FW_NEW)/train.log
	@touch $@
$(FW_BUILD)/mind/new.trace: $(FW_NEW)/stamp $(FW_TASK)
	$(FW_EVO) run $(FW_NEW_MIND)/Tasks/$(notdir $(FW_TASK)) --headless \
		--ticks $(FW_NEW_TRACE_TICKS) --trace $@

# The trace the firmware must reproduce, byte for byte.
$(FW_BUILD)/mind/run.trace: $(FW_EVO) $(FW_MIND_FILES) $(FW_TASK) $(FW_CONFIG)
	@mkdir -p $(dir $@)
	$(FW_EVO) run $(FW_TASK) --headless --ticks $(FW_TRACE_TICKS) --trace $@

# ---- the robot's key --------------------------------------------------------
# make firmware FW_KEY=FILE: the firmware takes only transfers (evo flash
# --key FILE) and CONFIG frames made with this key (docs/wire.md, Keys).
# FILE holds 32 to 128 hex digits; the rule reads it without printing it,
# and rewrites flash_key.h only when the key (or its absence) changed.
FW_KEY ?=
FW_KEY_H := $(FW_BUILD)/key/flash_key.h
.PHONY: fw-key-force
$(FW_KEY_H): fw-key-force
	@mkdir -p $(dir $@)
	@set -e; key='$(FW_KEY)'; tmp=$@.tmp; \
	if [ -z "$$key" ]; then echo '/* no key: make firmware FW_KEY=FILE */' > $$tmp; \
	else \
		[ -r "$$key" ] || { echo "firmware: FW_KEY=$$key: cannot read it" >&2; exit 1; }; \
		hex=$$(tr -d ' \t\r\n' < "$$key"); \
		if ! printf '%s' "$$hex" | grep -Eq '^([0-9a-fA-F]{2}){16,64}$$'; then \
			echo "firmware: FW_KEY=$$key: a key is 32 to 128 hex digits (16 to 64 bytes) on one line, and nothing else" >&2; exit 1; fi; \
		{ echo '/* the robot key from FW_KEY: do not publish this file */'; \
		  printf '#define FW_FLASH_KEY '; printf '%s' "$$hex" | sed 's/../0x&,/g'; echo; } > $$tmp; \
	fi; \
	if cmp -s $$tmp $@; then rm -f $$tmp; else mv $$tmp $@; fi

# The firmware test's keyed firmware, with the public test key.
FW_TEST_KEY := tests/data/flash/test.key
$(FW_BUILD)/key-test/flash_key.h: $(FW_TEST_KEY)
	@mkdir -p $(dir $@)
	@{ echo '/* the public test key of make firmware-test */'; \
	  printf '#define FW_FLASH_KEY '; tr -d ' \t\r\n' < $< | sed 's/../0x&,/g'; echo; } > $@

# ---- per core ------------------------------------------------------------
define FW_CORE_RULES
$(FW_BUILD)/$(1)/core/%.o: core/src/%.c
	@mkdir -p $$(dir $$@)
	$(ARM_CC) $(FW_CPU_$(1)) $(FW_CFLAGS) -MMD -MP -c $$< -o $$@

$(FW_BUILD)/$(1)/%.o: firmware/%.c $(FW_CONFIG)
	@mkdir -p $$(dir $$@)
	$(ARM_CC) $(FW_CPU_$(1)) $(FW_CFLAGS) -MMD -MP -c $$< -o $$@

$(FW_BUILD)/$(1)/mind_slot.o: $(FW_BUILD)/mind/mind.h
$(FW_BUILD)/$(1)/main.o $(FW_BUILD)/$(1)/main-noflash.o: $(FW_KEY_H)

$(FW_BUILD)/$(1)/libevoruntime.a: $(call fw_core_objs,$(1),$(FW_RUNTIME_NAMES))
	@rm -f $$@
	$(ARM_AR) rcs $$@ $$^

# (firmware.mk too: an archive made before a name was added to
# FW_LINK_NAMES is made again, though its new member's source is older)
$(FW_BUILD)/$(1)/libevolink.a: $(call fw_core_objs,$(1),$(FW_LINK_NAMES)) firmware/firmware.mk
	@rm -f $$@
	$(ARM_AR) rcs $$@ $$(filter %.o,$$^)

$(FW_BUILD)/evo-$(1).elf: $(call fw_objs,$(1)) $(call fw_libs,$(1)) \
		firmware/$(1).ld firmware/sections.ld
	$(ARM_CC) $(FW_CPU_$(1)) $(FW_CFLAGS) $(FW_LDFLAGS) -T firmware/$(1).ld \
		-Wl,-Map=$(FW_BUILD)/evo-$(1).map -o $$@ $(call fw_objs,$(1)) \
		$(call fw_libs,$(1)) -lgcc

# The firmware without the flash receiver (FW_FLASH=0), for make
# firmware-size: the difference is what taking minds over the bus costs.
$(FW_BUILD)/$(1)/main-noflash.o: firmware/main.c $(FW_CONFIG)
	@mkdir -p $$(dir $$@)
	$(ARM_CC) $(FW_CPU_$(1)) $(FW_CFLAGS) -DFW_FLASH=0 -MMD -MP -c $$< -o $$@

$(FW_BUILD)/noflash-$(1).elf: $(FW_BUILD)/$(1)/main-noflash.o \
		$(filter-out %/main.o,$(call fw_objs,$(1))) $(call fw_libs,$(1)) \
		firmware/$(1).ld firmware/sections.ld
	$(ARM_CC) $(FW_CPU_$(1)) $(FW_CFLAGS) $(FW_LDFLAGS) -T firmware/$(1).ld \
		-o $$@ $(FW_BUILD)/$(1)/main-noflash.o \
		$(filter-out %/main.o,$(call fw_objs,$(1))) $(call fw_libs,$(1)) -lgcc

# The firmware with the test key (make firmware-test): its key header is
# found before the one of FW_KEY.
$(FW_BUILD)/$(1)/main-keyed.o: firmware/main.c $(FW_BUILD)/key-test/flash_key.h $(FW_CONFIG)
	@mkdir -p $$(dir $$@)
	$(ARM_CC) $(FW_CPU_$(1)) -I$(FW_BUILD)/key-test $(FW_CFLAGS) -MMD -MP -c $$< -o $$@

$(FW_BUILD)/evo-$(1)-keyed.elf: $(FW_BUILD)/$(1)/main-keyed.o \
		$(filter-out %/main.o,$(call fw_objs,$(1))) $(call fw_libs,$(1)) \
		firmware/$(1).ld firmware/sections.ld
	$(ARM_CC) $(FW_CPU_$(1)) $(FW_CFLAGS) $(FW_LDFLAGS) -T firmware/$(1).ld \
		-o $$@ $(FW_BUILD)/$(1)/main-keyed.o \
		$(filter-out %/main.o,$(call fw_objs,$(1))) $(call fw_libs,$(1)) -lgcc

# The MIND runtime alone: what size_entry.c reaches of its archive.
$(FW_BUILD)/runtime-$(1).elf: $(FW_BUILD)/$(1)/size_entry.o $(FW_BUILD)/$(1)/libevoruntime.a
	$(ARM_CC) $(FW_CPU_$(1)) $(FW_CFLAGS) -nostdlib -nostartfiles \
		-Wl,--gc-sections -Wl,-e,fw_size_entry -o $$@ $$^ -lgcc
endef
$(foreach c,$(FW_CORES),$(eval $(call FW_CORE_RULES,$(c))))


$(FW_BUILD)/%.bin: $(FW_BUILD)/%.elf
	$(ARM_OBJCOPY) -O binary $< $@

# ---- host side: the test driver, the QEMU plugin, the fuzz target -------
FW_HOST_CFLAGS := -std=c11 $(OPT) $(WARN) -Icore/include -Ifirmware -Itests $(SAN)

# firmware/host/ holds what the host uses to drive a firmware under QEMU
# (a session over slcan, the trace reader): the test and make bench share it.
FW_HOST_HDRS := firmware/host/qemu_session.h firmware/host/trace_file.h \
	core/include/evo/wire.h
# core/src/hash.c: the CRC-32 a test repairs after patching an image.
# The host's CAN transports (sim/remote/can.c): the test is the slcan
# adapter evo flash talks to, on a pseudo-terminal.
# All of core: the keyed CONFIG frame is made with evo/flash.h.
FW_TEST_SRCS := tests/firmware/firmware_test.c firmware/host/qemu_session.c \
	firmware/host/trace_file.c $(CORE_SRCS) \
	sim/remote/can.c sim/remote/can_format.c sim/base/err.c
$(FW_BUILD)/firmware_test: $(FW_TEST_SRCS) $(FW_HOST_HDRS) tests/harness.h \
		core/include/evo/flash.h sim/remote/can.h
	@mkdir -p $(dir $@)
	$(CC) $(FW_HOST_CFLAGS) -Isim -o $@ $(FW_TEST_SRCS)

# Counts the instructions QEMU executes in an address range (TCG plugin).
$(FW_BUILD)/insn_count.so: firmware/qemu/insn_count.c firmware/qemu/qemu_plugin_api.h
	@mkdir -p $(dir $@)
	$(CC) -std=c11 -O2 $(WARN) -fPIC -shared -Ifirmware/qemu -o $@ $<

# make bench runs it: instructions per tick on the M3 beside the host's ns.
FW_HOST_OBJS := $(FW_BUILD)/host/qemu_session.o $(FW_BUILD)/host/trace_file.o
$(FW_BUILD)/host/%.o: firmware/host/%.c $(FW_HOST_HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_HOST) -Ifirmware -c $< -o $@
$(FW_BUILD)/host/bench_firmware.o: bench/bench_firmware.c $(FW_HOST_HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_HOST) -Ifirmware -c $< -o $@

$(BUILD)/bench/bench_firmware: $(FW_BUILD)/host/bench_firmware.o $(FW_HOST_OBJS) \
		$(BUILD)/libevohost.a $(BUILD)/libevocore.a \
		$(FW_BUILD)/evo-m3.elf $(FW_BUILD)/insn_count.so $(FW_BUILD)/mind/run.trace \
		$(FW_BUILD)/mind/mind.bin
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_ALL) -o $@ $(filter %.o %.a,$^) $(LIBS)

# ---- a firmware to try: make firmware-run ---------------------------------
# The firmware under QEMU with its UART as a CAN bus on two slcan
# pseudo-terminals, FW_RUN_DIR/bus and FW_RUN_DIR/bus2 (evo is the adapter
# on each), until Ctrl-C: `evo flash MIND --can slcan:FW_RUN_DIR/bus`
# sends it a mind, `evo serve TASK --robot --can slcan:FW_RUN_DIR/bus2`
# is a body it drives (docs/firmware.md, "Trying it under QEMU").
FW_RUN_CORE ?= m3
FW_RUN_DIR ?= $(FW_BUILD)/run
FW_RUN_SEED ?= 1
FW_RUN_SRCS := firmware/host/fw_run.c firmware/host/qemu_session.c \
	firmware/host/trace_file.c $(CORE_SRCS) sim/remote/can.c \
	sim/remote/can_format.c sim/remote/can_robot_frames.c sim/base/err.c
$(FW_BUILD)/fw_run: $(FW_RUN_SRCS) $(FW_HOST_HDRS) sim/remote/can.h \
		sim/remote/can_robot.h
	@mkdir -p $(dir $@)
	$(CC) $(FW_HOST_CFLAGS) -Isim -o $@ $(FW_RUN_SRCS)

.PHONY: firmware-run
firmware-run: $(FW_BUILD)/fw_run $(FW_BUILD)/evo-$(FW_RUN_CORE).elf
	@mkdir -p $(FW_RUN_DIR)
	$(FW_BUILD)/fw_run --qemu $(QEMU_ARM) --machine $(FW_MACHINE_$(FW_RUN_CORE)) \
		--kernel $(FW_BUILD)/evo-$(FW_RUN_CORE).elf \
		--can 'slcan-pty:?link=$(FW_RUN_DIR)/bus' \
		--can 'slcan-pty:?link=$(FW_RUN_DIR)/bus2' --episode-seed $(FW_RUN_SEED)

# ---- the targets -----------------------------------------------------------
FW_TEST_INPUTS := $(foreach c,$(FW_CORES),$(FW_BUILD)/evo-$(c).elf $(FW_BUILD)/evo-$(c)-keyed.elf) \
	$(FW_BUILD)/firmware_test $(FW_BUILD)/mind/mind.bin \
	$(FW_BUILD)/mind/other.bin $(FW_BUILD)/mind/run.trace \
	$(FW_BUILD)/mind/new.trace $(FW_BUILD)/fw_run
# Where the flash tests cut and corrupt a transfer: a new seed each run,
# printed, so that a failure can be run again (FW_TEST_SEED=N).
FW_TEST_SEED ?= $(shell date +%s)

firmware-test: $(FW_TEST_INPUTS)
	timeout -k 5 $(FW_TEST_TIMEOUT) $(FW_BUILD)/firmware_test \
		--qemu $(QEMU_ARM) --objcopy $(ARM_OBJCOPY) \
		--trace $(FW_BUILD)/mind/run.trace --image $(FW_BUILD)/mind/mind.bin \
		--other-image $(FW_BUILD)/mind/other.bin --tmp $(FW_BUILD)/test \
		--evo $(FW_EVO) --new-mind $(FW_NEW_MIND) \
		--new-trace $(FW_BUILD)/mind/new.trace --other-mind $(FW_OTHER_MIND) \
		--seed $(FW_TEST_SEED) --key $(FW_TEST_KEY) \
		$(foreach c,$(FW_CORES),--firmware $(FW_MACHINE_$(c))=$(FW_BUILD)/evo-$(c).elf) \
		$(foreach c,$(FW_CORES),--keyed $(FW_MACHINE_$(c))=$(FW_BUILD)/evo-$(c)-keyed.elf)
	timeout -k 5 300 sh tests/firmware/test_firmware_run.sh

# Per core: the firmware without its mind slot (the slot is flash kept for
# the image, printed apart), and the MIND runtime linked alone.
fw_sec = $(ARM_SIZE) -A $(1) | awk '$$1=="$(2)"{s+=$$2} END{print s+0}'
firmware-size: $(foreach c,$(FW_CORES),$(FW_BUILD)/evo-$(c).elf $(FW_BUILD)/runtime-$(c).elf \
		$(FW_BUILD)/noflash-$(c).elf) \
		$(FW_EVO) $(FW_BUILD)/mind/mind.bin
	@echo "bytes: text = code and constants (flash), data = initialised RAM (flash too), bss = zeroed RAM"
	@printf '%-5s %-34s %6s %6s %6s\n' core what text data bss
	@for c in $(FW_CORES); do \
		elf=$(FW_BUILD)/evo-$$c.elf; \
		text=$$($(call fw_sec,$$elf,.text)); data=$$($(call fw_sec,$$elf,.data)); \
		bss=$$($(call fw_sec,$$elf,.bss)); stack=$$($(call fw_sec,$$elf,.stack)); \
		slot=$$($(call fw_sec,$$elf,.mind)); \
		printf '%-5s %-34s %6s %6s %6s  + stack %s; + mind slot %s (image %s)\n' \
			$$c "firmware (mind slot apart)" $$text $$data $$bss $$stack $$slot \
			$$(wc -c < $(FW_BUILD)/mind/mind.bin); \
		$(ARM_SIZE) $(FW_BUILD)/runtime-$$c.elf | awk -v c=$$c 'NR==2{printf "%-5s %-34s %6s %6s %6s\n", c, "MIND runtime alone", $$1, $$2, $$3}'; \
		nf=$(FW_BUILD)/noflash-$$c.elf; \
		printf '%-5s %-34s %6s %6s %6s  (the firmware less one built with FW_FLASH=0); + mind slot %s\n' \
			$$c "flash receiver (evo flash)" \
			$$(( text - $$($(call fw_sec,$$nf,.text)) )) $$(( data - $$($(call fw_sec,$$nf,.data)) )) \
			$$(( bss - $$($(call fw_sec,$$nf,.bss)) )) $$slot; \
	done
	@for c in $(FW_CORES); do \
		m=$$(case $$c in m0) echo $(FW_MACHINE_m0);; m3) echo $(FW_MACHINE_m3);; esac); \
		state=$$(timeout -k 1 3 $(QEMU_ARM) -M $$m -nographic -monitor none -serial stdio \
			-semihosting-config enable=on,target=native -kernel $(FW_BUILD)/evo-$$c.elf \
			</dev/null 2>/dev/null | tr '\r' '\n' | sed -n 's/.*state \([0-9]*\) bytes in RAM.*/\1/p'); \
		echo "$$c    $(notdir $(FW_MIND)): image $$(wc -c < $(FW_BUILD)/mind/mind.bin) bytes in the slot, mind state $${state:-?} bytes of RAM in the bss above (as the firmware prints it at start under QEMU)"; \
	done

-include $(shell find $(FW_BUILD) -name '*.d' 2>/dev/null)
