# Sensitivity analysis (thesis chapter 6): the command, its tests, its run.
#
# Include from the top-level Makefile (make runs in the repository root),
# after the variables it uses are set (BUILD, HOST, HOSTSAN, HOST_CC,
# ROADS, ROAD_NAMES, DEPS_STAMP):
#
#   include mk/sensitivity.mk
#   test: test-sensitivity
#
# The command, $(HOST)/sensitivity (sim_host/tools/sensitivity.c), is built
# by the Makefile's template, as every tool is. Targets:
#   sensitivity           run it on the three bundled roads: tables on
#                         stdout, $(SENS_OUT)/NAME.csv and NAME.png; then
#                         the number of trucks swept, N = 1 .. 32 on the
#                         hilly road (scripts/n_sweep.sh): node and object
#                         fuel and instructions (callgrind), $(SENS_OUT)/n_sweep.csv
#   test-sensitivity      tests/host/test_sensitivity.c (CMocka, ASan +
#                         UBSan), then the command itself under ASan + UBSan
#                         on the three roads (exit 0, a CSV and a PNG each)
#                         and on a bad road file (exit 2, file and line named);
#                         the N sweep for N = 1 .. 3 (its table, CSV, and
#                         the node model costing more per truck than the object)
#
# The plots need gnuplot: scripts/deps.sh installs gnuplot-nox on first use.

SENS_OUT := $(BUILD)/sensitivity
SENS_CHECK := $(BUILD)/sensitivity-check
SENS_ROADS := $(addprefix $(ROADS)/,$(addsuffix .csv,$(ROAD_NAMES)))
SENS_PLOT_STAMP := $(BUILD)/.deps-gnuplot-ok

.PHONY: sensitivity test-sensitivity

$(SENS_PLOT_STAMP): scripts/deps.sh
	@mkdir -p $(@D)
	sh scripts/deps.sh gnuplot-nox
	@touch $@




# The N sweep needs platoon_compare (mk/thesis.mk) and valgrind (its stamp's rule there too).
SENS_SWEEP_DEPS := $(HOST)/platoon_compare $(BUILD)/.deps-valgrind scripts/n_sweep.sh

## the sensitivity analysis on the three roads (tables, CSV, plots) and the N sweep
sensitivity: $(HOST)/sensitivity $(SENS_PLOT_STAMP) $(SENS_SWEEP_DEPS)
	$(HOST)/sensitivity --out $(SENS_OUT) $(SENS_ROADS)
	sh scripts/n_sweep.sh $(HOST)/platoon_compare $(ROADS)/hilly.csv $(SENS_OUT) 1 32

## the sensitivity analysis's tests, and the tool on good and bad roads
test-sensitivity: $(HOSTSAN)/test_sensitivity $(HOSTSAN)/sensitivity $(SENS_PLOT_STAMP) $(SENS_SWEEP_DEPS)
	@echo "== host: test_sensitivity"; $(HOSTSAN)/test_sensitivity $(ROADS)
	@echo "== host: sensitivity on $(ROAD_NAMES), and on a bad road"
	@rm -rf $(SENS_CHECK) && mkdir -p $(SENS_CHECK)
	@sh scripts/expect_exit.sh 0 $(SENS_CHECK)/run.txt -q -- \
	    $(HOSTSAN)/sensitivity --out $(SENS_CHECK) $(SENS_ROADS)
	@set -e; for r in $(ROAD_NAMES); do \
	    grep -qx "csv: $(SENS_CHECK)/$$r.csv" $(SENS_CHECK)/run.txt; test -s $(SENS_CHECK)/$$r.csv; \
	    grep -qx "png: $(SENS_CHECK)/$$r.png (gnuplot script $(SENS_CHECK)/$$r.gp)" $(SENS_CHECK)/run.txt; \
	    test -s $(SENS_CHECK)/$$r.png; done
	@printf 'distance_m,grade_percent\n0,0\n12,1.2.3\n' > $(SENS_CHECK)/bad.csv
	@sh scripts/expect_exit.sh 2 $(SENS_CHECK)/bad.txt -q \
	    -l "sensitivity: $(SENS_CHECK)/bad.csv:3: bad number '1.2.3' in column 2 (grade_percent)" -- \
	    $(HOSTSAN)/sensitivity --out $(SENS_CHECK) $(SENS_CHECK)/bad.csv
	@echo "sensitivity: three roads tabulated and plotted; a bad road refused with its line"
	@sh scripts/n_sweep.sh $(HOST)/platoon_compare $(ROADS)/hilly.csv $(SENS_CHECK) 1 3 > $(SENS_CHECK)/sweep.txt
	@awk -F, 'NR > 1 { n++; if (!($$8 >= 0.9)) bad = bad " N=" $$1 " ratio/N " $$8 } \
	    END { if (n != 3 || bad != "") { print "n_sweep:" bad " (" n " rows)"; exit 1 } }' $(SENS_CHECK)/n_sweep.csv
	@sh scripts/expect_exit.sh 2 $(SENS_CHECK)/sweep-bad.txt -q -- \
	    sh scripts/n_sweep.sh $(HOST)/platoon_compare $(SENS_CHECK)/missing.csv $(SENS_CHECK)
	@echo "n_sweep: N = 1 .. 3 on the hilly road, the node model at least 0.9 N times the object's instructions; a missing road refused"
