# Virtual CAN: the SocketCAN backend (hal/socketcan/) tested on vcan0.
#
# Include from the top-level Makefile (make runs in the repository root),
# after mk/m4.mk so that both use one download of CMocka's source:
#
#   include mk/m4.mk
#   include mk/vcan.mk
#   test: test-vcan
#
# or try it alone:  make -f mk/vcan.mk test-vcan
#
# This machine's kernel has no CAN at all, so `test-vcan` runs everything
# through scripts/vcan_vm.sh: natively where this machine can have a vcan0,
# else in one boot of Debian's kernel under QEMU (TCG, about 10 s). One boot
# runs every check, through a driver script (tests/e2e/vcan_checks.sh):
#   test_guard           the real-bus guard: lo refused, vcan0 allowed, an
#                        slcan interface on a pseudo-terminal refused
#   test_hal_socketcan   the conformance suite (tests/hal/hal_conformance.h)
#                        and the backend's own tests, on vcan0
#   the same two again, built with ASan + UBSan
#   can-utils            cansend -> candump with a J1939 PGN filter,
#                        canplayer -> candump, cangen -> candump
# The VM gets one folder, $(VCAN_PAYLOAD): the tests linked with
# `gcc -static` (CMocka compiled from Debian's source, as for the Cortex-M4),
# the ASan + UBSan builds in san/ with the shared libraries they need in
# san/lib/, and the driver.
#
# Targets:
#   test-vcan         build, run all of the above, print the VM's run time
#   test-vcan-native  the ASan + UBSan builds, run right here: test_guard
#                     (vcan and slcan tests skipped on a kernel without CAN),
#                     test_hal_socketcan (exit 77, skipped, without vcan0)
#   vcan-build        build both flavours, run nothing
#   vcan-deps         install the Debian packages (scripts/deps.sh), the
#                     VM's too (vcan_vm.sh would install them on first use)
#   vcan-clean        remove $(VCAN_OUT)
#   vcan-vm-clean     remove the VM's cache (kernel, initramfs): $(VCAN_VM_DIR)
#
# Variables (set before the include to override those marked ?=):
#   BUILD              build folder                                 (build)
#   VCAN_OUT           outputs of this file                 ($(BUILD)/vcan)
#   VCAN_PAYLOAD       what the VM gets: static tests, driver
#                                                   ($(VCAN_OUT)/payload)
#   VCAN_CC            host compiler                                  (gcc)
#   VCAN_IF            interface the tests use                      (vcan0)
#   VCAN_TIMEOUT_S     limit of one vcan_vm.sh run, boot included     (300)
#   VCAN_VM_FLAGS      more vcan_vm.sh options, e.g. --vm to use QEMU even
#                      where vcan0 could be had natively
#   VCAN_VM_DIR        the VM's cache (kernel, base initramfs)
#                                                    ($(BUILD)/vcan-vm)
#   VCAN_VM            scripts/vcan_vm.sh
#   VCAN_WARN_FLAGS    warnings, all errors (the top Makefile's set)
#   VCAN_CFLAGS        flags for our sources, both flavours
#   VCAN_SAN_FLAGS     sanitizers of the native flavour
#   VCAN_HAL_SRCS      the backend's sources
#   VCAN_SUITE_SRCS    the conformance suite, for other backends' tests
#   VCAN_CMOCKA_SRC_DIR  CMocka's Debian source ($(M4_CMOCKA_SRC_DIR) when
#                      mk/m4.mk is included first)

VCAN_ROOT := $(patsubst %/,%,$(dir $(patsubst %/,%,$(dir $(lastword $(MAKEFILE_LIST))))))

# Including this file must not change the includer's default goal.
vcan__saved_goal := $(.DEFAULT_GOAL)
vcan__standalone := $(if $(filter 1,$(words $(MAKEFILE_LIST))),yes)

BUILD ?= build
VCAN_OUT ?= $(BUILD)/vcan
VCAN_PAYLOAD ?= $(VCAN_OUT)/payload
VCAN_CC ?= gcc
VCAN_IF ?= vcan0
VCAN_TIMEOUT_S ?= 900
VCAN_VM_FLAGS ?=
VCAN_VM_DIR ?= $(BUILD)/vcan-vm
VCAN_VM := $(VCAN_ROOT)/scripts/vcan_vm.sh

VCAN_WARN_FLAGS := -std=c11 -Wall -Wextra -Werror -Wconversion -Wsign-conversion \
    -Wshadow -Wdouble-promotion -Wstrict-prototypes -Wundef -Wcast-qual -Wpointer-arith
VCAN_SAN_FLAGS := -fsanitize=address,undefined -fno-sanitize-recover=all \
    -fno-omit-frame-pointer

VCAN_HAL_SRCS := $(VCAN_ROOT)/hal/socketcan/hal_socketcan.c $(VCAN_ROOT)/hal/posix/hal_time_posix.c
VCAN_HAL_HDRS := $(VCAN_ROOT)/hal/socketcan/hal_socketcan.h $(VCAN_ROOT)/hal/hal_can.h \
    $(VCAN_ROOT)/hal/hal_time.h $(VCAN_ROOT)/hal/posix/hal_time_posix.h \
    $(VCAN_ROOT)/firmware/pfe_can.h
