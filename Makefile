# Platoon fuel-prediction module: firmware, host tools, tests.
#
#   make            host tools (build/host/)
#   make test       every test
#   make help       every public target, one line each (the "## " comment
#                   above each target in this file and mk/*.mk)
#
# Missing Debian packages are installed on first use (scripts/deps.sh).
# Host programs and tests are built from the templates of mk/host.mk, the
# Cortex-M4 images and tests from those of mk/m4.mk. Tests are named test-*.

BUILD ?= build
HOST_CC ?= gcc
HOST := $(BUILD)/host
HOSTSAN := $(BUILD)/host-san
HOSTSTATIC := $(BUILD)/host-static
ROADS := sim_host/data/roads
ROAD_NAMES := flat uphill hilly

WARN := -std=c11 -Wall -Wextra -Werror -Wconversion -Wsign-conversion -Wshadow \
        -Wdouble-promotion -Wstrict-prototypes -Wundef -Wcast-qual -Wpointer-arith
# Project headers by their path: "firmware/x.h", "hal/x.h", and the host
# tools' "lib/x.h", "ref/x.h" (sim_host/); tests also name firmware headers
# alone; firmware/pfe_codec.h includes the generated "pfe_dbc.h" ($(BUILD)/gen).
HOST_INC := -I. -Isim_host -Ifirmware -I$(BUILD)/gen
SAN := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
HOST_CFLAGS := $(WARN) $(HOST_INC) -O2 -g
SAN_CFLAGS := $(WARN) $(HOST_INC) -O1 -g $(SAN)
STATIC_CFLAGS := $(WARN) $(HOST_INC) -O2

# The codec's tables and the ECU's receive filters are generated from the
# DBC (sim_host/tools/dbc2c.c) and compiled into every firmware build.
GEN := $(BUILD)/gen
DBC := can_dbc/pfe.dbc
FW_GEN_SRC := $(GEN)/pfe_dbc.c
# The header pfe_codec.h includes: PGNs, periods, table indices. Every
# object is compiled after it is written (order-only prerequisite of the
# compile rules); the compilers' dependency files then track it.
FW_GEN_HDR := $(GEN)/pfe_dbc.h
FW_SRC := $(sort $(wildcard firmware/*.c)) $(FW_GEN_SRC)
FW_HDR := $(sort $(wildcard firmware/*.h))
REF_SRC := sim_host/ref/ref_model.c sim_host/ref/sim_compare.c sim_host/lib/road_csv.c sim_host/ref/drive_trace.c
SIM_HDR := $(sort $(wildcard sim_host/*/*.h sim_host/*/*/*.h))
# The one CAN log reader of the host tools (sim_host/lib/log/log.h).
LOG_SRC := $(sort $(wildcard sim_host/lib/log/*.c))
LOG_HDR := $(sort $(wildcard sim_host/lib/log/*.h))
UNIT_TESTS := $(patsubst tests/unit/%.c,%,$(sort $(wildcard tests/unit/test_*.c)))

DEPS_STAMP := $(BUILD)/.deps-ok

.PHONY: all tools deps run test test-host test-codec-gen test-m4 firmware bench bench-figures test-bench-check help clean test-image \
        test-selfcheck test-replay-m4 test-judge-phase test-e2e test-bus-faults test-asserts
.DEFAULT_GOAL := all

all: tools

## this list: every public target, one line each
help:
	@awk '/^## / { d = substr($$0, 4); next } \
	    /^[a-z][a-zA-Z0-9_-]*:/ && d != "" { t = $$0; sub(/:.*/, "", t); printf "  %-24s %s\n", t, d } \
	    { d = "" }' $(MAKEFILE_LIST)

# ---------------------------------------------------------------- set-up

$(DEPS_STAMP): scripts/deps.sh
	@mkdir -p $(@D)
	sh scripts/deps.sh
	@touch $@

## install the Debian packages the build needs (scripts/deps.sh; also done on first use)
deps: $(DEPS_STAMP)

# ---------------------------------------------------------------- host tools

include mk/host.mk

# The module as a Linux process on SocketCAN (hal/socketcan, hal/posix).
ECU_LOOP_SRC := hal/hal_ecu_loop.c
ECU_HOST_HAL := $(ECU_LOOP_SRC) hal/socketcan/hal_socketcan.c hal/posix/hal_nvm_file.c \
    hal/posix/hal_time_posix.c
