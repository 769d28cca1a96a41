# Hardening checks of the firmware: MISRA C:2012, test coverage, worst-case
# stack.
#
# Included from the top-level Makefile after mk/m4.mk (it uses BUILD, HOST_CC,
# WARN, FW_SRC, FW_HDR, HAL_HDR, SIM_HDR, REF_SRC, UNIT_TESTS, ROADS,
# DEPS_STAMP, ECU_REPLAY_SRC, mk/m4.mk's M4_OUT, M4_CC, M4_CROSS, M4_RUN,
# M4_LDFLAGS_IMAGE, M4_HAL_IMAGE_SRCS, m4__objs, and the Makefile's rules
# for the Cortex-M4 images):
#
#   include mk/hardening.mk
#   test: test-hardening
#
# Targets:
#   misra          cppcheck's MISRA C:2012 addon over firmware/ and the MCU
#                  part of hal/ (MISRA_SRC; the STM32F405 image in a second
#                  run, MISRA_STM32_SRC), through scripts/misra_check.py:
#                  fails on any finding not covered by a deviation in
#                  misra/deviations.txt, and on a deviation that covers
#                  nothing; prints the counts. Then tests/misra/planted_test.sh
#                  shows that the same check fails on planted violations.
#   coverage       line and branch coverage of firmware/ by the host tests
#                  (COV_TESTS), built with --coverage in $(COV_OUT), measured
#                  with gcovr; fails below COV_LINE_MIN or COV_BRANCH_MIN
#                  (percent). Report: $(COV_OUT)/coverage.txt.
#   stack-check    worst-case stack of the Cortex-M4 product images
#                  pfe_mps2 and pfe_ecu_mps2 (scripts/stack_check.py): each
#                  linked again from its objects with -fstack-usage
#                  -fcallgraph-info=su in $(STACK_OUT) (byte-identical to
#                  the product image, or it fails), the deepest path from
#                  the reset vector plus each exception level, against the
#                  linker script's stack (__stack_size, 4 KiB); fails when it
#                  does not fit, or refuses a cycle, an indirect call with no
#                  target listed in scripts/stack_indirect.txt, or a stored
#                  function address not listed there (words of string
#                  literals, .rodata.str* in the map file, are not addresses). The bench image's
#                  bound is checked against its measured high-water mark.
#                  tests/stack/refusals.sh shows it refuses and fails.
#   test-hardening all three
#
# Variables:
#   COV_OUT         coverage build ($(BUILD)/coverage)
#   COV_LINE_MIN    line coverage floor, percent
#   COV_BRANCH_MIN  branch coverage floor, percent
#   STACK_OUT       stack analysis build ($(BUILD)/stack)

HARDEN_STAMP := $(BUILD)/.deps-hardening
COV_OUT ?= $(BUILD)/coverage
STACK_OUT ?= $(BUILD)/stack
MISRA_OUT := $(BUILD)/misra

.PHONY: misra coverage stack-check test-hardening

$(HARDEN_STAMP): scripts/deps.sh
	@mkdir -p $(@D)
	sh scripts/deps.sh cppcheck python3 gcovr
	@touch $@

# ---------------------------------------------------------------- MISRA C:2012

