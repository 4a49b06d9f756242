# Firmware (docs/FIRMWARE.md, issue 5).
#
# make firmware        the library cross-built with arm-none-eabi-gcc for each target
#                      (FW_TARGETS: Cortex-M4F float32 and fixed point, Cortex-M0+ and
#                      Cortex-M3 fixed point; build/firmware/<target>/), the example
#                      firmware images (firmware/example/), then make firmware-check
# make firmware-check  (after its self-test on fixtures that must fail)
#                      on the cross-built objects: no heap function, no soft-float helper in
#                      the soft-float and fixed-point builds, no double in the float32 build
#                      (arm-none-eabi-nm); worst-case stack of each public function from
#                      -fstack-usage and -fcallgraph-info=su; stack, flash and state budgets
#                      (FW_BUDGET_*, below); writes build/firmware/report.json
#                      (make firmware is part of make test)
# make pil             processor in the loop: PIL_LOG in PIL_CONFIGS through the estimator
#                      on QEMU's Cortex-M4 (mps2-an386: float32, fixed point), Cortex-M3
#                      (mps2-an385: fixed point) and Cortex-M0 (microbit: the Cortex-M0+
#                      fixed-point build), outputs compared with the host (fixed point bit
#                      for bit, float32 within the golden tolerance); instructions per step
#                      over the log's first steps (PIL_CONFIGS, PIL_COUNT_STEPS; QEMU's
#                      -d in_asm,exec log, checked against -singlestep); also runs the
#                      Cortex-M3 example firmware for 2 s (SysTick steps, none rejected);
#                      writes build/firmware/pil.json; part of make test
#                      Then the observer entries (PIL_OBS_ENTRIES): the composed pipeline
#                      (velocity observer + friction estimator) on PIL_OBS_LOG on the
#                      Cortex-M4F float32 build and the fixed-point builds (M4F, M3, M0+),
#                      compared with the same program built for the host (float32 within a
#                      tolerance derived from the host's float32 vs double difference; fixed
#                      point bit for bit, every word and discrete output) and with mu_replay
#                      --velocity observer, and instructions per pipeline, observer and
#                      friction step
# make pil-aux         the mass and grade estimator (UKF + ax, the seed's AUKF) and the tyre
#                      identifier on the Cortex-M4F float32 build (PIL_AUX_ENTRIES, below):
#                      compared with the same program built for the host (float32 within twice
#                      the host's float32 vs double difference per output; the tyre
#                      identifier's sigma-point filter within its golden test's float32 bound
#                      of the host double build), instructions per
#                      step, stack, flash, state; writes build/firmware/pil_aux.json. Part of
#                      make test (every estimator meets PIL), a gate of its own beside make pil
#                      (~1 min of QEMU, most of it the tyre identifier's: the APF's ~2.5 M
#                      instructions a step and the SCKF's 200 counted steps under the
#                      execution log)
#                      make pil and make pil-aux end with the regression gate of issue 21:
#                      each mean count of instructions per step against its budget in
#                      PIL_BUDGETS (firmware/pil_budgets.json): more than 2 % over fails,
#                      more than 5 % under prints a note that the budget can be lowered
# make pil-budgets     runs make pil and make pil-aux without the gate and sets every budget
#                      of PIL_BUDGETS to the measured count (commit it with the change that
#                      moved the counts); PIL_BUDGETS_RUNS / PIL_BUDGETS_ONLY (below) measure
#                      and set only some entries, the other budgets kept as they are
# make pil-profile     per-function instructions of a friction step (PIL_PROFILE_CONFIG) on
#                      the Cortex-M4F float32 and fixed-point and the M0+ PIL images, next to
#                      callgrind on the host: a table in docs/FIRMWARE.md (not in make test)
# make firmware-opt    the PIL images at -Os, -O2, -O3, with and without -flto: flash and
#                      instructions per step per core, a table in docs/FIRMWARE.md (not in
#                      make test; the shipped FW_OPT_* stay)
# make firmware-table  regenerates the firmware tables in docs/FIRMWARE.md ("Measured") from
#                      both JSON files (and pil_aux.json when make pil-aux wrote it), and the observer's cost in docs/OBSERVER_RESULTS.md
#                      and README.md (with the host's figure from make bench's bench.json
#                      when it exists)
# make deps-firmware   installs gcc-arm-none-eabi, libnewlib-arm-none-eabi and
#                      qemu-system-arm via apt when missing (part of make deps)
FW_CROSS   := arm-none-eabi-
FW_CC      := $(FW_CROSS)gcc
FW_DIR     := $(BUILD)/firmware
# The estimator needs n = 4, m = 3 (README "Using the library in firmware").
FW_DEFS    := -DRFE_N_MAX=4 -DRFE_M_MAX=3
# -O2 where speed is the point (Cortex-M4F, M3; the M4F's float32 build at -O3, below); -Os on
# the Cortex-M0+, whose parts have 32-128 KB of flash (the same choice as check-nofloat).
FW_OPT_m4f ?= -O2
FW_OPT_m3  ?= -O2
FW_OPT_m0p ?= -Os
# A target (<core>-<variant>) may override its core's setting. The float32 build on the
# Cortex-M4F takes -O3: make firmware-opt measured its default step 11 % faster with the same
# outputs, at flash an M4F part has to spare (docs/FIRMWARE.md "Optimisation levels"); the
# fixed-point builds stay at -O2, whose -O3 images exceed the 64 kB flash budget.
FW_OPT_m4f-f32 ?= -O3
fw_opt = $(or $(FW_OPT_$(1)),$(FW_OPT_$(call fw_core,$(1))))
FW_CFLAGS   = $(WARN) -g -ffunction-sections -fdata-sections $(FW_DEFS)
# Per-unit optimisation: the library sources listed in FW_UNITS_OS_<core> are compiled with
# FW_UNIT_OPT appended after FW_OPT_<core> (the last -O wins), the other units as above.
# Empty as shipped; docs/FIXED_POINT.md "Analytic input derivatives" measures the input
# derivative's units at -Os on the -O2 cores with it.
FW_UNIT_OPT     ?= -Os
FW_UNITS_OS_m4f ?=
FW_UNITS_OS_m3  ?=
FW_UNITS_OS_m0p ?=
# The same the other way: the sources listed in FW_UNITS_O2_<core> / FW_UNITS_O3_<core> are
# compiled at -O2 / -O3 after their core's level (e.g. the hot units of an -Os core). Empty as
# shipped: docs/FIRMWARE.md "Issue 21: per-unit levels on the Cortex-M0+" measures the M0+'s
# hot units at -O2 and -O3 (at best a quarter of the paper step's gap to 120,000 instructions
# for 14 % more flash, so not set).
FW_UNITS_O2_m4f ?=
FW_UNITS_O2_m3  ?=
FW_UNITS_O2_m0p ?=
FW_UNITS_O3_m4f ?=
FW_UNITS_O3_m3  ?=
FW_UNITS_O3_m0p ?=
# fw_unit_opt(core, source): the flags appended for a unit (empty for most).
fw_unit_opt = $(if $(filter $(2),$(FW_UNITS_OS_$(1))),$(FW_UNIT_OPT))$(foreach l,O2 O3,$(if $(filter $(2),$(FW_UNITS_$(l)_$(1))), -$(l)))
FW_ARCH_m4f := -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16
FW_ARCH_m3  := -mcpu=cortex-m3 -mthumb -mfloat-abi=soft
FW_ARCH_m0p := -mcpu=cortex-m0plus -mthumb -mfloat-abi=soft
# <core>-<variant>: the float32 library only where the core has a single-precision FPU.
FW_TARGETS := m4f-f32 m4f-q31 m0p-q31 m3-q31
fw_core     = $(word 1,$(subst -, ,$(1)))
fw_variant  = $(word 2,$(subst -, ,$(1)))
fw_srcs     = $(if $(filter q31,$(call fw_variant,$(1))),$(Q31_SRC),$(LIB_SRC))
fw_lib      = $(FW_DIR)/$(1)/$(if $(filter q31,$(call fw_variant,$(1))),librfe_q31.a,librfe.a)
FW_COMMON_H := $(wildcard firmware/common/*.h)
# Example images: float32 on the Cortex-M4F, fixed point on the M4F, the M0+ and the M3
# (the MPS2 board QEMU emulates).
FW_EXAMPLES := m4f-f32 m4f-q31 m0p-q31 m3-q31
FW_LD_m4f  := firmware/ld/stm32f407xg.ld
FW_LD_m0p  := firmware/ld/stm32g071xb.ld
FW_LD_m3   := firmware/ld/mps2.ld
FW_LDLIBS_f32 := -lm
FW_LDLIBS_q31 :=
FW_LDFLAGS  = --specs=nano.specs -nostartfiles -Wl,--gc-sections -Wl,--no-warn-rwx-segments

.PHONY: deps-firmware firmware firmware-libs firmware-check firmware-table firmware-table-aux pil pil-aux pil-budgets pil-profile pil-images firmware-opt
DEPS_EXTRA += deps-firmware
TEST_GATES += firmware pil pil-aux

## install the Cortex-M toolchain, newlib and QEMU (apt) when missing
deps-firmware:
	@missing=""; command -v arm-none-eabi-gcc >/dev/null 2>&1 || missing="$$missing gcc-arm-none-eabi"; \
	  [ -f /usr/lib/arm-none-eabi/newlib/libc.a ] || [ -f /usr/lib/arm-none-eabi/lib/libc.a ] || \
	    missing="$$missing libnewlib-arm-none-eabi"; \
	  command -v qemu-system-arm >/dev/null 2>&1 || missing="$$missing qemu-system-arm"; \
	  if [ -n "$$missing" ]; then echo "[deps] installing$$missing via apt"; \
	    $(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; fi

# ---- the library, per target -------------------------------------------------------------
# Objects keep their -fstack-usage (.su) and -fcallgraph-info=su (.ci) files beside them.
define FW_LIB_RULES
# $(1) = target (core-variant)
$(FW_DIR)/$(1)/lib/%.o: src/%.c | deps-firmware
	@mkdir -p $$(@D)
	$$(FW_CC) $$(DEPFLAGS) $$(FW_ARCH_$(call fw_core,$(1))) $$(call fw_opt,$(1)) \
	  $$(call fw_unit_opt,$(call fw_core,$(1)),$$<) $$(FW_CFLAGS) $$(CPPFLAGS_LIB) -fstack-usage \
	  -fcallgraph-info=su -fdump-ipa-cgraph -dumpdir $$(@D)/ -c $$< -o $$@
$(call fw_lib,$(1)): $(patsubst src/%.c,$(FW_DIR)/$(1)/lib/%.o,$(call fw_srcs,$(1)))
	rm -f $$@ && $(FW_CROSS)ar rcs $$@ $$^
$(FW_DIR)/$(1)/common/%.o: firmware/common/%.c | deps-firmware
	@mkdir -p $$(@D)
	$$(FW_CC) $$(DEPFLAGS) $$(FW_ARCH_$(call fw_core,$(1))) $$(call fw_opt,$(1)) $$(FW_CFLAGS) $$(CPPFLAGS_LIB) -Ifirmware/common -c $$< -o $$@
# startup_pil.o: the start-up of startup_cm.c that hands over to newlib's semihosting crt0.
$(FW_DIR)/$(1)/common/startup_pil.o: firmware/common/startup_cm.c $(FW_COMMON_H) | deps-firmware
	@mkdir -p $$(@D)
	$$(FW_CC) $$(DEPFLAGS) $$(FW_ARCH_$(call fw_core,$(1))) $$(call fw_opt,$(1)) $$(FW_CFLAGS) $$(CPPFLAGS_LIB) -Ifirmware/common -DSTARTUP_NEWLIB_CRT0 -c $$< -o $$@
endef
$(foreach t,$(FW_TARGETS),$(eval $(call FW_LIB_RULES,$(t))))
FW_LIBS := $(foreach t,$(FW_TARGETS),$(call fw_lib,$(t)))

# ---- the example firmware ----------------------------------------------------------------
define FW_EXAMPLE_RULES
# $(1) = target
$(FW_DIR)/$(1)/example/main.o: firmware/example/main.c | deps-firmware
	@mkdir -p $$(@D)
	$$(FW_CC) $$(DEPFLAGS) $$(FW_ARCH_$(call fw_core,$(1))) $$(call fw_opt,$(1)) $$(FW_CFLAGS) $$(CPPFLAGS_LIB) -Ifirmware/common \
	  $(if $(filter q31,$(call fw_variant,$(1))),-DFW_EXAMPLE_Q31) -fstack-usage -c $$< -o $$@
$(FW_DIR)/$(1)/example.elf: $(FW_DIR)/$(1)/example/main.o $(FW_DIR)/$(1)/common/startup_cm.o \
                            $(call fw_lib,$(1)) $(FW_LD_$(call fw_core,$(1))) firmware/ld/sections.ld
	$$(FW_CC) $$(FW_ARCH_$(call fw_core,$(1))) $$(FW_LDFLAGS) -Lfirmware/ld -T$(FW_LD_$(call fw_core,$(1))) \
	  -Wl,-Map=$$(@:.elf=.map) $$(filter %.o %.a,$$^) $$(FW_LDLIBS_$(call fw_variant,$(1))) -lc -lgcc -o $$@
endef
$(foreach t,$(FW_EXAMPLES),$(eval $(call FW_EXAMPLE_RULES,$(t))))
FW_EXAMPLE_ELFS := $(foreach t,$(FW_EXAMPLES),$(FW_DIR)/$(t)/example.elf)

## the library cross-built for each Cortex-M target
firmware-libs: $(FW_LIBS)
## Cortex-M libraries and example images, then firmware-check
firmware: $(FW_LIBS) $(FW_EXAMPLE_ELFS)
	@$(MAKE) --no-print-directory firmware-check

# Budgets (make firmware fails beyond them).
# Stack: 2 KB per public call (init, step, get; in the float32 build the mass and grade
#   estimator's and the tyre identifier's init and step too: 1.1-1.2 KB static for their
#   steps), what an RTOS task running the estimator can
#   spare on a 32-64 KB-RAM part; static worst case 1.4-1.6 KB (the default configuration's
#   step; the M0+ needs most), so ~25 % more stack in a change fails.
# Flash: the library's linked share (example image, --gc-sections) <= 48 KB. Set at 40 KB when
#   it measured 16 KB (float32) to 30 KB (fixed point, -O2); the observer, the monitor and the
#   holds took it to 26.5 KB (float32), 34 KB (fixed point, -Os, Cortex-M0+) and 41 KB (fixed
#   point, -O2, Cortex-M4 and M3) and the jump hold passed 40 KB by 36 B, so it was raised to
#   48 KB: ~17 % growth fails, and the library keeps under 3/8 of the 128 KB Cortex-M0+ part
#   (firmware/ld/stm32g071xb.ld).
#   Per core since issue 21's analytic input derivative (docs/FIXED_POINT.md "Analytic input
#   derivatives", Decision): the Cortex-M0+ (-Os) keeps 48 KB, the part it is set for; the -O2
#   Cortex-M4F and M3 builds, which trade flash for speed, get 64 KB, a quarter of a 256 KB
#   part (the smallest flash of the usual automotive Cortex-M4F families; the M4F example's
#   STM32F407xG has 1 MB). Not LTO instead: under LTO the step is inlined into the
#   application and its stack per public call (the budget above) can no longer be separated.
#   FW_BUDGET_FLASH is "core:bytes" for every core of FW_TARGETS (one figure: every core).
# State: sizeof of the estimator state <= 2 KB with RFE_N_MAX=4, RFE_M_MAX=3 (measured
#   1480-1544 B; it grows only with the filter's maxima).
FW_BUDGET_STACK ?= 2048
FW_BUDGET_FLASH ?= m0p:49152 m4f:65536 m3:65536
FW_BUDGET_STATE ?= 2048

## no heap, no soft float, stack, flash and state budgets
firmware-check: $(FW_LIBS) $(FW_EXAMPLE_ELFS)
	@python3 scripts/firmware/firmware_check.py --self-test --out $(FW_DIR)/report.json
	@python3 scripts/firmware/firmware_check.py --build $(FW_DIR) --targets "$(FW_TARGETS)" \
	  --budget-stack $(FW_BUDGET_STACK) --budget-flash "$(FW_BUDGET_FLASH)" --budget-state $(FW_BUDGET_STATE) \
	  --examples "$(FW_EXAMPLES)" --cflags "$(FW_CFLAGS) $(CPPFLAGS_LIB)" --out $(FW_DIR)/report.json

# ---- processor in the loop ---------------------------------------------------------------
# PIL_LOG is the benchmark's log (mk/bench.mk), so the Cortex-M column there and the host
# figures describe the same drive. PIL_CONFIGS: <golden tag>:<pil_gen / mu_replay options>:
# <steps whose instructions are counted> (the first ones of the log; QEMU's execution log
# grows with the count, so 100 steps each keep make pil well under a minute).
# PIL_COUNT_STEPS=N counts N steps in every configuration instead.
PIL_LOG         ?= scenarios/brake_in_turn.csv
PIL_CONFIGS     ?= paper.sckf:--preset,paper,--filter,sckf:100 default.sckf:--preset,default:100
PIL_COUNT_STEPS ?= 0
# The committed budgets of the instruction counts (scripts/firmware/pil_budgets.py); a run on
# another log or step count has none, so it fails the gate: PIL_BUDGETS= runs without it.
PIL_BUDGETS     ?= firmware/pil_budgets.json
# <core>-<variant>:<QEMU machine>
PIL_RUNS        := m4f-f32:mps2-an386 m4f-q31:mps2-an386 m3-q31:mps2-an385 m0p-q31:microbit
# Memory map of each PIL core's QEMU board.
PIL_LD_m4f      := firmware/ld/mps2.ld
PIL_LD_m3       := firmware/ld/mps2.ld
PIL_LD_m0p      := firmware/ld/microbit.ld
PIL_STEM        := $(basename $(notdir $(PIL_LOG)))
pil_tag          = $(word 1,$(subst :, ,$(1)))
pil_opts         = $(subst $(fw_comma), ,$(word 2,$(subst :, ,$(1))))
fw_comma        := ,

# pil_gen: a float unit, linked with both replays (replay_q31.o derives the Q parameters and
# samples, mu_replay --real q31's own conversions) and the libraries they need.
$(FW_DIR)/pil_gen: src/host/pil/pil_gen.c $(BUILD)/f32/host/replay_real.o $(BUILD)/f64/host/replay_real.o \
                   $(BUILD)/f64/host/replay_q31.o $(BUILD)/f64/hostlib.a $(BUILD)/f32/librfe.a $(BUILD)/f64/librfe.a \
                   $(BUILD)/q31/librfe_q31.a
	@mkdir -p $(@D)
	$(CC) $(WARN) $(OPT) -Wno-double-promotion $(CPPFLAGS_HOST) -Ifirmware/pil -c src/host/pil/pil_gen.c -o $(FW_DIR)/pil_gen.o
	$(CC) $(FW_DIR)/pil_gen.o $(BUILD)/f32/host/replay_real.o $(BUILD)/f64/host/replay_real.o $(BUILD)/f64/host/replay_q31.o \
	  $(BUILD)/f64/hostlib.a $(BUILD)/q31/librfe_q31.a $(BUILD)/f32/librfe.a $(BUILD)/f64/librfe.a -lm -o $@

define PIL_DATA_RULES
# $(1) = <tag>:<options>
$(FW_DIR)/pil/data/$(PIL_STEM).$(call pil_tag,$(1)).c: $(PIL_LOG) $(FW_DIR)/pil_gen
	@mkdir -p $$(@D)
	$(FW_DIR)/pil_gen --in $(PIL_LOG) --out $$@ $(call pil_opts,$(1))
endef
$(foreach c,$(PIL_CONFIGS),$(eval $(call PIL_DATA_RULES,$(c))))

define PIL_IMAGE_RULES
# $(1) = target, $(2) = golden tag
$(FW_DIR)/$(1)/pil/$(2).elf: firmware/pil/pil_main.c firmware/pil/pil_data.h $(FW_DIR)/pil/data/$(PIL_STEM).$(2).c \
                            $(FW_DIR)/$(1)/common/startup_pil.o $(call fw_lib,$(1)) $(PIL_LD_$(call fw_core,$(1))) firmware/ld/sections.ld
	@mkdir -p $$(@D)
	$$(FW_CC) $$(FW_ARCH_$(call fw_core,$(1))) $$(call fw_opt,$(1)) $$(FW_CFLAGS) $$(CPPFLAGS_LIB) -Ifirmware/pil -Ifirmware/common \
	  $(if $(filter q31,$(call fw_variant,$(1))),-DPIL_Q31) --specs=rdimon.specs -Wl,--gc-sections \
	  -Wl,--no-warn-rwx-segments -Lfirmware/ld -T$(PIL_LD_$(call fw_core,$(1))) -Wl,-Map=$$(@:.elf=.map) \
	  firmware/pil/pil_main.c $(FW_DIR)/pil/data/$(PIL_STEM).$(2).c $(FW_DIR)/$(1)/common/startup_pil.o \
	  $(call fw_lib,$(1)) $$(FW_LDLIBS_$(call fw_variant,$(1))) -o $$@
endef
$(foreach r,$(PIL_RUNS),$(foreach c,$(PIL_CONFIGS),$(eval $(call PIL_IMAGE_RULES,$(call pil_tag,$(r)),$(call pil_tag,$(c))))))

PIL_ELFS := $(foreach r,$(PIL_RUNS),$(foreach c,$(PIL_CONFIGS),$(FW_DIR)/$(call pil_tag,$(r))/pil/$(call pil_tag,$(c)).elf))

# Observer entries: <tag>:<target>:<QEMU machine>:<steps counted>. The tag names the estimator
# entry of firmware/pil/pil_main.c (PIL_OBS_DEFS_<tag>) and pil_gen's data for it
# (PIL_OBS_GEN_<tag>; one data file per tag, float and fixed point). PIL_OBS_LOG: ABS braking
# on split mu with the driver counter-steering (braking, yaw and lateral slip at once), 8 s,
# every step compared on every entry. Steps counted: float32 on the Cortex-M4F the first
# 200, 1 s cruising and the first second of ABS braking, so both observer states are in the
# count (about 80 k instructions a step). The fixed-point pipeline costs ~0.43 M instructions a
# step on the M4 and M3 and ~1.05 M on the M0+, and QEMU's execution log grows with that: the
# same 200 steps on the Cortex-M4 (the 15 % target's core), the first 100 (the cruising
# second) on the M3 and 20 on the M0+ (the observer's mean over the first 100 steps is within
# 0.5 % of its mean over 200); about 40 s of QEMU logging for the three.
PIL_OBS_LOG        ?= scenarios/observer/abs_brake_split_mu.csv
PIL_OBS_ENTRIES    ?= pipeline:m4f-f32:mps2-an386:200 pipeline:m4f-q31:mps2-an386:200 \
                      pipeline:m3-q31:mps2-an385:100 pipeline:m0p-q31:microbit:20
PIL_OBS_GEN_pipeline  := --estimator pipeline --preset default
PIL_OBS_DEFS_pipeline := -DPIL_PIPELINE
PIL_OBS_STEM       := $(basename $(notdir $(PIL_OBS_LOG)))
pil_obs_field       = $(word $(2),$(subst :, ,$(1)))
# The host builds of a PIL program: float32 and double (the tolerance's reference) for a
# float32 entry, fixed point for a fixed-point one.
pil_host_libs_f32  := f32:$(BUILD)/f32/librfe.a f64:$(BUILD)/f64/librfe.a
pil_host_libs_q31  := q31:$(BUILD)/q31/librfe_q31.a
PIL_HOST_DEFS_f32  :=
PIL_HOST_DEFS_f64  := -DRFE_REAL_DOUBLE
PIL_HOST_DEFS_q31  := -DPIL_Q31

define PIL_OBS_DATA_RULES
# $(1) = <tag> (one data file per tag: its float and fixed-point arms, pil_data.h)
$(FW_DIR)/pil/data/$(PIL_OBS_STEM).$(1).c: $(PIL_OBS_LOG) $(FW_DIR)/pil_gen
	@mkdir -p $$(@D)
	$(FW_DIR)/pil_gen --in $(PIL_OBS_LOG) --out $$@ $(PIL_OBS_GEN_$(1))
endef
define PIL_OBS_RULES
# $(1) = <tag>, $(2) = target
$(FW_DIR)/$(2)/pil/$(1).elf: firmware/pil/pil_main.c firmware/pil/pil_data.h $(FW_DIR)/pil/data/$(PIL_OBS_STEM).$(1).c \
                            $(FW_DIR)/$(2)/common/startup_pil.o $(call fw_lib,$(2)) $(PIL_LD_$(call fw_core,$(2))) firmware/ld/sections.ld
	@mkdir -p $$(@D)
	$$(FW_CC) $$(FW_ARCH_$(call fw_core,$(2))) $$(call fw_opt,$(2)) $$(FW_CFLAGS) $$(CPPFLAGS_LIB) -Ifirmware/pil -Ifirmware/common \
	  $(PIL_OBS_DEFS_$(1)) $(if $(filter q31,$(call fw_variant,$(2))),-DPIL_Q31) --specs=rdimon.specs -Wl,--gc-sections \
	  -Wl,--no-warn-rwx-segments -Lfirmware/ld -T$(PIL_LD_$(call fw_core,$(2))) -Wl,-Map=$$(@:.elf=.map) \
	  firmware/pil/pil_main.c $(FW_DIR)/pil/data/$(PIL_OBS_STEM).$(1).c $(FW_DIR)/$(2)/common/startup_pil.o \
	  $(call fw_lib,$(2)) $$(FW_LDLIBS_$(call fw_variant,$(2))) -o $$@
endef
define PIL_HOST_RULES
# $(1) = <tag>, $(2) = host build (f32, f64, q31), $(3) = its library
$(FW_DIR)/host-$(2)/pil/$(1): firmware/pil/pil_main.c firmware/pil/pil_data.h $(FW_DIR)/pil/data/$(PIL_OBS_STEM).$(1).c $(3)
	@mkdir -p $$(@D)
	$$(CC) $$(WARN) $$(OPT) -Wno-double-promotion $$(CPPFLAGS_LIB) -Ifirmware/pil -DPIL_HOST $(PIL_HOST_DEFS_$(2)) $(PIL_OBS_DEFS_$(1)) \
	  firmware/pil/pil_main.c $(FW_DIR)/pil/data/$(PIL_OBS_STEM).$(1).c $(3) -lm -o $$@
endef
# One data file per tag and one host program per tag and host build, however many targets
# run the tag (the float32 and fixed-point entries of "pipeline" share its data file).
PIL_OBS_TAGS := $(sort $(foreach e,$(PIL_OBS_ENTRIES),$(call pil_obs_field,$(e),1)))
PIL_OBS_HOSTS := $(sort $(foreach e,$(PIL_OBS_ENTRIES),\
  $(foreach h,$(pil_host_libs_$(call fw_variant,$(call pil_obs_field,$(e),2))),$(call pil_obs_field,$(e),1):$(h))))
$(foreach t,$(PIL_OBS_TAGS),$(eval $(call PIL_OBS_DATA_RULES,$(t))))
$(foreach e,$(PIL_OBS_ENTRIES),$(eval $(call PIL_OBS_RULES,$(call pil_obs_field,$(e),1),$(call pil_obs_field,$(e),2))))
$(foreach h,$(PIL_OBS_HOSTS),$(eval $(call PIL_HOST_RULES,$(call pil_obs_field,$(h),1),$(call pil_obs_field,$(h),2),$(call pil_obs_field,$(h),3))))
PIL_OBS_ELFS := $(foreach e,$(PIL_OBS_ENTRIES),$(FW_DIR)/$(call pil_obs_field,$(e),2)/pil/$(call pil_obs_field,$(e),1).elf)
PIL_OBS_HOST := $(foreach h,$(PIL_OBS_HOSTS),$(FW_DIR)/host-$(call pil_obs_field,$(h),2)/pil/$(call pil_obs_field,$(h),1))

# Entries of the estimators beside the friction estimator (make pil-aux): the mass and grade
# estimator and the tyre identifier in float32 (the identifier has no fixed-point twin; the
# Cortex-M3 and M0+ are fixed-point targets), on the Cortex-M4F (mps2-an386, as the float32
# runs above); the mass and grade estimator's Q31 twin below (PIL_AUX_Q31_ENTRIES). <tag>:<log>:<rows run and compared>:<steps counted>. The tag names the entry of
# firmware/pil/pil_main.c (PIL_AUX_DEFS_<tag>) and pil_gen's options (PIL_AUX_GEN_<tag>).
#   mg_ukf    UKF + ax, the recommended car preset (mu_replay's default) on car_hilly_road
#             (50 Hz, cruising on hills: every sample is above v_min, every step updates):
#             the first 1500 samples (30 s) compared, the first 500 counted;
#   mg_aukf   the seed's AUKF (speed only, adaptive mass noise), the same log and counts;
#   tid       the tyre identifier (RFE_TID_N = 256, seed 1) on tid_ramp_steer_high_mu (100 Hz):
#             ~4 M instructions a step on the M4F, so only the first 40 samples run, compared,
#             and the first 20 are counted (the log's first 0.2 s at 80 km/h; the cost per
#             step hardly depends on the manoeuvre: every particle runs the same RK4 and
#             likelihood each step).
#   tid_sckf  its sigma-point filter (tid_filter = sckf, TYRE_ID.md §15) on the same log:
#             ~144 k instructions a step, so the first 400 samples run and are compared, the
#             first 200 counted. Held to the host double build within its golden test's
#             float32 bound (300 x 2^-24 of value plus sd per step: 7.2e-3 over 400 rows),
#             not to the host float32 build (firmware_pil.py SCKF_EPS_PER_STEP says why).
#   tid_sckf_dstate  the same with the steering angle as its state (tid_delta_state_q 0.04,
#             TYRE_ID.md §15.7), the same log and counts; its bound 363 x 2^-24 per step
#             (Tria 11 x 33: firmware_pil.py SCKF_DS_EPS_PER_STEP).
PIL_AUX_ENTRIES ?= mg_ukf:scenarios/mass_grade/car_hilly_road.csv:1500:500 \
                   mg_aukf:scenarios/mass_grade/car_hilly_road.csv:1500:500 \
                   tid:scenarios/tyre_id/tid_ramp_steer_high_mu.csv:40:20 \
                   tid_sckf:scenarios/tyre_id/tid_ramp_steer_high_mu.csv:400:200 \
                   tid_sckf_dstate:scenarios/tyre_id/tid_ramp_steer_high_mu.csv:400:200
PIL_AUX_GEN_mg_ukf   := --estimator mass_grade --mg-config recommended
PIL_AUX_GEN_mg_aukf  := --estimator mass_grade --mg-config seed
PIL_AUX_GEN_tid      := --estimator tyre_id --preset default
PIL_AUX_GEN_tid_sckf := --estimator tyre_id --preset default
PIL_AUX_GEN_tid_sckf_dstate := --estimator tyre_id --preset default
PIL_AUX_DEFS_mg_ukf  := -DPIL_MASS_GRADE
PIL_AUX_DEFS_mg_aukf := -DPIL_MASS_GRADE
PIL_AUX_DEFS_tid     := -DPIL_TYRE_ID
PIL_AUX_DEFS_tid_sckf := -DPIL_TYRE_ID -DPIL_TID_SCKF
PIL_AUX_DEFS_tid_sckf_dstate := -DPIL_TYRE_ID -DPIL_TID_SCKF -DPIL_TID_DSTATE
PIL_AUX_TARGET       := m4f-f32
PIL_AUX_MACHINE      := mps2-an386

define PIL_AUX_RULES
# $(1) = <tag>, $(2) = log, $(3) = rows
$(FW_DIR)/pil/data/aux.$(1).c: $(2) $(FW_DIR)/pil_gen
	@mkdir -p $$(@D)
	$(FW_DIR)/pil_gen --in $(2) --out $$@ --rows $(3) $(PIL_AUX_GEN_$(1))
$(FW_DIR)/$(PIL_AUX_TARGET)/pil/$(1).elf: firmware/pil/pil_main.c firmware/pil/pil_data.h $(FW_DIR)/pil/data/aux.$(1).c \
                            $(FW_DIR)/$(PIL_AUX_TARGET)/common/startup_pil.o $(call fw_lib,$(PIL_AUX_TARGET)) $(PIL_LD_m4f) firmware/ld/sections.ld
	@mkdir -p $$(@D)
	$$(FW_CC) $$(FW_ARCH_m4f) $$(call fw_opt,$(PIL_AUX_TARGET)) $$(FW_CFLAGS) $$(CPPFLAGS_LIB) -Ifirmware/pil -Ifirmware/common \
	  $(PIL_AUX_DEFS_$(1)) --specs=rdimon.specs -Wl,--gc-sections \
	  -Wl,--no-warn-rwx-segments -Lfirmware/ld -T$(PIL_LD_m4f) -Wl,-Map=$$(@:.elf=.map) \
	  firmware/pil/pil_main.c $(FW_DIR)/pil/data/aux.$(1).c $(FW_DIR)/$(PIL_AUX_TARGET)/common/startup_pil.o \
	  $(call fw_lib,$(PIL_AUX_TARGET)) $$(FW_LDLIBS_f32) -o $$@
$(FW_DIR)/host-f32/pil/$(1): firmware/pil/pil_main.c firmware/pil/pil_data.h $(FW_DIR)/pil/data/aux.$(1).c $(BUILD)/f32/librfe.a
	@mkdir -p $$(@D)
	$$(CC) $$(WARN) $$(OPT) -Wno-double-promotion $$(CPPFLAGS_LIB) -Ifirmware/pil -DPIL_HOST $(PIL_AUX_DEFS_$(1)) \
	  firmware/pil/pil_main.c $(FW_DIR)/pil/data/aux.$(1).c $(BUILD)/f32/librfe.a -lm -o $$@
$(FW_DIR)/host-f64/pil/$(1): firmware/pil/pil_main.c firmware/pil/pil_data.h $(FW_DIR)/pil/data/aux.$(1).c $(BUILD)/f64/librfe.a
	@mkdir -p $$(@D)
	$$(CC) $$(WARN) $$(OPT) -Wno-double-promotion $$(CPPFLAGS_LIB) -Ifirmware/pil -DPIL_HOST -DRFE_REAL_DOUBLE $(PIL_AUX_DEFS_$(1)) \
	  firmware/pil/pil_main.c $(FW_DIR)/pil/data/aux.$(1).c $(BUILD)/f64/librfe.a -lm -o $$@
endef
$(foreach e,$(PIL_AUX_ENTRIES),$(eval $(call PIL_AUX_RULES,$(call pil_obs_field,$(e),1),$(call pil_obs_field,$(e),2),$(call pil_obs_field,$(e),3))))
# The mass and grade estimator's fixed-point twin on the fixed-point targets:
# <tag>:<target>:<QEMU machine>:<steps counted>, on the data file of the tag's float entry
# above (pil_gen writes its PIL_Q31 arm too: the same rows, 1500 run and compared on every
# target). Compared bit for bit with the same program built for the host (host-q31/pil/<tag>).
# Steps counted: 500 on the Cortex-M4 (the issue's cost target's core, as the float entries),
# 100 on the M3 and 50 on the M0+ (QEMU's execution log grows with the instructions; the
# log's first second is cruising on hills, every step an update).
PIL_AUX_Q31_ENTRIES ?= mg_ukf:m4f-q31:mps2-an386:500 mg_aukf:m4f-q31:mps2-an386:500 \
                       mg_ukf:m3-q31:mps2-an385:100 mg_ukf:m0p-q31:microbit:50 \
                       mg_aukf:m0p-q31:microbit:50
define PIL_AUX_Q31_RULES
# $(1) = <tag>, $(2) = target
$(FW_DIR)/$(2)/pil/$(1).elf: firmware/pil/pil_main.c firmware/pil/pil_data.h $(FW_DIR)/pil/data/aux.$(1).c \
                            $(FW_DIR)/$(2)/common/startup_pil.o $(call fw_lib,$(2)) $(PIL_LD_$(call fw_core,$(2))) firmware/ld/sections.ld
	@mkdir -p $$(@D)
	$$(FW_CC) $$(FW_ARCH_$(call fw_core,$(2))) $$(call fw_opt,$(2)) $$(FW_CFLAGS) $$(CPPFLAGS_LIB) -Ifirmware/pil -Ifirmware/common \
	  $(PIL_AUX_DEFS_$(1)) -DPIL_Q31 --specs=rdimon.specs -Wl,--gc-sections \
	  -Wl,--no-warn-rwx-segments -Lfirmware/ld -T$(PIL_LD_$(call fw_core,$(2))) -Wl,-Map=$$(@:.elf=.map) \
	  firmware/pil/pil_main.c $(FW_DIR)/pil/data/aux.$(1).c $(FW_DIR)/$(2)/common/startup_pil.o \
	  $(call fw_lib,$(2)) $$(FW_LDLIBS_q31) -o $$@
endef
define PIL_AUX_Q31_HOST_RULES
# $(1) = <tag>
$(FW_DIR)/host-q31/pil/$(1): firmware/pil/pil_main.c firmware/pil/pil_data.h $(FW_DIR)/pil/data/aux.$(1).c $(BUILD)/q31/librfe_q31.a
	@mkdir -p $$(@D)
	$$(CC) $$(WARN) $$(OPT) $$(CPPFLAGS_LIB) -Ifirmware/pil -DPIL_HOST -DPIL_Q31 $(PIL_AUX_DEFS_$(1)) \
	  firmware/pil/pil_main.c $(FW_DIR)/pil/data/aux.$(1).c $(BUILD)/q31/librfe_q31.a -o $$@
endef
$(foreach e,$(PIL_AUX_Q31_ENTRIES),$(eval $(call PIL_AUX_Q31_RULES,$(call pil_obs_field,$(e),1),$(call pil_obs_field,$(e),2))))
PIL_AUX_Q31_TAGS := $(sort $(foreach e,$(PIL_AUX_Q31_ENTRIES),$(call pil_obs_field,$(e),1)))
$(foreach t,$(PIL_AUX_Q31_TAGS),$(eval $(call PIL_AUX_Q31_HOST_RULES,$(t))))
PIL_AUX_Q31_FILES := $(foreach e,$(PIL_AUX_Q31_ENTRIES),$(FW_DIR)/$(call pil_obs_field,$(e),2)/pil/$(call pil_obs_field,$(e),1).elf) \
                     $(foreach t,$(PIL_AUX_Q31_TAGS),$(FW_DIR)/host-q31/pil/$(t))
PIL_AUX_TAGS := $(foreach e,$(PIL_AUX_ENTRIES),$(call pil_obs_field,$(e),1))
PIL_AUX_FILES := $(foreach t,$(PIL_AUX_TAGS),$(FW_DIR)/$(PIL_AUX_TARGET)/pil/$(t).elf $(FW_DIR)/host-f32/pil/$(t) $(FW_DIR)/host-f64/pil/$(t))

## processor in the loop on QEMU's Cortex-M4, M3 and M0: bit identity, instructions
pil: deps-firmware firmware $(PIL_ELFS) $(PIL_OBS_ELFS) $(PIL_OBS_HOST) $(BUILD)/mu_replay
	@python3 scripts/firmware/firmware_pil.py --build $(FW_DIR) --log $(PIL_LOG) --runs "$(PIL_RUNS)" \
	  --configs "$(PIL_CONFIGS)" --replay $(BUILD)/mu_replay --count-steps $(PIL_COUNT_STEPS) \
	  --obs-log $(PIL_OBS_LOG) --obs-entries "$(PIL_OBS_ENTRIES)" \
	  --example m3-q31:mps2-an385 --budgets "$(PIL_BUDGETS)" --report $(FW_DIR)/report.json --out $(FW_DIR)/pil.json

## PIL of the mass and grade estimator (float32 on the M4F, Q31 on the M4, M3, M0+) and the tyre identifier
pil-aux: deps-firmware firmware $(PIL_AUX_FILES) $(PIL_AUX_Q31_FILES)
	@python3 scripts/firmware/firmware_pil.py --build $(FW_DIR) --aux-entries "$(PIL_AUX_ENTRIES)" \
	  --aux-q31-entries "$(PIL_AUX_Q31_ENTRIES)" --budgets "$(PIL_BUDGETS)" --report $(FW_DIR)/report.json \
	  --out $(FW_DIR)/pil_aux.json

# ---- per-function profile of a friction step (make pil-profile) --------------------------
# PIL_PROFILE_CONFIG of PIL_CONFIGS on PIL_PROFILE_RUNS (<target>:<QEMU machine>), the log's
# first PIL_PROFILE_STEPS steps, next to callgrind on the same program built for the host.
PIL_PROFILE_CONFIG ?= default.sckf
PIL_PROFILE_RUNS   ?= m4f-f32:mps2-an386 m4f-q31:mps2-an386 m0p-q31:microbit
PIL_PROFILE_STEPS  ?= 100
PIL_PROFILE_VARIANTS := $(sort $(foreach r,$(PIL_PROFILE_RUNS),$(call fw_variant,$(call pil_obs_field,$(r),1))))
define PIL_PROFILE_HOST_RULES
# $(1) = host build (f32, q31), $(2) = its library
$(FW_DIR)/host-$(1)/pil/$(PIL_PROFILE_CONFIG): firmware/pil/pil_main.c firmware/pil/pil_data.h \
                            $(FW_DIR)/pil/data/$(PIL_STEM).$(PIL_PROFILE_CONFIG).c $(2)
	@mkdir -p $$(@D)
	$$(CC) $$(WARN) $$(OPT) -Wno-double-promotion $$(CPPFLAGS_LIB) -Ifirmware/pil -DPIL_HOST $(PIL_HOST_DEFS_$(1)) \
	  firmware/pil/pil_main.c $(FW_DIR)/pil/data/$(PIL_STEM).$(PIL_PROFILE_CONFIG).c $(2) -lm -o $$@
endef
$(eval $(call PIL_PROFILE_HOST_RULES,f32,$(BUILD)/f32/librfe.a))
$(eval $(call PIL_PROFILE_HOST_RULES,q31,$(BUILD)/q31/librfe_q31.a))

## per-function instruction profile of a friction step on the PIL cores and callgrind (docs/FIRMWARE.md)
pil-profile: deps-firmware $(foreach r,$(PIL_PROFILE_RUNS),$(FW_DIR)/$(call pil_obs_field,$(r),1)/pil/$(PIL_PROFILE_CONFIG).elf) \
             $(foreach v,$(PIL_PROFILE_VARIANTS),$(FW_DIR)/host-$(v)/pil/$(PIL_PROFILE_CONFIG))
	python3 scripts/firmware/pil_profile.py --build $(FW_DIR) --log $(PIL_LOG) --config $(PIL_PROFILE_CONFIG) \
	  --runs "$(PIL_PROFILE_RUNS)" --steps $(PIL_PROFILE_STEPS) --json $(FW_DIR)/pil_profile.json --page docs/FIRMWARE.md

# ---- optimisation levels (make firmware-opt) ---------------------------------------------
# The PIL images of make pil rebuilt at each FW_OPT_SETTINGS entry on every core (Os, O2, O3;
# <level>-lto adds link-time optimisation, with fat objects so that the archive's index still
# lists the library's symbols), one tree each under FW_OPT_DIR, then measured against the
# shipped FW_OPT_* (scripts/firmware/firmware_opt.py); each setting is one level for the whole
# library (the per-unit lists FW_UNITS_{OS,O2,O3}_<core> emptied). The shipped flags are not changed here:
# the budgets and the PIL goldens depend on them. At -O3, GCC 12 warns
# (-Waggressive-loop-optimizations) that filter_estimate in friction_flt.c could read
# est->hold.held[2]: only if the structure and est->n disagreed, which rfe_friction_init
# rules out; the sweep keeps the warning but not as an error, so -O3 can be measured.
FW_OPT_SETTINGS ?= Os O2 O3 Os-lto O2-lto O3-lto
FW_OPT_DIR      := $(BUILD)/firmware-opt
fw_opt_flags     = -$(patsubst %-lto,%,$(1))$(if $(filter %-lto,$(1)), -flto -ffat-lto-objects) \
                   -Wno-error=aggressive-loop-optimizations

## the PIL images of make pil, built only (make firmware-opt builds them per setting)
pil-images: $(PIL_ELFS)

## flash and instructions per step of the PIL images at -Os, -O2, -O3, with and without LTO (docs/FIRMWARE.md)
firmware-opt: deps-firmware $(PIL_ELFS)
	@mkdir -p $(FW_OPT_DIR)
	@$(foreach s,$(FW_OPT_SETTINGS),$(MAKE) --no-print-directory FW_DIR=$(FW_OPT_DIR)/$(s) \
	  FW_OPT_m4f="$(call fw_opt_flags,$(s))" FW_OPT_m4f-f32="$(call fw_opt_flags,$(s))" FW_OPT_m3="$(call fw_opt_flags,$(s))" FW_OPT_m0p="$(call fw_opt_flags,$(s))" \
	  $(foreach c,m4f m3 m0p,FW_UNITS_OS_$(c)= FW_UNITS_O2_$(c)= FW_UNITS_O3_$(c)=) pil-images >$(FW_OPT_DIR)/$(s).log 2>&1 || { tail -20 $(FW_OPT_DIR)/$(s).log; exit 1; } ;)
	python3 scripts/firmware/firmware_opt.py --build $(FW_OPT_DIR) --shipped-build $(FW_DIR) \
	  --shipped "m4f-f32=$(FW_OPT_m4f-f32) m4f=$(FW_OPT_m4f) m3=$(FW_OPT_m3) m0p=$(FW_OPT_m0p)" --settings "$(FW_OPT_SETTINGS)" \
	  --runs "$(PIL_RUNS)" --configs "$(foreach c,$(PIL_CONFIGS),$(call pil_tag,$(c)))" --log $(PIL_LOG) \
	  --steps 100 --json $(FW_OPT_DIR)/opt.json --page docs/FIRMWARE.md

# PIL_BUDGETS_RUNS: the targets measured (pil, pil-aux; each writes $(FW_DIR)/<target>.json,
# - as _); PIL_BUDGETS_ONLY: the entries whose budgets are set, every other budget kept with
# its source (empty: every run measured). A new entry's row alone:
# make pil-budgets PIL_BUDGETS_RUNS=pil-aux PIL_BUDGETS_ONLY=tid_sckf
PIL_BUDGETS_RUNS ?= pil pil-aux
PIL_BUDGETS_ONLY ?=
## set the PIL instruction budgets (PIL_BUDGETS) to a fresh make pil and make pil-aux
pil-budgets:
	@for t in $(PIL_BUDGETS_RUNS); do $(MAKE) --no-print-directory $$t PIL_BUDGETS= || exit 1; done
	python3 scripts/firmware/pil_budgets.py --write $(if $(strip $(PIL_BUDGETS_ONLY)),--only "$(strip $(PIL_BUDGETS_ONLY))") \
	  $(PIL_BUDGETS) $(foreach t,$(PIL_BUDGETS_RUNS),$(FW_DIR)/$(subst -,_,$(t)).json)

## regenerate only the other estimators' PIL table of docs/FIRMWARE.md (from make pil-aux)
firmware-table-aux:
	@test -f $(FW_DIR)/pil_aux.json || $(MAKE) --no-print-directory pil-aux
	python3 scripts/firmware/firmware_table.py --aux-only --page docs/FIRMWARE.md --pil-aux $(FW_DIR)/pil_aux.json

## regenerate the firmware tables of docs/FIRMWARE.md
firmware-table:
	@test -f $(FW_DIR)/report.json || $(MAKE) --no-print-directory firmware
	@test -f $(FW_DIR)/pil.json || $(MAKE) --no-print-directory pil
	python3 scripts/firmware/firmware_table.py --report $(FW_DIR)/report.json --pil $(FW_DIR)/pil.json --page docs/FIRMWARE.md \
	  --obs-page docs/OBSERVER_RESULTS.md --readme-page README.md --bench $(BUILD)/bench/bench.json \
	  --pil-aux $(FW_DIR)/pil_aux.json
