# make run: the module on a virtual CAN bus, fed a recorded drive, judged
# against the double-precision reference. Also the drive logs, the recorder
# and the report tool, and their tests.
#
# Include from the top-level Makefile, after its host variables (BUILD, HOST,
# HOSTSAN, HOST_CC, HOST_CFLAGS, SAN_CFLAGS, WARN, FW_SRC, FW_HDR, REF_SRC,
# ROADS, ROAD_NAMES, DEPS_STAMP) and after mk/vcan.mk (VCAN_VM, VCAN_VM_DIR,
# VCAN_IF).
#
# Targets:
#   run               build, then scripts/run_drive.sh: pfe_ecu and pfe_record
#                     on vcan0 (natively, else under QEMU), the drive replayed
#                     by pfe_replay, then run_report: summary, CSV, plot, and
#                     the verdict on RUN_EXPECT (exit status 1 when it fails)
#   drive-logs        regenerate the committed logs sim_host/data/logs/*.log.gz
#   logs              expand them into $(LOG_DIR)/
#   test-drive-logs   regenerating each committed log gives it byte for byte
#   test-run-host     capture reader, noise, run_report (ASan, UBSan)
#   test-record-vm    pfe_record against candump -L on the same traffic
#
# Variables:
#   RUN_LOG       drive to replay (default: the first RUN_DRIVE_S seconds of
#                 the bundled hilly drive, $(RUN_DIR)/hilly_run.log)
#   RUN_DRIVE_S   length of that slice in seconds                        (120)
#   RUN_PREVIEW_SAMPLES  its grade previews' length in 12 m samples       (150)
#   RUN_EXPECT    expected values and tolerances (sim_host/data/logs/hilly_run.expect)
#   RUN_JUNIT     JUnit XML report                    ($(RUN_DIR)/junit.xml)
#   RUN_REPORT_FLAGS  more run_report options (e.g. --module-sa 0x90)
#   RUN_TIMEOUT_S     limit of the bus part, VM boot included            (600)

RUN_DIR := $(BUILD)/run
RUN_PAYLOAD := $(RUN_DIR)/payload
LOGS_SRC := sim_host/data/logs
LOG_DIR := $(BUILD)/logs
RUN_DRIVE_S ?= 120
RUN_LOG ?= $(RUN_DIR)/hilly_run.log
RUN_EXPECT ?= $(LOGS_SRC)/hilly_run.expect
RUN_JUNIT ?= $(RUN_DIR)/junit.xml
RUN_REPORT_FLAGS ?=
RUN_TIMEOUT_S ?= 600
GNUPLOT_STAMP := $(BUILD)/.gnuplot-ok

# The committed drives: the thesis's three roads, a 5-truck platoon at
# 90 km/h, 10 m apart, this truck second (position 1), with a little sensor
# noise (0.05 km/h on the speed, 0.02 deg on the pitch, seed 1).
DRIVE_FLAGS := --vehicles 5 --position 1 --gap-m 10 --set-speed-kmh 90 \
               --speed-noise-kmh 0.05 --pitch-noise-deg 0.02 --seed 1

CAPTURE_SRC := sim_host/lib/capture.c $(LOG_SRC) sim_host/ref/bus_ref.c sim_host/ref/ref_model.c
CAPTURE_HDR := sim_host/lib/capture.h $(LOG_HDR) sim_host/ref/bus_ref.h sim_host/ref/ref_model.h
# run_report's judge of the prediction (its header lists what it needs)
PJ_SRC := sim_host/ref/prediction_judge.c sim_host/lib/plot.c
PJ_HDR := sim_host/ref/prediction_judge.h

.PHONY: run run-sim drive-logs logs test-drive-logs test-run-host test-record-vm

# ---------------------------------------------------------------- tools

$(GNUPLOT_STAMP): scripts/deps.sh
	@mkdir -p $(@D)
	sh scripts/deps.sh gnuplot-nox
	@touch $@

# Only listens: built without the real-bus guard, which it does not need.
$(HOST)/pfe_record: sim_host/tools/pfe_record.c | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -o $@ $<

