# Road profiles from route planners' data: roadimport (GPX with elevations,
# distance/elevation CSV; sim_host/lib/road_import.h), its tests, and the route
# demo.
#
# Include from the top-level Makefile after mk/thesis.mk (it uses BUILD,
# HOST, HOSTSAN, HOST_CC, HOST_CFLAGS, SAN_CFLAGS, DEPS_STAMP, GNUPLOT_STAMP
# and $(HOST)/route_choice):
#
#   include mk/roads.mk
#   test: test-road-import
#
# Targets:
#   test-road-import  tests/host/test_road_import.c (ASan, UBSan): made-up
#                     tracks with known answers, noise, bad input; then
#                     roadimport itself on a GPX and a bad file
#   route-demo        three made-up GPX tracks (scripts/demo_gpx.sh) imported,
#                     compared by route_choice with their bounds, and
#                     plotted: $(ROUTE_DEMO)/route_demo.png

ROUTE_DEMO := $(BUILD)/route-demo
ROUTE_DEMO_NAMES := pass valley coast

.PHONY: test-road-import route-demo




## roadimport's tests: made-up tracks with known answers, noise, bad input
test-road-import: $(HOSTSAN)/test_road_import $(HOSTSAN)/roadimport
	@rm -rf $(BUILD)/road-import-test && mkdir -p $(BUILD)/road-import-test
	@echo "== host: test_road_import"; $(HOSTSAN)/test_road_import $(BUILD)/road-import-test
	@echo "== host: roadimport on a made-up GPX, and on a GPX without elevations"
	@sh scripts/demo_gpx.sh $(BUILD)/road-import-test > /dev/null
	@sh scripts/expect_exit.sh 0 $(BUILD)/road-import-test/ok.txt -q -- \
	    $(HOSTSAN)/roadimport $(BUILD)/road-import-test/pass.gpx --out $(BUILD)/road-import-test/pass.csv
	@grep -q "^distance_m,grade_percent$$" $(BUILD)/road-import-test/pass.csv
	@test "$$(grep -c '^[0-9]' $(BUILD)/road-import-test/pass.csv)" -eq 1800
	@sed 's|<ele>[^<]*</ele>||' $(BUILD)/road-import-test/pass.gpx > $(BUILD)/road-import-test/noele.gpx
	@sh scripts/expect_exit.sh 2 $(BUILD)/road-import-test/bad.txt -q \
	    -l "roadimport: $(BUILD)/road-import-test/noele.gpx:4: a track point without <ele>: the track has no elevation" -- \
	    $(HOSTSAN)/roadimport $(BUILD)/road-import-test/noele.gpx --out $(BUILD)/road-import-test/noele.csv
	@test ! -e $(BUILD)/road-import-test/noele.csv
	@echo "roadimport: an 18 km GPX imported to 1800 samples; a GPX without elevations refused with its line"

## three made-up GPX tracks imported, compared by route_choice and plotted
route-demo: $(HOST)/roadimport $(HOST)/route_choice $(GNUPLOT_STAMP)
	@sh scripts/demo_gpx.sh $(ROUTE_DEMO)
	@set -e; for r in $(ROUTE_DEMO_NAMES); do \
	    $(HOST)/roadimport $(ROUTE_DEMO)/$$r.gpx --out $(ROUTE_DEMO)/$$r.csv \
	        --elevation-out $(ROUTE_DEMO)/$$r.elevation.csv; done
	@$(HOST)/route_choice $(addprefix $(ROUTE_DEMO)/,$(addsuffix .csv,$(ROUTE_DEMO_NAMES))) \
	    > $(ROUTE_DEMO)/choice.txt; rc=$$?; cat $(ROUTE_DEMO)/choice.txt; \
	    test $$rc -eq 0 -o $$rc -eq 3 || exit 1; \
	    echo "route_choice exit $$rc ($$(test $$rc -eq 0 && echo guaranteed || echo not guaranteed))"
	@sh scripts/route_demo_plot.sh $(ROUTE_DEMO) $(ROUTE_DEMO_NAMES)
