# STM32F405 target (hal/stm32f4/): the product image, its QEMU twin, and
# the host tests of its drivers against register models (tests/stm32/).
#
# Included from the top-level Makefile after mk/m4.mk and the Cortex-M4
# flags (uses M4_CC, M4_CFLAGS, M4_ARCH_FLAGS, M4_OUT, m4__objs, M4_CHECK,
# FW_SRC, ECU_LOOP_SRC, HOST_CC, SAN_CFLAGS, HAL_HDR, DEPS_STAMP, and the
# Makefile's rule for $(BUILD)/gen/road_hilly.c).
#
#   make stm32            build/stm32/pfe_stm32.elf, .bin, .hex (and its size)
#   make test-stm32-host  bxCAN and flash drivers on their register models,
#                         the HAL conformance suite on bxCAN, the time base
#   make test-stm32-qemu  the image's bring-up and self-check on QEMU's
#                         netduinoplus2: the digest equals the host's
#   make test-stm32-bench-guide  the bench guide's commands that run here
#   make test-stm32       all three
#
# Sources are compiled once, as the mps2 images' are ($(M4_OUT)/obj/image/),
# so the firmware objects are the same in both targets.

STM32_OUT := $(BUILD)/stm32
STM32_LDSCRIPT := linker/stm32f405.ld
STM32_HAL_SRC := hal/stm32f4/startup.c hal/stm32f4/hal_stm32_board.c \
    hal/stm32f4/hal_stm32_time.c
STM32_ECU_SRC := $(FW_SRC) $(ECU_LOOP_SRC) hal/hal_can_mem.c $(STM32_HAL_SRC) hal/stm32f4/hal_stm32_tick.c \
    hal/stm32f4/hal_stm32_can.c hal/stm32f4/hal_stm32_nvm.c hal/stm32f4/hal_stm32_ecu.c \
    hal/stm32f4/main_ecu.c
# The bench: the mps2 ECU replay (hal/mps2/main_ecu.c, hal/replay) on this
# board, TIM2 counting instructions under QEMU (hal/stm32f4/icount_tim2.c).
STM32_BENCH_SRC := $(FW_SRC) $(ECU_LOOP_SRC) hal/hal_can_mem.c hal/replay/hal_replay.c hal/hal_can_mem_api.c \
    hal/replay/hal_replay_ecu.c hal/stm32f4/startup.c hal/stm32f4/hal_stm32_board.c \
    hal/stm32f4/hal_stm32_time.c hal/stm32f4/icount_tim2.c hal/stm32f4/main_bench_glue.c \
    hal/mps2/main_ecu.c hal/mps2/calib_default.c hal/mps2/semihost.c
STM32_QEMU_SRC := $(FW_SRC) $(STM32_HAL_SRC) hal/stm32f4/hal_stm32_tick.c hal/stm32f4/main_qemu.c \
    hal/mps2/main_selfcheck.c hal/mps2/semihost.c $(BUILD)/gen/road_hilly.c

# The product's sources for MISRA (mk/hardening.mk); the QEMU-only glue
# (main_qemu.c, main_bench_glue.c, icount_tim2.c) is not product code.
STM32_MISRA_SRC := $(filter hal/stm32f4/%,$(STM32_ECU_SRC))

# Recursive: $@ is the ELF being linked.
STM32_LDFLAGS = $(M4_ARCH_FLAGS) -O2 -flto -nostartfiles -nostdlib -Llinker -T$(STM32_LDSCRIPT) \
    -Wl,--gc-sections -Wl,-Map=$(@:.elf=.map) -Wl,--start-group -lc -lgcc -Wl,--end-group

.PHONY: stm32 test-stm32 test-stm32-host test-stm32-qemu test-stm32-bench-guide

# $(call stm32_image,NAME,SOURCES,LDFLAGS): $(STM32_OUT)/NAME.elf from the
# Cortex-M4 objects of SOURCES (compiled once, $(M4_OUT)/obj/image/), linked
# for the STM32F405 (and LDFLAGS), refused by scripts/check_image.sh if it
# links the heap or floating point. Its objects' dependency files are read,
# so that a changed header rebuilds them (main_ecu.o is in no M4 image).
define stm32__image
$(STM32_OUT)/$(1).elf: $(call m4__objs,image,$(2)) $(STM32_LDSCRIPT)
	@mkdir -p $$(@D)
	$$(M4_CC) $$(filter %.o,$$^) $$(STM32_LDFLAGS) $(3) -o $$@
	$$(M4_CHECK) $$@ || { rm -f $$@; exit 1; }
