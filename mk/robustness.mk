# Robustness (docs/ROBUSTNESS.md, issue 7): fuzzing, fault scenarios, soak.
#
# make fuzz [FUZZ_SECONDS=60]  every libFuzzer harness (test/fuzz/: the step of the float,
#                              double and fixed-point estimator and velocity observer, the
#                              mass and grade estimator and the tyre identifier in float and
#                              double, the CLI's readers) FUZZ_SECONDS each, clang
#                              -fsanitize=fuzzer,address,undefined;
#                              the corpus grows in build/fuzz/corpus/, crashes land in
#                              build/fuzz/artifacts/
# make fuzz-smoke              each harness FUZZ_SMOKE_SECONDS over the committed seeds
#                              (test/fuzz/corpus/), fixed seed; part of make test
# make fault-scenarios         scenarios/faults/ from the bundled logs (scripts/sim/faults.py)
# make soak / make soak-short  SOAK_SECONDS (one hour) / SOAK_SHORT_SECONDS of simulated mixed
#                              driving (scripts/data/soak_drive.py) through the float, double and
#                              fixed-point estimator and the composed pipeline (observer +
#                              friction, float and double), invariants at every step, saturation
#                              counts (test/soak/soak.c); then the mass and grade estimator and
#                              the tyre identifier, float and double, the mass and grade one also
#                              in Q31 (test/soak/soak_run_aux.c;
#                              the identifier on SOAK_SHORT_TID's stretch in the short one);
#                              the short one is part of make test
# INV_FLAGS=-DINV_MU_TOL=1e-3 relaxes the [mu_min, mu_max] invariant by 1e-3 in the fuzz
# and soak builds (to look past a known rounding excursion); by default it is exact.
FUZZ_LLVM          ?= 19
FUZZ_CC            ?= clang-$(FUZZ_LLVM)
FUZZ_SECONDS       ?= 60
FUZZ_SMOKE_SECONDS ?= 2
INV_FLAGS          ?=
FUZZ_CFLAGS := -std=c99 -g -O1 -fno-omit-frame-pointer -fsanitize=address,undefined \
               -fno-sanitize-recover=all $(INV_FLAGS)
FUZZ_OPTS   := -max_len=16384 -print_final_stats=1
FUZZ_BINS   := fuzz_step_f32 fuzz_step_f64 $(if $(Q31_SRC),fuzz_step_q31) fuzz_velocity_f32 \
               fuzz_velocity_f64 $(if $(Q31_SRC),fuzz_velocity_q31) fuzz_mass_grade_f32 \
               fuzz_mass_grade_f64 $(if $(Q31_SRC),fuzz_mass_grade_q31) fuzz_tyre_id_f32 fuzz_tyre_id_f64 fuzz_csv
# The tyre identifier's harnesses build its sources with FUZZ_TID_N particles (RFE_TID_N,
# rfe/config.h; every loop over the particles runs to it): a step costs N particles' RK4
# and likelihoods, so a small N gives the fuzzer more steps per second on the same code.
# The soak runs the shipped N (256); FUZZ_TID_N=256 fuzzes it too.
FUZZ_TID_N  ?= 32
FUZZ_LIB_F32 := $(patsubst src/%.c,$(BUILD)/fuzz-f32/lib/%.o,$(LIB_SRC))
FUZZ_LIB_F64 := $(patsubst src/%.c,$(BUILD)/fuzz-f64/lib/%.o,$(LIB_SRC))
FUZZ_LIB_Q31 := $(patsubst src/%.c,$(BUILD)/fuzz-q31/lib/%.o,$(Q31_SRC))
FUZZ_TID_SRC := $(filter src/estimators/tyre_id/%,$(LIB_SRC))
FUZZ_TID_F32 := $(patsubst src/%.c,$(BUILD)/fuzz-tid-f32/lib/%.o,$(FUZZ_TID_SRC)) \
                $(filter-out $(BUILD)/fuzz-f32/lib/estimators/tyre_id/%,$(FUZZ_LIB_F32))
FUZZ_TID_F64 := $(patsubst src/%.c,$(BUILD)/fuzz-tid-f64/lib/%.o,$(FUZZ_TID_SRC)) \
                $(filter-out $(BUILD)/fuzz-f64/lib/estimators/tyre_id/%,$(FUZZ_LIB_F64))
