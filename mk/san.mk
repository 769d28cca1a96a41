# Every host tool built with ASan and UBSan (build/host-san/tools/), and the
# bad-input tests run against those builds (tests/host/bad_input.sh): empty,
# binary and directory inputs, a huge line, bad numbers, missing files.
# Included from the Makefile; `make test` runs test-san, and with it
# test-doc-options.

SAN_TOOLS_DIR := $(HOSTSAN)/tools

.PHONY: san test-san test-doc-options
# The tools' own rules, with the sanitizer flags and a build tree of their own.
san:
	@$(MAKE) --no-print-directory BUILD=$(BUILD)/san HOST=$(SAN_TOOLS_DIR) \
	    HOST_CFLAGS='$(SAN_CFLAGS)' tools

# Every option the README and docs/ name for a host tool is in its --help
# (tests/host/doc_options.sh); the programs of the README's tool table.
DOC_TOOLS := $(TOOLS) $(addprefix $(HOST)/,selfcheck ecu_check pfe_faults roadimport truckgen truck_judge cal2c)
test-doc-options: $(DOC_TOOLS)
	@sh tests/host/doc_options.sh $(HOST)

test-san: san test-doc-options
	@echo "== host: bad input to every tool, ASan and UBSan builds ($(SAN_TOOLS_DIR))"
	@sh tests/host/bad_input.sh $(SAN_TOOLS_DIR) $(BUILD)/bad-input can_dbc/pfe.dbc
