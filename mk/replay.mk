# Log replay and decoding: pfe_replay and pfe_decode (sim_host/), their tests
# and their benchmark.
#
# Included from the top-level Makefile after mk/vcan.mk; uses its BUILD,
# HOST, HOSTSAN, HOST_CC, HOST_CFLAGS, SAN_CFLAGS, WARN, DEPS_STAMP, its rule
# for the e2e drive log and mk/vcan.mk's VCAN_VM, VCAN_VM_DIR.
#
# Targets:
#   test-replay        host tests, ASan + UBSan: test_canlog (CMocka: every
#                      format, every kind of bad input, the drive log in three
#                      formats), then tests/host/test_decode.sh (pfe_decode)
#                      and tests/host/test_replay.sh (pfe_replay: dry run,
#                      filters, ASC from can-utils' log2asc, exit codes, the
#                      real-bus guard on lo)
#   test-replay-vcan   tests/e2e/replay_vcan.sh on vcan0 through
#                      scripts/vcan_vm.sh: round trips of the bundled logs and
#                      of candump logs of cangen, the drive as ASC and as
#                      candump output, pacing against canplayer, the guard
#                      on lo and on an slcan interface
#   replay-bench       bench: log_parse_fps (this machine) and, in one VM run,
#                      pfe_replay against canplayer (tests/bench/replay_bench.sh)
#
# Variables:
#   REPLAY_OUT         outputs of this file ($(BUILD)/replay)
#   REPLAY_BENCH_FRAMES  frames of the benchmark log (1000000)
#   REPLAY_BENCH_RUNS  runs per program, the median is kept (5 here, 3 in the VM)

REPLAY_OUT ?= $(BUILD)/replay
# The e2e drive: the Makefile's rule for $$(E2E_PAYLOAD)/drive.log, whose
# variable is defined after this file is included; named here by its path.
REPLAY_DRIVE_LOG := $(BUILD)/e2e/payload/drive.log
REPLAY_PAYLOAD := $(REPLAY_OUT)/payload
REPLAY_BENCH_PAYLOAD := $(REPLAY_OUT)/bench-payload
REPLAY_BENCH_FRAMES ?= 1000000
REPLAY_BENCH_RUNS ?= 5
REPLAY_VM_TIMEOUT_S ?= 1800


.PHONY: test-replay test-replay-vcan replay-bench

# ---------------------------------------------------------------- host tools


# ---------------------------------------------------------------- host tests (ASan, UBSan)




# can-utils' log2asc writes the ASC that test_replay.sh reads back.
$(REPLAY_OUT)/.deps-ok: scripts/deps.sh
	@mkdir -p $(@D)
	sh scripts/deps.sh can-utils
	@touch $@

## pfe_replay and pfe_decode on the host: every log format, bad input, exit codes, the real-bus guard on lo
test-replay: $(HOSTSAN)/test_canlog $(HOSTSAN)/pfe_replay $(HOSTSAN)/pfe_decode $(REPLAY_DRIVE_LOG) \
        $(REPLAY_OUT)/.deps-ok $(HOST)/pfe_ecu_replay $(HOST)/pfe_ecu
	@echo "== host: test_canlog"; $(HOSTSAN)/test_canlog $(REPLAY_DRIVE_LOG)
	@echo "== host: test_decode.sh"; sh tests/host/test_decode.sh $(HOSTSAN)/pfe_decode can_dbc/pfe.dbc
	@echo "== host: test_replay.sh"; sh tests/host/test_replay.sh $(HOSTSAN)/pfe_replay $(REPLAY_DRIVE_LOG) \
	    $(HOST)/pfe_ecu_replay $(HOST)/pfe_ecu

# ---------------------------------------------------------------- on vcan (scripts/vcan_vm.sh)