FUZZ_HOST    := $(patsubst src/host/%.c,$(BUILD)/fuzz-f32/host/%.o,$(HOST_SRC) src/host/replay_real.c)

.PHONY: deps-fuzz fuzz fuzz-smoke fault-scenarios soak soak-short
DEPS_EXTRA += deps-fuzz
TEST_GATES += fuzz-smoke soak-short

## install clang-19 with libFuzzer (apt) when missing
deps-fuzz:
	@if ! command -v $(FUZZ_CC) >/dev/null 2>&1 || \
	  ! echo 'int LLVMFuzzerTestOneInput(const char *d, unsigned long n) { return (int)n & (int)*d & 0; }' | \
	    $(FUZZ_CC) -x c - -fsanitize=fuzzer -o /dev/null >/dev/null 2>&1; then \
	  echo "[deps] installing $(FUZZ_CC) and libclang-rt-$(FUZZ_LLVM)-dev (libFuzzer) via apt"; \
	  $(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq clang-$(FUZZ_LLVM) libclang-rt-$(FUZZ_LLVM)-dev; fi

# The library and host code instrumented for coverage (fuzzer-no-link): float, double, q31.
$(BUILD)/fuzz-f32/lib/%.o: src/%.c | deps-fuzz
	@mkdir -p $(@D)
	$(FUZZ_CC) $(DEPFLAGS) $(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link $(CPPFLAGS_LIB) -c $< -o $@
$(BUILD)/fuzz-f64/lib/%.o: src/%.c | deps-fuzz
	@mkdir -p $(@D)
	$(FUZZ_CC) $(DEPFLAGS) $(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link -DRFE_REAL_DOUBLE $(CPPFLAGS_LIB) -c $< -o $@
$(BUILD)/fuzz-q31/lib/%.o: src/%.c | deps-fuzz
	@mkdir -p $(@D)
	$(FUZZ_CC) $(DEPFLAGS) $(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link $(CPPFLAGS_LIB) -c $< -o $@
# The tyre identifier's sources at FUZZ_TID_N particles (its harnesses link these instead).
$(BUILD)/fuzz-tid-f32/lib/%.o: src/%.c | deps-fuzz
	@mkdir -p $(@D)
	$(FUZZ_CC) $(DEPFLAGS) $(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link -DRFE_TID_N=$(FUZZ_TID_N) $(CPPFLAGS_LIB) -c $< -o $@
$(BUILD)/fuzz-tid-f64/lib/%.o: src/%.c | deps-fuzz
	@mkdir -p $(@D)
	$(FUZZ_CC) $(DEPFLAGS) $(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link -DRFE_TID_N=$(FUZZ_TID_N) -DRFE_REAL_DOUBLE $(CPPFLAGS_LIB) -c $< -o $@
$(BUILD)/fuzz-f32/host/%.o: src/host/%.c | deps-fuzz
	@mkdir -p $(@D)
	$(FUZZ_CC) $(DEPFLAGS) $(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link $(CPPFLAGS_HOST) -c $< -o $@
FUZZ_STEP_DEPS := test/fuzz/fuzz_step_flt.c test/fuzz/fuzz_input.h test/fuzz/fuzz_real.h test/support/invariants.h
$(BUILD)/fuzz/fuzz_step_f32: $(FUZZ_STEP_DEPS) $(FUZZ_LIB_F32)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer $(CPPFLAGS_LIB) -Itest/support -Itest/fuzz $< $(FUZZ_LIB_F32) -lm -o $@
$(BUILD)/fuzz/fuzz_step_f64: $(FUZZ_STEP_DEPS) $(FUZZ_LIB_F64)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer -DRFE_REAL_DOUBLE $(CPPFLAGS_LIB) -Itest/support -Itest/fuzz $< $(FUZZ_LIB_F64) -lm -o $@
# The fixed-point harness: the double library gives the presets and their conversion.
$(BUILD)/fuzz/fuzz_step_q31: test/fuzz/fuzz_step_q31.c test/fuzz/fuzz_input.h test/support/invariants.h $(FUZZ_LIB_Q31) $(FUZZ_LIB_F64)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer $(CPPFLAGS_LIB) -Itest/support -Itest/fuzz $< $(FUZZ_LIB_Q31) $(FUZZ_LIB_F64) -lm -o $@
# The velocity observer's harness (float, double): the same decoding, an ESC sample.
FUZZ_VEL_DEPS := test/fuzz/fuzz_velocity_flt.c test/fuzz/fuzz_input.h test/fuzz/fuzz_real.h
$(BUILD)/fuzz/fuzz_velocity_f32: $(FUZZ_VEL_DEPS) $(FUZZ_LIB_F32)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer $(CPPFLAGS_LIB) -Itest/fuzz $< $(FUZZ_LIB_F32) -lm -o $@
$(BUILD)/fuzz/fuzz_velocity_f64: $(FUZZ_VEL_DEPS) $(FUZZ_LIB_F64)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer -DRFE_REAL_DOUBLE $(CPPFLAGS_LIB) -Itest/fuzz $< $(FUZZ_LIB_F64) -lm -o $@
# The mass and grade estimator's and the tyre identifier's harnesses (float, double): the same
# record decoding, their parameters through test/fuzz/fuzz_params.h.
FUZZ_MG_DEPS := test/fuzz/fuzz_mass_grade_flt.c test/fuzz/fuzz_input.h test/fuzz/fuzz_real.h test/fuzz/fuzz_params.h
$(BUILD)/fuzz/fuzz_mass_grade_f32: $(FUZZ_MG_DEPS) $(FUZZ_LIB_F32)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer $(CPPFLAGS_LIB) -Itest/fuzz $< $(FUZZ_LIB_F32) -lm -o $@
$(BUILD)/fuzz/fuzz_mass_grade_f64: $(FUZZ_MG_DEPS) $(FUZZ_LIB_F64)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer -DRFE_REAL_DOUBLE $(CPPFLAGS_LIB) -Itest/fuzz $< $(FUZZ_LIB_F64) -lm -o $@
FUZZ_TID_DEPS := test/fuzz/fuzz_tyre_id_flt.c test/fuzz/fuzz_input.h test/fuzz/fuzz_real.h test/fuzz/fuzz_params.h
$(BUILD)/fuzz/fuzz_tyre_id_f32: $(FUZZ_TID_DEPS) $(FUZZ_TID_F32)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer -DRFE_TID_N=$(FUZZ_TID_N) $(CPPFLAGS_LIB) -Itest/fuzz $< $(FUZZ_TID_F32) -lm -o $@
$(BUILD)/fuzz/fuzz_tyre_id_f64: $(FUZZ_TID_DEPS) $(FUZZ_TID_F64)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer -DRFE_TID_N=$(FUZZ_TID_N) -DRFE_REAL_DOUBLE $(CPPFLAGS_LIB) -Itest/fuzz $< $(FUZZ_TID_F64) -lm -o $@
# The fixed-point observer's harness: the double library gives the defaults and their conversion.
$(BUILD)/fuzz/fuzz_velocity_q31: test/fuzz/fuzz_velocity_q31.c test/fuzz/fuzz_input.h $(FUZZ_LIB_Q31) $(FUZZ_LIB_F64)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer $(CPPFLAGS_LIB) -Itest/fuzz $< $(FUZZ_LIB_Q31) $(FUZZ_LIB_F64) -lm -o $@
# The fixed-point mass and grade estimator's harness: the double library gives the presets and
# their conversion.
$(BUILD)/fuzz/fuzz_mass_grade_q31: test/fuzz/fuzz_mass_grade_q31.c test/fuzz/fuzz_input.h test/fuzz/fuzz_params.h $(FUZZ_LIB_Q31) $(FUZZ_LIB_F64)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer $(CPPFLAGS_LIB) -Itest/fuzz $< $(FUZZ_LIB_Q31) $(FUZZ_LIB_F64) -lm -o $@
$(BUILD)/fuzz/fuzz_csv: test/fuzz/fuzz_csv.c $(FUZZ_HOST) $(FUZZ_LIB_F32)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer $(CPPFLAGS_HOST) $< $(FUZZ_HOST) $(FUZZ_LIB_F32) -lm -o $@

# $(1) = output directory, $(2) = libFuzzer options. Seeds: test/fuzz/corpus/fuzz_step (every
# step harness, the observer's too: one decoding) and test/fuzz/corpus/fuzz_csv; new inputs go to $(1)/corpus/<harness>.
# Prints executions, corpus size and coverage per harness; a failure shows its first lines,
# the other harnesses still run, and the target fails at the end.
define FUZZ_RUN
	@failed=0; for h in $(FUZZ_BINS); do \
	  seeds=test/fuzz/corpus/$$(echo $$h | sed 's/_\(f32\|f64\|q31\)$$//; s/^fuzz_velocity$$/fuzz_step/'); \
	  mkdir -p $(1)/corpus/$$h $(1)/artifacts; \
	  if ! $(BUILD)/fuzz/$$h $(FUZZ_OPTS) $(2) -artifact_prefix=$(1)/artifacts/$$h- \
	      $(1)/corpus/$$h $$seeds > $(1)/$$h.log 2>&1; then \
	    grep -m3 -E '^(fuzz_|==[0-9]+==ERROR|SUMMARY)' $(1)/$$h.log; \
	    echo "$$h: FAILED (input in $(1)/artifacts/, log $(1)/$$h.log)"; failed=1; continue; fi; \
	  echo "$$h: $$(grep -m1 -o 'number_of_executed_units: [0-9]*' $(1)/$$h.log | sed 's/.*: //') executions," \
	    "$$(grep -o 'corp: [0-9]*' $(1)/$$h.log | tail -1 | sed 's/corp: //') corpus inputs," \
	    "$$(grep -o 'cov: [0-9]*' $(1)/$$h.log | tail -1 | sed 's/cov: //') coverage points, no failure"; \
	done; exit $$failed
endef
FUZZ_TARGETS := $(addprefix $(BUILD)/fuzz/,$(FUZZ_BINS))
## every libFuzzer harness FUZZ_SECONDS each
fuzz: deps-fuzz $(FUZZ_TARGETS)
	$(call FUZZ_RUN,$(BUILD)/fuzz,-max_total_time=$(FUZZ_SECONDS))
## each harness FUZZ_SMOKE_SECONDS over the committed seeds
fuzz-smoke: deps-fuzz $(FUZZ_TARGETS)
	@rm -rf $(BUILD)/fuzz-smoke
	$(call FUZZ_RUN,$(BUILD)/fuzz-smoke,-seed=1 -max_total_time=$(FUZZ_SMOKE_SECONDS))

## regenerate scenarios/faults/ from the bundled logs
fault-scenarios: venv
	$(PY) scripts/data/make_fault_scenarios.py --scenarios scenarios --out scenarios/faults

# Soak: the drive is simulated once per length and seed (cached in build/soak/), the runner
# is one program linking the float, double and q31 libraries (test/soak/soak_run.c,
# soak_run_pipeline.c and soak_run_aux.c twice, test/soak/soak_run_q31.c and
# soak_run_pipeline_q31.c).
SOAK_SECONDS       ?= 3600
SOAK_SHORT_SECONDS ?= 300
SOAK_SEED          ?= 1
# The tyre identifier runs over the rows with SOAK_TID_FROM <= t < SOAK_TID_TO [s] in the
# short soak (60 s of the drive: accelerating, sine steer, braking in a turn, ABS, a stop;
# ~3.3 s on one core for float and double), over the whole drive in make soak.
SOAK_SHORT_TID     ?= --tid-from 20 --tid-to 80
SOAK_JOBS          ?= $(shell nproc 2>/dev/null || echo 1)
$(BUILD)/soak/drive_%s.csv: scripts/data/soak_drive.py $(wildcard scripts/sim/*.py) | venv
	@mkdir -p $(@D)
	$(PY) scripts/data/soak_drive.py --seconds $* --seed $(SOAK_SEED) --jobs $(SOAK_JOBS) --out $@
$(BUILD)/soak/run_%.o: test/soak/soak_run.c test/soak/soak.h test/support/invariants.h $(wildcard include/rfe/*.h include/rfe/component/*.h src/host/*.h)
	@mkdir -p $(@D)
	$(CC) $(TEST_WARN) $(OPT) $(INV_FLAGS) $(if $(filter f64,$*),-DRFE_REAL_DOUBLE) $(CPPFLAGS_HOST) -Itest/support -Itest/soak -c $< -o $@
$(BUILD)/soak/pipeline_%.o: test/soak/soak_run_pipeline.c test/soak/soak.h test/support/invariants.h $(wildcard include/rfe/*.h include/rfe/component/*.h src/host/*.h)
	@mkdir -p $(@D)
	$(CC) $(TEST_WARN) $(OPT) $(INV_FLAGS) $(if $(filter f64,$*),-DRFE_REAL_DOUBLE) $(CPPFLAGS_HOST) -Itest/support -Itest/soak -c $< -o $@
# The mass and grade estimator and the tyre identifier (float, double; the double unit also
# runs the mass and grade estimator's fixed-point twin when the q31 library exists).
$(BUILD)/soak/aux_%.o: test/soak/soak_run_aux.c test/soak/soak.h $(wildcard include/rfe/*.h include/rfe/component/*.h src/host/*.h)
	@mkdir -p $(@D)
	$(CC) $(TEST_WARN) $(OPT) $(INV_FLAGS) $(if $(filter f64,$*),-DRFE_REAL_DOUBLE $(if $(Q31_SRC),-DSOAK_Q31)) $(CPPFLAGS_HOST) -Itest/support -Itest/soak -c $< -o $@
# The fixed-point variant joins when the q31 library exists (*_q31.c sources).
$(BUILD)/soak/run_q31.o: test/soak/soak_run_q31.c test/soak/soak.h test/support/invariants.h $(wildcard include/rfe/*.h include/rfe/component/*.h src/host/*.h)
	@mkdir -p $(@D)
	$(CC) $(TEST_WARN) $(OPT) $(INV_FLAGS) $(CPPFLAGS_HOST) -Itest/support -Itest/soak -c $< -o $@
# (an explicit rule: it wins over the pipeline_% pattern above)
$(BUILD)/soak/pipeline_q31.o: test/soak/soak_run_pipeline_q31.c test/soak/soak.h test/support/invariants.h $(wildcard include/rfe/*.h include/rfe/component/*.h src/host/*.h)
	@mkdir -p $(@D)
	$(CC) $(TEST_WARN) $(OPT) $(INV_FLAGS) $(CPPFLAGS_HOST) -Itest/support -Itest/soak -c $< -o $@
SOAK_LINK := $(BUILD)/soak/run_f32.o $(BUILD)/soak/run_f64.o $(BUILD)/soak/pipeline_f32.o $(BUILD)/soak/pipeline_f64.o \
             $(BUILD)/soak/aux_f32.o $(BUILD)/soak/aux_f64.o $(if $(Q31_SRC),$(BUILD)/soak/run_q31.o $(BUILD)/soak/pipeline_q31.o $(BUILD)/f64/host/replay_q31.o) \
             $(BUILD)/f32/host/replay_real.o $(BUILD)/f64/host/replay_real.o $(BUILD)/f64/hostlib.a \
             $(BUILD)/f32/librfe.a $(if $(Q31_SRC),$(BUILD)/q31/librfe_q31.a) $(BUILD)/f64/librfe.a
$(BUILD)/soak/soak: test/soak/soak.c test/soak/soak.h $(SOAK_LINK)
	$(CC) $(TEST_WARN) $(OPT) $(CPPFLAGS_HOST) $(if $(Q31_SRC),-DSOAK_Q31) -Itest/soak $< $(SOAK_LINK) -lm -o $@
## SOAK_SECONDS (one hour) of simulated driving, invariants at every step
soak: $(BUILD)/soak/soak $(BUILD)/soak/drive_$(SOAK_SECONDS)s.csv
	$(BUILD)/soak/soak --in $(BUILD)/soak/drive_$(SOAK_SECONDS)s.csv --json $(BUILD)/soak/summary_$(SOAK_SECONDS)s.json
## the short soak (SOAK_SHORT_SECONDS), part of make test
soak-short: $(BUILD)/soak/soak $(BUILD)/soak/drive_$(SOAK_SHORT_SECONDS)s.csv
	$(BUILD)/soak/soak --in $(BUILD)/soak/drive_$(SOAK_SHORT_SECONDS)s.csv --json $(BUILD)/soak/summary_$(SOAK_SHORT_SECONDS)s.json $(SOAK_SHORT_TID)
