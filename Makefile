# rfe — road-friction estimator (SCKF, 3-DOF vehicle model, Magic Formula / Dugoff tyre), C99.
#
#   make help       every target with one line on what it does (from the ## lines above
#                   each rule); the README's two commands are make demo and make test.
#
# `make demo` and `make test` install what they need when it is missing (apt: cmocka, the
# Cortex-M toolchain, newlib, QEMU, valgrind, cppcheck, clang/LLVM 19; a Python venv .venv
# from the pinned scripts/requirements.txt).

# Every recipe runs in the C locale and UTC, Python in UTF-8 mode: sort order, character
# ranges of grep and sed, printf's number format, the linker's quoting that the no-float
# check parses, and the encoding Python opens files with then do not depend on the user's
# settings (docs/PORTABILITY.md).
export LC_ALL     := C
export TZ         := UTC
export PYTHONUTF8 := 1

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
CPPFLAGS_LIB  := -Iinclude -Isrc
CPPFLAGS_HOST := -Iinclude -Isrc -Isrc/host -D_POSIX_C_SOURCE=200809L
# Tests: strict, except the conversions cmocka's macros trip over and truncation of
# diagnostic messages (harmless in a test).
TEST_WARN := -std=c99 -Wall -Wextra -Wshadow -Werror -Wno-unused-parameter -Wno-format-truncation
LDLIBS_TEST := -lcmocka -lm

# The library, the host code and the test binaries in every build tree: mk/lib.mk (first,
# since the other fragments reuse its rules for their trees).
include mk/lib.mk

