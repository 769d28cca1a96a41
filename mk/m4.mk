# Cortex-M4 target build on QEMU's MPS2 AN386 board (hal/mps2/).
#
# Include from the top-level Makefile (make runs in the repository root):
#
#   include mk/m4.mk
#   $(call m4_image,fuel_bench,firmware/model.c sim_host/bench_main.c)
#   $(call m4_test,test_model,firmware/model.c tests/test_model.c)
#
# or try it alone:  make -f mk/m4.mk test-m4-selftest
#
# Functions (call them at the top level of a makefile, not in a recipe):
#
#   $(call m4_image,NAME,SOURCES)
#       Product image $(M4_OUT)/NAME.elf and its map file NAME.map: SOURCES
#       (C files, relative to the repository root) compiled with M4_CFLAGS,
#       plus the HAL objects (startup, semihosting output, instruction
#       counter), linked with M4_LDFLAGS_IMAGE. The link fails, and removes
#       the ELF, when scripts/check_image.sh finds malloc & co or floating
#       point in it. Appends the ELF to M4_IMAGES.
#
#   $(call m4_test,NAME,SOURCES)
#       CMocka test image $(M4_OUT)/NAME.elf: SOURCES compiled with
#       M4_CFLAGS_TEST (adds CMocka's include folder), plus cmocka.o and the
#       test HAL objects, linked with M4_LDFLAGS_TEST. Appends the ELF to
#       M4_TESTS.
#
# Sources are compiled once per flavour, into $(M4_OUT)/obj/image/<path>.o
# and $(M4_OUT)/obj/test/<path>.o, whatever image they go into.
#
# Running: $(M4_RUN) ELF runs an ELF on QEMU and returns its exit code (the
# program's console and stdout on stdout, its stderr on stderr);
# making $(M4_OUT)/NAME.pass runs NAME.elf and records success, so that
#   m4-test: $(M4_TESTS:.elf=.pass)
# reruns only tests whose ELF changed.
#
# Run make in the repository root: sources and objects are named relative to
# it ($(M4_OUT)/obj/<flavour>/<source path>.o).
#
# newlib here is built without C99 printf conversions: in target tests print
# size_t with %u or %lu and a cast, not %zu (%lld and %llx do work).
#
# Variables (set before the include to override those marked ?=):
#   BUILD              build folder                              (build)
#   M4_OUT             target outputs                   ($(BUILD)/m4)
#   M4_CROSS           toolchain prefix                (arm-none-eabi-)
#   M4_CC, M4_NM, M4_SIZE, M4_OBJDUMP                 toolchain programs
#   M4_ARCH_FLAGS      -mcpu=cortex-m4 -mthumb -mfloat-abi=soft: the firmware
#                      uses no floating point, so no FPU code and no FPU
#                      register ABI
#   M4_WARN_FLAGS      warnings, all errors
#   M4_CFLAGS          flags for product sources; append with +=
#   M4_CFLAGS_TEST     flags for test sources: M4_CFLAGS + CMocka includes
#   M4_LDFLAGS_IMAGE   product link: no startup files (hal/mps2/startup.c
#                      instead), linker/mps2_an386.ld (no heap), --gc-sections,
#                      map file, only libc (for memcpy/memset) and libgcc; a
#                      call to printf or malloc fails at link time because
#                      nothing provides _sbrk or _write
#                      Budgets: append -Wl,--defsym=__stack_size=N (default
#                      4 KiB), __ram_size (32 KiB), __flash_size (256 KiB)
#   M4_LDFLAGS_TEST    test link: linker/mps2_an386_test.ld (1 MiB heap, 64 KiB
#                      stack), full newlib (not nano: CMocka prints 64-bit
#                      values with %llx, which newlib-nano's printf lacks)
#                      and librdimon, whose stdio and exit go through
#                      semihosting
#   M4_HAL_IMAGE_SRCS  HAL sources linked into every product image
#   M4_HAL_TEST_SRCS   HAL sources linked into every test image
#   M4_CMOCKA_C, M4_CMOCKA_INC  CMocka's Debian source (scripts/cmocka_src.sh)
#   M4_CMOCKA_OBJ      $(M4_OUT)/cmocka.o
#   M4_RUN             scripts/run_m4.sh; M4_TIMEOUT_S (environment) sets
#                      its time limit, 120 s by default
#   M4_CHECK           scripts/check_image.sh
#   M4_IMAGES, M4_TESTS  every ELF declared so far with m4_image / m4_test
#
# Targets: m4-deps (install packages), test-m4-selftest (build and run the demos
# in tests/m4/ and check their exit codes), m4-clean.

M4_ROOT := $(patsubst %/,%,$(dir $(patsubst %/,%,$(dir $(lastword $(MAKEFILE_LIST))))))