VCAN_SUITE_SRCS := $(VCAN_ROOT)/tests/hal/hal_conformance.c
VCAN_SUITE_HDRS := $(VCAN_ROOT)/tests/hal/hal_conformance.h

# One download of CMocka's source for the Cortex-M4 and for us.
ifdef M4_CMOCKA_C
VCAN_CMOCKA_SRC_DIR ?= $(M4_CMOCKA_SRC_DIR)
vcan__cmocka_c := $(M4_CMOCKA_C)
else
VCAN_CMOCKA_SRC_DIR ?= $(BUILD)/m4/cmocka-src
vcan__cmocka_c := $(VCAN_CMOCKA_SRC_DIR)/cmocka/src/cmocka.c
$(vcan__cmocka_c):
	$(VCAN_ROOT)/scripts/cmocka_src.sh $(VCAN_CMOCKA_SRC_DIR)
endif
VCAN_CMOCKA_INC := $(VCAN_CMOCKA_SRC_DIR)/cmocka/include

VCAN_CFLAGS := $(VCAN_WARN_FLAGS) -g -I$(VCAN_ROOT)

VCAN_DRIVER := $(VCAN_PAYLOAD)/run_vcan_tests.sh
VCAN_STATIC_TESTS := $(VCAN_PAYLOAD)/test_hal_socketcan $(VCAN_PAYLOAD)/test_guard
VCAN_SAN_TESTS := $(VCAN_PAYLOAD)/san/test_hal_socketcan $(VCAN_PAYLOAD)/san/test_guard
VCAN_SAN_LIBS := $(VCAN_PAYLOAD)/san/lib/.copied
VCAN_DEPS_STAMP := $(VCAN_OUT)/.deps-ok

vcan__socketcan_srcs := $(VCAN_ROOT)/tests/hal/test_hal_socketcan.c $(VCAN_SUITE_SRCS) \
    $(VCAN_HAL_SRCS)
vcan__guard_srcs := $(VCAN_ROOT)/tests/hal/test_guard.c $(VCAN_HAL_SRCS)
vcan__hdrs := $(VCAN_HAL_HDRS) $(VCAN_SUITE_HDRS)

$(VCAN_DEPS_STAMP): $(VCAN_ROOT)/scripts/deps.sh
	@mkdir -p $(@D)
	sh $(VCAN_ROOT)/scripts/deps.sh
	@touch $@

# CMocka for static programs: Debian ships libcmocka only as a shared
# library. Third-party code: built as Debian ships it, without our warnings;
# the HAVE_* macros stand in for the config.h that CMocka's CMake generates.
$(VCAN_OUT)/cmocka.o: $(vcan__cmocka_c) | $(VCAN_DEPS_STAMP)
	@mkdir -p $(@D)
	$(VCAN_CC) -std=gnu99 -O2 -g -w -D_GNU_SOURCE -DHAVE_SIGNAL_H -DHAVE_INTTYPES_H \
	    -DHAVE_STRINGS_H -DHAVE_STRSIGNAL -DHAVE_STRUCT_TIMESPEC -DHAVE_CLOCK_REALTIME \
	    -DHAVE_SIGLONGJMP -I$(VCAN_CMOCKA_INC) -c $< -o $@

# Static: they run in the VM's initramfs, which has no C library.
$(VCAN_PAYLOAD)/test_hal_socketcan: $(vcan__socketcan_srcs) $(vcan__hdrs) $(VCAN_OUT)/cmocka.o
	@mkdir -p $(@D)
	$(VCAN_CC) $(VCAN_CFLAGS) -O2 -I$(VCAN_CMOCKA_INC) -static -o $@ \
	    $(vcan__socketcan_srcs) $(VCAN_OUT)/cmocka.o

$(VCAN_PAYLOAD)/test_guard: $(vcan__guard_srcs) $(vcan__hdrs) $(VCAN_OUT)/cmocka.o
	@mkdir -p $(@D)
	$(VCAN_CC) $(VCAN_CFLAGS) -O2 -I$(VCAN_CMOCKA_INC) -static -o $@ \
	    $(vcan__guard_srcs) $(VCAN_OUT)/cmocka.o

# ASan + UBSan flavour, with Debian's shared libcmocka: run natively, and in
# the VM too, which has no such libraries: they are copied next to the
# programs (san/lib/), found through the run path $ORIGIN/lib. DT_RPATH, not
# DT_RUNPATH (--disable-new-dtags): only DT_RPATH also serves the libraries'
# own dependencies (libasan needs libm).
vcan__san_link := -Wl,--disable-new-dtags '-Wl,-rpath,$$ORIGIN/lib' -lcmocka

