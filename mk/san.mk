# Every host tool built with ASan and UBSan ($(HOSTSAN)/NAME, mk/host.mk's
# host-san flavour), and the bad-input tests run against those builds
# (tests/host/bad_input.sh): empty, binary and directory inputs, a huge
# line, bad numbers, missing files. Included from the Makefile; `make test`
# runs test-san, and with it test-doc-options.

SAN_TOOLS_DIR := $(HOSTSAN)

.PHONY: san test-san test-doc-options
## every host tool built with ASan and UBSan (build/host-san/)
san: $(addprefix $(HOSTSAN)/,$(TOOL_NAMES))

## every option the README and docs/ name for a host tool is in its --help
test-doc-options: $(addprefix $(HOST)/,$(TOOL_NAMES))
	@sh tests/host/doc_options.sh $(HOST)

## bad input (empty, binary, huge lines, bad numbers, missing files) to every tool's ASan and UBSan build
test-san: san test-doc-options
	@echo "== host: bad input to every tool, ASan and UBSan builds ($(SAN_TOOLS_DIR))"
	@sh tests/host/bad_input.sh $(SAN_TOOLS_DIR) $(BUILD)/bad-input can_dbc/pfe.dbc
