# Benchmarks (docs/BENCHMARKS.md, issue 8): cost per estimator step, not a test.
#
# make bench        builds the optimised host benchmarks (build/bench/bench_{f32,f64,q31}:
#                   bench/*.c against the -O2 libraries) and runs scripts/bench/bench_run.py:
#                   host time per call (median, min, max over BENCH_REPS passes over
#                   BENCH_LOG), instructions per call (valgrind --tool=callgrind, with the
#                   per-function profile of every step), FilterPy's CubatureKalmanFilter on
#                   the same model and log, the operation-count lower bound, the Cortex-M4
#                   column from build/firmware/pil.json when the firmware run wrote it;
#                   writes build/bench/bench.json and the tables in docs/BENCHMARKS.md;
#                   then scripts/bench/bench_aux.py: the mass and grade estimator and the
#                   tyre identifier (bench/bench_aux.c), build/bench/bench_aux.json and
#                   their table
# make bench-build  only the benchmark binaries
# BENCH_LOG=scenarios/brake_in_turn.csv BENCH_REPS=51 BENCH_ARGS= (e.g. --no-callgrind,
# --no-page, --quick, --render-only) choose the log, the passes and what runs. Not part of
# make test (a benchmark gates nothing); about a minute on two cores.
BENCH_LOG  ?= scenarios/brake_in_turn.csv
BENCH_REPS ?= 51
BENCH_ARGS ?=
BENCH_CFLAGS := -std=c99 -Wall -Wextra -Wshadow -Werror -O2 -g 
BENCH_BINS := $(BUILD)/bench/bench_f32 $(BUILD)/bench/bench_f64 $(if $(Q31_SRC),$(BUILD)/bench/bench_q31) \
              $(BUILD)/bench/bench_aux_f32 $(BUILD)/bench/bench_aux_f64

.PHONY: bench bench-build
## only the benchmark binaries
bench-build: $(BENCH_BINS) $(BUILD)/mu_replay

$(BUILD)/bench/bench_f32: bench/bench_flt.c bench/harness.h $(BUILD)/f32/librfe.a $(BUILD)/f32/hostlib.a $(BUILD)/f32/host/replay_real.o
	@mkdir -p $(@D)
	$(CC) $(BENCH_CFLAGS) $(CPPFLAGS_HOST) $< $(BUILD)/f32/host/replay_real.o $(BUILD)/f32/hostlib.a \
	  $(BUILD)/f32/librfe.a -lm -o $@
$(BUILD)/bench/bench_f64: bench/bench_flt.c bench/harness.h $(BUILD)/f64/librfe.a $(BUILD)/f64/hostlib.a $(BUILD)/f64/host/replay_real.o
	@mkdir -p $(@D)
	$(CC) $(BENCH_CFLAGS) -DRFE_REAL_DOUBLE $(CPPFLAGS_HOST) $< $(BUILD)/f64/host/replay_real.o \
	  $(BUILD)/f64/hostlib.a $(BUILD)/f64/librfe.a -lm -o $@
$(BUILD)/bench/bench_q31: bench/bench_q31.c bench/harness.h $(BUILD)/q31/librfe_q31.a $(BUILD)/f64/librfe.a $(BUILD)/f64/hostlib.a $(BUILD)/f64/host/replay_real.o
	@mkdir -p $(@D)
	$(CC) $(BENCH_CFLAGS) -DRFE_REAL_DOUBLE $(CPPFLAGS_HOST) $< $(BUILD)/f64/host/replay_real.o \
	  $(BUILD)/f64/hostlib.a $(BUILD)/q31/librfe_q31.a $(BUILD)/f64/librfe.a -lm -o $@

# The mass and grade estimator and the tyre identifier (bench/bench_aux.c, scripts/bench/
# bench_aux.py): their own logs (BENCH_AUX_MG_LOG, BENCH_AUX_TID_LOG), a few seconds in all.
BENCH_AUX_MG_LOG  ?= scenarios/mass_grade/car_hilly_road.csv
BENCH_AUX_TID_LOG ?= scenarios/tyre_id/tid_ramp_steer_high_mu.csv
$(BUILD)/bench/bench_aux_f32: bench/bench_aux.c src/host/pil/aux_input.h $(BUILD)/f32/librfe.a $(BUILD)/f32/hostlib.a $(BUILD)/f32/host/replay_real.o
	@mkdir -p $(@D)
	$(CC) $(BENCH_CFLAGS) $(CPPFLAGS_HOST) $< $(BUILD)/f32/host/replay_real.o $(BUILD)/f32/hostlib.a \
	  $(BUILD)/f32/librfe.a -lm -o $@
$(BUILD)/bench/bench_aux_f64: bench/bench_aux.c src/host/pil/aux_input.h $(BUILD)/f64/librfe.a $(BUILD)/f64/hostlib.a $(BUILD)/f64/host/replay_real.o
	@mkdir -p $(@D)
	$(CC) $(BENCH_CFLAGS) -DRFE_REAL_DOUBLE $(CPPFLAGS_HOST) $< $(BUILD)/f64/host/replay_real.o \
	  $(BUILD)/f64/hostlib.a $(BUILD)/f64/librfe.a -lm -o $@

## cost per step: host time, callgrind, FilterPy, lower bound -> docs/BENCHMARKS.md
bench: deps-valgrind venv bench-build
	$(PY) scripts/bench/bench_run.py --bin-dir $(BUILD)/bench --replay $(BUILD)/mu_replay \
	  --log $(BENCH_LOG) --reps $(BENCH_REPS) --out $(BUILD)/bench --page docs/BENCHMARKS.md $(BENCH_ARGS)
	$(PY) scripts/bench/bench_aux.py --bin-dir $(BUILD)/bench --mg-log $(BENCH_AUX_MG_LOG) \
	  --tid-log $(BENCH_AUX_TID_LOG) --pil $(FW_DIR)/pil_aux.json --out $(BUILD)/bench --page docs/BENCHMARKS.md \
	  --mg-page docs/MASS_GRADE_RESULTS.md --tid-page docs/TYRE_ID_RESULTS.md
