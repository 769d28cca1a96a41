# Platoon fuel-prediction module: firmware, host tools, tests.
#
#   make            host tools (build/host/)
#   make run        simulate the bundled hilly road, fixed point against double
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
ROADS := sim_host/roads
ROAD_NAMES := flat uphill hilly

WARN := -std=c11 -Wall -Wextra -Werror -Wconversion -Wsign-conversion -Wshadow \
        -Wdouble-promotion -Wstrict-prototypes -Wundef -Wcast-qual -Wpointer-arith
SAN := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
HOST_CFLAGS := $(WARN) -O2 -g
SAN_CFLAGS := $(WARN) -O1 -g $(SAN)

FW_SRC := $(sort $(wildcard firmware/*.c))
FW_HDR := $(sort $(wildcard firmware/*.h))
REF_SRC := sim_host/ref_model.c sim_host/sim_compare.c sim_host/road_csv.c sim_host/drive_trace.c
SIM_HDR := $(sort $(wildcard sim_host/*.h))
UNIT_TESTS := $(patsubst tests/unit/%.c,%,$(sort $(wildcard tests/unit/test_*.c)))

DEPS_STAMP := $(BUILD)/.deps-ok

.PHONY: all tools deps run test test-host test-m4 firmware bench help clean check-image check-checksum
.DEFAULT_GOAL := all

all: tools

help:
	@sed -n '3,10p' Makefile | sed 's/^# \{0,1\}//'

# ---------------------------------------------------------------- set-up

$(DEPS_STAMP): scripts/deps.sh
	@mkdir -p $(@D)
	sh scripts/deps.sh
	@touch $@

deps: $(DEPS_STAMP)

# ---------------------------------------------------------------- host tools

TOOLS := $(HOST)/platoon_sim $(HOST)/roadgen $(HOST)/road2c
tools: $(TOOLS)

$(HOST)/platoon_sim: sim_host/platoon_sim.c $(FW_SRC) $(REF_SRC) $(FW_HDR) $(SIM_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -Ifirmware -o $@ sim_host/platoon_sim.c $(FW_SRC) $(REF_SRC) -lm

$(HOST)/roadgen: sim_host/roadgen.c | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -o $@ $< -lm

$(HOST)/road2c: sim_host/road2c.c sim_host/road_csv.c sim_host/road_csv.h | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -Isim_host -o $@ sim_host/road2c.c sim_host/road_csv.c -lm

run: $(HOST)/platoon_sim
	$(HOST)/platoon_sim --road $(ROADS)/hilly.csv --vehicles 5 --set-speed-kmh 90 \
	    --trace $(BUILD)/run_hilly_trace.csv
	@echo "per-step trace: $(BUILD)/run_hilly_trace.csv"

# ---------------------------------------------------------------- host tests (ASan, UBSan)

$(HOSTSAN)/unit_%: tests/unit/%.c $(FW_SRC) $(FW_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -Ifirmware -o $@ $< $(FW_SRC) -lcmocka

$(HOSTSAN)/test_accuracy: tests/host/test_accuracy.c $(FW_SRC) $(REF_SRC) $(FW_HDR) $(SIM_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -Ifirmware -o $@ $< $(FW_SRC) $(REF_SRC) -lcmocka -lm

$(HOSTSAN)/test_road_csv: tests/host/test_road_csv.c sim_host/road_csv.c sim_host/road_csv.h | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -Isim_host -o $@ $< sim_host/road_csv.c -lcmocka -lm

$(HOSTSAN)/roadgen: sim_host/roadgen.c | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -o $@ $< -lm

HOST_TEST_BINS := $(addprefix $(HOSTSAN)/unit_,$(UNIT_TESTS)) $(HOSTSAN)/test_accuracy \
                  $(HOSTSAN)/test_road_csv $(HOSTSAN)/roadgen

test-host: $(HOST_TEST_BINS)
	@set -e; for t in $(UNIT_TESTS); do echo "== host unit: $$t"; $(HOSTSAN)/unit_$$t; done
	@echo "== host: test_accuracy"; $(HOSTSAN)/test_accuracy $(ROADS)
	@echo "== host: test_road_csv"; $(HOSTSAN)/test_road_csv $(ROADS) $(HOSTSAN)/roadgen

test: test-host

clean:
	rm -rf $(BUILD)

-include mk/m4.mk
