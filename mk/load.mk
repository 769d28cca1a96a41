# The suite on a busy machine (scripts/load_test.sh): make test while more
# CPU-bound processes than cores run and a parallel build churns in a
# scratch copy, all bounded in time. Not part of make test (it runs it).
# Included from the Makefile. docs/ci.md has the times.

.PHONY: test-loaded
## make test on a busy machine (scripts/load_test.sh)
test-loaded:
	mkdir -p $(BUILD)
	sh scripts/load_test.sh --log $(BUILD)/test-loaded.log -- $(MAKE) --no-print-directory test
