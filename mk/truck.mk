# The truck a module runs on: calibration files (sim_host/lib/truck_cal.h) and
# logs of foreign trucks to test against (sim_host/tools/truckgen.c).
#
#   test-truck-cal    the calibration file parser: fields, units, sections,
#                     errors (CMocka, ASan, UBSan); every tool's --calib
#                     refuses a bad file with exit status 2, and drivegen,
#                     pfe_ecu_replay, run_report agree on a 60 t truck
#   test-foreign-trucks  foreign-truck logs (12 t, 60 t; no SSI, SSI, VDS;
#                     the engine's LFE1 stopping; identification from it
#                     with the default calibration, then 5 minutes
#                     without it; hostile variants),
#                     generated at test time, replayed on the host, judged
#                     (tests/host/foreign_trucks.sh)
#   foreign-bench     the same, printing only its bench: lines
#   test-replay-calib  a foreign truck's log through pfe_ecu_replay --calib
#                     FILE and through the Cortex-M4 image built for FILE:
#                     identical records, unlike the default calibration's
#   firmware CALIB=FILE  also builds $(M4_OUT)/pfe_ecu_mps2_calib.elf, the
#                     replay image with FILE compiled in (sim_host/tools/cal2c.c);
#                     the bundled trucks have images of their own:
#                     $(M4_OUT)/pfe_ecu_mps2_truck12t.elf, ..._truck60t.elf
#
# Variables: HOSTILE_RANDOM_XFAIL (1: the random-payload check is a known
# failure of the firmware, reported but not failing; 0: it must pass).
#
# Included from the top-level Makefile.

TRUCKS := sim_host/data/trucks
TRUCK_GEN := $(BUILD)/gen

.PHONY: test-truck-cal test-foreign-trucks foreign-bench test-replay-calib
HOSTILE_RANDOM_XFAIL ?= 1
FOREIGN_TOOLS := $(HOST)/truckgen $(HOST)/truck_judge $(HOST)/pfe_ecu_replay


## the truck calibration parser, and every tool's --calib
test-truck-cal: $(HOSTSAN)/test_truck_cal $(HOST)/pfe_ecu_replay $(HOST)/pfe_ecu $(HOST)/drivegen \
        $(HOST)/run_report
	@echo "== host: test_truck_cal"; $(HOSTSAN)/test_truck_cal $(TRUCKS)
	@sh tests/host/truck_cal_tools.sh $(HOST) $(TRUCKS) $(BUILD)/truck-cal $(ROADS)/uphill.csv



## foreign trucks' logs (12 t, 60 t, hostile variants) replayed on the host and judged
test-foreign-trucks: $(FOREIGN_TOOLS)
	@HOSTILE_RANDOM_XFAIL=$(HOSTILE_RANDOM_XFAIL) sh tests/host/foreign_trucks.sh $(HOST) $(TRUCKS) $(BUILD)/foreign

## bench: the foreign-truck figures
foreign-bench: $(FOREIGN_TOOLS)
	@HOSTILE_RANDOM_XFAIL=$(HOSTILE_RANDOM_XFAIL) sh tests/host/foreign_trucks.sh $(HOST) $(TRUCKS) \
	    $(BUILD)/foreign-bench > $(BUILD)/foreign-bench.txt 2>&1 || { cat $(BUILD)/foreign-bench.txt; exit 1; }
	@cat $(BUILD)/foreign-bench/bench.lines

# ---------------------------------------------------------------- calibrated Cortex-M4 images


TRUCK_NAMES := truck12t truck60t
.SECONDARY: $(patsubst %,$(TRUCK_GEN)/calib_%.c,$(TRUCK_NAMES) user)
$(TRUCK_GEN)/calib_%.c: $(TRUCKS)/%.cal $(HOST)/cal2c
	@mkdir -p $(@D)
	$(HOST)/cal2c $< $@
ECU_IMAGE_SRC := $(FW_SRC) $(ECU_REPLAY_SRC) hal/mps2/main_ecu.c
$(foreach t,$(TRUCK_NAMES),$(call m4_image,pfe_ecu_mps2_$(t),$(ECU_IMAGE_SRC) $(TRUCK_GEN)/calib_$(t).c))

# make firmware CALIB=FILE: the replay image for that truck. The generated
# file is rewritten when FILE's name changes, not only its contents.
ifneq ($(strip $(CALIB)),)
CALIB_STAMP := $(TRUCK_GEN)/calib_user.name
$(CALIB_STAMP): FORCE_CALIB
	@mkdir -p $(@D)
	@echo '$(abspath $(CALIB))' | cmp -s - $@ || echo '$(abspath $(CALIB))' > $@
$(TRUCK_GEN)/calib_user.c: $(CALIB) $(CALIB_STAMP) $(HOST)/cal2c
	@mkdir -p $(@D)
	$(HOST)/cal2c $(CALIB) $@
$(call m4_image,pfe_ecu_mps2_calib,$(ECU_IMAGE_SRC) $(TRUCK_GEN)/calib_user.c)
firmware: $(M4_OUT)/pfe_ecu_mps2_calib.elf
.PHONY: FORCE_CALIB
FORCE_CALIB:
endif

CALIB_LOG := $(BUILD)/foreign-m4/12t.log
$(CALIB_LOG): $(HOST)/truckgen $(TRUCKS)/truck12t.cal
	@mkdir -p $(@D)
	$(HOST)/truckgen --calib $(TRUCKS)/truck12t.cal --profile 0:3,80:40,50:20,85:25,0:20 --start-s 10 \
	    --others 60 --ssi --format log --out $@

## a foreign truck's log through pfe_ecu_replay --calib and the image built for it: identical records
test-replay-calib: $(HOST)/pfe_ecu_replay $(M4_OUT)/pfe_ecu_mps2_truck12t.elf $(M4_OUT)/pfe_ecu_mps2.elf $(CALIB_LOG)
	sh tests/replay/calib_host_vs_m4.sh $(BUILD)/foreign-m4 $(HOST) $(M4_OUT)/pfe_ecu_mps2_truck12t.elf \
	    $(M4_OUT)/pfe_ecu_mps2.elf $(TRUCKS)/truck12t.cal $(CALIB_LOG)
