# NVM save path under resets, torn and failed writes (tests/host/test_nvm_faults.c),
# and the same test against a planted bug it must catch. Included from the Makefile.

NVM_FAULTS_SRC := tests/host/test_nvm_faults.c hal/hal_ecu_loop.c hal/fake/hal_fake.c hal/hal_can_mem_api.c hal/hal_can_mem.c


# The planted bug: a failed write advances the slot, the sequence and the
# interval as a completed one (the save path before retries). The copy must
# differ from the source, or the plant no longer applies.
NVM_PLANTED := $(HOSTSAN)/nvm-planted
$(NVM_PLANTED)/pfe_ecu.c: firmware/pfe_ecu.c
	@mkdir -p $(@D)
	sed 's|^\(        count_up(&ecu->count.nvm_write_failures, 1U);\)$$|\1 ecu->nvm_sequence++; ecu->nvm_last_slot = (int)pfe_nvm_next_slot(ecu->nvm_last_slot); ecu->last_save_us = ecu->now_us;|' $< > $@
	@if cmp -s $< $@; then echo "nvm planted bug: the plant no longer applies to $<"; rm -f $@; exit 1; fi

$(NVM_PLANTED)/test_nvm_faults: $(NVM_FAULTS_SRC) $(NVM_PLANTED)/pfe_ecu.c $(FW_SRC) $(FW_HDR) $(HAL_HDR) | $(DEPS_STAMP)
	$(HOST_CC) $(SAN_CFLAGS) -I. -Ifirmware -o $@ $(NVM_FAULTS_SRC) $(NVM_PLANTED)/pfe_ecu.c \
	    $(filter-out firmware/pfe_ecu.c,$(FW_SRC)) -lcmocka

.PHONY: test-nvm-faults
## NVM under resets, torn and failed writes; the same test catches a planted bug
test-nvm-faults: $(HOSTSAN)/test_nvm_faults $(NVM_PLANTED)/test_nvm_faults
	@echo "== host: NVM under resets, torn and failed writes (10,000 sequences, seeds 1 to 4)"
	@$(HOSTSAN)/test_nvm_faults
	@echo "== host: the same test catches a planted bug (a failed write advances the slot)"
	@sh scripts/expect_exit.sh 1 $(NVM_PLANTED)/path.out -q -- $(NVM_PLANTED)/test_nvm_faults 200 1
	@grep -q 'is retried on the next pass to the same slot' $(NVM_PLANTED)/path.out
	@sh scripts/expect_exit.sh 1 $(NVM_PLANTED)/boot.out -q -- $(NVM_PLANTED)/test_nvm_faults --boot-checks-only 200 1
	@grep -q 'restores the last completed write' $(NVM_PLANTED)/boot.out
	@grep -h 'seed 1 sequence' $(NVM_PLANTED)/path.out $(NVM_PLANTED)/boot.out | head -2
	@echo "nvm planted bug: caught by the retry check and by the boot check alone"
