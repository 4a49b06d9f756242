# rfe — road-friction estimator (SCKF, 3-DOF vehicle model, Dugoff tyre), C99.
#
#   make            library (float32 and double builds) and build/mu_replay
#   make demo       run the estimator on the bundled scenarios, print accuracy, draw plots
#   make test       all tests (C unit + golden + host + Python) and the coverage gate
#   make coverage   gcovr HTML / Cobertura XML / text summary for src/, with thresholds
#   make sanitize   the C tests built with ASan + UBSan (build/asan-*) and run
#   make valgrind   the optimised C tests and the CLI script run under valgrind memcheck
#   make goldens    regenerate scenarios/*.csv and scenarios/golden/ from the Python tools
#   make readme-table  regenerate the accuracy table in README.md
#
# `make demo` and `make test` install what they need when it is missing: cmocka via apt,
# and a Python venv (.venv) from the pinned scripts/requirements.txt.

CC      ?= gcc
ifeq ($(origin CC),default)
CC      := gcc
endif
BUILD   := build
VENV    := .venv
PY      := $(VENV)/bin/python
PYSTAMP := $(VENV)/.installed

# Strict flags for library code (the rules of the project: C99, every warning an error).
WARN := -std=c99 -pedantic -Wall -Wextra -Wconversion -Wsign-conversion -Wshadow \
        -Wdouble-promotion -Wcast-qual -Wstrict-prototypes -Wundef -Werror
OPT  ?= -O2 -g
CPPFLAGS_LIB  := -Iinclude
CPPFLAGS_HOST := -Iinclude -Isrc/host -D_POSIX_C_SOURCE=200809L
# Tests: strict, except the conversions cmocka's macros trip over and truncation of
# diagnostic messages (harmless in a test).
TEST_WARN := -std=c99 -Wall -Wextra -Wshadow -Werror -Wno-unused-parameter -Wno-format-truncation
LDLIBS_TEST := -lcmocka -lm