-include $(patsubst %.o,%.d,$(call m4__objs,image,$(2)))
endef
stm32_image = $(eval $(call stm32__image,$(1),$(2),$(3)))

# The self-check's road does not fit the product's 48 KiB: QEMU's flash is 1 MiB.
STM32_QEMU_LDFLAGS := -Wl,--defsym=__flash_size=512K
STM32_BENCH_LDFLAGS := -Wl,--defsym=__flash_size=512K -Wl,--defsym=__ram_size=128K
$(call stm32_image,pfe_stm32,$(STM32_ECU_SRC))
$(call stm32_image,pfe_stm32_qemu,$(STM32_QEMU_SRC),$(STM32_QEMU_LDFLAGS))
$(call stm32_image,pfe_stm32_bench,$(STM32_BENCH_SRC),$(STM32_BENCH_LDFLAGS))

# The image for a programmer: .hex (and the ELF) program only the sectors
# they cover; the .bin spans the NVM sectors (filled 0xFF), so writing it
# erases the saved fuel totals (docs/stm32_bench.md).
# An empty .data keeps its RAM address as load address (ld does not move
# an empty section): left out, or the .bin would reach up to 0x20000000.
$(STM32_OUT)/%.bin: $(STM32_OUT)/%.elf
	$(M4_CROSS)objcopy -O binary --gap-fill 0xFF \
	    $$($(M4_SIZE) -A $< | awk '$$1 == ".data" && $$2 == 0 { print "-R .data" }') $< $@
$(STM32_OUT)/%.hex: $(STM32_OUT)/%.elf
	$(M4_CROSS)objcopy -O ihex $< $@

## the STM32F405 image: build/stm32/pfe_stm32.elf, .bin, .hex
stm32: $(DEPS_STAMP) $(STM32_OUT)/pfe_stm32.elf $(STM32_OUT)/pfe_stm32.bin $(STM32_OUT)/pfe_stm32.hex
	@$(M4_SIZE) $(STM32_OUT)/pfe_stm32.elf

# Image checks (make test-image): no heap, no floating-point helpers
# (scripts/check_image.sh), and no FPU instruction at all: the FPU stays off,
# so one would fault.
.PHONY: test-stm32-image
## the STM32 images: no heap, no floating point, no FPU instruction
test-stm32-image: $(STM32_OUT)/pfe_stm32.elf $(STM32_OUT)/pfe_stm32_qemu.elf $(STM32_OUT)/pfe_stm32_bench.elf
	@set -e; for e in $^; do $(M4_CHECK) $$e; \
	    if $(M4_OBJDUMP) -d $$e | grep -Eq '\s(v[a-z0-9]+(\.[a-z0-9]+)*)\s+(s[0-9]|d[0-9]|\{[sd])'; then \
	        echo "test-stm32-image: $$e has FPU instructions"; exit 1; fi; \
	    echo "test-stm32-image: $$e: no heap, no floating point, no FPU instruction"; done

# ---------------------------------------------------------------- host tests (register models)

STM32_SAN_CFLAGS := $(SAN_CFLAGS) -DHAL_STM32_REG_MODEL -I. -Ifirmware
STM32_MODEL_SRC := tests/stm32/bxcan_model.c tests/stm32/flash_model.c tests/stm32/reg_model.c \
    hal/stm32f4/hal_stm32_can.c hal/hal_can_mem.c
