# Platoon fuel-prediction module: firmware, host tools, tests.
#
#   make            host tools (build/host/)
#   make run        the module on vcan fed the bundled hilly drive, judged: summary, CSV, plot
#   make run-sim    simulate the bundled hilly road, fixed point against double
#   make test       every test: host (ASan, UBSan), Cortex-M4 under QEMU, image checks
#   make firmware   the Cortex-M4 image for QEMU's mps2-an386 (build/m4/)
#   make bench      figures: instructions, memory, accuracy (bench: lines)
#   make help       this list
#
# Missing Debian packages are installed on first use (scripts/deps.sh).

BUILD ?= build
HOST_CC ?= gcc
HOST := $(BUILD)/host
HOSTSAN := $(BUILD)/host-san
ROADS := sim_host/data/roads
ROAD_NAMES := flat uphill hilly

WARN := -std=c11 -Wall -Wextra -Werror -Wconversion -Wsign-conversion -Wshadow \
        -Wdouble-promotion -Wstrict-prototypes -Wundef -Wcast-qual -Wpointer-arith
# Project headers by their path: "firmware/x.h", "hal/x.h", and the host
# tools' "lib/x.h", "ref/x.h" (sim_host/); tests also name firmware headers alone.
HOST_INC := -I. -Isim_host -Ifirmware
SAN := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
HOST_CFLAGS := $(WARN) $(HOST_INC) -O2 -g
SAN_CFLAGS := $(WARN) $(HOST_INC) -O1 -g $(SAN)