# Including this file must not change the includer's default goal.
m4__saved_goal := $(.DEFAULT_GOAL)
m4__standalone := $(if $(filter 1,$(words $(MAKEFILE_LIST))),yes)

BUILD ?= build
M4_OUT ?= $(BUILD)/m4

M4_CROSS ?= arm-none-eabi-
M4_CC ?= $(M4_CROSS)gcc
M4_NM ?= $(M4_CROSS)nm
M4_SIZE ?= $(M4_CROSS)size
M4_OBJDUMP ?= $(M4_CROSS)objdump

M4_ARCH_FLAGS := -mcpu=cortex-m4 -mthumb -mfloat-abi=soft
M4_WARN_FLAGS := -Wall -Wextra -Werror -Wconversion -Wsign-conversion \
    -Wdouble-promotion
M4_CFLAGS := $(M4_ARCH_FLAGS) -std=c11 -Os -g -ffunction-sections \
    -fdata-sections $(M4_WARN_FLAGS) -I$(M4_ROOT) -MMD -MP

M4_CMOCKA_SRC_DIR := $(M4_OUT)/cmocka-src
M4_CMOCKA_C := $(M4_CMOCKA_SRC_DIR)/cmocka/src/cmocka.c
M4_CMOCKA_INC := $(M4_CMOCKA_SRC_DIR)/cmocka/include
M4_CMOCKA_OBJ := $(M4_OUT)/cmocka.o

M4_CFLAGS_TEST = $(M4_CFLAGS) -I$(M4_CMOCKA_INC)

M4_LINKER_DIR := $(M4_ROOT)/linker
M4_LDSCRIPT_IMAGE := $(M4_LINKER_DIR)/mps2_an386.ld
M4_LDSCRIPT_TEST := $(M4_LINKER_DIR)/mps2_an386_test.ld
M4_LDSCRIPTS := $(M4_LDSCRIPT_IMAGE) $(M4_LDSCRIPT_TEST) \
    $(M4_LINKER_DIR)/mps2_an386_sections.ld

# Recursive (=): $@ is the ELF being linked.
M4_LDFLAGS_IMAGE = $(M4_ARCH_FLAGS) -nostartfiles -nostdlib \
    -L$(M4_LINKER_DIR) -T$(M4_LDSCRIPT_IMAGE) -Wl,--gc-sections \
    -Wl,-Map=$(@:.elf=.map) -Wl,--start-group -lc -lgcc -Wl,--end-group
M4_LDFLAGS_TEST = $(M4_ARCH_FLAGS) -nostartfiles --specs=rdimon.specs \
    -L$(M4_LINKER_DIR) -T$(M4_LDSCRIPT_TEST) -Wl,--gc-sections \
    -Wl,-Map=$(@:.elf=.map)

M4_HAL_IMAGE_SRCS := $(M4_ROOT)/hal/mps2/startup.c \
    $(M4_ROOT)/hal/mps2/semihost.c $(M4_ROOT)/hal/mps2/icount.c
M4_HAL_TEST_SRCS := $(M4_HAL_IMAGE_SRCS) $(M4_ROOT)/hal/mps2/newlib_glue.c

M4_RUN := $(M4_ROOT)/scripts/run_m4.sh
M4_CHECK := $(M4_ROOT)/scripts/check_image.sh

M4_IMAGES :=
M4_TESTS :=

m4__norm = $(patsubst ./%,%,$(1))
m4__objs = $(patsubst %.c,$(M4_OUT)/obj/$(1)/%.o,$(call m4__norm,$(2)))

define m4__image_rule
$(M4_OUT)/$(1).elf: $(call m4__objs,image,$(2) $(M4_HAL_IMAGE_SRCS)) $(M4_LDSCRIPTS)
	$$(M4_CC) $$(filter %.o,$$^) $$(M4_LDFLAGS_IMAGE) -o $$@
	M4_NM=$$(M4_NM) M4_SIZE=$$(M4_SIZE) $$(M4_CHECK) $$@ || { rm -f $$@; exit 1; }
M4_IMAGES += $(M4_OUT)/$(1).elf
-include $(patsubst %.o,%.d,$(call m4__objs,image,$(2) $(M4_HAL_IMAGE_SRCS)))
endef

define m4__test_rule
$(M4_OUT)/$(1).elf: $(call m4__objs,test,$(2) $(M4_HAL_TEST_SRCS)) $(M4_CMOCKA_OBJ) $(M4_LDSCRIPTS)
	$$(M4_CC) $$(filter %.o,$$^) $$(M4_LDFLAGS_TEST) -o $$@
M4_TESTS += $(M4_OUT)/$(1).elf
-include $(patsubst %.o,%.d,$(call m4__objs,test,$(2) $(M4_HAL_TEST_SRCS)))
endef

