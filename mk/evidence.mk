# Certification evidence (docs/EVIDENCE.md, issue 6): traceability, MC/DC,
# justified uncovered lines, and one folder with all of it.
#
# make trace        the traceability matrix requirement -> tests -> result of the last run
#                   (docs/REQUIREMENTS.md, scripts/evidence/trace_requirements.py) from the JUnit XML
#                   that make test-c / test-py leave in build/results/; fails on a requirement
#                   without a passing test or a test citing an unknown ID; part of make test
#                   (it needs test-c and test-py, and reruns nothing else)
# make trace-report the same from whatever results are in build/results/, running nothing
# make mcdc         clang-19 source-based coverage with MC/DC (-fcoverage-mcdc): the float,
#                   double and q31 libraries with the unit, golden, host and CLI tests in
#                   build/mcdc-*, one profile per process, llvm-profdata-19 merge, llvm-cov-19
#                   report (--show-mcdc-summary) and show --show-mcdc (HTML) over src/ only;
#                   build/mcdc/{report.txt,summary.md,gaps.md,html/}. Not part of make test.
# make mcdc-readme  make mcdc, then the figure into docs/EVIDENCE.md (its name is historic)
# make coverage-justify  every line left uncovered in src/ by make coverage (and every MC/DC
#                   gap, when build/mcdc/ exists) is listed in docs/COVERAGE_JUSTIFICATION.md,
#                   else it fails (scripts/evidence/evidence_coverage.py); run by make coverage
# make evidence     coverage, MC/DC, MISRA, traceability, JUnit results, tool versions and the
#                   firmware size/stack table (when built) in build/evidence/ with index.html
MCDC_LLVM     ?= 19
MCDC_CC       := clang-$(MCDC_LLVM)
LLVM_PROFDATA := llvm-profdata-$(MCDC_LLVM)
LLVM_COV      := llvm-cov-$(MCDC_LLVM)
MCDC_FLAGS    := -O0 -g -fprofile-instr-generate -fcoverage-mapping -fcoverage-mcdc
MCDC_DIR      := $(BUILD)/mcdc
EVIDENCE_DIR  := $(BUILD)/evidence

.PHONY: trace trace-report mcdc mcdc-run mcdc-readme coverage-justify evidence deps-mcdc
DEPS_EXTRA += deps-mcdc
TEST_GATES += trace

# ---- traceability ------------------------------------------------------------------------
## the requirements traceability matrix from the last test results (gates)
trace: test-c test-py
	@$(PY) scripts/evidence/trace_requirements.py --results $(RESULTS) --out $(BUILD)/trace
## the traceability matrix from whatever results exist, running nothing
trace-report: venv
	@$(PY) scripts/evidence/trace_requirements.py --results $(RESULTS) --out $(BUILD)/trace

