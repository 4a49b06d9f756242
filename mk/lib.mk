# The library (float, double and the q31 twins), the host code and the test binaries, in
# every build tree (f32, f64, q31 and their cov-, asan- and mcdc- twins), and mu_replay.
# Included by the Makefile before the other fragments, which reuse FLAVOUR_RULES, Q31_RULES
# and REPLAY_RULE for their own trees.
#
# Every compile writes its header dependencies beside the object (-MMD -MP: a changed header
# rebuilds exactly the objects that include it; a removed one breaks nothing).
DEPFLAGS := -MMD -MP

# The fixed-point twins (*_q31.c, integer only) are built into their own library,
# librfe_q31.a, never into the float/double ones; their tests (test/<folder>/test_*_q31.c) are built
# once (Q31_RULES below), not per precision like UNIT_TESTS.
# The library's folders (docs/LAYOUT.md): shared numerics, filters, models, parameters,
# estimators; src/host/ is host code, never part of it.
LIB_DIRS      := src/numerics src/filters src/models src/params src/estimators/friction \
                 src/estimators/velocity src/estimators/pipeline src/estimators/tyre_id \
                 src/estimators/mass_grade
LIB_ALL_SRC   := $(foreach d,$(LIB_DIRS),$(wildcard $(d)/*.c))
LIB_HDRS      := $(wildcard include/rfe/*.h include/rfe/component/*.h $(addsuffix /*.h,$(LIB_DIRS)))
Q31_SRC       := $(filter %_q31.c,$(LIB_ALL_SRC))
LIB_SRC       := $(filter-out $(Q31_SRC),$(LIB_ALL_SRC))
# replay_q31.c (the `--real q31` replay) needs the q31 library: linked only into mu_replay and
# the q31 tests, never into hostlib.a (whose objects the fuzz harnesses link one by one);
# replay_mem.c (the in-memory replay of the Python package) needs all three replays, and
# mu_replay.c's set-up: compiled with mu_replay.
HOST_SRC      := $(filter-out src/host/mu_replay.c src/host/replay_real.c src/host/replay_q31.c \
                   src/host/replay_mem.c,$(wildcard src/host/*.c))
# The C tests (test/README.md): per module in the folder of its layer, and by concern
# (golden, robustness, mcdc); named <folder>/test_<name> (binaries build/<tree>/test/<folder>/).
TEST_DIRS     := test/numerics test/filters test/models test/params test/estimators/friction \
                 test/estimators/velocity test/estimators/pipeline test/estimators/tyre_id \
                 test/estimators/mass_grade \
                 test/golden test/robustness test/mcdc
TEST_ALL      := $(patsubst test/%.c,%,$(foreach d,$(TEST_DIRS),$(wildcard $(d)/test_*.c)))
Q31_TESTS     := $(filter %_q31,$(TEST_ALL))
UNIT_TESTS    := $(filter-out $(Q31_TESTS),$(TEST_ALL))
HOST_TESTS    := $(basename $(notdir $(wildcard test/host/test_*.c)))
# The Cortex-M0+ forms of a library source (RFE_FIX_MUL64_W16 = 1) run on the host: each test
# in test/numerics/w16/ includes the source it checks, compiled in that form. Built in the q31
# tree and run by test-c; outside TEST_DIRS, so the coverage and MC/DC runs, which read src/
# through every test binary, see the library's form only.
W16_TESTS     := $(patsubst test/%.c,%,$(wildcard test/numerics/w16/test_*.c))
TEST_SUPPORT  := $(wildcard test/support/*.c)

# One build tree per flavour: f32 (float), f64 (double); cov-* are the instrumented twins.
define FLAVOUR_RULES
# $(1) = tree name, $(2) = real-type defines, $(3) = extra compile flags
$(BUILD)/$(1)/lib/%.o: src/%.c | $(BUILD)/$(1)/lib
	@mkdir -p $$(@D)
	$$(CC) $$(DEPFLAGS) $$(WARN) $(3) $(2) $$(CPPFLAGS_LIB) -c $$< -o $$@
$(BUILD)/$(1)/librfe.a: $(patsubst src/%.c,$(BUILD)/$(1)/lib/%.o,$(LIB_SRC))
	rm -f $$@ && ar rcs $$@ $$^
$(BUILD)/$(1)/host/replay_real.o: src/host/replay_real.c | $(BUILD)/$(1)/host
	$$(CC) $$(DEPFLAGS) $$(WARN) $(3) $(2) $$(CPPFLAGS_HOST) -c $$< -o $$@
$(BUILD)/$(1)/support/%.o: test/support/%.c | $(BUILD)/$(1)/support
	$$(CC) $$(DEPFLAGS) $$(TEST_WARN) $(3) $(2) $$(CPPFLAGS_HOST) -Itest/support -c $$< -o $$@
$(BUILD)/$(1)/test/%: test/%.c $(BUILD)/$(1)/librfe.a $(patsubst test/support/%.c,$(BUILD)/$(1)/support/%.o,$(TEST_SUPPORT)) $(BUILD)/$(1)/hostlib.a $(BUILD)/$(1)/host/replay_real.o
	@mkdir -p $$(@D)
	$$(CC) $$(DEPFLAGS) $$(TEST_WARN) $(3) $(2) $$(CPPFLAGS_HOST) -Itest/support -Isrc $$< \
	  $(patsubst test/support/%.c,$(BUILD)/$(1)/support/%.o,$(TEST_SUPPORT)) \
	  $(BUILD)/$(1)/host/replay_real.o $(BUILD)/$(1)/hostlib.a $(BUILD)/$(1)/librfe.a $$(LDLIBS_TEST) -o $$@
$(BUILD)/$(1)/hostlib.a: $(patsubst src/host/%.c,$(BUILD)/$(1)/host/%.o,$(HOST_SRC))
	rm -f $$@ && ar rcs $$@ $$^
$(BUILD)/$(1)/host/%.o: src/host/%.c | $(BUILD)/$(1)/host
	$$(CC) $$(DEPFLAGS) $$(WARN) $(3) $$(CPPFLAGS_HOST) -c $$< -o $$@
$(BUILD)/$(1)/lib $(BUILD)/$(1)/host $(BUILD)/$(1)/test $(BUILD)/$(1)/support:
	mkdir -p $$@
endef

COVFLAGS := -O0 -g --coverage
$(eval $(call FLAVOUR_RULES,f32,,$(OPT)))
$(eval $(call FLAVOUR_RULES,f64,-DRFE_REAL_DOUBLE,$(OPT)))
$(eval $(call FLAVOUR_RULES,cov-f32,,$(COVFLAGS)))
$(eval $(call FLAVOUR_RULES,cov-f64,-DRFE_REAL_DOUBLE,$(COVFLAGS)))
# asan-*: AddressSanitizer + UndefinedBehaviorSanitizer twins; any report aborts the test.
SANFLAGS := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all -O1 -g
$(eval $(call FLAVOUR_RULES,asan-f32,,$(SANFLAGS)))
$(eval $(call FLAVOUR_RULES,asan-f64,-DRFE_REAL_DOUBLE,$(SANFLAGS)))

# Fixed-point trees: q31 (optimised), cov-q31 (instrumented), asan-q31 (ASan + UBSan). The
# library gets the same strict flags and no real-type define. The tests are compiled for
# double and also link the double tree of the same kind ($(2): f64, cov-f64, asan-f64) with
# its test support, so a back-to-back test can compare a _q31 function with its _f64 twin.
define Q31_RULES
# $(1) = tree name, $(2) = double tree, $(3) = extra compile flags
$(BUILD)/$(1)/lib/%.o: src/%.c | $(BUILD)/$(1)/lib
	@mkdir -p $$(@D)
	$$(CC) $$(DEPFLAGS) $$(WARN) $(3) $$(CPPFLAGS_LIB) -c $$< -o $$@
$(BUILD)/$(1)/librfe_q31.a: $(patsubst src/%.c,$(BUILD)/$(1)/lib/%.o,$(Q31_SRC))
	rm -f $$@ && ar rcs $$@ $$^
$(BUILD)/$(1)/test/%: test/%.c $(BUILD)/$(1)/librfe_q31.a $(BUILD)/$(2)/librfe.a $(patsubst test/support/%.c,$(BUILD)/$(2)/support/%.o,$(TEST_SUPPORT)) $(BUILD)/$(2)/hostlib.a $(BUILD)/$(2)/host/replay_real.o $(BUILD)/$(2)/host/replay_q31.o
	@mkdir -p $$(@D)
	$$(CC) $$(DEPFLAGS) $$(TEST_WARN) $(3) -DRFE_REAL_DOUBLE $$(CPPFLAGS_HOST) -Itest/support -Isrc $$< \
	  $(patsubst test/support/%.c,$(BUILD)/$(2)/support/%.o,$(TEST_SUPPORT)) \
	  $(BUILD)/$(2)/host/replay_q31.o $(BUILD)/$(2)/host/replay_real.o $(BUILD)/$(2)/hostlib.a $(BUILD)/$(1)/librfe_q31.a \
	  $(BUILD)/$(2)/librfe.a $$(LDLIBS_TEST) -o $$@
$(BUILD)/$(1)/lib:
	mkdir -p $$@
endef
$(eval $(call Q31_RULES,q31,f64,$(OPT)))
$(eval $(call Q31_RULES,cov-q31,cov-f64,$(COVFLAGS)))
$(eval $(call Q31_RULES,asan-q31,asan-f64,$(SANFLAGS)))

# The host tests (built in the double trees) also link the fixed-point replay (replay_q31.o
# and the q31 library of the same kind), so test_replay.c checks `--real q31` beside the
# double runs. Its stem is shorter than that of FLAVOUR_RULES' test rule, so make takes it.
define HOST_TEST_RULES
# $(1) = double tree, $(2) = its q31 tree, $(3) = extra compile flags
$(BUILD)/$(1)/test/host/%: test/host/%.c $(BUILD)/$(1)/librfe.a $(patsubst test/support/%.c,$(BUILD)/$(1)/support/%.o,$(TEST_SUPPORT)) $(BUILD)/$(1)/hostlib.a $(BUILD)/$(1)/host/replay_real.o $(BUILD)/$(1)/host/replay_q31.o $(BUILD)/$(2)/librfe_q31.a
	@mkdir -p $$(@D)
	$$(CC) $$(DEPFLAGS) $$(TEST_WARN) $(3) -DRFE_REAL_DOUBLE $$(CPPFLAGS_HOST) -Itest/support -Isrc $$< \
	  $(patsubst test/support/%.c,$(BUILD)/$(1)/support/%.o,$(TEST_SUPPORT)) \
	  $(BUILD)/$(1)/host/replay_q31.o $(BUILD)/$(1)/host/replay_real.o $(BUILD)/$(1)/hostlib.a \
	  $(BUILD)/$(2)/librfe_q31.a $(BUILD)/$(1)/librfe.a $$(LDLIBS_TEST) -o $$@
# test_replay_mem: the in-memory replay (replay_mem.c) with mu_replay's set-up (mu_replay.c,
# main renamed as the Python package builds it) and the float replay (its f32 twin tree) too.
$(BUILD)/$(1)/test/host/test_replay_mem: test/host/test_replay_mem.c $(BUILD)/$(1)/host/mu_replay_lib.o \
    $(BUILD)/$(1)/host/replay_mem.o $(BUILD)/$(subst f64,f32,$(1))/host/replay_real.o \
    $(BUILD)/$(subst f64,f32,$(1))/librfe.a $(BUILD)/$(1)/librfe.a $(BUILD)/$(1)/hostlib.a \
    $(BUILD)/$(1)/host/replay_real.o $(BUILD)/$(1)/host/replay_q31.o $(BUILD)/$(2)/librfe_q31.a \
    $(patsubst test/support/%.c,$(BUILD)/$(1)/support/%.o,$(TEST_SUPPORT))
	@mkdir -p $$(@D)
	$$(CC) $$(DEPFLAGS) $$(TEST_WARN) $(3) -DRFE_REAL_DOUBLE $$(CPPFLAGS_HOST) -Itest/support -Isrc $$< \
	  $(patsubst test/support/%.c,$(BUILD)/$(1)/support/%.o,$(TEST_SUPPORT)) \
	  $(BUILD)/$(1)/host/mu_replay_lib.o $(BUILD)/$(1)/host/replay_mem.o \
	  $(BUILD)/$(subst f64,f32,$(1))/host/replay_real.o $(BUILD)/$(1)/host/replay_q31.o \
	  $(BUILD)/$(1)/host/replay_real.o $(BUILD)/$(1)/hostlib.a $(BUILD)/$(2)/librfe_q31.a \
	  $(BUILD)/$(subst f64,f32,$(1))/librfe.a $(BUILD)/$(1)/librfe.a $$(LDLIBS_TEST) -o $$@
$(BUILD)/$(1)/host/mu_replay_lib.o: src/host/mu_replay.c | $(BUILD)/$(1)/host
	$$(CC) $$(DEPFLAGS) $$(WARN) $(3) -Dmain=rfe_mu_replay_main $$(CPPFLAGS_HOST) -c $$< -o $$@
endef
$(eval $(call HOST_TEST_RULES,f64,q31,$(OPT)))
$(eval $(call HOST_TEST_RULES,cov-f64,cov-q31,$(COVFLAGS)))
$(eval $(call HOST_TEST_RULES,asan-f64,asan-q31,$(SANFLAGS)))

# mu_replay: precision-independent host code once, the replay core twice (float, double),
# and the fixed-point replay (replay_q31.o, a double unit) with the q31 library.
define REPLAY_RULE
# $(1) = output, $(2) = f32 tree, $(3) = f64 tree, $(4) = flags, $(5) = q31 tree
$(1): src/host/mu_replay.c src/host/replay_mem.c $(BUILD)/$(2)/host/replay_real.o $(BUILD)/$(3)/host/replay_real.o \
      $(BUILD)/$(3)/host/replay_q31.o $(BUILD)/$(3)/hostlib.a $(BUILD)/$(5)/librfe_q31.a \
      $(BUILD)/$(2)/librfe.a $(BUILD)/$(3)/librfe.a
	$$(CC) $$(DEPFLAGS) $$(WARN) $(4) $$(CPPFLAGS_HOST) $$(filter %.c %.o %.a,$$^) -lm -o $$@
endef
$(eval $(call REPLAY_RULE,$(BUILD)/mu_replay,f32,f64,$(OPT),q31))
$(eval $(call REPLAY_RULE,$(BUILD)/cov-mu_replay,cov-f32,cov-f64,$(COVFLAGS),cov-q31))
$(eval $(call REPLAY_RULE,$(BUILD)/asan-mu_replay,asan-f32,asan-f64,$(SANFLAGS),asan-q31))

# Keep intermediate objects (test support) so a second make does not rebuild them.
.SECONDARY:

# The header dependencies of everything built so far (none before the first build).
-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
