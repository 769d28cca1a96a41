# The truck a module runs on: calibration files (sim_host/truck_cal.h) and
# logs of foreign trucks to test against (sim_host/truckgen.c).
#
#   test-truck-cal    the calibration file parser: fields, units, sections,
#                     errors (CMocka, ASan, UBSan); every tool's --calib
#                     refuses a bad file with exit status 2
#
# Included from the top-level Makefile.

TRUCKS := sim_host/trucks

.PHONY: test-truck-cal

$(HOSTSAN)/test_truck_cal: tests/host/test_truck_cal.c $(TRUCK_CAL_SRC) $(FW_SRC) $(FW_HDR) $(SIM_HDR) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(HOST_CC) $(SAN_CFLAGS) -I. -Ifirmware -o $@ $< $(TRUCK_CAL_SRC) $(FW_SRC) -lcmocka

test-truck-cal: $(HOSTSAN)/test_truck_cal $(HOST)/pfe_ecu_replay $(HOST)/pfe_ecu
	@echo "== host: test_truck_cal"; $(HOSTSAN)/test_truck_cal $(TRUCKS)
	@sh tests/host/truck_cal_tools.sh $(HOST) $(TRUCKS) $(BUILD)/truck-cal