STM32_MODEL_HDR := $(wildcard tests/stm32/*.h)

# $(call stm32_model_test,NAME,SOURCES,FLAGS): $(HOSTSAN)/NAME from
# tests/stm32/NAME.c, SOURCES and the register models, every file compiled
# with the models in place of the registers (and FLAGS).
define stm32__model_test
$(HOSTSAN)/$(1): tests/stm32/$(1).c $(2) $(STM32_MODEL_SRC) $(STM32_MODEL_HDR) $(HAL_HDR) $(FW_HDR) | $(DEPS_STAMP)
	@mkdir -p $$(@D)
	$$(HOST_CC) $$(STM32_SAN_CFLAGS) $(3) -o $$@ $$(sort $$(filter %.c,$$^)) -lcmocka
endef
stm32_model_test = $(eval $(call stm32__model_test,$(1),$(2),$(3)))

$(call stm32_model_test,test_stm32_can,$(ECU_LOOP_SRC) $(FW_SRC))
$(call stm32_model_test,test_hal_stm32,tests/hal/hal_conformance.c hal/stm32f4/hal_stm32_time.c \
    hal/stm32f4/hal_stm32_tick.c $(FW_SRC),-DSTM32_MODEL_OWN_CLOCK)
$(call stm32_model_test,test_stm32_nvm,hal/stm32f4/hal_stm32_nvm.c $(FW_SRC))
$(call stm32_model_test,test_stm32_board,hal/stm32f4/hal_stm32_time.c hal/stm32f4/hal_stm32_tick.c \
    hal/stm32f4/hal_stm32_board.c,-DSTM32_MODEL_OWN_CLOCK)
$(call stm32_model_test,test_stm32_ecu,hal/stm32f4/hal_stm32_ecu.c hal/stm32f4/hal_stm32_nvm.c \
    $(ECU_LOOP_SRC) $(FW_SRC))

STM32_HOST_TESTS := test_stm32_can test_hal_stm32 test_stm32_nvm test_stm32_board test_stm32_ecu

## the STM32 drivers on register models, the HAL conformance suite on bxCAN, the time base
test-stm32-host: $(addprefix $(HOSTSAN)/,$(STM32_HOST_TESTS))
	@set -e; for t in $(STM32_HOST_TESTS); do echo "== host: $$t (register models)"; $(HOSTSAN)/$$t; done

# ---------------------------------------------------------------- QEMU netduinoplus2

STM32_QEMU := scripts/run_stm32_qemu.sh

## the STM32 image's bring-up and self-check on QEMU's netduinoplus2
test-stm32-qemu: $(STM32_OUT)/pfe_stm32_qemu.elf $(HOST)/selfcheck $(M4_OUT)/pfe_mps2.elf
	$(HOST)/selfcheck $(ROADS)/hilly.csv > $(STM32_OUT)/selfcheck_host.txt
	$(M4_RUN) $(M4_OUT)/pfe_mps2.elf > $(STM32_OUT)/selfcheck_mps2.txt
	$(STM32_QEMU) $(STM32_OUT)/pfe_stm32_qemu.elf $(STM32_OUT)/uart.txt > $(STM32_OUT)/selfcheck_stm32.txt
	@cat $(STM32_OUT)/uart.txt
	@grep -q '^stm32: clock hse [01] pll [01] reset_cause [0-3]$$' $(STM32_OUT)/uart.txt
	@grep -q '^stm32: ticks_10ms 10 ticks_us 1000[0-9][0-9]$$' $(STM32_OUT)/uart.txt
	@grep -q '^stm32: selfcheck_us [0-9]* timer_ok 1 stack_used [0-9]*$$' $(STM32_OUT)/uart.txt
	@grep -q digest $(STM32_OUT)/selfcheck_host.txt
	@if cmp -s $(STM32_OUT)/selfcheck_host.txt $(STM32_OUT)/selfcheck_stm32.txt && \
	    cmp -s $(STM32_OUT)/selfcheck_host.txt $(STM32_OUT)/selfcheck_mps2.txt; then \
	    echo "selfcheck: host, mps2-an386 and STM32F405 (netduinoplus2) outputs identical:"; \
	    grep digest $(STM32_OUT)/selfcheck_host.txt; \
	else echo "selfcheck: host, mps2 and STM32F405 outputs differ:"; \
	    diff $(STM32_OUT)/selfcheck_host.txt $(STM32_OUT)/selfcheck_stm32.txt; \
	    diff $(STM32_OUT)/selfcheck_host.txt $(STM32_OUT)/selfcheck_mps2.txt; exit 1; fi

# openocd and st-flash (stlink-tools) for the bench guide's commands.
STM32_DEPS_STAMP := $(BUILD)/.deps-stm32
$(STM32_DEPS_STAMP): scripts/deps.sh
	@mkdir -p $(@D)
	sh scripts/deps.sh $(STM32_BENCH_PACKAGES)
	@touch $@
STM32_BENCH_PACKAGES := openocd stlink-tools

## the STM32 bench guide's commands that run here
test-stm32-bench-guide: $(STM32_DEPS_STAMP) $(STM32_OUT)/pfe_stm32.elf $(STM32_OUT)/pfe_stm32.hex \
        $(STM32_OUT)/pfe_stm32.bin $(HOST)/pfe_replay $(HOST)/pfe_record $(HOST)/run_report \
        $(BUILD)/e2e/payload/drive.log
	sh tests/stm32/bench_guide.sh $(STM32_OUT) $(HOST) $(BUILD)/e2e/payload/drive.log

## test-stm32-host, test-stm32-qemu and test-stm32-bench-guide
test-stm32: test-stm32-host test-stm32-qemu test-stm32-bench-guide

# ---------------------------------------------------------------- bench (make bench)

# Sizes of the product image (flash = text + data, RAM = data + bss with
# the stack, as scripts/check_image.sh counts them; heap: the size of any
# heap section, none), and the ECU's tick over the replayed drive on
# netduinoplus2, in instructions (TIM2 under -icount: exact).
.PHONY: stm32-bench
## bench: the STM32 image's sizes and its ECU tick on netduinoplus2
stm32-bench: $(STM32_OUT)/pfe_stm32.elf $(STM32_OUT)/pfe_stm32_bench.elf $(BUILD)/e2e/payload/drive.log \
        $(M4_OUT)/pfe_ecu_mps2.elf
	@$(M4_CHECK) --bench pfe_stm32 $(STM32_OUT)/pfe_stm32.elf
	@echo "bench: pfe_stm32_heap $$($(M4_SIZE) -A $(STM32_OUT)/pfe_stm32.elf | \
	    awk '/heap/ { n += $$2 } END { print n + 0 }') bytes"
	@# The mps2 ECU image's heap, next to its flash and RAM lines (Makefile).
	@echo "bench: pfe_ecu_mps2_heap $$($(M4_SIZE) -A $(M4_OUT)/pfe_ecu_mps2.elf | \
	    awk '/heap/ { n += $$2 } END { print n + 0 }') bytes"
	@$(STM32_QEMU) $(STM32_OUT)/pfe_stm32_bench.elf /dev/null --log $(BUILD)/e2e/payload/drive.log | \
	    awk '/^m4:/ { print "bench: stm32_ecu_drive_tick_mean " $$5 " insn"; \
	    print "bench: stm32_ecu_drive_tick_max " $$7 " insn"; ok = 1 } END { exit !ok }'

# ---------------------------------------------------------------- worst-case stack (make stack-check)

# The product image linked again with -fstack-usage -fcallgraph-info=su
# (as mk/hardening.mk does for the mps2 images: the same bytes, or the
# analysis is of something else), then scripts/stack_check.py: the deepest
# thread path plus each exception level (the CAN and TIM2 interrupts all at
# reset priority, so they cannot preempt each other), against __stack_size.
STM32_STACK_OUT := $(BUILD)/stack/pfe_stm32
.PHONY: stm32-stack-check
$(STM32_STACK_OUT)/pfe_stm32.elf: $(STM32_OUT)/pfe_stm32.elf scripts/stack_check.py scripts/stack_indirect.txt
	@rm -rf $(@D)
	@mkdir -p $(@D)
	$(M4_CC) $(call m4__objs,image,$(STM32_ECU_SRC)) $(STM32_LDFLAGS) \
	    -fstack-usage -fcallgraph-info=su -dumpdir $(@D)/pfe_stm32. -o $@
	@$(M4_CROSS)objcopy -O binary $@ $(@D)/analysed.bin
	@$(M4_CROSS)objcopy -O binary $(STM32_OUT)/pfe_stm32.elf $(@D)/product.bin
	@cmp -s $(@D)/analysed.bin $(@D)/product.bin || { echo "stack-check: the analysis link of" \
	    "pfe_stm32 differs from $(STM32_OUT)/pfe_stm32.elf"; exit 1; }

## worst-case stack of the STM32 image
stm32-stack-check: $(STM32_STACK_OUT)/pfe_stm32.elf
	$(STACK_CHECK) --elf $(STM32_OUT)/pfe_stm32.elf --ci $(STM32_STACK_OUT)/*.ci --su $(STM32_STACK_OUT)/*.su