# ---- MC/DC (clang source-based coverage) -----------------------------------------------------
## install clang-19 and llvm-19 (apt) when missing
deps-mcdc:
	@if ! command -v $(MCDC_CC) >/dev/null 2>&1 || ! command -v $(LLVM_COV) >/dev/null 2>&1 || \
	  ! command -v $(LLVM_PROFDATA) >/dev/null 2>&1; then \
	  echo "[deps] installing clang-$(MCDC_LLVM) and llvm-$(MCDC_LLVM) via apt"; \
	  $(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq clang-$(MCDC_LLVM) llvm-$(MCDC_LLVM); fi

# The mcdc-* trees are the coverage trees built by clang: the same rules (FLAVOUR_RULES,
# Q31_RULES, REPLAY_RULE), the compiler and flags replaced per tree. Warnings stay on but are
# not errors there (clang's set differs from GCC's; the gating builds are the GCC ones), and
# GCC-only warning options in TEST_WARN are not an error for clang.
$(BUILD)/mcdc-f32/% $(BUILD)/mcdc-f64/% $(BUILD)/mcdc-q31/% $(BUILD)/mcdc-mu_replay: CC := $(MCDC_CC)
$(BUILD)/mcdc-f32/% $(BUILD)/mcdc-f64/% $(BUILD)/mcdc-q31/% $(BUILD)/mcdc-mu_replay: WARN += -Wno-error
$(BUILD)/mcdc-f32/% $(BUILD)/mcdc-f64/% $(BUILD)/mcdc-q31/% $(BUILD)/mcdc-mu_replay: TEST_WARN += -Wno-error -Wno-unknown-warning-option
$(eval $(call FLAVOUR_RULES,mcdc-f32,,$(MCDC_FLAGS)))
$(eval $(call FLAVOUR_RULES,mcdc-f64,-DRFE_REAL_DOUBLE,$(MCDC_FLAGS)))
$(eval $(call Q31_RULES,mcdc-q31,mcdc-f64,$(MCDC_FLAGS)))
$(eval $(call HOST_TEST_RULES,mcdc-f64,mcdc-q31,$(MCDC_FLAGS)))
$(eval $(call REPLAY_RULE,$(BUILD)/mcdc-mu_replay,mcdc-f32,mcdc-f64,$(MCDC_FLAGS),mcdc-q31))

MCDC_TEST_BINS := $(foreach f,mcdc-f32 mcdc-f64,$(addprefix $(BUILD)/$(f)/test/,$(UNIT_TESTS))) \
                  $(if $(Q31_SRC),$(addprefix $(BUILD)/mcdc-q31/test/,$(Q31_TESTS))) \
                  $(addprefix $(BUILD)/mcdc-f64/test/host/,$(HOST_TESTS))
MCDC_SOURCES   := $(LIB_ALL_SRC) $(wildcard $(addsuffix /*.h,$(LIB_DIRS)))

# Runs the suite with one raw profile per process (%p) and merges them. The tests write their
# JUnit XML to build/results/mcdc-*. A failing test does not stop the run (the coverage of the
# rest is still measured): it is listed in build/mcdc/failed.txt, reported by make mcdc and in
# the evidence index; the gating runs of the tests are make test-c / make test.
# $(1) = results tree, $(2) = test names, $(3) = binary folder
mcdc_run_tree = rm -rf $(RESULTS)/$(1); mkdir -p $(RESULTS)/$(1); \
  for t in $(2); do ( $(call run_cmocka,$(1)/$$t,$(BUILD)/$(3)/$$t,$(RESULTS)/$(1)) ) || \
  echo "$(1)/$$t" >> $(MCDC_DIR)/failed.txt; done
MCDC_ENV = LLVM_PROFILE_FILE=$(abspath $(MCDC_DIR))/prof/%m-%p.profraw
## run the suite built for MC/DC and merge the profiles
mcdc-run: deps-c deps-mcdc venv $(MCDC_TEST_BINS) $(BUILD)/mcdc-mu_replay
	@rm -rf $(MCDC_DIR) && mkdir -p $(MCDC_DIR)/prof
	@export $(MCDC_ENV); $(call mcdc_run_tree,mcdc-f32,$(UNIT_TESTS),mcdc-f32/test)
	@export $(MCDC_ENV); $(call mcdc_run_tree,mcdc-f64,$(UNIT_TESTS),mcdc-f64/test)
	@$(if $(Q31_SRC),export $(MCDC_ENV); $(call mcdc_run_tree,mcdc-q31,$(Q31_TESTS),mcdc-q31/test))
	@export $(MCDC_ENV); $(call mcdc_run_tree,mcdc-host,$(HOST_TESTS),mcdc-f64/test/host)
	@if [ -f test/host/test_cli.sh ]; then export $(MCDC_ENV); \
	  if bash test/host/test_cli.sh $(BUILD)/mcdc-mu_replay >$(MCDC_DIR)/cli.log 2>&1; then \
	    echo "== mcdc cli: $$(tail -n 1 $(MCDC_DIR)/cli.log)"; \
	  else cat $(MCDC_DIR)/cli.log; echo "mcdc-cli/test_cli" >> $(MCDC_DIR)/failed.txt; fi; fi
	@$(LLVM_PROFDATA) merge -sparse $(MCDC_DIR)/prof/*.profraw -o $(MCDC_DIR)/merged.profdata
	@rm -rf $(MCDC_DIR)/prof
	@if [ -s $(MCDC_DIR)/failed.txt ]; then echo "mcdc: WARNING: failed in the MC/DC build (coverage measured anyway):"; \
	  sed 's/^/  /' $(MCDC_DIR)/failed.txt; fi

MCDC_OBJECTS = $(firstword $(MCDC_TEST_BINS)) $(addprefix -object ,$(wordlist 2,999,$(MCDC_TEST_BINS)) $(BUILD)/mcdc-mu_replay)
## MC/DC coverage with clang 19 (build/mcdc/)
mcdc: mcdc-run
	@$(LLVM_COV) report --show-mcdc-summary --show-region-summary=false --show-instantiation-summary=false \
	  -instr-profile=$(MCDC_DIR)/merged.profdata $(MCDC_OBJECTS) $(MCDC_SOURCES) > $(MCDC_DIR)/report.txt
	@$(LLVM_COV) show --show-mcdc --show-branches=count --format=html --output-dir=$(MCDC_DIR)/html \
	  --show-line-counts-or-regions --project-title="rfe src/ MC/DC" \
	  -instr-profile=$(MCDC_DIR)/merged.profdata $(MCDC_OBJECTS) $(MCDC_SOURCES)
	@$(LLVM_COV) show --show-mcdc --format=text -instr-profile=$(MCDC_DIR)/merged.profdata \
	  $(MCDC_OBJECTS) $(MCDC_SOURCES) > $(MCDC_DIR)/show.txt
	@$(LLVM_COV) export --format=text --summary-only -instr-profile=$(MCDC_DIR)/merged.profdata \
	  $(MCDC_OBJECTS) $(MCDC_SOURCES) > $(MCDC_DIR)/summary.json
	@$(PY) scripts/evidence/evidence_mcdc.py --summary $(MCDC_DIR)/summary.json --show $(MCDC_DIR)/show.txt \
	  --out $(MCDC_DIR) --tool "$$($(LLVM_COV) --version | grep -m1 -o 'LLVM version [0-9.]*')"
	@echo "mcdc: report $(MCDC_DIR)/report.txt, HTML $(MCDC_DIR)/html/index.html, gaps $(MCDC_DIR)/gaps.md"
	@# every decision with a condition not shown independent is tested or justified
	@$(PY) scripts/evidence/evidence_coverage.py --mcdc $(MCDC_DIR)/show.txt \
	  --justifications docs/COVERAGE_JUSTIFICATION.md --out $(MCDC_DIR)/justified.md

## make mcdc, then its figure into docs/EVIDENCE.md
mcdc-readme: mcdc
	@$(PY) scripts/evidence/evidence_mcdc.py --summary $(MCDC_DIR)/summary.json --show $(MCDC_DIR)/show.txt \
	  --out $(MCDC_DIR) --page docs/EVIDENCE.md

# ---- uncovered lines: tested or justified --------------------------------------------------------
## every uncovered line and MC/DC gap is justified
coverage-justify: venv
	@$(PY) scripts/evidence/evidence_coverage.py --justifications docs/COVERAGE_JUSTIFICATION.md \
	  $(if $(wildcard $(BUILD)/coverage/coverage.xml),--cobertura $(BUILD)/coverage/coverage.xml) \
	  $(if $(wildcard $(MCDC_DIR)/show.txt),--mcdc $(MCDC_DIR)/show.txt) --out $(BUILD)/coverage/justified.md

# ---- the evidence folder ------------------------------------------------------------------
# Runs misra, coverage (with the whole C suite instrumented), test-c, test-py, the trace and
# mcdc, then copies their outputs into build/evidence/ and writes index.html.
## the assessor's folder build/evidence/ with index.html
evidence: misra coverage test-c test-py trace mcdc
	@rm -rf $(EVIDENCE_DIR) && mkdir -p $(EVIDENCE_DIR)
	@$(PY) scripts/evidence/evidence_index.py --build $(BUILD) --out $(EVIDENCE_DIR) \
	  --cc "$(CC)" --mcdc-cc "$(MCDC_CC)" --llvm-cov "$(LLVM_COV)" --clang-tidy "$(CLANG_TIDY)"
	@echo "evidence: $(EVIDENCE_DIR)/index.html"
