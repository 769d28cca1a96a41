# Hardening checks of the firmware: MISRA C:2012, test coverage, worst-case
# stack.
#
# Included from the top-level Makefile after mk/m4.mk (it uses BUILD, HOST_CC,
# WARN, FW_SRC, FW_HDR, HAL_HDR, REF_SRC, SIM_HDR, UNIT_TESTS, ROADS,
# DEPS_STAMP, M4_OUT, M4_CC, M4_ARCH_FLAGS, M4_LINKER_DIR, M4_HAL_IMAGE_SRCS,
# ECU_REPLAY_SRC and the rule for $(GEN)/road_hilly.c):
#
#   include mk/hardening.mk
#   test: test-hardening
#
# Targets:
#   misra          cppcheck's MISRA C:2012 addon over firmware/ and the MCU
#                  part of hal/ (MISRA_SRC), through scripts/misra_check.py:
#                  fails on any finding not covered by a deviation in
#                  misra/deviations.txt, and on a deviation that covers
#                  nothing; prints the counts. Then tests/misra/planted_test.sh
#                  shows that the same check fails on planted violations.
#   coverage       line and branch coverage of firmware/ by the host tests
#                  (COV_TESTS), built with --coverage in $(COV_OUT), measured
#                  with gcovr; fails below COV_LINE_MIN or COV_BRANCH_MIN
#                  (percent). Report: $(COV_OUT)/coverage.txt.
#   stack-check    worst-case stack of the Cortex-M4 product images
#                  (scripts/stack_check.py): a build of the images' sources
#                  with -fstack-usage -fcallgraph-info=su in $(STACK_OUT),
#                  the worst path from the reset vector and from each
#                  exception handler, against the linker script's stack
#                  (__stack_size, 4 KiB); fails when it does not fit or when
#                  the call graph has a cycle or an indirect call with no
#                  target listed in scripts/stack_indirect.txt
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
             hal/hal_ecu_loop.c hal/hal_can_mem.c
MISRA_CHECK := python3 scripts/misra_check.py --deviations misra/deviations.txt

misra: $(HARDEN_STAMP)
	@mkdir -p $(MISRA_OUT)
	$(MISRA_CHECK) --build-dir $(MISRA_OUT)/cache -I. -Ifirmware $(MISRA_SRC)
	@sh tests/misra/planted_test.sh $(MISRA_CHECK)

test-hardening: misra