m4_image = $(eval $(call m4__image_rule,$(strip $(1)),$(strip $(2))))
m4_test = $(eval $(call m4__test_rule,$(strip $(1)),$(strip $(2))))

$(M4_OUT)/obj/image/%.o: %.c | $(FW_GEN_HDR)
	@mkdir -p $(@D)
	$(M4_CC) $(M4_CFLAGS) -c $< -o $@

# Test sources include cmocka.h: fetch CMocka first.
$(M4_OUT)/obj/test/%.o: %.c | $(M4_CMOCKA_C) $(FW_GEN_HDR)
	@mkdir -p $(@D)
	$(M4_CC) $(M4_CFLAGS_TEST) -c $< -o $@

$(M4_CMOCKA_C):
	$(M4_ROOT)/scripts/cmocka_src.sh $(M4_CMOCKA_SRC_DIR)

# Third-party code: built as Debian ships it, with our config.h and without
# our warning flags.
$(M4_CMOCKA_OBJ): $(M4_CMOCKA_C) $(M4_ROOT)/tests/m4/config.h
	@mkdir -p $(@D)
	$(M4_CC) $(M4_ARCH_FLAGS) -std=gnu99 -Os -g -ffunction-sections \
	    -fdata-sections -w -DHAVE_CONFIG_H -I$(M4_ROOT)/tests/m4 \
	    -I$(M4_CMOCKA_INC) -c $< -o $@

$(M4_OUT)/%.pass: $(M4_OUT)/%.elf
	$(M4_RUN) $<
	@touch $@

.PHONY: m4-help m4-deps test-m4-selftest m4-clean

## the Cortex-M4 rules' own targets (mk/m4.mk)
m4-help:
	@echo "mk/m4.mk: Cortex-M4 (QEMU mps2-an386) build; see its header."
	@echo "  test-m4-selftest  build and run the demos in tests/m4/, check exit codes"
	@echo "  m4-deps      install the Debian packages (scripts/deps.sh)"
	@echo "  m4-clean     remove $(M4_OUT)"

## install the Cortex-M4 toolchain and QEMU
m4-deps:
	@$(M4_ROOT)/scripts/deps.sh

## remove the Cortex-M4 outputs
m4-clean:
	rm -rf $(M4_OUT)

# Demonstration and self-check of this backend (tests/m4/).
$(call m4_image,m4_demo_image,$(M4_ROOT)/tests/m4/demo_image.c)
$(call m4_image,m4_demo_fault,$(M4_ROOT)/tests/m4/demo_fault.c)
$(call m4_test,m4_demo_test_pass,$(M4_ROOT)/tests/m4/test_demo_pass.c)
$(call m4_test,m4_demo_test_fail,$(M4_ROOT)/tests/m4/test_demo_fail.c)

M4_DEMOS := $(M4_OUT)/m4_demo_image.elf $(M4_OUT)/m4_demo_fault.elf \
    $(M4_OUT)/m4_demo_test_pass.elf $(M4_OUT)/m4_demo_test_fail.elf

M4_EXPECT := $(M4_ROOT)/scripts/expect_exit.sh

# Each run states the exit code and output lines it expects; anything else
# fails the target.
## the Cortex-M4 backend's demos (tests/m4/): exit codes and output as expected
test-m4-selftest: m4-deps
	@$(MAKE) --no-print-directory -f $(M4_ROOT)/mk/m4.mk BUILD=$(BUILD) M4_OUT=$(M4_OUT) $(M4_DEMOS)
	@$(M4_EXPECT) 0 $(M4_OUT)/m4_demo_image.out \
	    -l 'fmt: 0 4294967295 -2147483648 -7 18446744073709551615 -9223372036854775808 1234567890123 0x0000abcd 0x0123456789abcdef' \
	    -l 'm4 demo: ok' -- $(M4_RUN) $(M4_OUT)/m4_demo_image.elf
	@$(M4_EXPECT) 131 $(M4_OUT)/m4_demo_fault.out \
	    -- $(M4_RUN) $(M4_OUT)/m4_demo_fault.elf
	@$(M4_EXPECT) 0 $(M4_OUT)/m4_demo_test_pass.out \
	    -l '[  PASSED  ] 4 test(s).' -- $(M4_RUN) $(M4_OUT)/m4_demo_test_pass.elf
	@$(M4_EXPECT) 2 $(M4_OUT)/m4_demo_test_fail.out -q \
	    -l '[  FAILED  ] 2 test(s), listed below:' \
	    -- $(M4_RUN) $(M4_OUT)/m4_demo_test_fail.elf
	@$(M4_CHECK) --bench m4_demo_image $(M4_OUT)/m4_demo_image.elf
	@echo "test-m4-selftest: all passed"

.DEFAULT_GOAL := $(if $(m4__standalone),m4-help,$(m4__saved_goal))