# ---- sources -------------------------------------------------------------------------
LIB_SRC       := $(wildcard src/*.c)
HOST_SRC      := $(filter-out src/host/mu_replay.c src/host/replay_real.c,$(wildcard src/host/*.c))
UNIT_TESTS    := $(basename $(notdir $(wildcard test/test_*.c)))
HOST_TESTS    := $(basename $(notdir $(wildcard test/host/test_*.c)))
TEST_SUPPORT  := $(wildcard test/support/*.c)

# One build tree per flavour: f32 (float), f64 (double); cov-* are the instrumented twins.
define FLAVOUR_RULES
# $(1) = tree name, $(2) = real-type defines, $(3) = extra compile flags
$(BUILD)/$(1)/lib/%.o: src/%.c $(wildcard include/rfe/*.h src/*.h) | $(BUILD)/$(1)/lib
	$$(CC) $$(WARN) $(3) $(2) $$(CPPFLAGS_LIB) -c $$< -o $$@
$(BUILD)/$(1)/librfe.a: $(patsubst src/%.c,$(BUILD)/$(1)/lib/%.o,$(LIB_SRC))
	rm -f $$@ && ar rcs $$@ $$^
$(BUILD)/$(1)/host/replay_real.o: src/host/replay_real.c $(wildcard src/host/*.h include/rfe/*.h) | $(BUILD)/$(1)/host
	$$(CC) $$(WARN) $(3) $(2) $$(CPPFLAGS_HOST) -c $$< -o $$@
$(BUILD)/$(1)/support/%.o: test/support/%.c $(wildcard test/support/*.h src/host/*.h include/rfe/*.h) | $(BUILD)/$(1)/support
	$$(CC) $$(TEST_WARN) $(3) $(2) $$(CPPFLAGS_HOST) -Itest/support -c $$< -o $$@
$(BUILD)/$(1)/test/%: test/%.c $(BUILD)/$(1)/librfe.a $(patsubst test/support/%.c,$(BUILD)/$(1)/support/%.o,$(TEST_SUPPORT)) $(BUILD)/$(1)/hostlib.a $(BUILD)/$(1)/host/replay_real.o
	@mkdir -p $$(@D)
	$$(CC) $$(TEST_WARN) $(3) $(2) $$(CPPFLAGS_HOST) -Itest/support -Isrc $$< \
	  $(patsubst test/support/%.c,$(BUILD)/$(1)/support/%.o,$(TEST_SUPPORT)) \
	  $(BUILD)/$(1)/host/replay_real.o $(BUILD)/$(1)/hostlib.a $(BUILD)/$(1)/librfe.a $$(LDLIBS_TEST) -o $$@
$(BUILD)/$(1)/hostlib.a: $(patsubst src/host/%.c,$(BUILD)/$(1)/host/%.o,$(HOST_SRC))
	rm -f $$@ && ar rcs $$@ $$^
$(BUILD)/$(1)/host/%.o: src/host/%.c $(wildcard src/host/*.h include/rfe/*.h) | $(BUILD)/$(1)/host
	$$(CC) $$(WARN) $(3) $$(CPPFLAGS_HOST) -c $$< -o $$@
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

# mu_replay: precision-independent host code once, the replay core twice (float, double).
define REPLAY_RULE
# $(1) = output, $(2) = f32 tree, $(3) = f64 tree, $(4) = flags
$(1): src/host/mu_replay.c $(BUILD)/$(2)/host/replay_real.o $(BUILD)/$(3)/host/replay_real.o \
      $(BUILD)/$(3)/hostlib.a $(BUILD)/$(2)/librfe.a $(BUILD)/$(3)/librfe.a
	$$(CC) $$(WARN) $(4) $$(CPPFLAGS_HOST) $$^ -lm -o $$@
endef
$(eval $(call REPLAY_RULE,$(BUILD)/mu_replay,f32,f64,$(OPT)))
$(eval $(call REPLAY_RULE,$(BUILD)/cov-mu_replay,cov-f32,cov-f64,$(COVFLAGS)))
$(eval $(call REPLAY_RULE,$(BUILD)/asan-mu_replay,asan-f32,asan-f64,$(SANFLAGS)))

# Keep intermediate objects (test support) so a second make does not rebuild them.
.SECONDARY:

.PHONY: all lib deps deps-c deps-valgrind venv test test-c test-py sanitize valgrind coverage demo goldens scenarios clean vectors shared-sync check-shared readme-table \
        check-goldens help
all: lib $(BUILD)/mu_replay
lib: $(BUILD)/f32/librfe.a $(BUILD)/f64/librfe.a

help:
	@sed -n '1,14p' Makefile

# ---- dependencies (installed when missing) --------------------------------------------
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
deps-c:
	@if [ ! -f /usr/include/cmocka.h ]; then \
	  echo "[deps] installing libcmocka-dev via apt"; \
	  $(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq libcmocka-dev; fi
deps-valgrind:
	@if ! command -v valgrind >/dev/null 2>&1; then \
	  echo "[deps] installing valgrind via apt"; \
	  $(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq valgrind; fi

$(PYSTAMP): scripts/requirements.txt
	@echo "[deps] creating Python venv $(VENV) from scripts/requirements.txt"
	python3 -m venv $(VENV)
	$(VENV)/bin/pip install -q --upgrade pip
	$(VENV)/bin/pip install -q -r scripts/requirements.txt
	touch $@
venv: $(PYSTAMP)
deps: deps-c venv

# ---- tests -----------------------------------------------------------------------------
# Unit and golden tests run in both precisions; host tests once.
run_tests = set -e; for t in $(UNIT_TESTS); do echo "== $(1)/$$t"; $(BUILD)/$(1)/test/$$t; done

test-c: deps-c $(foreach f,f32 f64,$(addprefix $(BUILD)/$(f)/test/,$(UNIT_TESTS))) \
        $(addprefix $(BUILD)/f64/test/host/,$(HOST_TESTS)) $(BUILD)/mu_replay
	@$(call run_tests,f32)
	@$(call run_tests,f64)
	@set -e; for t in $(HOST_TESTS); do echo "== host/$$t"; $(BUILD)/f64/test/host/$$t; done
	@if [ -f test/host/test_cli.sh ]; then echo "== cli"; bash test/host/test_cli.sh $(BUILD)/mu_replay; fi

# The same tests built with ASan + UBSan (build/asan-*); any report fails the run. ASan
# aborts (exit 134); for the CLI script UBSan exits 98, so a report can never pass for one of
# the CLI's own exit codes (0, 1, 2) that test_cli.sh expects.
SAN_ENV := ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
sanitize: deps-c $(foreach f,asan-f32 asan-f64,$(addprefix $(BUILD)/$(f)/test/,$(UNIT_TESTS))) \
          $(addprefix $(BUILD)/asan-f64/test/host/,$(HOST_TESTS)) $(BUILD)/asan-mu_replay
	@export $(SAN_ENV); $(call run_tests,asan-f32)
	@export $(SAN_ENV); $(call run_tests,asan-f64)
	@export $(SAN_ENV); set -e; for t in $(HOST_TESTS); do echo "== asan host/$$t"; $(BUILD)/asan-f64/test/host/$$t; done
	@if [ -f test/host/test_cli.sh ]; then echo "== asan cli"; export $(SAN_ENV); \
	  export UBSAN_OPTIONS=$$UBSAN_OPTIONS:exitcode=98; bash test/host/test_cli.sh $(BUILD)/asan-mu_replay; fi
	@echo "sanitize: all tests clean under ASan + UBSan"

# The optimised test binaries under valgrind memcheck. Exit code 99 = a valgrind error (the
# CLI itself uses 1 and 2); test/support/valgrind_wrap.sh runs mu_replay for test_cli.sh and
# records every such run in $(BUILD)/valgrind-cli.log, which must stay empty.
VALGRIND := valgrind --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite,indirect -q
valgrind: deps-c deps-valgrind $(foreach f,f32 f64,$(addprefix $(BUILD)/$(f)/test/,$(UNIT_TESTS))) \
          $(addprefix $(BUILD)/f64/test/host/,$(HOST_TESTS)) $(BUILD)/mu_replay
	@set -e; for f in f32 f64; do for t in $(UNIT_TESTS); do echo "== valgrind $$f/$$t"; \
	  $(VALGRIND) $(BUILD)/$$f/test/$$t; done; done
	@set -e; for t in $(HOST_TESTS); do echo "== valgrind host/$$t"; $(VALGRIND) $(BUILD)/f64/test/host/$$t; done
	@if [ -f test/host/test_cli.sh ]; then echo "== valgrind cli"; rm -f $(BUILD)/valgrind-cli.log; \
	  VALGRIND_WRAP_BIN=$(abspath $(BUILD)/mu_replay) VALGRIND_WRAP_LOG=$(abspath $(BUILD)/valgrind-cli.log) \
	  bash test/host/test_cli.sh test/support/valgrind_wrap.sh; \
	  if [ -s $(BUILD)/valgrind-cli.log ]; then cat $(BUILD)/valgrind-cli.log; exit 1; fi; fi
	@echo "valgrind: all tests clean under memcheck"

test-py: venv
	$(PY) -m pytest -q -p no:cacheprovider scripts

COV_MIN_LINES    := 95
COV_MIN_BRANCHES := 85
coverage: deps $(foreach f,cov-f32 cov-f64,$(addprefix $(BUILD)/$(f)/test/,$(UNIT_TESTS))) \
          $(addprefix $(BUILD)/cov-f64/test/host/,$(HOST_TESTS)) $(BUILD)/cov-mu_replay
	@find $(BUILD) -name '*.gcda' -delete
	@$(call run_tests,cov-f32) >/dev/null
	@$(call run_tests,cov-f64) >/dev/null
	@set -e; for t in $(HOST_TESTS); do $(BUILD)/cov-f64/test/host/$$t >/dev/null; done
	@if [ -f test/host/test_cli.sh ]; then bash test/host/test_cli.sh $(BUILD)/cov-mu_replay >/dev/null; fi
	@mkdir -p $(BUILD)/coverage
	$(VENV)/bin/gcovr --root . --filter 'src/' --exclude-unreachable-branches \
	  --html-details $(BUILD)/coverage/index.html --cobertura $(BUILD)/coverage/coverage.xml \
	  --txt $(BUILD)/coverage/summary.txt --print-summary \
	  --fail-under-line $(COV_MIN_LINES) --fail-under-branch $(COV_MIN_BRANCHES) \
	  $(BUILD)/cov-f32 $(BUILD)/cov-f64 $(BUILD)
	@cat $(BUILD)/coverage/summary.txt
	@echo "coverage report: $(BUILD)/coverage/index.html (per-file detail), coverage.xml (Cobertura)"

test: deps lib check-shared test-c sanitize valgrind test-py coverage
	@echo "make test: all tests passed, coverage gate met"

# $(BUILD)/f64/test/host/test_x comes from test/host/test_x.c through the pattern rule.

# ---- demo, goldens ---------------------------------------------------------------------
demo: deps $(BUILD)/mu_replay
	$(PY) scripts/demo.py --replay $(BUILD)/mu_replay --out $(BUILD)/demo --trust

# Regenerates the accuracy table in README.md (never typed by hand).
readme-table: deps $(BUILD)/mu_replay
	$(PY) scripts/demo.py --replay $(BUILD)/mu_replay --out $(BUILD)/demo --no-plots --trust --readme README.md

scenarios: venv
	$(PY) scripts/make_scenarios.py --out scenarios
goldens: scenarios
	$(PY) scripts/make_goldens.py --scenarios scenarios --out scenarios/golden

# The specification (MODEL.md, DATA.md) and the test vectors of the independent
# implementation live in the project's shared folder (../shared); copies sit in docs/spec
# and test/vectors so a clone is self-contained. This refreshes the copies.
SHARED ?= ../shared
shared-sync:
	cp $(SHARED)/docs/MODEL.md $(SHARED)/docs/DATA.md docs/spec/
	cp $(SHARED)/vectors/model_vectors.csv $(SHARED)/vectors/sckf_step_vectors.csv test/vectors/
vectors: shared-sync
# Fails when the copies differ from ../shared (where it exists): run `make shared-sync`.
check-shared:
	@if [ -d $(SHARED) ]; then \
	  for f in docs/MODEL.md docs/DATA.md vectors/model_vectors.csv vectors/sckf_step_vectors.csv; do \
	    copy=$$(case $$f in docs/*) echo docs/spec/$${f#docs/};; *) echo test/$$f;; esac); \
	    cmp -s $(SHARED)/$$f $$copy || { echo "$$copy differs from $(SHARED)/$$f: run make shared-sync"; exit 1; }; \
	  done; echo "shared copies: up to date"; \
	else echo "shared copies: $(SHARED) not present, not checked"; fi

clean:
	rm -rf $(BUILD)