# Static programs: the VM's initramfs has no C library.
$(call host_payload,$(REPLAY_PAYLOAD),pfe_replay lateness_check slcan_run)
$(call host_payload,$(REPLAY_BENCH_PAYLOAD),pfe_replay biglog_gen bench_time)
# The bundled drive logs, committed gzip-compressed, expanded into
# $(BUILD)/logs/ by mk/run.mk's rule.
REPLAY_LOGS := $(patsubst sim_host/data/logs/%.log.gz,$(BUILD)/logs/%.log,$(sort $(wildcard sim_host/data/logs/*.log.gz)))




$(REPLAY_PAYLOAD)/replay_vcan.sh: tests/e2e/replay_vcan.sh
	@mkdir -p $(@D)
	cp $< $@

$(REPLAY_PAYLOAD)/drive.log: $(REPLAY_DRIVE_LOG)
	@mkdir -p $(@D)
	cp $< $@

# The committed logs, if any, in logs/ (rebuilt each time: a log may be removed).
$(REPLAY_PAYLOAD)/logs/.copied: $(REPLAY_LOGS) mk/replay.mk
	@rm -rf $(@D) && mkdir -p $(@D)
	@for f in $(REPLAY_LOGS); do cp "$$f" $(@D)/ || exit 1; done
	@echo "replay: $(words $(REPLAY_LOGS)) bundled log(s) from sim_host/data/logs in the payload"
	@touch $@

REPLAY_PAYLOAD_FILES := $(addprefix $(REPLAY_PAYLOAD)/,pfe_replay lateness_check slcan_run \
    replay_vcan.sh drive.log logs/.copied)

## pfe_replay on vcan0 in the VM: round trips of the bundled logs, pacing against canplayer, the guard
test-replay-vcan: $(REPLAY_PAYLOAD_FILES)
	VCAN_VM_DIR=$(VCAN_VM_DIR) $(VCAN_VM) --time --timeout $(REPLAY_VM_TIMEOUT_S) \
	    --payload $(abspath $(REPLAY_PAYLOAD)) -- sh $(abspath $(REPLAY_PAYLOAD))/replay_vcan.sh

# ---------------------------------------------------------------- benchmark



$(REPLAY_OUT)/big.log: $(HOST)/biglog_gen
	@mkdir -p $(@D)
	$(HOST)/biglog_gen $(REPLAY_BENCH_FRAMES) > $@.tmp && mv $@.tmp $@



$(REPLAY_BENCH_PAYLOAD)/replay_bench.sh: tests/bench/replay_bench.sh
	@mkdir -p $(@D)
	cp $< $@

# canplayer cannot run on this machine (its kernel has no CAN sockets, and
# canplayer opens one even for stdout=): the comparison runs both programs
# in one VM, on a copy of the log generated there (checked by its md5sum).
## bench: log_parse_fps, and pfe_replay against canplayer in one VM run
replay-bench: $(HOST)/pfe_replay $(HOST)/bench_time $(REPLAY_OUT)/big.log \
        $(addprefix $(REPLAY_BENCH_PAYLOAD)/,pfe_replay biglog_gen bench_time replay_bench.sh)
	@set -e; out=$$($(HOST)/bench_time $(REPLAY_BENCH_RUNS) $(HOST)/pfe_replay -t --quiet \
	    -I $(REPLAY_OUT)/big.log stdout=vcan0 2>/dev/null); \
	echo "replay-bench: pfe_replay -t -I big.log stdout=vcan0 > /dev/null, here: $$out"; \
	med=$$(echo "$$out" | awk '{ print $$2 }'); \
	awk -v n=$(REPLAY_BENCH_FRAMES) -v t="$$med" \
	    'BEGIN { printf "bench: log_parse_fps %.0f frames/s\n", n / t }'
	@VCAN_VM_DIR=$(VCAN_VM_DIR) $(VCAN_VM) --timeout $(REPLAY_VM_TIMEOUT_S) \
	    --payload $(abspath $(REPLAY_BENCH_PAYLOAD)) -- sh $(abspath $(REPLAY_BENCH_PAYLOAD))/replay_bench.sh \
	    $(REPLAY_BENCH_FRAMES) $$(md5sum < $(REPLAY_OUT)/big.log | cut -d' ' -f1)