# The Cortex-M4's code: the firmware, the board (hal/mps2) and the log-replay
# backend it runs drives on (hal/replay), the ECU loop and the CAN queue. Not
# hal/socketcan, hal/posix (Linux) nor hal/fake (host tests).
MISRA_SRC := $(FW_SRC) $(sort $(wildcard hal/mps2/*.c hal/replay/*.c)) \
             hal/hal_ecu_loop.c hal/hal_can_mem.c hal/hal_can_mem_api.c
MISRA_CHECK := python3 scripts/misra_check.py --deviations misra/deviations.txt
# Recursive: STM32_MISRA_SRC comes from mk/stm32.mk, included later.
MISRA_STM32_SRC = $(FW_SRC) hal/hal_ecu_loop.c hal/hal_can_mem.c $(STM32_MISRA_SRC)

## MISRA C:2012 on the Cortex-M4 code and the STM32 image (cppcheck's addon, misra/deviations.txt)
misra: $(HARDEN_STAMP) $(FW_GEN_SRC) $(FW_GEN_HDR)
	@mkdir -p $(MISRA_OUT)
	$(MISRA_CHECK) --build-dir $(MISRA_OUT)/cache -I. -Ifirmware -I$(GEN) $(MISRA_SRC)
	@# The STM32F405 image apart (its sources: mk/stm32.mk), as its own
	@# program: the same HAL functions as hal/replay's, another startup.
	@cat misra/deviations.txt misra/deviations_stm32.txt > $(MISRA_OUT)/deviations_stm32.txt
	python3 scripts/misra_check.py --deviations $(MISRA_OUT)/deviations_stm32.txt --allow-unused \
	    --build-dir $(MISRA_OUT)/cache-stm32 -I. -Ifirmware -I$(GEN) $(MISRA_STM32_SRC)
	@sh tests/misra/planted_test.sh $(MISRA_CHECK)

# ---------------------------------------------------------------- coverage

# Floors, percent: what the tests reach, rounded down (make coverage prints it).
COV_LINE_MIN ?= 99
COV_BRANCH_MIN ?= 92

# Force-inlined helpers (PFE_ALWAYS_INLINE) compiled as ordinary functions:
# see firmware/pfe_fixed.h.
COV_CFLAGS := $(WARN) $(HOST_INC) -O0 -g --coverage -DPFE_NO_FORCE_INLINE
COV_OBJ := $(COV_OUT)/obj
# The firmware and the sources every test links with it, compiled once: the
# counts of all the tests add up in one .gcda per source.
COV_LIB_SRC := $(FW_SRC) hal/fake/hal_fake.c hal/hal_can_mem_api.c hal/hal_can_mem.c $(REF_SRC) sim_host/lib/dbc.c
COV_LIB_OBJ := $(patsubst %.c,$(COV_OBJ)/%.o,$(COV_LIB_SRC))
COV_TESTS := $(addprefix unit_,$(UNIT_TESTS)) test_accuracy test_predict test_dbc_codec
COV_TEST_OBJ := $(patsubst %,$(COV_OBJ)/tests/unit/%.o,$(UNIT_TESTS)) \
                $(patsubst %,$(COV_OBJ)/tests/host/%.o,test_accuracy test_predict test_dbc_codec)
# Kept: their .gcno files are the coverage notes of this build.
.SECONDARY: $(COV_LIB_OBJ) $(COV_TEST_OBJ)

$(COV_OBJ)/%.o: %.c $(FW_HDR) $(FW_GEN_HDR) $(HAL_HDR) $(SIM_HDR) | $(HARDEN_STAMP) $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(COV_CFLAGS) -I. -Ifirmware -Isim_host -c $< -o $@

$(COV_OUT)/unit_%: $(COV_OBJ)/tests/unit/%.o $(COV_LIB_OBJ)
	$(HOST_CC) --coverage -o $@ $^ -lcmocka -lm
$(COV_OUT)/test_%: $(COV_OBJ)/tests/host/test_%.o $(COV_LIB_OBJ)
	$(HOST_CC) --coverage -o $@ $^ -lcmocka -lm

# Each run starts from zero counts; gcovr reads firmware/ only.
## line and branch coverage of firmware/ by the host tests, held to its floors
coverage: $(addprefix $(COV_OUT)/,$(COV_TESTS))
	@find $(COV_OUT) -name '*.gcda' -delete
	@set -e; for t in $(UNIT_TESTS); do $(COV_OUT)/unit_$$t >$(COV_OUT)/unit_$$t.log 2>&1 || \
	    { cat $(COV_OUT)/unit_$$t.log; exit 1; }; done
	@$(COV_OUT)/test_accuracy $(ROADS) >$(COV_OUT)/test_accuracy.log 2>&1 || \
	    { cat $(COV_OUT)/test_accuracy.log; exit 1; }
	@$(COV_OUT)/test_predict $(ROADS) >$(COV_OUT)/test_predict.log 2>&1 || \
	    { cat $(COV_OUT)/test_predict.log; exit 1; }
	@$(COV_OUT)/test_dbc_codec can_dbc/pfe.dbc >$(COV_OUT)/test_dbc_codec.log 2>&1 || \
	    { cat $(COV_OUT)/test_dbc_codec.log; exit 1; }
	@gcovr --root . --object-directory $(COV_OUT) --filter 'firmware/' \
	    --exclude-unreachable-branches --txt $(COV_OUT)/coverage.txt
	@gcovr --root . --object-directory $(COV_OUT) --filter 'firmware/' \
	    --exclude-unreachable-branches --branches --txt $(COV_OUT)/coverage_branches.txt
	@gcovr --root . --object-directory $(COV_OUT) --filter 'firmware/' \
	    --exclude-unreachable-branches --print-summary \
	    --fail-under-line $(COV_LINE_MIN) --fail-under-branch $(COV_BRANCH_MIN) \
	    --txt /dev/null >$(COV_OUT)/summary.txt; rc=$$?; \
	    sed -n 's/^\(lines\|branches\): /coverage: firmware\/ \1 /p' $(COV_OUT)/summary.txt; \
	    if [ $$rc -ne 0 ]; then cat $(COV_OUT)/summary.txt; echo "coverage: below the floor" \
	        "(lines $(COV_LINE_MIN) %, branches $(COV_BRANCH_MIN) %): see $(COV_OUT)/coverage.txt"; exit 1; fi
	@echo "coverage: floor lines $(COV_LINE_MIN) %, branches $(COV_BRANCH_MIN) %; per file:" \
	    "$(COV_OUT)/coverage.txt, $(COV_OUT)/coverage_branches.txt"

# ---------------------------------------------------------------- worst-case stack

# The product images and their sources (as the Makefile's m4_image calls
# list them), and the bench image, whose measured high-water mark
# (hal_mps2_stack_used_bytes, "bench: stack_used") cross-checks the bound.
STACK_IMAGES := pfe_mps2 pfe_ecu_mps2 pfe_bench
STACK_SRC_pfe_mps2 := $(FW_SRC) hal/mps2/main_selfcheck.c $(BUILD)/gen/road_hilly.c
STACK_SRC_pfe_ecu_mps2 := $(FW_SRC) $(ECU_REPLAY_SRC) hal/mps2/main_ecu.c hal/mps2/calib_default.c
STACK_SRC_pfe_bench := $(FW_SRC) tests/bench/m4_bench.c $(BUILD)/gen/road_hilly.c
STACK_CHECK := python3 scripts/stack_check.py --indirect scripts/stack_indirect.txt

# The image linked again from its own objects with -fstack-usage and
# -fcallgraph-info=su: with -flto, code is generated at the link, which
# writes the .su and .ci files of the very code linked. The link must give
# the product image's bytes, or the analysis is of something else.
define stack__rule
$(STACK_OUT)/$(1)/$(1).elf: $(M4_OUT)/$(1).elf scripts/stack_check.py scripts/stack_indirect.txt
	@rm -rf $$(@D)
	@mkdir -p $$(@D)
	$$(M4_CC) $$(call m4__objs,image,$(STACK_SRC_$(1)) $$(M4_HAL_IMAGE_SRCS)) $$(M4_LDFLAGS_IMAGE) \
	    -fstack-usage -fcallgraph-info=su -dumpdir $$(@D)/$(1). -o $$@
	@$$(M4_CROSS)objcopy -O binary $$@ $$(@D)/analysed.bin
	@$$(M4_CROSS)objcopy -O binary $(M4_OUT)/$(1).elf $$(@D)/product.bin
	@cmp -s $$(@D)/analysed.bin $$(@D)/product.bin || { echo "stack-check: the analysis link of" \
	    "$(1) differs from $(M4_OUT)/$(1).elf: update STACK_SRC_$(1) in mk/hardening.mk"; exit 1; }
endef
$(foreach i,$(STACK_IMAGES),$(eval $(call stack__rule,$(i))))

# The self-check image linked with a 512-byte stack, which its worst case
# exceeds: the check must fail on it (tests/stack/refusals.sh).
$(STACK_OUT)/small/pfe_mps2.elf: $(M4_OUT)/pfe_mps2.elf
	@rm -rf $(@D)
	@mkdir -p $(@D)
	$(M4_CC) $(call m4__objs,image,$(STACK_SRC_pfe_mps2) $(M4_HAL_IMAGE_SRCS)) $(M4_LDFLAGS_IMAGE) \
	    -Wl,--defsym=__stack_size=512 -fstack-usage -fcallgraph-info=su -dumpdir $(@D)/pfe_mps2. -o $@

## worst-case stack of each product image from its call graph, against its stack size
stack-check: $(HARDEN_STAMP) $(foreach i,$(STACK_IMAGES),$(STACK_OUT)/$(i)/$(i).elf) stm32-stack-check \
        $(STACK_OUT)/small/pfe_mps2.elf
	@set -e; for i in pfe_mps2 pfe_ecu_mps2; do \
	    $(STACK_CHECK) --elf $(M4_OUT)/$$i.elf --ci $(STACK_OUT)/$$i/*.ci --su $(STACK_OUT)/$$i/*.su; done
	@measured=$$($(M4_RUN) $(M4_OUT)/pfe_bench.elf | sed -n 's/^bench: stack_used \([0-9]*\) bytes$$/\1/p'); \
	    test -n "$$measured" || { echo "stack-check: pfe_bench printed no stack_used"; exit 1; }; \
	    $(STACK_CHECK) --elf $(M4_OUT)/pfe_bench.elf --ci $(STACK_OUT)/pfe_bench/*.ci \
	        --su $(STACK_OUT)/pfe_bench/*.su --measured $$measured
	@sh tests/stack/refusals.sh $(STACK_OUT) $(M4_OUT) $(STACK_CHECK)

## misra, coverage and stack-check
test-hardening: misra coverage stack-check
