# Fuzzing: libFuzzer targets (clang, ASan, UBSan) over the ECU's frame input,
# every log parser, the DBC parser and the NVM records (tests/fuzz/).
#
# Included from the top-level Makefile; uses its BUILD, WARN, FW_SRC,
# FW_HDR, HAL_HDR and its rule for the e2e drive log.
#
# Targets:
#   fuzz          each target for FUZZ_SECONDS, after its regression inputs;
#                 one summary line each (runs, libFuzzer's cov and ft, corpus,
#                 crashes)
#   test-fuzz-smoke    the same for FUZZ_SMOKE_SECONDS each (part of `make test`)
#   fuzz-build    the targets only, in $(FUZZ_OUT)/
#   fuzz-seeds    rewrites the committed seeds (tests/fuzz/corpus/) from the
#                 bundled logs (tests/fuzz/make_seeds.sh)
#
# Targets (tests/fuzz/fuzz_NAME.c), each with its seeds in tests/fuzz/corpus/
# NAME and the inputs of every crash found, replayed first, in
# tests/fuzz/regress/NAME:
#   ecu      frame sequences and time steps into pfe_ecu (firmware/)
#   canlog   sim_host/lib/log/: candump log, candump printed, Vector ASC
#   replay   hal/replay/hal_replay.c: the replay bus's candump parser
#   capture  sim_host/lib/capture.c: the capture reader
#   dbc      sim_host/lib/dbc.c, seeded with can_dbc/pfe.dbc
#   nvm      firmware/pfe_nvm.c: pfe_nvm_decode, pfe_nvm_pick, and the ECU
#            started from the record picked
#
# Variables:
#   FUZZ_SECONDS        per target for `make fuzz` (60)
#   FUZZ_SMOKE_SECONDS  per target for `make test-fuzz-smoke` (12)
#   FUZZ_TARGETS        the targets to run (all of the above)
#   FUZZ_CC             clang (Debian's clang 14, libFuzzer from libclang-rt-14-dev)
#   FUZZ_OUT            $(BUILD)/fuzz: binaries, growing corpora, crashes, logs

FUZZ_SECONDS ?= 60
FUZZ_SMOKE_SECONDS ?= 12
FUZZ_TARGETS ?= ecu canlog replay capture dbc nvm
FUZZ_CC ?= clang
FUZZ_OUT ?= $(BUILD)/fuzz
FUZZ_PACKAGES := clang libclang-rt-14-dev
FUZZ_CFLAGS := $(WARN) $(HOST_INC) -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
               -fno-omit-frame-pointer
FUZZ_DEPS := $(FUZZ_OUT)/.deps-ok
FUZZ_HDR := tests/fuzz/fuzz_check.h

.PHONY: fuzz test-fuzz-smoke fuzz-build fuzz-seeds

$(FUZZ_DEPS): scripts/deps.sh
	@mkdir -p $(@D)
	sh scripts/deps.sh $(FUZZ_PACKAGES)
	@touch $@

# $(call fuzz_target,NAME,SOURCES): $(FUZZ_OUT)/fuzz_NAME from tests/fuzz/fuzz_NAME.c
# and SOURCES, compiled whole by clang (the libFuzzer flags on every file).
define fuzz__target
$(FUZZ_OUT)/fuzz_$(1): tests/fuzz/fuzz_$(1).c $(2) $(FUZZ_HDR) $(FW_HDR) $(HAL_HDR) $(SIM_HDR) | $(FUZZ_DEPS)
	$$(FUZZ_CC) $$(FUZZ_CFLAGS) -o $$@ $$(filter %.c,$$^) -lm
endef
fuzz_target = $(eval $(call fuzz__target,$(1),$(2)))

$(call fuzz_target,ecu,$(FW_SRC))
$(call fuzz_target,nvm,$(FW_SRC))
$(call fuzz_target,canlog,$(LOG_SRC))
$(call fuzz_target,replay,hal/replay/hal_replay.c hal/hal_can_mem_api.c hal/hal_can_mem.c)
$(call fuzz_target,capture,sim_host/lib/capture.c $(LOG_SRC))
$(call fuzz_target,dbc,sim_host/lib/dbc.c)

# The DBC's seed is the DBC itself, as it is now (16 KB: inputs up to 20 KB).
FUZZ_SEED_DIRS_dbc := $(FUZZ_OUT)/seed/dbc
$(FUZZ_OUT)/seed/dbc/pfe.dbc: can_dbc/pfe.dbc
	@mkdir -p $(@D)
	cp $< $@

FUZZ_BINS := $(addprefix $(FUZZ_OUT)/fuzz_,$(FUZZ_TARGETS))

## the libFuzzer targets only (build/fuzz/)
fuzz-build: $(FUZZ_BINS) $(FUZZ_OUT)/seed/dbc/pfe.dbc

# $(1): seconds per target
define fuzz_run
	@set -e; for t in $(FUZZ_TARGETS); do \
	    case $$t in dbc) seeds="$(FUZZ_SEED_DIRS_dbc)" len=20480 ;; *) seeds="" len=4096 ;; esac; \
	    FUZZ_MAX_LEN=$$len sh tests/fuzz/run_fuzz.sh $(FUZZ_OUT)/fuzz_$$t $$t $(1) $(FUZZ_OUT) $$seeds; \
	done
endef

## each libFuzzer target for FUZZ_SECONDS after its regression inputs
fuzz: fuzz-build
	$(call fuzz_run,$(FUZZ_SECONDS))

## each libFuzzer target for FUZZ_SMOKE_SECONDS (part of make test)
test-fuzz-smoke: fuzz-build
	$(call fuzz_run,$(FUZZ_SMOKE_SECONDS))

# The seed writer: a host program of the host flavour (mk/host.mk).
$(call host_program,ecu_seed,tests/fuzz/ecu_seed.c)

## rewrite the committed fuzzing seeds from the bundled logs
fuzz-seeds: $(HOST)/ecu_seed $(BUILD)/e2e/payload/drive.log
	sh tests/fuzz/make_seeds.sh $(BUILD)/e2e/payload/drive.log $(HOST)/ecu_seed
