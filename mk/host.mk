# Host builds from templates: every C file compiled once per flavour, into
# $(BUILD)/<flavour>/obj/<path>.o with its header dependencies (-MMD); the
# firmware, sim_host/lib/ and sim_host/ref/ archived once per flavour
# (libpfe_fw.a, libpfe_host.a, libpfe_ref.a); every program and test linked
# by one of the rules below.
#
# Flavours (directory, flags):
#   host         $(HOST)        $(HOST_CFLAGS): -O2 -g, the tools of `make`
#   host-san     $(HOSTSAN)     $(SAN_CFLAGS): ASan + UBSan, tests and `make san`
#   host-static  $(HOSTSTATIC)  $(STATIC_CFLAGS), linked -static: programs the
#                               vcan VM runs (its initramfs has no C library)
#
# Templates (call them at the top level of a makefile):
#   $(call host_program,NAME,SOURCES)
#       NAME in every flavour ($(HOST)/NAME, $(HOSTSAN)/NAME,
#       $(HOSTSTATIC)/NAME): SOURCES (default sim_host/tools/NAME.c) and the
#       HAL sources it needs, linked with the three archives and libm.
#   $(call host_test,NAME,SOURCES)
#       $(HOSTSAN)/NAME: a CMocka test, SOURCES linked with the archives.
#   $(call host_payload,DIR,NAMES)
#       DIR/NAME for each NAME: a copy of $(HOSTSTATIC)/NAME, for a VM payload.
#
# Included from the top-level Makefile after its variables (BUILD, HOST,
# HOSTSAN, HOSTSTATIC, HOST_CC, HOST_CFLAGS, SAN_CFLAGS, STATIC_CFLAGS, SAN,
# FW_SRC, DEPS_STAMP).

HOST_FLAVOURS := host host-san host-static
host__dir_host = $(HOST)
host__dir_host-san = $(HOSTSAN)
host__dir_host-static = $(HOSTSTATIC)
host__cflags_host = $(HOST_CFLAGS)
host__cflags_host-san = $(SAN_CFLAGS)
host__cflags_host-static = $(STATIC_CFLAGS)
host__ldflags_host :=
host__ldflags_host-san :=
host__ldflags_host-static := -static

# The archives, in link order: ref/ uses lib/ and the firmware, lib/ the firmware.
HOSTLIB_SRC := $(sort $(wildcard sim_host/lib/*.c sim_host/lib/*/*.c))
HOSTREF_SRC := $(sort $(wildcard sim_host/ref/*.c))
HOST_ARCHIVES := libpfe_ref.a libpfe_host.a libpfe_fw.a

# $(call host_objs,FLAVOUR,SOURCES)
host_objs = $(patsubst %.c,$(host__dir_$(1))/obj/%.o,$(2))
host_libs = $(addprefix $(host__dir_$(1))/,$(HOST_ARCHIVES))

# Per-object flags, as target-specific HOST_OBJ_FLAGS.
HOST_OBJ_FLAGS :=

define host__flavour
$(host__dir_$(1))/obj/%.o: %.c | $(DEPS_STAMP) $(FW_GEN_HDR)
	@mkdir -p $$(@D)
	$$(HOST_CC) $$(host__cflags_$(1)) $$(HOST_OBJ_FLAGS) -MMD -MP -c $$< -o $$@

$(host__dir_$(1))/libpfe_fw.a: $(call host_objs,$(1),$(FW_SRC))
$(host__dir_$(1))/libpfe_host.a: $(call host_objs,$(1),$(HOSTLIB_SRC))
$(host__dir_$(1))/libpfe_ref.a: $(call host_objs,$(1),$(HOSTREF_SRC))
$(call host_libs,$(1)):
	@rm -f $$@
	ar rcs $$@ $$^

# sim_host/lib/dbc.c draws a false maybe-uninitialized warning at -O2
# without the sanitizers (expect_u32's v, written by parse_u64_token
# whenever it returns 0): that one warning is off for this object.
$(host__dir_$(1))/obj/sim_host/lib/dbc.o: HOST_OBJ_FLAGS := $(if $(filter host-san,$(1)),,-Wno-maybe-uninitialized)
endef
$(foreach f,$(HOST_FLAVOURS),$(eval $(call host__flavour,$(f))))

define host__program
$(host__dir_$(1))/$(2): $(call host_objs,$(1),$(3)) $(call host_libs,$(1))
	$$(HOST_CC) $$(host__cflags_$(1)) $(host__ldflags_$(1)) -o $$@ $$(filter %.o,$$^) $$(filter %.a,$$^) -lm
endef
host_program = $(foreach f,$(HOST_FLAVOURS),$(eval $(call host__program,$(f),$(strip $(1)),$(or $(strip $(2)),sim_host/tools/$(strip $(1)).c))))

define host__test
$(HOSTSAN)/$(1): $(call host_objs,host-san,$(2)) $(call host_libs,host-san)
	$$(HOST_CC) $$(SAN_CFLAGS) -o $$@ $$(filter %.o,$$^) $$(filter %.a,$$^) -lcmocka -lm
endef
host_test = $(eval $(call host__test,$(strip $(1)),$(strip $(2))))

define host__payload
$(1)/$(2): $(HOSTSTATIC)/$(2)
	@mkdir -p $$(@D)
	cp $$< $$@
endef
host_payload = $(foreach p,$(2),$(eval $(call host__payload,$(strip $(1)),$(p))))

-include $(shell find $(HOST)/obj $(HOSTSAN)/obj $(HOSTSTATIC)/obj -name '*.d' 2>/dev/null)