FW_SRC := $(sort $(wildcard firmware/*.c))
FW_HDR := $(sort $(wildcard firmware/*.h))
REF_SRC := sim_host/ref/ref_model.c sim_host/ref/sim_compare.c sim_host/lib/road_csv.c sim_host/ref/drive_trace.c
SIM_HDR := $(sort $(wildcard sim_host/*/*.h sim_host/*/*/*.h))
# The one CAN log reader of the host tools (sim_host/lib/log/log.h).
LOG_SRC := $(sort $(wildcard sim_host/lib/log/*.c))
LOG_HDR := $(sort $(wildcard sim_host/lib/log/*.h))
UNIT_TESTS := $(patsubst tests/unit/%.c,%,$(sort $(wildcard tests/unit/test_*.c)))

DEPS_STAMP := $(BUILD)/.deps-ok

.PHONY: all tools deps run test test-host test-m4 firmware bench bench-figures test-bench-check help clean check-image \
        check-selfcheck check-replay e2e-test bus-fault-test
.DEFAULT_GOAL := all

all: tools

help:
	@sed -n '3,11p' Makefile | sed 's/^# \{0,1\}//'

# ---------------------------------------------------------------- set-up

$(DEPS_STAMP): scripts/deps.sh
	@mkdir -p $(@D)
	sh scripts/deps.sh
	@touch $@

deps: $(DEPS_STAMP)

# ---------------------------------------------------------------- host tools

TOOLS := $(HOST)/platoon_sim $(HOST)/roadgen $(HOST)/road2c $(HOST)/pfe_ecu $(HOST)/pfe_ecu_replay \
         $(HOST)/sensitivity $(HOST)/drivegen $(HOST)/pfe_record $(HOST)/run_report \
         $(HOST)/pfe_replay $(HOST)/pfe_decode $(HOST)/platoon_compare $(HOST)/route_choice \
         $(HOST)/routegen
tools: $(TOOLS)

$(HOST)/platoon_sim: sim_host/tools/platoon_sim.c $(FW_SRC) $(REF_SRC) $(FW_HDR) $(SIM_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -Ifirmware -o $@ sim_host/tools/platoon_sim.c $(FW_SRC) $(REF_SRC) -lm

# The module as a Linux process on SocketCAN (hal/socketcan, hal/posix).
ECU_LOOP_SRC := hal/hal_ecu_loop.c
# The truck calibration file (--calib) of the host tools that run the model.
TRUCK_CAL_SRC := sim_host/lib/truck_cal.c sim_host/lib/cli_args.c
ECU_HOST_SRC := sim_host/tools/pfe_ecu.c $(ECU_LOOP_SRC) hal/socketcan/hal_socketcan.c \
    hal/posix/hal_nvm_file.c hal/posix/hal_time_posix.c $(TRUCK_CAL_SRC)
HAL_HDR := $(sort $(wildcard hal/*.h hal/*/*.h))
$(HOST)/pfe_ecu: $(ECU_HOST_SRC) $(FW_SRC) $(FW_HDR) $(HAL_HDR) $(SIM_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -I. -Ifirmware -o $@ $(ECU_HOST_SRC) $(FW_SRC)

# The same firmware over a log in logical time (hal/replay); its twin on the
# Cortex-M4 is $(M4_OUT)/pfe_ecu_mps2.elf.
ECU_REPLAY_SRC := $(ECU_LOOP_SRC) hal/hal_can_mem.c hal/replay/hal_replay.c hal/hal_can_mem_api.c hal/replay/hal_replay_ecu.c
# The host reads the log through sim_host/lib/log/ (every form), the image
# through hal/replay's own parser.
REPLAY_SOURCE_SRC := sim_host/lib/replay_source.c $(LOG_SRC)
$(HOST)/pfe_ecu_replay: sim_host/tools/pfe_ecu_replay.c $(ECU_REPLAY_SRC) $(REPLAY_SOURCE_SRC) $(TRUCK_CAL_SRC) $(FW_SRC) $(FW_HDR) $(HAL_HDR) $(SIM_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -I. -Ifirmware -o $@ sim_host/tools/pfe_ecu_replay.c $(ECU_REPLAY_SRC) $(REPLAY_SOURCE_SRC) $(TRUCK_CAL_SRC) $(FW_SRC)

$(HOST)/roadgen: sim_host/tools/roadgen.c | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -o $@ $< -lm

$(HOST)/road2c: sim_host/tools/road2c.c sim_host/lib/road_csv.c sim_host/lib/road_csv.h | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -Isim_host -o $@ sim_host/tools/road2c.c sim_host/lib/road_csv.c -lm

# ---------------------------------------------------------------- host tests (ASan, UBSan)

# Unit tests: the firmware plus the test backend (hal/fake), nothing else.
UNIT_SRC := $(FW_SRC) hal/fake/hal_fake.c hal/hal_can_mem_api.c hal/hal_can_mem.c

$(HOSTSAN)/unit_%: tests/unit/%.c $(UNIT_SRC) $(FW_HDR) $(HAL_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -I. -Ifirmware -o $@ $< $(UNIT_SRC) -lcmocka

$(HOSTSAN)/test_accuracy: tests/host/test_accuracy.c $(FW_SRC) $(REF_SRC) $(FW_HDR) $(SIM_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -Ifirmware -o $@ $< $(FW_SRC) $(REF_SRC) -lcmocka -lm

$(HOSTSAN)/test_road_csv: tests/host/test_road_csv.c sim_host/lib/road_csv.c sim_host/lib/road_csv.h | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -Isim_host -o $@ $< sim_host/lib/road_csv.c -lcmocka -lm

# The module's prediction over a preview against the double-precision model.
$(HOSTSAN)/test_predict: tests/host/test_predict.c $(FW_SRC) $(REF_SRC) $(FW_HDR) $(SIM_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -I. -Ifirmware -o $@ $< $(FW_SRC) $(REF_SRC) -lcmocka -lm

# The identification against its double-precision reference and the
# reference model's truth (sim_host/ref/identify_ref).
$(HOSTSAN)/test_identify_ref: tests/host/test_identify_ref.c sim_host/ref/identify_ref.c $(FW_SRC) $(REF_SRC) $(FW_HDR) $(SIM_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -I. -Ifirmware -Isim_host -o $@ $< sim_host/ref/identify_ref.c $(FW_SRC) $(REF_SRC) -lcmocka -lm

# Every codec signal checked against can_dbc/pfe.dbc, and the other way round.
$(HOSTSAN)/test_dbc_codec: tests/host/test_dbc_codec.c sim_host/lib/dbc.c sim_host/lib/dbc.h $(FW_SRC) $(FW_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -I. -Ifirmware -Isim_host -o $@ $< sim_host/lib/dbc.c $(FW_SRC) -lcmocka -lm

# The HAL conformance suite on the test backend (on SocketCAN: mk/vcan.mk).
$(HOSTSAN)/test_hal_fake: tests/hal/test_hal_fake.c tests/hal/hal_conformance.c hal/fake/hal_fake.c hal/hal_can_mem_api.c hal/hal_can_mem.c $(HAL_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -I. -Ifirmware -o $@ $(filter %.c,$^) -lcmocka

# ... and on the replay backend, with the backend's own tests.
$(HOSTSAN)/test_hal_replay: tests/hal/test_hal_replay.c tests/hal/hal_conformance.c hal/replay/hal_replay.c hal/hal_can_mem_api.c hal/hal_can_mem.c $(HAL_HDR) tests/replay/log_vectors.h | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -I. -Ifirmware -o $@ $(filter %.c,$^) -lcmocka

$(HOSTSAN)/roadgen: sim_host/tools/roadgen.c | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -o $@ $< -lm

HOST_TEST_BINS := $(addprefix $(HOSTSAN)/unit_,$(UNIT_TESTS)) $(HOSTSAN)/test_accuracy \
                  $(HOSTSAN)/test_road_csv $(HOSTSAN)/roadgen $(HOSTSAN)/test_dbc_codec \
                  $(HOSTSAN)/test_hal_fake $(HOSTSAN)/test_hal_replay $(HOSTSAN)/test_predict \
                  $(HOSTSAN)/test_identify_ref

test-host: $(HOST_TEST_BINS)
	@set -e; for t in $(UNIT_TESTS); do echo "== host unit: $$t"; $(HOSTSAN)/unit_$$t; done
	@echo "== host: test_accuracy"; $(HOSTSAN)/test_accuracy $(ROADS)
	@echo "== host: test_predict"; $(HOSTSAN)/test_predict $(ROADS)
	@echo "== host: test_identify_ref"; $(HOSTSAN)/test_identify_ref
	@echo "== host: test_road_csv"; $(HOSTSAN)/test_road_csv $(ROADS) $(HOSTSAN)/roadgen
	@echo "== host: test_dbc_codec"; $(HOSTSAN)/test_dbc_codec can_dbc/pfe.dbc
	@echo "== host: HAL conformance on hal/fake"; $(HOSTSAN)/test_hal_fake
	@echo "== host: HAL conformance on hal/replay"; $(HOSTSAN)/test_hal_replay

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
M4_CFLAGS := $(filter-out -Os,$(M4_CFLAGS)) -O2 -flto -Ifirmware -DPFE_CODEC_NO_NAMES
M4_LDFLAGS_IMAGE += -O2 -flto
M4_LDFLAGS_TEST += -O2 -flto
include mk/stm32.mk

GEN := $(BUILD)/gen
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

firmware: $(DEPS_STAMP) $(FIRMWARE_ELF)
	@$(M4_SIZE) $(FIRMWARE_ELF)

# Fails if an image links the heap or floating-point helpers; and shows that
# it can fail, on an image made to use floating point.
$(M4_OUT)/test_bad_image_float.elf: $(M4_OUT)/obj/image/tests/m4/bad_image_float.o \
        $(call m4__objs,image,$(M4_HAL_IMAGE_SRCS))
	$(M4_CC) $(filter %.o,$^) $(M4_LDFLAGS_IMAGE) -o $@

check-image: $(FIRMWARE_ELF) $(M4_OUT)/pfe_ecu_mps2.elf $(M4_OUT)/pfe_bench.elf \
        $(M4_OUT)/test_bad_image_float.elf stm32-check-image
	$(M4_CHECK) $(FIRMWARE_ELF)
	$(M4_CHECK) $(M4_OUT)/pfe_ecu_mps2.elf
	$(M4_CHECK) $(M4_OUT)/pfe_bench.elf
	@if $(M4_CHECK) $(M4_OUT)/test_bad_image_float.elf >$(BUILD)/bad_image.txt 2>&1; then \
	    echo "check-image: a floating-point image passed the check"; exit 1; fi
	@grep -q __aeabi_f $(BUILD)/bad_image.txt && \
	    echo "check-image: refuses an image with floating point, as it should"

test-m4: $(DEPS_STAMP) $(addprefix $(M4_OUT)/unit_,$(addsuffix .elf,$(UNIT_TESTS))) \
        $(M4_OUT)/test_hal_replay.elf
	@set -e; for t in $(UNIT_TESTS); do echo "== Cortex-M4 unit: $$t"; \
	    $(M4_RUN) $(M4_OUT)/unit_$$t.elf; done
	@echo "== Cortex-M4: HAL conformance on hal/replay"; $(M4_RUN) $(M4_OUT)/test_hal_replay.elf

# Same inputs, bit-identical outputs on the host and on the Cortex-M4.
$(HOST)/selfcheck: sim_host/tools/selfcheck.c sim_host/lib/road_csv.c $(FW_SRC) $(FW_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -Ifirmware -o $@ sim_host/tools/selfcheck.c sim_host/lib/road_csv.c $(FW_SRC) -lm

check-selfcheck: $(HOST)/selfcheck $(FIRMWARE_ELF)
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
E2E_STATIC := -static -O2
$(E2E_PAYLOAD)/pfe_ecu: $(ECU_HOST_SRC) $(FW_SRC) $(FW_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(WARN) $(HOST_INC) $(E2E_STATIC) -I. -Ifirmware -o $@ $(ECU_HOST_SRC) $(FW_SRC)
$(E2E_PAYLOAD)/ecu_check: sim_host/tools/ecu_check.c $(CAPTURE_SRC) $(CAPTURE_HDR) $(FW_SRC) $(FW_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(WARN) $(HOST_INC) $(E2E_STATIC) -I. -Ifirmware -o $@ sim_host/tools/ecu_check.c $(CAPTURE_SRC) $(FW_SRC) -lm
$(HOST)/drivegen: sim_host/tools/drivegen.c sim_host/ref/drive_trace.c $(REF_SRC) $(TRUCK_CAL_SRC) $(FW_SRC) $(FW_HDR) $(SIM_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -I. -Ifirmware -o $@ sim_host/tools/drivegen.c $(REF_SRC) $(TRUCK_CAL_SRC) $(FW_SRC) -lm
$(E2E_PAYLOAD)/drive.log: $(HOST)/drivegen Makefile
	@mkdir -p $(@D)
	$(HOST)/drivegen --segment 600:0 --segment 50:0.5 --segment 50:1 --segment 50:1.5 \
	    --segment 750:2 --set-speed-kmh 90 --out $@
$(E2E_PAYLOAD)/ecu_vcan.sh: tests/e2e/ecu_vcan.sh
	@mkdir -p $(@D)
	cp $< $@

$(E2E_PAYLOAD)/pfe_faults: sim_host/tools/pfe_faults.c hal/replay/hal_replay.c hal/hal_can_mem_api.c hal/hal_can_mem.c $(REPLAY_SOURCE_SRC) $(FW_SRC) $(FW_HDR) $(HAL_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(WARN) $(HOST_INC) $(E2E_STATIC) -I. -Ifirmware -o $@ sim_host/tools/pfe_faults.c hal/replay/hal_replay.c hal/hal_can_mem_api.c hal/hal_can_mem.c $(REPLAY_SOURCE_SRC) $(FW_SRC)
$(E2E_PAYLOAD)/faults.log: $(HOST)/pfe_faults $(E2E_PAYLOAD)/drive.log
	$(HOST)/pfe_faults inject $(E2E_PAYLOAD)/drive.log $@

# Bus faults in the real kernel: vcan0 down and up, a flood, an address
# conflict, during a drive (tests/e2e/bus_faults.sh).
FAULTS_PAYLOAD := $(BUILD)/bus-faults/payload
$(FAULTS_PAYLOAD)/pfe_ecu: $(E2E_PAYLOAD)/pfe_ecu
	@mkdir -p $(@D)
	cp $< $@
$(FAULTS_PAYLOAD)/pfe_replay: $(REPLAY_PAYLOAD)/pfe_replay
	@mkdir -p $(@D)
	cp $< $@
$(FAULTS_PAYLOAD)/pfe_decode: $(DECODE_SRC) $(DECODE_HDR) sim_host/lib/dbc.c sim_host/lib/dbc.h | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(WARN) $(HOST_INC) $(E2E_STATIC) -Wno-maybe-uninitialized -I. -o $@ $(DECODE_SRC) sim_host/lib/dbc.c -lm
$(FAULTS_PAYLOAD)/pfe.dbc: can_dbc/pfe.dbc
	@mkdir -p $(@D)
	cp $< $@
$(FAULTS_PAYLOAD)/drive.log: $(E2E_PAYLOAD)/drive.log
	@mkdir -p $(@D)
	cp $< $@
$(FAULTS_PAYLOAD)/bus_faults.sh: tests/e2e/bus_faults.sh
	@mkdir -p $(@D)
	cp $< $@

bus-fault-test: $(addprefix $(FAULTS_PAYLOAD)/,pfe_ecu pfe_replay pfe_decode pfe.dbc drive.log bus_faults.sh)
	$(VCAN_VM) --time --timeout 300 --payload $(abspath $(FAULTS_PAYLOAD)) -- \
	    sh $(abspath $(FAULTS_PAYLOAD))/bus_faults.sh

e2e-test: $(addprefix $(E2E_PAYLOAD)/,pfe_ecu ecu_check pfe_faults drive.log faults.log ecu_vcan.sh)
	$(VCAN_VM) --time --timeout 500 --payload $(abspath $(E2E_PAYLOAD)) -- \
	    sh $(abspath $(E2E_PAYLOAD))/ecu_vcan.sh

# One log through the firmware on the host and in the Cortex-M4 image, in
# the log's time: identical records; then judged (tests/replay/host_vs_m4.sh).
$(HOST)/ecu_check: sim_host/tools/ecu_check.c $(CAPTURE_SRC) $(FW_SRC) $(FW_HDR) $(SIM_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -I. -Ifirmware -o $@ sim_host/tools/ecu_check.c $(CAPTURE_SRC) $(FW_SRC) -lm
$(HOST)/pfe_faults: sim_host/tools/pfe_faults.c hal/replay/hal_replay.c hal/hal_can_mem_api.c hal/hal_can_mem.c $(REPLAY_SOURCE_SRC) $(FW_SRC) $(FW_HDR) $(HAL_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -I. -Ifirmware -o $@ sim_host/tools/pfe_faults.c hal/replay/hal_replay.c hal/hal_can_mem_api.c hal/hal_can_mem.c $(REPLAY_SOURCE_SRC) $(FW_SRC)

check-replay: $(HOST)/pfe_ecu_replay $(HOST)/ecu_check $(HOST)/pfe_faults $(M4_OUT)/pfe_ecu_mps2.elf \
        $(E2E_PAYLOAD)/drive.log $(BUILD)/logs/hilly.log
	sh tests/replay/host_vs_m4.sh $(BUILD)/replay $(HOST) $(M4_OUT)/pfe_ecu_mps2.elf \
	    $(E2E_PAYLOAD)/drive.log $(BUILD)/logs/hilly.log

test: test-host test-m4 check-selfcheck check-replay check-image m4-selftest vcan-test e2e-test \
      test-sensitivity test-run-host test-drive-logs test-record-vm replay-test replay-vcan-test \
      thesis-test test-hardening bus-fault-test fuzz-smoke test-bench-check test-truck-cal \
      test-foreign-trucks check-replay-calib test-stm32 test-road-import \
      test-nvm-faults test-san

test-bench-check:
	@sh tests/bench/bench_check_test.sh

# ---------------------------------------------------------------- benchmarks

$(HOST)/host_bench: tests/bench/host_bench.c $(FW_SRC) $(REF_SRC) $(FW_HDR) $(SIM_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -Ifirmware -o $@ $< $(FW_SRC) $(REF_SRC) -lm

# Every figure, then the targets of tests/bench/targets.txt held to them
# (a figure above its limit, or missing, fails the bench).
bench:
	@mkdir -p $(BUILD)
	@{ $(MAKE) --no-print-directory bench-figures; echo "bench-exit $$?"; } | tee $(BUILD)/bench.out
	@grep -qx 'bench-exit 0' $(BUILD)/bench.out
	@sh scripts/bench_check.sh tests/bench/targets.txt $(BUILD)/bench.out

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

clean:
	rm -rf $(BUILD)