# The in-memory backends: the test bus (hal/fake) and the replayed log (hal/replay).
HAL_FAKE_SRC := hal/fake/hal_fake.c hal/hal_can_mem_api.c hal/hal_can_mem.c
HAL_REPLAY_SRC := hal/replay/hal_replay.c hal/hal_can_mem_api.c hal/hal_can_mem.c
# The same firmware over a log in logical time (hal/replay); its twin on the
# Cortex-M4 is $(M4_OUT)/pfe_ecu_mps2.elf. The host reads the log through
# sim_host/lib/log/ (every form), the image through hal/replay's own parser.
ECU_REPLAY_SRC := $(ECU_LOOP_SRC) hal/hal_can_mem.c hal/replay/hal_replay.c hal/hal_can_mem_api.c \
    hal/replay/hal_replay_ecu.c
HAL_HDR := $(sort $(wildcard hal/*.h hal/*/*.h))

# One file per program (sim_host/tools/NAME.c builds NAME), with the HAL
# sources it runs on; sim_host/lib, sim_host/ref and the firmware come from
# the archives (mk/host.mk).
TOOL_NAMES := $(sort $(notdir $(basename $(wildcard sim_host/tools/*.c))))
$(foreach t,$(filter-out dbc2c pfe_ecu pfe_ecu_replay pfe_faults pfe_replay,$(TOOL_NAMES)),$(call host_program,$(t)))
# dbc2c writes the tables the firmware archive compiles, so it is linked
# from its own sources alone (the DBC reader), never from the archives.
DBC2C_SRC := sim_host/tools/dbc2c.c sim_host/lib/dbc.c sim_host/lib/out_file.c
define dbc2c__rule
$(host__dir_$(1))/dbc2c: $(DBC2C_SRC) sim_host/lib/dbc.h sim_host/lib/cli_help.h sim_host/lib/out_file.h | $(DEPS_STAMP)
	@mkdir -p $$(@D)
	$$(HOST_CC) $$(host__cflags_$(1)) $(host__ldflags_$(1)) -Wno-maybe-uninitialized -o $$@ $(DBC2C_SRC) -lm
endef
$(foreach f,$(HOST_FLAVOURS),$(eval $(call dbc2c__rule,$(f))))
.SECONDARY: $(FW_GEN_SRC) $(FW_GEN_HDR)
$(FW_GEN_SRC) $(FW_GEN_HDR) &: $(DBC) $(HOST)/dbc2c
	@mkdir -p $(@D)
	$(HOST)/dbc2c $(DBC) $(FW_GEN_SRC) $(FW_GEN_HDR)
$(call host_program,pfe_ecu,sim_host/tools/pfe_ecu.c $(ECU_HOST_HAL))
$(call host_program,pfe_ecu_replay,sim_host/tools/pfe_ecu_replay.c $(ECU_REPLAY_SRC))
$(call host_program,pfe_faults,sim_host/tools/pfe_faults.c $(HAL_REPLAY_SRC))
$(call host_program,pfe_replay,sim_host/tools/pfe_replay.c hal/socketcan/hal_socketcan.c)
# Test and benchmark programs that are not tools.
$(call host_program,lateness_check,tests/e2e/lateness_check.c)
$(call host_program,slcan_run,tests/e2e/slcan_run.c)
$(call host_program,biglog_gen,tests/bench/biglog_gen.c)
$(call host_program,bench_time,tests/bench/bench_time.c)
$(call host_program,host_bench,tests/bench/host_bench.c)

TOOLS := $(addprefix $(HOST)/,$(TOOL_NAMES))
## every host tool (build/host/), one per file of sim_host/tools/
tools: $(TOOLS)

# ---------------------------------------------------------------- host tests (ASan, UBSan)

# Unit tests: the firmware plus the test backend (hal/fake), nothing else.
UNIT_SRC := $(FW_SRC) $(HAL_FAKE_SRC)
$(foreach t,$(UNIT_TESTS),$(call host_test,unit_$(t),tests/unit/$(t).c $(HAL_FAKE_SRC)))
# tests/host/NAME.c alone over the archives.
HOST_TESTS := test_accuracy test_road_csv test_predict test_identify_ref test_dbc_codec test_canlog \
    test_capture test_truck_cal test_sensitivity test_node_model test_fuel_bounds test_road_import \
    test_cli_args
$(foreach t,$(HOST_TESTS),$(call host_test,$(t),tests/host/$(t).c))
$(call host_test,ecu_offline,tests/host/ecu_offline.c)
$(call host_test,test_nvm_faults,tests/host/test_nvm_faults.c $(ECU_LOOP_SRC) $(HAL_FAKE_SRC))
# The HAL conformance suite on the test backend (on SocketCAN: mk/vcan.mk),
# and on the replay backend, with the backend's own tests.
$(call host_test,test_hal_fake,tests/hal/test_hal_fake.c tests/hal/hal_conformance.c $(HAL_FAKE_SRC))
$(call host_test,test_ecu_loop,tests/hal/test_ecu_loop.c $(ECU_LOOP_SRC) $(HAL_FAKE_SRC))
$(call host_test,test_hal_replay,tests/hal/test_hal_replay.c tests/hal/hal_conformance.c $(HAL_REPLAY_SRC))

HOST_TEST_BINS := $(addprefix $(HOSTSAN)/unit_,$(UNIT_TESTS)) $(HOSTSAN)/test_accuracy \
                  $(HOSTSAN)/test_road_csv $(HOSTSAN)/roadgen $(HOSTSAN)/test_dbc_codec \
                  $(HOSTSAN)/test_hal_fake $(HOSTSAN)/test_hal_replay $(HOSTSAN)/test_ecu_loop $(HOSTSAN)/test_predict \
                  $(HOSTSAN)/test_identify_ref $(HOSTSAN)/test_cli_args

# No assert compares without printing the values (scripts/check_asserts.py
# over tests/); the check shown to fail on planted comparisons and the
# asserts of tests/test_assert.h shown to print them (tests/asserts/).
$(call host_test,test_assert_demo,tests/asserts/test_assert_demo.c)

## no bare comparison in a test's assert (scripts/check_asserts.py), the check shown to catch planted ones
test-asserts: $(HOSTSAN)/test_assert_demo
	@echo "== host: no bare comparison in an assert"; python3 scripts/check_asserts.py tests
	@sh tests/asserts/check_asserts_test.sh $(HOSTSAN)/test_assert_demo

## host tests under ASan and UBSan: firmware units, accuracy, prediction, road loader, codec against the DBC, HAL conformance, the ECU loop, the tools' option tables, the asserts check
test-host: $(HOST_TEST_BINS) test-asserts
	@set -e; for t in $(UNIT_TESTS); do echo "== host unit: $$t"; $(HOSTSAN)/unit_$$t; done
	@echo "== host: test_accuracy"; $(HOSTSAN)/test_accuracy $(ROADS)
	@echo "== host: test_predict"; $(HOSTSAN)/test_predict $(ROADS)
	@echo "== host: test_identify_ref"; $(HOSTSAN)/test_identify_ref
	@echo "== host: test_road_csv"; $(HOSTSAN)/test_road_csv $(ROADS) $(HOSTSAN)/roadgen
	@echo "== host: test_dbc_codec"; $(HOSTSAN)/test_dbc_codec can_dbc/pfe.dbc
	@echo "== host: HAL conformance on hal/fake"; $(HOSTSAN)/test_hal_fake
	@echo "== host: HAL conformance on hal/replay"; $(HOSTSAN)/test_hal_replay
	@echo "== host: the ECU loop on hal/fake"; $(HOSTSAN)/test_ecu_loop
	@echo "== host: the tools' option tables"; $(HOSTSAN)/test_cli_args

## the codec generated from the DBC: a changed copy (scale, period, unit, PGN) changes the firmware built over it alone; the unchanged DBC gives the build's tables; dbc2c's refusals
test-codec-gen: $(HOST)/dbc2c $(FW_GEN_SRC) $(FW_GEN_HDR)
	@echo "== host: the codec generated from $(DBC), and from a changed copy"
	@CC="$(HOST_CC)" CFLAGS="$(HOST_CFLAGS)" sh tests/codec_gen/codec_gen_test.sh $(HOST)/dbc2c $(DBC) $(FW_GEN_SRC) $(FW_GEN_HDR) $(BUILD)/codec-gen

# ---------------------------------------------------------------- Cortex-M4 (QEMU mps2-an386)

include mk/m4.mk
# Optimised for instruction count, across files: the model's small helpers
# (clamps, saturating adds) live in their own files and must inline.
include mk/vcan.mk
include mk/sensitivity.mk
include mk/replay.mk
include mk/run.mk
include mk/thesis.mk
include mk/roads.mk
include mk/hardening.mk
include mk/fuzz.mk
include mk/nvm.mk
include mk/san.mk
include mk/load.mk
include mk/truck.mk
M4_CFLAGS := $(filter-out -Os,$(M4_CFLAGS)) -O2 -flto -Ifirmware -I$(GEN) -DPFE_CODEC_NO_NAMES
M4_LDFLAGS_IMAGE += -O2 -flto
M4_LDFLAGS_TEST += -O2 -flto
include mk/stm32.mk

.SECONDARY: $(GEN)/road_hilly.c
$(GEN)/road_%.c: $(ROADS)/%.csv $(HOST)/road2c
	@mkdir -p $(@D)
	$(HOST)/road2c $* $< $@

# The product image: the model's known-answer run over the bundled hilly road.
$(call m4_image,pfe_mps2,$(FW_SRC) hal/mps2/main_selfcheck.c $(GEN)/road_hilly.c)
# The firmware running a drive from a log, files through semihosting.
$(call m4_image,pfe_ecu_mps2,$(FW_SRC) $(ECU_REPLAY_SRC) hal/mps2/main_ecu.c hal/mps2/calib_default.c)
# Instruction counts (make bench).
$(call m4_image,pfe_bench,$(FW_SRC) tests/bench/m4_bench.c $(GEN)/road_hilly.c)
# The firmware's unit tests, cross-compiled.
$(foreach t,$(UNIT_TESTS),$(call m4_test,unit_$(t),$(UNIT_SRC) tests/unit/$(t).c))
# The replay backend the image runs drives on, conformance suite included.
$(call m4_test,test_hal_replay,tests/hal/test_hal_replay.c tests/hal/hal_conformance.c hal/replay/hal_replay.c hal/hal_can_mem_api.c hal/hal_can_mem.c)

FIRMWARE_ELF := $(M4_OUT)/pfe_mps2.elf

## the Cortex-M4 image for QEMU's mps2-an386 (build/m4/pfe_mps2.elf); CALIB=FILE adds the replay image for that truck
firmware: $(DEPS_STAMP) $(FIRMWARE_ELF)
	@$(M4_SIZE) $(FIRMWARE_ELF)

# Fails if an image links the heap or floating-point helpers; and shows that
# it can fail, on an image made to use floating point.
$(M4_OUT)/test_bad_image_float.elf: $(M4_OUT)/obj/image/tests/m4/bad_image_float.o \
        $(call m4__objs,image,$(M4_HAL_IMAGE_SRCS))
	$(M4_CC) $(filter %.o,$^) $(M4_LDFLAGS_IMAGE) -o $@

## the images refused if they link the heap or floating point (and a floating-point image refused, as it should be)
test-image: $(FIRMWARE_ELF) $(M4_OUT)/pfe_ecu_mps2.elf $(M4_OUT)/pfe_bench.elf \
        $(M4_OUT)/test_bad_image_float.elf test-stm32-image
	$(M4_CHECK) $(FIRMWARE_ELF)
	$(M4_CHECK) $(M4_OUT)/pfe_ecu_mps2.elf
	$(M4_CHECK) $(M4_OUT)/pfe_bench.elf
	@if $(M4_CHECK) $(M4_OUT)/test_bad_image_float.elf >$(BUILD)/bad_image.txt 2>&1; then \
	    echo "test-image: a floating-point image passed the check"; exit 1; fi
	@grep -q __aeabi_f $(BUILD)/bad_image.txt && \
	    echo "test-image: refuses an image with floating point, as it should"

## the firmware's unit tests and the replay backend's conformance on the Cortex-M4 under QEMU
test-m4: $(DEPS_STAMP) $(addprefix $(M4_OUT)/unit_,$(addsuffix .elf,$(UNIT_TESTS))) \
        $(M4_OUT)/test_hal_replay.elf
	@set -e; for t in $(UNIT_TESTS); do echo "== Cortex-M4 unit: $$t"; \
	    $(M4_RUN) $(M4_OUT)/unit_$$t.elf; done
	@echo "== Cortex-M4: HAL conformance on hal/replay"; $(M4_RUN) $(M4_OUT)/test_hal_replay.elf

# Same inputs, bit-identical outputs on the host and on the Cortex-M4.

## the self-check on the host and on the Cortex-M4: identical outputs
test-selfcheck: $(HOST)/selfcheck $(FIRMWARE_ELF)
	$(HOST)/selfcheck $(ROADS)/hilly.csv > $(BUILD)/selfcheck_host.txt
	$(M4_RUN) $(FIRMWARE_ELF) > $(BUILD)/selfcheck_m4.txt
	@grep -q digest $(BUILD)/selfcheck_host.txt
	@if cmp -s $(BUILD)/selfcheck_host.txt $(BUILD)/selfcheck_m4.txt; then \
	    echo "selfcheck: host and Cortex-M4 outputs identical:"; \
	    grep digest $(BUILD)/selfcheck_host.txt; \
	else echo "selfcheck: host and Cortex-M4 outputs differ:"; \
	    diff $(BUILD)/selfcheck_host.txt $(BUILD)/selfcheck_m4.txt; exit 1; fi

# End to end: the host ECU on vcan, fed a drive (600 m flat, a 150 m vertical
# curve, then 750 m at 2 %, 90 km/h) by canplayer, recorded by candump, judged
# by ecu_check.
E2E_PAYLOAD := $(BUILD)/e2e/payload
$(call host_payload,$(E2E_PAYLOAD),pfe_ecu ecu_check pfe_faults)
$(E2E_PAYLOAD)/drive.log: $(HOST)/drivegen Makefile
	@mkdir -p $(@D)
	$(HOST)/drivegen --segment 600:0 --segment 50:0.5 --segment 50:1 --segment 50:1.5 \
	    --segment 750:2 --set-speed-kmh 90 --out $@
$(E2E_PAYLOAD)/ecu_vcan.sh: tests/e2e/ecu_vcan.sh
	@mkdir -p $(@D)
	cp $< $@

$(E2E_PAYLOAD)/faults.log: $(HOST)/pfe_faults $(E2E_PAYLOAD)/drive.log
	$(HOST)/pfe_faults inject $(E2E_PAYLOAD)/drive.log $@

# Bus faults in the real kernel: vcan0 down and up, a flood, an address
# conflict, during a drive (tests/e2e/bus_faults.sh).
FAULTS_PAYLOAD := $(BUILD)/bus-faults/payload
$(call host_payload,$(FAULTS_PAYLOAD),pfe_ecu pfe_replay pfe_decode)
$(FAULTS_PAYLOAD)/pfe.dbc: can_dbc/pfe.dbc
	@mkdir -p $(@D)
	cp $< $@
$(FAULTS_PAYLOAD)/drive.log: $(E2E_PAYLOAD)/drive.log
	@mkdir -p $(@D)
	cp $< $@
$(FAULTS_PAYLOAD)/bus_faults.sh: tests/e2e/bus_faults.sh
	@mkdir -p $(@D)
	cp $< $@

## bus faults in the VM's kernel: vcan0 down and up, a flood, an address conflict, during a drive
test-bus-faults: $(addprefix $(FAULTS_PAYLOAD)/,pfe_ecu pfe_replay pfe_decode pfe.dbc drive.log bus_faults.sh)
	$(VCAN_VM) --time --timeout 900 --payload $(abspath $(FAULTS_PAYLOAD)) -- \
	    sh $(abspath $(FAULTS_PAYLOAD))/bus_faults.sh

## the host ECU on vcan in the VM, fed a drive by canplayer, recorded by candump, judged by ecu_check
test-e2e: $(addprefix $(E2E_PAYLOAD)/,pfe_ecu ecu_check pfe_faults drive.log faults.log ecu_vcan.sh)
	$(VCAN_VM) --time --timeout 1200 --payload $(abspath $(E2E_PAYLOAD)) -- \
	    sh $(abspath $(E2E_PAYLOAD))/ecu_vcan.sh

# One log through the firmware on the host and in the Cortex-M4 image, in
# the log's time: identical records; then judged (tests/replay/host_vs_m4.sh).

## one log through the firmware on the host and in the Cortex-M4 image: identical records, then judged
test-replay-m4: $(HOST)/pfe_ecu_replay $(HOST)/ecu_check $(HOST)/pfe_faults $(M4_OUT)/pfe_ecu_mps2.elf \
        $(E2E_PAYLOAD)/drive.log $(BUILD)/logs/hilly.log
	sh tests/replay/host_vs_m4.sh $(BUILD)/replay $(HOST) $(M4_OUT)/pfe_ecu_mps2.elf \
	    $(E2E_PAYLOAD)/drive.log $(BUILD)/logs/hilly.log

## ecu_check against a module whose tick phase is not the reference's: every CCVS1 phase passes, a wrong truck fails
test-judge-phase: $(HOST)/drivegen $(HOST)/pfe_ecu_replay $(HOST)/ecu_check
	sh tests/replay/judge_phase.sh $(BUILD)/judge-phase $(HOST)

## every test: host (ASan, UBSan), Cortex-M4 under QEMU, images, vcan VM, fuzzing smoke, MISRA, coverage, stack
test: test-host test-m4 test-selfcheck test-replay-m4 test-judge-phase test-image test-m4-selftest test-vcan test-e2e \
      test-sensitivity test-run-host test-drive-logs test-record-vm test-replay test-replay-vcan \
      test-thesis test-hardening test-bus-faults test-fuzz-smoke test-bench-check test-truck-cal \
      test-foreign-trucks test-replay-calib test-stm32 test-road-import \
      test-nvm-faults test-san test-codec-gen

## the bench checker against made-up figures (tests/bench/bench_check_test.sh)
test-bench-check:
	@sh tests/bench/bench_check_test.sh

# ---------------------------------------------------------------- benchmarks


# Every figure, then the targets of tests/bench/targets.txt held to them
# (a figure above its limit, or missing, fails the bench).
## every figure (bench: lines), held to the limits of tests/bench/targets.txt
bench:
	@mkdir -p $(BUILD)
	@{ $(MAKE) --no-print-directory bench-figures; echo "bench-exit $$?"; } | tee $(BUILD)/bench.out
	@grep -qx 'bench-exit 0' $(BUILD)/bench.out
	@sh scripts/bench_check.sh tests/bench/targets.txt $(BUILD)/bench.out

## the figures alone, not held to their limits
bench-figures: $(HOST)/host_bench $(M4_OUT)/pfe_bench.elf $(FIRMWARE_ELF) $(M4_OUT)/pfe_ecu_mps2.elf \
        $(E2E_PAYLOAD)/drive.log replay-bench thesis-bench foreign-bench stm32-bench
	@$(M4_RUN) $(M4_OUT)/pfe_bench.elf
	@# The ECU's tick over a whole drive (61.6 s, 6263 ticks) in the image that
	@# replays it: receive, decode, estimate, encode, send, and the prediction's
	@# share over the drive's grade previews; feeding the log apart.
	@$(M4_RUN) $(M4_OUT)/pfe_ecu_mps2.elf --log $(E2E_PAYLOAD)/drive.log | awk '/^m4:/ { \
	    print "bench: ecu_drive_tick_mean " $$5 " insn"; print "bench: ecu_drive_tick_max " $$7 " insn"; \
	    print "bench: replay_feed_mean " $$9 " insn"; ok = 1 } END { exit !ok }'
	@$(M4_CHECK) --bench pfe_mps2 $(FIRMWARE_ELF)
	@$(M4_CHECK) --bench pfe_ecu_mps2 $(M4_OUT)/pfe_ecu_mps2.elf
	@echo "bench: pfe_mps2_heap $$($(M4_SIZE) -A $(FIRMWARE_ELF) | \
	    awk '/heap/ { n += $$2 } END { print n + 0 }') bytes"
	@$(HOST)/host_bench $(ROADS)

## remove the build folder
clean:
	rm -rf $(BUILD)

# ---------------------------------------------------------------- old names

# Names of tests before the test-* scheme, kept because the README uses them.
.PHONY: check-image check-replay check-replay-calib e2e-test bus-fault-test fuzz-smoke replay-test replay-vcan-test thesis-test vcan-test
## old name of test-image
check-image: test-image
## old name of test-replay-m4
check-replay: test-replay-m4
## old name of test-replay-calib
check-replay-calib: test-replay-calib
## old name of test-e2e
e2e-test: test-e2e
## old name of test-bus-faults
bus-fault-test: test-bus-faults
## old name of test-fuzz-smoke
fuzz-smoke: test-fuzz-smoke
## old name of test-replay
replay-test: test-replay
## old name of test-replay-vcan
replay-vcan-test: test-replay-vcan
## old name of test-thesis
thesis-test: test-thesis
## old name of test-vcan
vcan-test: test-vcan
