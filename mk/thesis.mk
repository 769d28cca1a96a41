# The thesis's claims on the host: node model against object model (5.2),
# fuel bounds (5.1) and route choice (sim_host/ref/node_model.h, fuel_bounds.h,
# route_gen.h).
#
# Include from the top-level Makefile after mk/vcan.mk (it uses HOST,
# HOSTSAN, ROADS, FW_SRC, FW_HDR, HOST_CFLAGS, SAN_CFLAGS, DEPS_STAMP):
#
#   include mk/thesis.mk
#   test: test-thesis
#   bench: thesis-bench
#
# Targets:
#   test-thesis     the node-model, truck-length and fuel-bound tests (ASan,
#                   UBSan; test_truck_length: object against node with 16.5 m
#                   trucks on the three roads and 250 random routes), the
#                   property test over 250 seeded hilly routes included, and
#                   the bundled routes regenerated and compared byte for byte
#   thesis-bench    instructions of node and object model over the 12 km
#                   hilly road for N = 5, 10, 20, 50 (callgrind, counted
#                   inside node_sim_run and object_sim_run only; both models
#                   step 0.1 s of time), their ratio, which must reach 0.9 N;
#                   and the host time of 12 km of the object model (median
#                   of 21 runs); and the same instructions for five
#                   16.5 m trucks under the headway policy, with the object
#                   model's followers driven by their own controller beside
#   thesis-report   the tables 5.1 to 5.5 analogues on the three roads with
#                   N = 5, beside the thesis's values (5.4: both fuel models
#                   fed the node model's mean speeds), the same with 16.5 m
#                   trucks under both spacing policies (sim_host/ref/node_model.h),
#                   the same without
#                   drag reduction (the
#                   cause of the uphill difference), and the route choice on
#                   the bundled routes: ridge, detour and rolling; ridge
#                   against the long bypass (guaranteed, exit 0); uphill
#                   against flat and detour against bypass (not guaranteed:
#                   the thesis's bounds' assumptions fail, exit 3)

ROUTES := sim_host/data/routes
ROUTE_NAMES := ridge detour rolling bypass
THESIS_ROADS := $(foreach r,$(ROAD_NAMES),--road $(ROADS)/$(r).csv)
THESIS_BENCH_N := 5 10 20 50
VALGRIND_STAMP := $(BUILD)/.deps-valgrind

.PHONY: test-thesis thesis-bench thesis-report






$(call host_test,test_truck_length,tests/host/test_truck_length.c)

## node model, truck length and fuel bounds tests, the 250-route property test, the bundled routes regenerated
test-thesis: $(HOSTSAN)/test_node_model $(HOSTSAN)/test_truck_length $(HOSTSAN)/test_fuel_bounds $(HOSTSAN)/routegen
	@echo "== host: test_node_model"; $(HOSTSAN)/test_node_model $(ROADS)
	@echo "== host: test_truck_length"; $(HOSTSAN)/test_truck_length $(ROADS)
	@echo "== host: test_fuel_bounds"; $(HOSTSAN)/test_fuel_bounds
	@echo "== host: bundled routes against routegen"
	@set -e; for r in $(ROUTE_NAMES); do \
	    $(HOSTSAN)/routegen $$r --out $(BUILD)/route_$$r.csv; \
	    if cmp -s $(BUILD)/route_$$r.csv $(ROUTES)/$$r.csv; then echo "   $$r.csv: identical"; \
	    else echo "$(ROUTES)/$$r.csv differs from routegen $$r: regenerate it"; exit 1; fi; done

$(VALGRIND_STAMP): scripts/deps.sh
	@mkdir -p $(@D)
	sh scripts/deps.sh valgrind
	@touch $@

# Instruction counts: callgrind counts only while node_sim_run or
# object_sim_run runs (loading the road and the rest are left out).
## bench: instructions of the node and object models for N = 5, 10, 20, 50
thesis-bench: $(HOST)/platoon_compare $(VALGRIND_STAMP)
	@set -e; mkdir -p $(BUILD)/callgrind; for n in $(THESIS_BENCH_N); do \
	    for m in node object; do \
	        valgrind --tool=callgrind --callgrind-out-file=$(BUILD)/callgrind/$$m.n$$n \
	            --toggle-collect=$${m}_sim_run $(HOST)/platoon_compare --only $$m \
	            --road $(ROADS)/hilly.csv --vehicles $$n >/dev/null 2>$(BUILD)/callgrind/$$m.n$$n.log \
	        || { cat $(BUILD)/callgrind/$$m.n$$n.log; exit 1; }; \
	    done; \
	    node=$$(awk '/^totals:/ { print $$2 }' $(BUILD)/callgrind/node.n$$n); \
	    obj=$$(awk '/^totals:/ { print $$2 }' $(BUILD)/callgrind/object.n$$n); \
	    echo "bench: node_12km_insn_n$$n $$node insn"; \
	    echo "bench: object_12km_insn_n$$n $$obj insn"; \
	    awk -v a=$$node -v b=$$obj -v n=$$n 'BEGIN { r = a / b; \
	        printf "bench: node_object_insn_ratio_n%d %.2f x\n", n, r; \
	        if (!(r >= 0.9 * n)) { printf "thesis-bench: ratio %.2f below 0.9 N = %.1f\n", r, 0.9 * n; exit 1 } }'; \
	done
	@# Trucks of 16.5 m under the headway policy: the node model, the object
	@# model and the object model with the followers driven by their own
	@# controller (sim_host/ref/node_model.h), five trucks, the hilly road.
	@set -e; for m in node object followers; do \
	    sim=$$m; test $$m = node || sim=object; \
	    valgrind --tool=callgrind --callgrind-out-file=$(BUILD)/callgrind/$$m.length \
	        --toggle-collect=$${sim}_sim_run $(HOST)/platoon_compare --only $$m --road $(ROADS)/hilly.csv \
	        --vehicles 5 --length-m 16.5 --spacing headway >/dev/null 2>$(BUILD)/callgrind/$$m.length.log \
	    || { cat $(BUILD)/callgrind/$$m.length.log; exit 1; }; \
	    echo "bench: $${m}_12km_insn_n5_length $$(awk '/^totals:/ { print $$2 }' $(BUILD)/callgrind/$$m.length) insn"; \
	done
	@$(HOST)/platoon_compare --bench --repeat 21 --road $(ROADS)/hilly.csv --vehicles 5

## the thesis's tables 5.1 to 5.5 on the three roads, and the route choice on the bundled routes
thesis-report: $(HOST)/platoon_compare $(HOST)/route_choice
	$(HOST)/platoon_compare $(THESIS_ROADS) --vehicles 5
	$(HOST)/platoon_compare $(THESIS_ROADS) --vehicles 5 --length-m 16.5 --repeat 1
	$(HOST)/platoon_compare $(THESIS_ROADS) --vehicles 5 --length-m 16.5 --spacing headway --repeat 1
	$(HOST)/platoon_compare $(THESIS_ROADS) --vehicles 5 --no-drag-reduction --repeat 1
	$(HOST)/route_choice $(ROUTES)/ridge.csv $(ROUTES)/detour.csv $(ROUTES)/rolling.csv; \
	    rc=$$?; test $$rc -eq 0 -o $$rc -eq 3
	$(HOST)/route_choice $(ROUTES)/ridge.csv $(ROUTES)/bypass.csv
	$(HOST)/route_choice $(ROADS)/uphill.csv $(ROADS)/flat.csv; rc=$$?; test $$rc -eq 3
	$(HOST)/route_choice $(ROUTES)/detour.csv $(ROUTES)/bypass.csv; rc=$$?; test $$rc -eq 3