$(HOST)/run_report: sim_host/tools/run_report.c $(CAPTURE_SRC) $(TRUCK_CAL_SRC) $(CAPTURE_HDR) $(SIM_HDR) $(PJ_SRC) $(PJ_HDR) $(FW_SRC) $(FW_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(HOST_CFLAGS) -I. -Ifirmware -o $@ sim_host/tools/run_report.c $(CAPTURE_SRC) $(TRUCK_CAL_SRC) $(PJ_SRC) $(FW_SRC) -lm

# ---------------------------------------------------------------- drive logs

# Written only on request: the committed files are the reference.
drive-logs: $(HOST)/drivegen
	@mkdir -p $(LOG_DIR)
	@set -e; for r in $(ROAD_NAMES); do \
	    $(HOST)/drivegen --road $(ROADS)/$$r.csv $(DRIVE_FLAGS) --out $(LOG_DIR)/$$r.log; \
	    gzip -9n -c $(LOG_DIR)/$$r.log > $(LOGS_SRC)/$$r.log.gz; \
	    echo "wrote $(LOGS_SRC)/$$r.log.gz ($$(wc -c < $(LOGS_SRC)/$$r.log.gz) bytes," \
	         "$$(wc -c < $(LOG_DIR)/$$r.log) expanded)"; done

# canplayer cannot read gzip: the logs are expanded here.
$(LOG_DIR)/%.log: $(LOGS_SRC)/%.log.gz
	@mkdir -p $(@D)
	gzip -dc $< > $@

logs: $(addprefix $(LOG_DIR)/,$(addsuffix .log,$(ROAD_NAMES)))

# The bundled run drive: the hilly drive's first RUN_DRIVE_S seconds (its
# log starts at 1700000000.000000), with grade previews of
# RUN_PREVIEW_SAMPLES samples (1.8 km, about 72 s at 90 km/h) instead of the
# committed log's 12 km, so that the predictions of its first 48 s reach
# their horizon's end within the drive and are judged (prediction_judge.h).
# Every other frame is the committed hilly.log.gz's, byte for byte: the
# previews do not move the simulation.
RUN_PREVIEW_SAMPLES ?= 150
$(RUN_DIR)/hilly_run.log: $(HOST)/drivegen $(ROADS)/hilly.csv $(lastword $(MAKEFILE_LIST))
	@mkdir -p $(@D)
	$(HOST)/drivegen --road $(ROADS)/hilly.csv $(DRIVE_FLAGS) --preview-samples $(RUN_PREVIEW_SAMPLES) \
	    --out $(RUN_DIR)/hilly_preview.log 2> /dev/null
	awk -v end="($$((1700000000 + $(RUN_DRIVE_S))).000000)" '$$1 < end' $(RUN_DIR)/hilly_preview.log > $@

test-drive-logs: $(HOST)/drivegen
	@mkdir -p $(BUILD)/logs-check
	@set -e; for r in $(ROAD_NAMES); do \
	    $(HOST)/drivegen --road $(ROADS)/$$r.csv $(DRIVE_FLAGS) --out $(BUILD)/logs-check/$$r.log \
	        2> /dev/null; \
	    if gzip -dc $(LOGS_SRC)/$$r.log.gz | cmp -s - $(BUILD)/logs-check/$$r.log; then \
	        echo "test-drive-logs: $$r.log regenerated byte for byte ($$(wc -l < $(BUILD)/logs-check/$$r.log) frames)"; \
	    else echo "test-drive-logs: $(LOGS_SRC)/$$r.log.gz differs from what drivegen writes now" \
	        "(make drive-logs rewrites it)"; exit 1; fi; done

# ---------------------------------------------------------------- make run

# What the bus part gets (scripts/run_drive.sh): static programs, the drive.
RUN_PAYLOAD_FILES := pfe_ecu pfe_record pfe_replay drive.log run_drive.sh
RUN_STATIC := $(WARN) $(HOST_INC) -static -O2

$(RUN_PAYLOAD)/pfe_ecu: $(ECU_HOST_SRC) $(FW_SRC) $(FW_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(RUN_STATIC) -I. -Ifirmware -o $@ $(ECU_HOST_SRC) $(FW_SRC)

$(RUN_PAYLOAD)/pfe_record: sim_host/tools/pfe_record.c | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(RUN_STATIC) -o $@ $<

# The replayer, static as mk/replay.mk builds it for its own VM tests.
$(RUN_PAYLOAD)/pfe_replay: $(REPLAY_PAYLOAD)/pfe_replay
	@mkdir -p $(@D)
	cp $< $@

$(RUN_PAYLOAD)/run_drive.sh: scripts/run_drive.sh
	@mkdir -p $(@D)
	cp $< $@

# Copied again on every run: RUN_LOG may name any file.
.PHONY: $(RUN_PAYLOAD)/drive.log
$(RUN_PAYLOAD)/drive.log: $(RUN_LOG)
	@mkdir -p $(@D)
	cp $< $@

run: $(HOST)/run_report $(GNUPLOT_STAMP) $(addprefix $(RUN_PAYLOAD)/,$(RUN_PAYLOAD_FILES))
	@t0=$$(date +%s); \
	VCAN_VM_DIR=$(VCAN_VM_DIR) sh scripts/run_drive.sh --payload $(RUN_PAYLOAD) --out $(RUN_DIR) \
	    --expect $(RUN_EXPECT) --junit $(RUN_JUNIT) --timeout $(RUN_TIMEOUT_S) \
	    -- --title "$(notdir $(RUN_LOG))" $(RUN_REPORT_FLAGS); rc=$$?; \
	echo "make run: $$(( $$(date +%s) - t0 )) s, exit $$rc"; exit $$rc

# The earlier `make run`: the platoon simulation over the hilly road, fixed
# point against double, no bus.
run-sim: $(HOST)/platoon_sim
	$(HOST)/platoon_sim --road $(ROADS)/hilly.csv --vehicles 5 --set-speed-kmh 90 \
	    --trace $(BUILD)/run_hilly_trace.csv
	@echo "per-step trace: $(BUILD)/run_hilly_trace.csv"

# ---------------------------------------------------------------- tests

$(HOSTSAN)/test_capture: tests/host/test_capture.c $(CAPTURE_SRC) $(CAPTURE_HDR) sim_host/ref/drive_trace.c \
        sim_host/ref/drive_trace.h $(FW_SRC) $(FW_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -I. -Ifirmware -o $@ $< $(CAPTURE_SRC) sim_host/ref/drive_trace.c \
	    $(FW_SRC) -lcmocka -lm

$(HOSTSAN)/run_report: sim_host/tools/run_report.c $(CAPTURE_SRC) $(TRUCK_CAL_SRC) $(CAPTURE_HDR) $(SIM_HDR) $(PJ_SRC) $(PJ_HDR) $(FW_SRC) $(FW_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -I. -Ifirmware -o $@ sim_host/tools/run_report.c $(CAPTURE_SRC) $(TRUCK_CAL_SRC) $(PJ_SRC) $(FW_SRC) -lm

$(HOSTSAN)/ecu_offline: tests/host/ecu_offline.c sim_host/lib/capture.c $(LOG_SRC) sim_host/lib/capture.h $(FW_SRC) $(FW_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -I. -Ifirmware -o $@ $< sim_host/lib/capture.c $(LOG_SRC) $(FW_SRC) -lm

test-run-host: $(HOSTSAN)/test_capture $(HOSTSAN)/run_report $(HOSTSAN)/ecu_offline \
        $(LOG_DIR)/hilly.log $(GNUPLOT_STAMP) $(HOST)/drivegen $(HOST)/run_report
	@echo "== host: test_capture"; $(HOSTSAN)/test_capture
	@echo "== host: run_report on the firmware ECU run offline"
	@sh tests/host/run_report_test.sh $(HOSTSAN)/run_report $(HOSTSAN)/ecu_offline \
	    $(LOG_DIR)/hilly.log $(BUILD)/run-report-test $(HOST)/run_report
	@echo "== host: run_report's prediction judge on the firmware ECU run offline"
	@sh tests/host/prediction_judge_test.sh $(HOSTSAN)/run_report $(HOSTSAN)/ecu_offline \
	    $(HOST)/drivegen $(ROADS)/hilly.csv $(BUILD)/prediction-judge-test

# The recorder in the VM, next to candump -L, on every kind of frame.
RECORD_PAYLOAD := $(BUILD)/record-vm
$(RECORD_PAYLOAD)/pfe_record: sim_host/tools/pfe_record.c | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(RUN_STATIC) -o $@ $<
$(RECORD_PAYLOAD)/record_vs_candump.sh: tests/e2e/record_vs_candump.sh
	@mkdir -p $(@D)
	cp $< $@

test-record-vm: $(RECORD_PAYLOAD)/pfe_record $(RECORD_PAYLOAD)/record_vs_candump.sh
	VCAN_VM_DIR=$(VCAN_VM_DIR) $(VCAN_VM) --time --timeout 300 --payload $(abspath $(RECORD_PAYLOAD)) -- \
	    sh $(abspath $(RECORD_PAYLOAD))/record_vs_candump.sh