# One file per further concern (mk/*.mk: robustness, firmware, benchmarks, evidence). Each
# adds its installers to DEPS_EXTRA and the checks that gate to TEST_GATES (run by make test
# after the unit tests).
DEPS_EXTRA :=
TEST_GATES :=
include $(sort $(filter-out mk/lib.mk,$(wildcard mk/*.mk)))

.PHONY: deps-apt figures mass-grade-scenarios observer-res-scenarios observer-loop-scenarios mass-grade-results mass-grade-textbook mass-sensitivity mass-headwind mass-slip mass-slip-ramp mass-curve mass-curve-pause mass-pause-grade mass-grade-walk mass-offset mass-gust tyre-id-feed-results tyre-id-trust mass-grade-goldens trust-invariant names car-format-logs observer-goldens observer-goldens-q31 observer-results monitor-results shape-results test-pkg all lib deps deps-c deps-valgrind deps-arm venv test test-c test-py sanitize valgrind valgrind-unit valgrind-cli coverage demo goldens goldens-q31 scenarios observer-scenarios clean vectors shared-sync check-shared readme-table \
        check-kernels check-tools layers help-check goldens-ref check-nofloat help deps-analysis misra tidy complexity structural analysis \
        twins check-twins tyre-id-scenarios tyre-id-results tyre-id-goldens tyre-id-ellipse-results \
        tyre-id-results-ellipse tyre-id-results-delta-filter tyre-id-results-delta-state tyre-id-results-spread tyre-id-bound tyre-id-targets tyre-id-m4-count snoise-reuse snoise-reuse-vxvy
## the libraries and build/mu_replay (the default target)
all: lib $(BUILD)/mu_replay
## the float, double and fixed-point libraries (build/{f32,f64,q31}/)
lib: $(BUILD)/f32/librfe.a $(BUILD)/f64/librfe.a $(if $(Q31_SRC),$(BUILD)/q31/librfe_q31.a)

## this list, generated from the ## lines of the Makefiles
help:
	@python3 scripts/checks/make_help.py
## every .PHONY target has its ## description (so make help cannot drift)
help-check:
	@python3 scripts/checks/make_help.py --check

# ---- dependencies (installed when missing) --------------------------------------------
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
## install libcmocka-dev (apt) when it is missing
deps-c:
	@if [ ! -f /usr/include/cmocka.h ]; then \
	  echo "[deps] installing libcmocka-dev via apt"; \
	  $(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq libcmocka-dev; fi
## install valgrind (apt) when it is missing
deps-valgrind:
	@if ! command -v valgrind >/dev/null 2>&1; then \
	  echo "[deps] installing valgrind via apt"; \
	  $(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq valgrind; fi
# Cortex-M0+ cross compiler for check-nofloat (the link uses libgcc only, so newlib, which
# apt would add as a recommendation, is not installed).
## install the Cortex-M cross compiler gcc-arm-none-eabi (apt) when it is missing
deps-arm:
	@if ! command -v arm-none-eabi-gcc >/dev/null 2>&1; then \
	  echo "[deps] installing gcc-arm-none-eabi via apt"; \
	  $(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq --no-install-recommends gcc-arm-none-eabi; fi

$(PYSTAMP): scripts/requirements.txt
	@echo "[deps] creating Python venv $(VENV) from scripts/requirements.txt"
	python3 -m venv $(VENV)
	$(VENV)/bin/pip install -q --upgrade pip
	$(VENV)/bin/pip install -q -r scripts/requirements.txt
	touch $@
## the Python venv .venv from the pinned scripts/requirements.txt
venv: $(PYSTAMP)
## every installer above, each only when its tool is missing
deps: deps-apt venv
# make test runs the venv's pip install (~70 s, mostly download) as its first check, beside
# the C builds, instead of before them.
## the system packages alone (deps without the venv)
deps-apt: deps-c deps-arm $(DEPS_EXTRA)

# ---- tests -----------------------------------------------------------------------------
# Unit and golden tests run in both precisions; host tests once. Each cmocka binary runs once,
# its results written as JUnit XML to $(RESULTS)/<tree>/<test>.xml (read by the traceability
# gate, mk/evidence.mk) and its console output to <test>.log beside it; one line per binary,
# and when it fails its log and the failures, on stderr.
RESULTS := $(BUILD)/results
# $(1) = label, $(2) = binary, $(3) = results directory
run_cmocka = x=$(3)/$$(basename $(2)).xml; l=$(3)/$$(basename $(2)).log; rm -f $$x; \
  if CMOCKA_MESSAGE_OUTPUT=XML CMOCKA_XML_FILE=$$x $(2) >$$l 2>&1; then \
    n=$$(grep -c '<testcase ' $$x 2>/dev/null || true); s=$$(grep -c '<skipped' $$x 2>/dev/null || true); \
    n=$${n:-0}; s=$${s:-0}; echo "== $(1): $$((n - s)) passed$$([ "$$s" = 0 ] || echo ", $$s skipped")"; \
  else rc=$$?; { cat $$l; [ ! -f $$x ] || sed -n '/<failure>/,/<\/failure>/p' $$x; \
    echo "== $(1): FAILED (exit $$rc; log $$l)"; } >&2; exit 1; fi
run_tests = set -e; rm -rf $(RESULTS)/$(1); mkdir -p $(RESULTS)/$(1); \
  for t in $(UNIT_TESTS); do $(call run_cmocka,$(1)/$$t,$(BUILD)/$(1)/test/$$t,$(RESULTS)/$(1)); done
# Fixed-point tests, once per tree (q31, asan-q31, cov-q31).
run_q31_tests = set -e; rm -rf $(RESULTS)/$(1); mkdir -p $(RESULTS)/$(1); \
  for t in $(Q31_TESTS); do $(call run_cmocka,$(1)/$$t,$(BUILD)/$(1)/test/$$t,$(RESULTS)/$(1)); done
# Host tests (test/host/*.c, built in the double tree $(1)) into $(RESULTS)/$(2).
run_host_tests = set -e; rm -rf $(RESULTS)/$(2); mkdir -p $(RESULTS)/$(2); \
  for t in $(HOST_TESTS); do $(call run_cmocka,host/$$t,$(BUILD)/$(1)/test/host/$$t,$(RESULTS)/$(2)); done
# The CLI script ($(1) = mu_replay) as one JUnit test case "test_cli" in $(RESULTS)/cli.
run_cli_test = if [ -f test/host/test_cli.sh ]; then mkdir -p $(RESULTS)/cli; l=$(RESULTS)/cli/test_cli.log; \
  if bash test/host/test_cli.sh $(1) >$$l 2>&1; then r=''; else r='<failure><![CDATA[see test_cli.log]]></failure>'; fi; \
  printf '<?xml version="1.0" encoding="UTF-8" ?>\n<testsuites><testsuite name="test_cli" tests="1" failures="%d">\n<testcase name="test_cli">%s</testcase>\n</testsuite></testsuites>\n' \
    $$([ -z "$$r" ] && echo 0 || echo 1) "$$r" >$(RESULTS)/cli/test_cli.xml; \
  if [ -z "$$r" ]; then echo "== $$(tail -n 1 $$l)"; else cat $$l >&2; echo "== cli: FAILED (log $$l)" >&2; exit 1; fi; fi

## the C tests: float, double, fixed point, host, and the CLI script
test-c: deps-c $(foreach f,f32 f64,$(addprefix $(BUILD)/$(f)/test/,$(UNIT_TESTS))) \
        $(addprefix $(BUILD)/q31/test/,$(Q31_TESTS) $(W16_TESTS)) \
        $(addprefix $(BUILD)/f64/test/host/,$(HOST_TESTS)) $(BUILD)/mu_replay \
        $(BUILD)/abi/test_abi_mismatch_flt $(BUILD)/abi/test_abi_mismatch_q31
	@$(call run_tests,f32)
	@$(call run_tests,f64)
	@$(call run_q31_tests,q31)
	@set -e; for t in $(W16_TESTS); do $(call run_cmocka,q31/$$t,$(BUILD)/q31/test/$$t,$(RESULTS)/q31); done
	@$(call run_host_tests,f64,host)
	@$(call run_cmocka,abi/test_abi_mismatch_flt,$(BUILD)/abi/test_abi_mismatch_flt,$(RESULTS)/host)
	@$(call run_cmocka,abi/test_abi_mismatch_q31,$(BUILD)/abi/test_abi_mismatch_q31,$(RESULTS)/host)
	@$(call run_cli_test,$(BUILD)/mu_replay)

# The ABI guard (REQ-ABI-001, rfe/config.h RFE_CONFIG_*): a test compiled with other maxima
# (the README's firmware build) and linked against the libraries built with the defaults, as
# an application linking a prebuilt librfe.a; its results go with the host tests'.
ABI_MISMATCH := -DRFE_N_MAX=4 -DRFE_M_MAX=3
$(BUILD)/abi/test_abi_mismatch_flt: test/abi/test_abi_mismatch_flt.c $(BUILD)/f32/librfe.a
	@mkdir -p $(@D)
	$(CC) $(DEPFLAGS) $(TEST_WARN) $(ABI_MISMATCH) $(CPPFLAGS_HOST) $< $(BUILD)/f32/librfe.a $(LDLIBS_TEST) -o $@
$(BUILD)/abi/test_abi_mismatch_q31: test/abi/test_abi_mismatch_q31.c $(BUILD)/q31/librfe_q31.a
	@mkdir -p $(@D)
	$(CC) $(DEPFLAGS) $(TEST_WARN) $(ABI_MISMATCH) $(CPPFLAGS_HOST) $< $(BUILD)/q31/librfe_q31.a $(LDLIBS_TEST) -o $@
-include $(wildcard $(BUILD)/abi/*.d)

# The same tests built with ASan + UBSan (build/asan-*); any report fails the run. ASan
# aborts (exit 134); for the CLI script UBSan exits 98, so a report can never pass for one of
# the CLI's own exit codes (0, 1, 2) that test_cli.sh expects.
SAN_ENV := ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
## the C tests and the CLI under ASan + UBSan
sanitize: deps-c $(foreach f,asan-f32 asan-f64,$(addprefix $(BUILD)/$(f)/test/,$(UNIT_TESTS))) \
          $(addprefix $(BUILD)/asan-q31/test/,$(Q31_TESTS)) \
          $(addprefix $(BUILD)/asan-f64/test/host/,$(HOST_TESTS)) $(BUILD)/asan-mu_replay
	@export $(SAN_ENV); $(call run_tests,asan-f32)
	@export $(SAN_ENV); $(call run_tests,asan-f64)
	@export $(SAN_ENV); $(call run_q31_tests,asan-q31)
	@export $(SAN_ENV); set -e; for t in $(HOST_TESTS); do echo "== asan host/$$t"; $(BUILD)/asan-f64/test/host/$$t; done
	@if [ -f test/host/test_cli.sh ]; then echo "== asan cli"; export $(SAN_ENV); \
	  export UBSAN_OPTIONS=$$UBSAN_OPTIONS:exitcode=98; bash test/host/test_cli.sh $(BUILD)/asan-mu_replay; fi
	@echo "sanitize: all tests clean under ASan + UBSan"

# The optimised test binaries under valgrind memcheck. Exit code 99 = a valgrind error (the
# CLI itself uses 1 and 2); test/support/valgrind_wrap.sh runs mu_replay for test_cli.sh and
# records every such run in $(BUILD)/valgrind-cli.log, which must stay empty.
# --read-inline-info=no: a report's stack names the enclosing functions, not the inlined ones;
# it saves a fifth of valgrind's ~0.35 s start, which the CLI script pays ~300 times.
VALGRIND := valgrind --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite,indirect -q \
            --read-inline-info=no
# The unit tests run under valgrind side by side, one per core (each is single-threaded and
# valgrind is ~50x slower than native; the q31 back-to-back tests and the host replay tests
# are the long ones, so they start first; the host tests read their files relative to the
# repository root, where make runs). A failing test's log is printed and stops the run
# (xargs: exit 255).
# RFE_TEST_LIGHT=1: the long back-to-back tests walk a subset of their logs and random
# inputs (test/support/test_light.h); the full sets run natively, under ASan and in coverage.
# The float tests run under memcheck in their double build only: the float and double
# libraries are one source compiled twice (rfe_real_t), so memcheck of the double build walks
# the same code; the float build runs under ASan + UBSan (make sanitize), in full.
VALGRIND_JOBS ?= $(shell nproc 2>/dev/null || echo 1)
# Two halves, so that make test can run the CLI script's memcheck (serial, minutes) beside
# the unit tests' instead of after them.
## the C tests and the CLI under valgrind memcheck
valgrind: valgrind-unit valgrind-cli
	@echo "valgrind: all tests clean under memcheck"
## the unit and host tests under valgrind memcheck
valgrind-unit: deps-c deps-valgrind $(addprefix $(BUILD)/f64/test/,$(UNIT_TESTS)) \
          $(addprefix $(BUILD)/q31/test/,$(Q31_TESTS)) \
          $(addprefix $(BUILD)/f64/test/host/,$(HOST_TESTS))
	@mkdir -p $(BUILD)/valgrind; \
	{ for t in $(Q31_TESTS); do echo $(BUILD)/q31/test/$$t; done; \
	  for t in $(HOST_TESTS); do echo $(BUILD)/f64/test/host/$$t; done; \
	  for t in $(UNIT_TESTS); do echo $(BUILD)/f64/test/$$t; done; } | \
	RFE_TEST_LIGHT=1 xargs -P $(VALGRIND_JOBS) -I{} sh -c 'log=$(BUILD)/valgrind/$$(echo {} | tr / _).log; \
	  if $(VALGRIND) {} > $$log 2>&1; then echo "== valgrind {}: clean"; \
	  else cat $$log; echo "== valgrind {}: FAILED (log $$log)"; exit 255; fi'
## the CLI script with every mu_replay run under valgrind memcheck
valgrind-cli: deps-c deps-valgrind $(BUILD)/mu_replay
	@if [ -f test/host/test_cli.sh ]; then echo "== valgrind cli"; rm -f $(BUILD)/valgrind-cli.log; \
	  RFE_TEST_LIGHT=1 VALGRIND_WRAP_BIN=$(abspath $(BUILD)/mu_replay) VALGRIND_WRAP_LOG=$(abspath $(BUILD)/valgrind-cli.log) \
	  bash test/host/test_cli.sh test/support/valgrind_wrap.sh; \
	  if [ -s $(BUILD)/valgrind-cli.log ]; then cat $(BUILD)/valgrind-cli.log; exit 1; fi; fi

# (mu_replay: the demo's tests run it)
## the Python tests (simulator, reference, tools)
test-py: venv $(BUILD)/mu_replay
	@mkdir -p $(RESULTS)/py
	$(PY) -m pytest -q -p no:cacheprovider scripts --junitxml=$(RESULTS)/py/pytest.xml

# The Python package (docs/PYTHON.md): pip builds it from pyproject.toml and setup.py (the C
# sources of LIB_DIRS and src/host/, compiled as mu_replay's) into $(BUILD)/py, not into the
# venv; without build isolation, from the venv's pinned setuptools and cffi, so the build
# needs no network and no version but the pinned ones. Its tests then compare it with
# $(BUILD)/mu_replay.
PKG_DIR := $(BUILD)/py
## the Python package rfe built into build/py, and its tests against mu_replay
test-pkg: venv $(BUILD)/mu_replay
	@rm -rf $(PKG_DIR) && mkdir -p $(RESULTS)/pkg
	@RFE_BUILD_JOBS=$(TEST_JOBS) $(VENV)/bin/pip install -q --no-build-isolation --no-deps \
	  --no-cache-dir --target $(PKG_DIR) . >$(BUILD)/pkg-build.log 2>&1 || \
	  { cat $(BUILD)/pkg-build.log; echo "test-pkg: the package build failed"; exit 1; }
	@echo "test-pkg: rfe built into $(PKG_DIR)"
	PYTHONPATH=$(abspath $(PKG_DIR)) MU_REPLAY=$(abspath $(BUILD)/mu_replay) $(PY) -m pytest -q \
	  -p no:cacheprovider python/tests --junitxml=$(RESULTS)/pkg/pytest.xml

# The fleet replay's speed (docs/PYTHON.md "Fleet replay"): a benchmark, not a test. The package
# is built into $(PKG_DIR) as test-pkg builds it.
.PHONY: fleet-bench
## logs per second of python -m rfe.fleet with 1 and 2 workers against a plain loop (docs/PYTHON.md)
fleet-bench: venv
	@mkdir -p $(BUILD)
	@RFE_BUILD_JOBS=$(TEST_JOBS) $(VENV)/bin/pip install -q --no-build-isolation --no-deps \
	  --no-cache-dir --target $(PKG_DIR) --upgrade . >$(BUILD)/pkg-build.log 2>&1 || \
	  { cat $(BUILD)/pkg-build.log; echo "fleet-bench: the package build failed"; exit 1; }
	PYTHONPATH=$(abspath $(PKG_DIR)) $(PY) scripts/bench/fleet_bench.py $(FLEET_BENCH_ARGS)

COV_MIN_LINES    := 95
COV_MIN_BRANCHES := 85
# The coverage run walks the light subsets (RFE_TEST_LIGHT=1, as valgrind does) of the long
# fixed-point tests in COV_LIGHT_TESTS: what it measures is which lines and branches the
# tests reach, and these tests' light subsets reach every one their full sets reach
# (measured: the same covered lines and branches, file by file, as with COV_LIGHT= ; the
# light subsets of test_velocity_q31, test_friction_q31, the step noise's and the host replay
# tests miss branches, so those run in full; test_meas_q31's derivative and column tests take
# no stride, ~0.5 s natively, so its light subset, the scenarios' and random samples', does not). The full sets' assertions run
# natively and under ASan + UBSan. COV_LIGHT= runs every test in full here too.
COV_LIGHT ?= RFE_TEST_LIGHT=1
COV_LIGHT_TESTS := numerics/test_fxmath_q31 filters/test_ckf_q31 filters/test_sckf_q31 models/test_meas_q31 \
  models/test_obsmat_q31 models/test_tyre_internal_q31 models/test_tyre_magic_q31 \
  models/test_tyre_q31 estimators/mass_grade/test_mass_grade_q31 \
  golden/test_golden_observer_q31 golden/test_golden_q31 robustness/test_faults_q31 \
  robustness/test_robust_q31
## gcov line and branch coverage of src/ with its gate and justifications
coverage: deps $(foreach f,cov-f32 cov-f64,$(addprefix $(BUILD)/$(f)/test/,$(UNIT_TESTS))) \
          $(addprefix $(BUILD)/cov-q31/test/,$(Q31_TESTS)) \
          $(addprefix $(BUILD)/cov-f64/test/host/,$(HOST_TESTS)) $(BUILD)/cov-mu_replay
	@find $(BUILD) -name '*.gcda' -delete
	@# every binary and the CLI script side by side, TEST_JOBS at a time (libgcov merges the
	@# counters of concurrent processes into each .gcda under a file lock); a failure prints
	@# its output and stops the run
	@mkdir -p $(BUILD)/cov-logs; \
	{ for t in $(filter $(COV_LIGHT_TESTS),$(Q31_TESTS)); do echo $(COV_LIGHT) $(BUILD)/cov-q31/test/$$t; done; \
	  for t in $(filter-out $(COV_LIGHT_TESTS),$(Q31_TESTS)); do echo $(BUILD)/cov-q31/test/$$t; done; \
	  for f in cov-f32 cov-f64; do for t in $(UNIT_TESTS); do echo $(BUILD)/$$f/test/$$t; done; done; \
	  for t in $(HOST_TESTS); do echo $(BUILD)/cov-f64/test/host/$$t; done; \
	  if [ -f test/host/test_cli.sh ]; then echo "bash test/host/test_cli.sh $(BUILD)/cov-mu_replay"; fi; } | \
	xargs -P $(TEST_JOBS) -I{} sh -c 'log=$(BUILD)/cov-logs/$$(echo "{}" | tr "/ " "__").log; \
	  if {} > $$log 2>&1; then :; else cat $$log; echo "== coverage run {}: FAILED (log $$log)"; exit 255; fi'
	@mkdir -p $(BUILD)/coverage
	@# (hit counts above 2^32 are real here: the q31 back-to-back tests execute the bit-length
	@# loop of internal_q31.h ~6e9 times; gcovr's default 2^32 "suspicious" threshold, meant for
	@# GCC bug 68080's wrapped counters, is raised to 2^40)
	$(VENV)/bin/gcovr --root . --filter 'src/' --exclude-unreachable-branches \
	  --gcov-suspicious-hits-threshold 1099511627776 \
	  --html-details $(BUILD)/coverage/index.html --cobertura $(BUILD)/coverage/coverage.xml \
	  --txt $(BUILD)/coverage/summary.txt --print-summary \
	  --fail-under-line $(COV_MIN_LINES) --fail-under-branch $(COV_MIN_BRANCHES) \
	  $(BUILD)/cov-f32 $(BUILD)/cov-f64 $(if $(Q31_SRC),$(BUILD)/cov-q31) $(BUILD)
	@cat $(BUILD)/coverage/summary.txt
	@echo "coverage report: $(BUILD)/coverage/index.html (per-file detail), coverage.xml (Cobertura)"
	@# every line left uncovered is tested or justified (docs/COVERAGE_JUSTIFICATION.md)
	@$(PY) scripts/evidence/evidence_coverage.py --cobertura $(BUILD)/coverage/coverage.xml \
	  --justifications docs/COVERAGE_JUSTIFICATION.md --out $(BUILD)/coverage/justified.md

# make test: the system installers first, then the venv and every check, TEST_JOBS of them side by side (they
# share nothing but their common prerequisites, which make builds once); --output-sync
# prints each check's output whole when it ends, so a long one (coverage) is quiet a while.
# Memcheck (make valgrind) is not among them: it took 12 of make test's 45 CPU minutes
# (valgrind runs ~45x slower than native) for the uninitialised reads that ASan + UBSan do
# not see, over the same tests; CI runs it after make test (.ci/run), so nothing lands
# without it, and make test stays a quarter-hour loop on two cores.
# The order is the start order: the venv first (the Python checks wait for it, the C ones do
# not), then the long checks (cppcheck, pytest, coverage, ASan), so that the short ones fill
# the other job slot instead of one long check running alone at the end.
TEST_STEPS = venv misra test-py coverage sanitize lib test-c tidy bench-build check-tools layers names help-check \
             check-shared check-twins check-nofloat complexity structural $(TEST_GATES) test-pkg check-kernels
TEST_JOBS ?= $(shell nproc 2>/dev/null || echo 1)
## every check, TEST_JOBS at a time (the README's test command)
test: deps-apt
	@echo "make test: $(words $(TEST_STEPS)) checks ($(TEST_STEPS)), $(TEST_JOBS) at a time"
	@$(MAKE) --no-print-directory -j$(TEST_JOBS) --output-sync=target $(TEST_STEPS)
	@echo "make test: all tests passed, coverage gate met"

# $(BUILD)/f64/test/host/test_x comes from test/host/test_x.c through the pattern rule.

# ---- static analysis (docs/MISRA.md) --------------------------------------------------
# make misra       cppcheck + MISRA C:2012 addon, float and double configurations, zero findings
#                  outside the deviations recorded in docs/MISRA.md (reports in build/misra/)
# make tidy        clang-tidy (.clang-tidy: bugprone-*, cert-*, readability-* less a justified
#                  few) over the library, every finding an error
# make complexity  lizard: cyclomatic complexity of every library function <= CCN_MAX
# make structural  no dynamic memory, no recursion, no VLA: nm, the GCC call graph and stack
#                  usage (scripts/checks/check_structural.py), after its self-test on test/structural/
# The library is LIB_DIRS' *.c (float/double sources and the *_q31.c twins) with include/rfe/
# and their *.h; src/host/ is host code and not part of it.
CLANG_TIDY := clang-tidy-19
CCN_MAX    := 15
ANALYSIS_SRC := $(LIB_ALL_SRC)
# No variable-length arrays in any build (checked again by make structural).
WARN += -Werror=vla

## install cppcheck and clang-tidy-19 (apt) when missing
deps-analysis:
	@if ! command -v cppcheck >/dev/null 2>&1 || ! command -v $(CLANG_TIDY) >/dev/null 2>&1; then \
	  echo "[deps] installing cppcheck and $(CLANG_TIDY) via apt"; \
	  $(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq cppcheck $(CLANG_TIDY); fi

## cppcheck's MISRA C:2012 addon, zero findings beyond docs/MISRA.md
misra: deps-analysis
	@MISRA_SRC="$(ANALYSIS_SRC)" bash scripts/checks/check_misra.sh

# (clang-tidy's stderr mostly counts the diagnostics it suppressed in system headers: kept in
# build/tidy.log, shown without those counts when the run fails; findings go to stdout.)
TIDY_RUN = $(CLANG_TIDY) --quiet -warnings-as-errors='*' $(1) -- $(WARN) $(2) $(CPPFLAGS_LIB) \
           2>$(BUILD)/tidy.log || { grep -vE '^\[[0-9]+/[0-9]+\] Processing|^[0-9]+ warnings? generated' \
           $(BUILD)/tidy.log; echo "tidy: findings above (.clang-tidy)"; exit 1; }
## clang-tidy over the library, every finding an error
tidy: deps-analysis
	@mkdir -p $(BUILD)
	@echo "tidy: $$($(CLANG_TIDY) --version | grep -m1 -o 'LLVM version [0-9.]*'), .clang-tidy"
	@$(call TIDY_RUN,$(LIB_SRC),)
	@$(call TIDY_RUN,$(LIB_SRC),-DRFE_REAL_DOUBLE)
	@$(if $(Q31_SRC),$(call TIDY_RUN,$(Q31_SRC),))
	@echo "tidy: clean ($(words $(ANALYSIS_SRC)) library sources and the headers they include)"

## cyclomatic complexity of every library function <= CCN_MAX
complexity: venv
	@$(VENV)/bin/lizard -l c -C $(CCN_MAX) -w $(ANALYSIS_SRC) $(LIB_HDRS) \
	  || { echo "complexity: a function exceeds cyclomatic complexity $(CCN_MAX) (above)"; exit 1; }
	@echo "complexity: every library function has cyclomatic complexity <= $(CCN_MAX); the highest:"
	@$(VENV)/bin/lizard -l c --csv $(ANALYSIS_SRC) $(LIB_HDRS) | \
	  sort -t, -k2 -n -r | head -3 | awk -F, '{ printf "  %3d  %s\n", $$2, $$6 }'

## no heap, no recursion, no VLA (objects, call graph, stack)
structural: lib
	@python3 scripts/checks/check_structural.py --self-test --cflags "$(WARN)" --out $(BUILD)/structural
	@python3 scripts/checks/check_structural.py --cflags "$(WARN) $(CPPFLAGS_LIB)" --out $(BUILD)/structural/f32 \
	  --label "float + q31" --archive $(BUILD)/f32/librfe.a \
	  $(if $(Q31_SRC),--archive $(BUILD)/q31/librfe_q31.a) $(ANALYSIS_SRC)
	@python3 scripts/checks/check_structural.py --cflags "$(WARN) -DRFE_REAL_DOUBLE $(CPPFLAGS_LIB)" \
	  --label double --out $(BUILD)/structural/f64 --archive $(BUILD)/f64/librfe.a $(LIB_SRC)

## misra, tidy, complexity and structural
analysis: misra tidy complexity structural

# ---- demo, goldens ---------------------------------------------------------------------
## run the estimator on every bundled scenario: tables, plots and their index.md in build/demo/
demo: venv $(BUILD)/mu_replay
	$(PY) scripts/tools/demo.py --replay $(BUILD)/mu_replay --out $(BUILD)/demo --trust

# Regenerates the accuracy, trust and fixed-point tables of docs/RESULTS.md and the headline
# table of README.md (a few columns of the trust table); never typed by hand.
## regenerate the tables of docs/RESULTS.md and the README headline
readme-table: venv $(BUILD)/mu_replay
	$(PY) scripts/tools/demo.py --replay $(BUILD)/mu_replay --out $(BUILD)/demo --no-plots --trust \
	  --results docs/RESULTS.md --readme README.md

# Issue 17's trust invariant on every bundled log in float, double and Q31 (docs/RESULTS.md).
## rewrite docs/RESULTS.md's trust-invariant table (every bundled log, three precisions)
trust-invariant: venv $(BUILD)/mu_replay
	$(PY) scripts/tools/trust_invariant.py --replay $(BUILD)/mu_replay --out $(BUILD)/trust \
	  --page docs/RESULTS.md

## regenerate the sensor and fault logs with the simulator
scenarios: venv
	$(PY) scripts/data/make_scenarios.py --out scenarios
	$(PY) scripts/data/make_fault_scenarios.py --scenarios scenarios --out scenarios/faults
## regenerate the velocity / sideslip observer logs (scenarios/observer/) with the simulator
observer-scenarios: venv
	$(PY) scripts/data/make_observer_scenarios.py --out scenarios/observer
## regenerate the observer logs with the car's rolling resistance and drag for the mass studies (scenarios/observer_res/)
observer-res-scenarios: venv
	$(PY) scripts/data/make_observer_scenarios.py --resistances --out scenarios/observer_res
## regenerate the friction loop's observer log, a mu step while cornering (scenarios/observer_loop/)
observer-loop-scenarios: venv
	$(PY) scripts/data/make_observer_scenarios.py --loop --out scenarios/observer_loop
## regenerate the tyre identification logs (scenarios/tyre_id/, docs/TYRE_ID.md) with the simulator
tyre-id-scenarios: venv
	$(PY) scripts/data/make_tyre_id_scenarios.py --out scenarios/tyre_id
## measure the reference tyre identifier and write the tables of docs/TYRE_ID_RESULTS.md
tyre-id-results: venv
	$(PY) scripts/tools/tyre_id_results.py --jobs 2 --page docs/TYRE_ID_RESULTS.md
	$(PY) scripts/tools/tyre_id_targets.py --page docs/TYRE_ID_RESULTS.md
## issue 20's mu targets per log, filter and axle from the accuracy table of docs/TYRE_ID_RESULTS.md (no run)
tyre-id-targets: venv
	$(PY) scripts/tools/tyre_id_targets.py --page docs/TYRE_ID_RESULTS.md
## the accuracy table of the reference identifier without and with the friction ellipse at its default dead band (docs/TYRE_ID_RESULTS.md)
tyre-id-results-ellipse: venv
	$(PY) scripts/tools/tyre_id_results.py --ellipse --jobs 2 --page docs/TYRE_ID_RESULTS.md
## the accuracy table without and with the steering-angle filter, tid_delta_q (docs/TYRE_ID_RESULTS.md)
tyre-id-results-delta-filter: venv
	$(PY) scripts/tools/tyre_id_results.py --delta-filter --jobs 2 --page docs/TYRE_ID_RESULTS.md
## the SCKF off, with the steering-angle filter and with delta as a state, tid_delta_state_q (docs/TYRE_ID_RESULTS.md)
tyre-id-results-delta-state: venv
	$(PY) scripts/tools/tyre_id_results.py --delta-state --jobs 2 --page docs/TYRE_ID_RESULTS.md
## the SCKF off, with delta as a state and with each remedy for the spread of mu while linear (docs/TYRE_ID_RESULTS.md)
tyre-id-results-spread: venv
	$(PY) scripts/tools/tyre_id_results.py --spread --jobs 2 --page docs/TYRE_ID_RESULTS.md
## the Van Trees bound on mu from D of the identifier's model per log and axle, beside the SCKF (docs/TYRE_ID_RESULTS.md)
tyre-id-bound: venv
	$(PY) scripts/tools/tyre_id_bound.py --jobs 2 --page docs/TYRE_ID_RESULTS.md
## the APF's particle count that fits 20 % of a 168 MHz Cortex-M4 at 100 Hz and the reference's accuracy there (docs/TYRE_ID_RESULTS.md)
tyre-id-m4-count: venv
	$(PY) scripts/tools/tyre_id_m4_count.py --jobs 2 --page docs/TYRE_ID_RESULTS.md
## the reference identifier without and with the friction ellipse over the brake-in-turn braking (docs/TYRE_ID_RESULTS.md)
tyre-id-ellipse-results: venv
	$(PY) scripts/tools/tyre_id_ellipse_results.py --jobs 2 --page docs/TYRE_ID_RESULTS.md
## regenerate the mass and grade logs (scenarios/mass_grade/) with the simulator
mass-grade-scenarios: venv
	$(PY) scripts/data/make_mass_grade_scenarios.py --out scenarios/mass_grade
## rewrite observer scenarios in a car logger's format (scenarios/car_format/, DATA.md)
car-format-logs: venv
	$(PY) scripts/data/make_car_format_logs.py --src scenarios/observer --out scenarios/car_format
## regenerate the scenarios and every golden (reference and q31)
goldens: scenarios
	$(MAKE) goldens-ref goldens-q31 observer-goldens-q31
# The reference goldens alone, from the committed scenarios. Byte-stable on one machine; each
# records the BLAS kernel and numpy SIMD paths that wrote it (metadata blas, numpy_simd).
## regenerate the reference goldens from the committed scenarios
goldens-ref: venv
	$(PY) scripts/data/make_goldens.py --scenarios scenarios --out scenarios/golden

# The dependency rules of the source tree (docs/LAYOUT.md) on every #include.
## the dependency rules of src/ and include/rfe/ (docs/LAYOUT.md)
layers:
	@python3 scripts/checks/check_layers.py

# The twins' shared sequences (docs/LAYOUT.md "What is generated from one source"): each is one
# template in scripts/codegen/templates/, written into a marked region of the *_flt.c and
# *_q31.c files; the committed C is what the compilers and the analysers read.
## regenerate the twins' generated regions from scripts/codegen/templates/
twins:
	@python3 scripts/codegen/twins.py
## every generated region of the twins equals its template's output (else: which, and make twins)
check-twins:
	@python3 scripts/codegen/twins.py --check

# Every public symbol carries its type's suffix and is written out in a header, so grep finds
# it (docs/LAYOUT.md "Names"): nm on the three libraries.
## every library symbol suffixed (_f32, _f64) and written out in a header
names: lib
	@python3 scripts/checks/check_names.py --lib $(BUILD)/f32/librfe.a:_f32 \
	  --lib $(BUILD)/f64/librfe.a:_f64 --lib $(BUILD)/q31/librfe_q31.a:

# The tools outside the Python pins whose version can change an outcome, against the versions
# the gates were calibrated with (scripts/checks/check_tools.py; TOOL_PINS=warn only reports).
TOOL_PINS ?= fail
## the system tools' versions against their pins (TOOL_PINS=warn reports only)
check-tools:
	@python3 scripts/checks/check_tools.py $(if $(filter warn,$(TOOL_PINS)),--warn)

# The golden checks do not depend on the CPU (docs/PORTABILITY.md): the reference goldens
# regenerated under this machine's BLAS kernels, thread counts and numpy SIMD paths agree with
# the committed ones and with each other within the golden tolerance (1e-9), decisions exactly.
## the reference goldens under this CPU's other BLAS kernels and numpy paths
check-kernels: venv
	@$(PY) scripts/checks/check_kernels.py --scenarios scenarios --goldens scenarios/golden --out $(BUILD)/kernels

# Fixed-point goldens (docs/FIXED_POINT.md "Estimator"): the estimate logs of `mu_replay --real
# q31` on the noisy scenario logs in the four configurations of the float goldens, written to
# scenarios/golden/<stem>.<config>.q31.csv; test/golden/test_golden_q31.c requires every value bit
# for bit (the Q values converted exactly to double, written in the shortest exact form).
Q31_GOLDEN_LOGS = $(filter-out %.nf.csv %.mf.csv,$(wildcard scenarios/*.csv))
# The velocity observer measured through the C library (docs/OBSERVER_RESULTS.md).
## measure the velocity observer and write docs/OBSERVER_RESULTS.md
observer-results: $(BUILD)/mu_replay venv
	$(PY) scripts/tools/observer_results.py --replay $(BUILD)/mu_replay --page docs/OBSERVER_RESULTS.md

# The mass and grade estimator measured with its float64 reference (docs/MASS_GRADE_RESULTS.md;
# about 1.5 min on 2 cores); the truck's mass error vs time into build/mass_grade/.
## measure the mass and grade estimator and write docs/MASS_GRADE_RESULTS.md
mass-grade-results: venv
	$(PY) scripts/tools/mass_grade_results.py --page docs/MASS_GRADE_RESULTS.md \
	  --plot $(BUILD)/mass_grade/mass_error.png
# The results pages' figures (SVG, committed): the mass error vs time of the mass and grade
# estimator, the identified tyre curves against the truth and the observer's beta with its band,
# drawn from the studies' own runs (scripts/tools/figures.py; about 10 s on 2 cores). Not part of
# `make test`.
## write the results pages' figures into docs/figures/ (mass error, tyre curve, observer beta)
figures: venv $(BUILD)/mu_replay
	$(PY) scripts/tools/figures.py --replay $(BUILD)/mu_replay --out docs/figures \
	  --work $(BUILD)/figures --jobs $(TEST_JOBS)
# The textbook (full-covariance) form in float32 and with an int32 P, beside the library's float
# and Q31 (square-root) runs, on every mass and grade log and the stress runs: where each loses
# positive definiteness (docs/MASS_GRADE_RESULTS.md "Why the square-root form"; about 3 min on
# 2 cores). The two drivers are test/tools/mg_run_{flt,q31}.c, built by the test rules.
## the textbook covariance form in float32 and int32 vs the library's float and Q31 runs (docs/MASS_GRADE_RESULTS.md)
mass-grade-textbook: venv $(BUILD)/f32/test/tools/mg_run_flt $(BUILD)/q31/test/tools/mg_run_q31
	$(PY) scripts/tools/mass_grade_textbook.py --page docs/MASS_GRADE_RESULTS.md --jobs $(TEST_JOBS) \
	  --lib-f32 $(BUILD)/f32/test/tools/mg_run_flt --lib-q31 $(BUILD)/q31/test/tools/mg_run_q31
## the friction estimator with and without the tyre identifier's curve fed, every steering scenario (docs/TYRE_ID_RESULTS.md)
tyre-id-feed-results: venv $(BUILD)/mu_replay
	$(PY) scripts/tools/tyre_id_feed_results.py --page docs/TYRE_ID_RESULTS.md --jobs $(TEST_JOBS)

# Issue 17's trust invariant with the tyre identifier's curve fed (docs/MONITOR.md section 7;
# the 72 logs of trust-invariant, float and double, 17 runs each: about 5 min on 2 cores).
## the trust invariant with and without the tyre identifier's fed curve, every bundled log (docs/MONITOR.md section 7)
tyre-id-trust: venv $(BUILD)/mu_replay
	$(PY) scripts/tools/tyre_id_trust.py --replay $(BUILD)/mu_replay --out $(BUILD)/tyre_id_trust \
	  --jobs $(TEST_JOBS) --page docs/MONITOR.md

## what a fixed-point tyre identifier would have to hold: likelihood, weight and state ranges (docs/FIXED_POINT.md)
tyre-id-q31-ranges: venv
	$(PY) scripts/tools/tyre_id_q31_ranges.py --page docs/FIXED_POINT.md

## what a +-20 % mass error costs the friction estimator, and how far the fed online mass is
## from the truth (tables in docs/MASS_GRADE_RESULTS.md)
mass-sensitivity: venv $(BUILD)/mu_replay
	$(PY) scripts/tools/mass_sensitivity.py --page docs/MASS_GRADE_RESULTS.md
	$(PY) scripts/tools/mass_feed_results.py --page docs/MASS_GRADE_RESULTS.md
	$(PY) scripts/tools/mass_online_friction.py --jobs $(TEST_JOBS) --page docs/MASS_GRADE_RESULTS.md
	$(PY) scripts/tools/mass_online_friction.py --folder observer_res --jobs $(TEST_JOBS) \
	  --page docs/MASS_GRADE_RESULTS.md

## what the library's slip pause does to the mass filter's own estimate (docs/MASS_GRADE.md)
mass-slip: venv $(BUILD)/mu_replay
	$(PY) scripts/tools/mass_slip_study.py --jobs $(TEST_JOBS) --page docs/MASS_GRADE.md

## the mass error the slip pause leaves on the traction logs and a rollback at its onset,
## in the float64 reference (docs/MASS_GRADE.md)
mass-slip-ramp: venv
	$(PY) scripts/tools/mass_slip_ramp_study.py --jobs $(TEST_JOBS) --page docs/MASS_GRADE.md

## why the mass filter's mass is wrong on a steady curve: the cornering resistance and ax's sideslip term (docs/MASS_GRADE_RESULTS.md)
mass-curve: venv
	$(PY) scripts/tools/mass_curve_study.py --jobs $(TEST_JOBS) --page docs/MASS_GRADE_RESULTS.md

## a curve pause (|ay| over a threshold holds the mass filter) or the cornering resistance taken
## out, on every observer and mass and grade log (docs/MASS_GRADE_RESULTS.md; about 5 min on 2 cores)
mass-curve-pause: venv
	$(PY) scripts/tools/mass_curve_pause_study.py --jobs $(TEST_JOBS) --page docs/MASS_GRADE_RESULTS.md

## the grade learned from ax in the brake, shift and curve pauses (mg_pause_grade) on every mass
## and grade and observer log (docs/MASS_GRADE_RESULTS.md; about 1 min on 2 cores)
mass-pause-grade: venv
	$(PY) scripts/tools/mass_pause_grade_study.py --jobs $(TEST_JOBS) --page docs/MASS_GRADE_RESULTS.md

## the grade's two-level random walk (mg_q_theta_hi) against the fixed ones, every mass and
## grade log from four starts (docs/MASS_GRADE_RESULTS.md; about 2 min on 2 cores)
mass-grade-walk: venv
	$(PY) scripts/tools/mass_grade_walk_study.py --jobs $(TEST_JOBS) --page docs/MASS_GRADE_RESULTS.md

## a force-offset state learned from ax against the headwind, every mass and grade log from four
## starts, in the float64 reference (docs/MASS_GRADE_RESULTS.md; about 6 min on 2 cores)
mass-offset: venv
	$(PY) scripts/tools/mass_offset_study.py --jobs $(TEST_JOBS) --page docs/MASS_GRADE_RESULTS.md

## a Gauss-Markov gust state beside the force offset, and the information bound of the
## headwind's first 10 s, in the float64 reference (docs/MASS_GRADE_RESULTS.md; about 8 min
## on 2 cores)
mass-gust: venv
	$(PY) scripts/tools/mass_gust_study.py --jobs $(TEST_JOBS) --page docs/MASS_GRADE_RESULTS.md

## whether the mass filter's innovations or a drag fit see the headwind (docs/MASS_GRADE_RESULTS.md)
mass-headwind: venv
	$(PY) scripts/tools/mass_headwind_study.py --page docs/MASS_GRADE_RESULTS.md

# The model-validity monitor measured with the float64 reference (docs/MONITOR.md; the runs
# are cached in build/monitor/, about 10 min on 2 cores the first time).
## measure the model-validity monitor and write the tables of docs/MONITOR.md
monitor-results: venv
	$(PY) scripts/tools/monitor_results.py --jobs 2 --page docs/MONITOR.md
# Issue 21's step noise every N steps, measured in the float64 reference (docs/BENCHMARKS.md;
# 57 logs x 7 runs, about 8 min on 2 cores; per-log table in build/snoise_reuse.md).
## measure the step noise every N steps and write its table of docs/BENCHMARKS.md
snoise-reuse: venv
	@mkdir -p $(BUILD)
	$(PY) scripts/tools/snoise_reuse_study.py --jobs 2 --md $(BUILD)/snoise_reuse.md --page docs/BENCHMARKS.md
# Then only vx's and vy's columns reused (57 logs x 3 runs, about 7 min on 1 core; per-log
# table in build/snoise_reuse_vxvy.md).
## measure the step noise's vx, vy columns every N steps and write its table of docs/BENCHMARKS.md
snoise-reuse-vxvy: venv
	@mkdir -p $(BUILD)
	$(PY) scripts/tools/snoise_reuse_study.py --jobs 2 --variants vxvy_every2,vxvy_every5 \
	  --tag snoise-reuse-vxvy --md $(BUILD)/snoise_reuse_vxvy.md --page docs/BENCHMARKS.md
# The shape-ambiguity study (docs/MONITOR.md section 6): the reference and a shadow estimator
# per second tyre hypothesis on the 72 bundled logs (cached in build/shape/, about 25 min on
# 2 cores the first time).
## measure the second tyre-shape hypotheses and write section 6's tables of docs/MONITOR.md
shape-results: venv
	$(PY) scripts/tools/shape_results.py --jobs 2 --page docs/MONITOR.md
	RFE_SHAPE_CLAIM=1 $(PY) -m pytest -q -p no:cacheprovider scripts/tools/test_shape_results.py

# The velocity observer's goldens (docs/OBSERVER.md) from its float64 reference.
## regenerate the velocity observer's goldens (scenarios/golden/observer/ at the defaults, observer_every1/: every step, observer_out_floor0/: the reported sd(vy)'s floor off)
observer-goldens: venv
	$(PY) scripts/data/make_observer_goldens.py --scenarios scenarios --out scenarios/golden/observer
	$(PY) scripts/data/make_observer_goldens.py --scenarios scenarios --lat-every 1 \
	  --only brake_in_turn_low_mu.csv sine_steer_low_mu.csv --out scenarios/golden/observer_every1
	$(PY) scripts/data/make_observer_goldens.py --scenarios scenarios --vy-out-floor-mu 0 \
	  --only brake_in_turn_low_mu.csv sine_steer_low_mu.csv --out scenarios/golden/observer_out_floor0

# The tyre identifier's goldens (docs/TYRE_ID.md) from its float64 reference, libm backend (the
# C library's double build agrees bit for bit); the particle count is the C build's. The
# sigma-point filter's (tyre_id_sckf.py, §15) too: its QR and products are LAPACK's and BLAS's,
# so the C agrees within the bound test_tyre_id_golden_flt.c derives, not bit for bit.
## regenerate the tyre identifier's goldens and its stream check (scenarios/golden/tyre_id/)
tyre-id-goldens: venv
	$(PY) scripts/data/make_tyre_id_goldens.py --n 256 --out scenarios/golden/tyre_id
# The mass and grade estimator's goldens (docs/MASS_GRADE.md) from its float64 reference.
## regenerate the mass and grade estimator's goldens (scenarios/golden/mass_grade/)
mass-grade-goldens: venv
	$(PY) scripts/data/make_mass_grade_goldens.py --scenarios scenarios/mass_grade \
	  --out scenarios/golden/mass_grade

## regenerate the fixed-point goldens with mu_replay --real q31
goldens-q31: $(BUILD)/mu_replay
	@set -e; for f in $(Q31_GOLDEN_LOGS); do s=$$(basename $$f .csv); \
	  for c in "paper.sckf --preset paper --filter sckf" "paper.ckf --preset paper --filter ckf" \
	           "absolute.sckf --preset paper --tyre absolute" "default.sckf --preset default"; do \
	    set -- $$c; tag=$$1; shift; \
	    $(BUILD)/mu_replay --in $$f --out scenarios/golden/$$s.$$tag.q31.csv "$$@" --real q31 --quiet; \
	  done; echo "goldens-q31: scenarios/golden/$$s.{paper.sckf,paper.ckf,absolute.sckf,default.sckf}.q31.csv"; done

# Fixed-point observer goldens (docs/FIXED_POINT.md "Observer"): the estimate logs of `mu_replay
# --real q31 --velocity observer` (the Q31 pipeline, default preset) on a subset of the observer
# scenarios that takes every path of the observer (ABS on one and on split friction, lane
# change, sine with dwell, rear-wheel traction, a known grade, creeping to a stop) and on one
# car-format log (km/h, the steering-wheel angle, jittered 50 Hz), written to
# scenarios/golden/observer_q31/[car_format.]<stem>.q31.csv; test/golden/test_golden_observer_q31.c
# requires every value bit for bit. A subset so that the test stays fast under valgrind too.
Q31_OBS_GOLDEN_LOGS = $(addprefix scenarios/observer/,abs_brake_mu02.csv abs_brake_split_mu.csv \
                        dlc_mu035.csv sine_dwell_mu09.csv traction_rwd_mu03.csv \
                        hill_known_grade.csv creep_stop.csv) scenarios/car_format/dlc_mu035.csv
## regenerate the fixed-point observer goldens (scenarios/golden/observer_q31/) with mu_replay
observer-goldens-q31: $(BUILD)/mu_replay
	@set -e; mkdir -p scenarios/golden/observer_q31; for f in $(Q31_OBS_GOLDEN_LOGS); do \
	  case $$f in scenarios/car_format/*) p=car_format. ;; *) p= ;; esac; \
	  g=scenarios/golden/observer_q31/$$p$$(basename $$f .csv).q31.csv; \
	  $(BUILD)/mu_replay --in $$f --out $$g --velocity observer --real q31 --quiet; \
	  echo "observer-goldens-q31: $$g"; done

# The specification (MODEL.md, DATA.md) and the test vectors of the independent
# implementation came from the project's shared folder (../shared); copies sit in docs/spec
# and test/vectors so a clone is self-contained. MODEL.md and the vectors stay equal to the
# shared ones (this refreshes them). docs/spec/DATA.md is the project's own since the new
# estimators add columns and keys: it is never overwritten, and check-shared requires only
# that it still documents every column and key the shared DATA.md names.
SHARED ?= ../shared
## copy MODEL.md and the test vectors from ../shared (docs/spec/DATA.md is the project's)
shared-sync:
	cp $(SHARED)/docs/MODEL.md docs/spec/
	cp $(SHARED)/vectors/model_vectors.csv $(SHARED)/vectors/sckf_step_vectors.csv test/vectors/
## the same as shared-sync
vectors: shared-sync
# Fails when MODEL.md or the vectors differ from ../shared (where it exists), or when the
# project's DATA.md lost a column or key of the shared one.
## the copies of ../shared are up to date; DATA.md still documents the shared names
check-shared:
	@if [ -d $(SHARED) ]; then \
	  for f in docs/MODEL.md vectors/model_vectors.csv vectors/sckf_step_vectors.csv; do \
	    copy=$$(case $$f in docs/*) echo docs/spec/$${f#docs/};; *) echo test/$$f;; esac); \
	    cmp -s $(SHARED)/$$f $$copy || { echo "$$copy differs from $(SHARED)/$$f: run make shared-sync"; exit 1; }; \
	  done; \
	  python3 scripts/checks/check_data_names.py $(SHARED)/docs/DATA.md docs/spec/DATA.md || exit 1; \
	  echo "shared copies: up to date"; \
	else echo "shared copies: $(SHARED) not present, not checked"; fi

# The fixed-point translation units (*_q31.c) hold no floating point: built for Cortex-M0+
# with -mfloat-abi=soft and linked against libgcc only, they may not use float/double, any
# soft-float helper (__aeabi_f*, __aeabi_d*, __addsf3, …) or libm. The self-test first proves
# that the checker rejects such code (fixtures in test/nofloat/).
## the fixed-point sources hold no float, soft-float or libm (Cortex-M0+)
check-nofloat: deps-arm
	bash scripts/checks/check_nofloat.sh --self-test
	bash scripts/checks/check_nofloat.sh

## remove build/
clean:
	rm -rf $(BUILD)
