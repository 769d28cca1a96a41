# Every host tool built with ASan and UBSan (build/host-san/tools/), and the
# bad-input tests run against those builds (tests/host/bad_input.sh): empty,
# binary and directory inputs, a huge line, bad numbers, missing files.
# Included from the Makefile; `make test` runs test-san.

SAN_TOOLS_DIR := $(HOSTSAN)/tools

.PHONY: san test-san
# The tools' own rules, with the sanitizer flags and a build tree of their own.
san:
	@$(MAKE) --no-print-directory BUILD=$(BUILD)/san HOST=$(SAN_TOOLS_DIR) \
	    HOST_CFLAGS='$(SAN_CFLAGS)' tools

test-san: san
	@echo "== host: bad input to every tool, ASan and UBSan builds ($(SAN_TOOLS_DIR))"
	@sh tests/host/bad_input.sh $(SAN_TOOLS_DIR) $(BUILD)/bad-input can_dbc/pfe.dbc