$(VCAN_PAYLOAD)/san/test_hal_socketcan: $(vcan__socketcan_srcs) $(vcan__hdrs) | $(VCAN_DEPS_STAMP)
	@mkdir -p $(@D)
	$(VCAN_CC) $(VCAN_CFLAGS) -O1 $(VCAN_SAN_FLAGS) -o $@ $(vcan__socketcan_srcs) $(vcan__san_link)

$(VCAN_PAYLOAD)/san/test_guard: $(vcan__guard_srcs) $(vcan__hdrs) | $(VCAN_DEPS_STAMP)
	@mkdir -p $(@D)
	$(VCAN_CC) $(VCAN_CFLAGS) -O1 $(VCAN_SAN_FLAGS) -o $@ $(vcan__guard_srcs) $(vcan__san_link)

# Every library ldd resolves for them (about 16 MB, mostly libasan).
$(VCAN_SAN_LIBS): $(VCAN_SAN_TESTS)
	@rm -rf $(@D) && mkdir -p $(@D)
	@libs=$$(ldd $(VCAN_SAN_TESTS) | sed -n 's/.*=> \(\/[^ ]*\) .*/\1/p' | sort -u); \
	[ -n "$$libs" ] || { echo "vcan: ldd found no libraries for $(VCAN_SAN_TESTS)"; exit 1; }; \
	cp -L $$libs $(@D)/ && echo "copied to $(@D):" $$libs
	@touch $@

# The driver that one VM boot runs (tests/e2e/vcan_checks.sh): every check,
# whatever fails before it; "vcan: NAME ok" or "vcan: NAME FAILED (exit N)"
# for each, and the number of failed checks as its exit status.
$(VCAN_DRIVER): $(VCAN_ROOT)/tests/e2e/vcan_checks.sh | $(VCAN_PAYLOAD)
	cp $< $@
	@chmod 0755 $@

$(VCAN_PAYLOAD):
	mkdir -p $@

.PHONY: vcan-help vcan-deps vcan-build test-vcan test-vcan-native vcan-clean vcan-vm-clean

## the vcan rules' own targets (mk/vcan.mk)
vcan-help:
	@echo "mk/vcan.mk: the SocketCAN backend on vcan0; see its header."
	@echo "  test-vcan         static tests + can-utils checks in one run of scripts/vcan_vm.sh"
	@echo "  test-vcan-native  ASan/UBSan builds on this machine (skips what needs vcan0)"
	@echo "  vcan-build        build both flavours"
	@echo "  vcan-deps         install the Debian packages"
	@echo "  vcan-clean        remove $(VCAN_OUT)"
	@echo "  vcan-vm-clean     remove the VM's cache $(VCAN_VM_DIR)"

## install the packages of the vcan tests and of the VM
vcan-deps:
	@$(VCAN_ROOT)/scripts/deps.sh qemu-system-x86 busybox-static cpio can-utils binutils

## build the vcan tests, both flavours, run nothing
vcan-build: $(VCAN_STATIC_TESTS) $(VCAN_DRIVER) $(VCAN_SAN_TESTS) $(VCAN_SAN_LIBS)

# The time printed is the whole vcan_vm.sh run: VM boot, tests, power-off
# (vcan_vm.sh --time adds the boot-to-command split).
## the SocketCAN backend on vcan0 in the VM: guard, conformance, can-utils round trips
test-vcan: $(VCAN_STATIC_TESTS) $(VCAN_DRIVER) $(VCAN_SAN_TESTS) $(VCAN_SAN_LIBS)
	@t0=$$(date +%s%N); \
	VCAN_VM_DIR=$(VCAN_VM_DIR) $(VCAN_VM) --time --timeout $(VCAN_TIMEOUT_S) \
	    --payload $(VCAN_PAYLOAD) $(VCAN_VM_FLAGS) -- $(VCAN_DRIVER) $(VCAN_IF); rc=$$?; \
	t1=$$(date +%s%N); ms=$$(( (t1 - t0) / 1000000 )); \
	echo "test-vcan: vcan_vm.sh run took $$((ms / 1000)).$$(( (ms % 1000) / 100 )) s, exit $$rc"; \
	exit $$rc

# 77: test_hal_socketcan found no vcan0 (skipped).
## the vcan tests' ASan and UBSan builds run here (what needs vcan0 skipped)
test-vcan-native: $(VCAN_SAN_TESTS)
	$(VCAN_PAYLOAD)/san/test_guard $(VCAN_IF)
	@$(VCAN_PAYLOAD)/san/test_hal_socketcan $(VCAN_IF); rc=$$?; \
	if [ $$rc -eq 77 ]; then echo "test-vcan-native: test_hal_socketcan skipped (no $(VCAN_IF))"; \
	elif [ $$rc -ne 0 ]; then exit $$rc; fi

## remove the vcan outputs
vcan-clean:
	rm -rf $(VCAN_OUT)

## remove the VM's cache (kernel, initramfs)
vcan-vm-clean:
	rm -rf $(VCAN_VM_DIR)

.DEFAULT_GOAL := $(if $(vcan__standalone),vcan-help,$(vcan__saved_goal))
