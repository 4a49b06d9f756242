/**
 * @file pil_gen.c
 * @brief Host tool: turns a sensor log into the C data of a processor-in-the-loop image
 *        (firmware/pil/pil_main.c): the estimator parameters and every sample, in float32
 *        and in the Q formats, exactly as `mu_replay` derives them for the same options.
 *
 *   pil_gen --in LOG.csv --out DATA.c [--preset paper|default] [--filter sckf|ckf]
 *           [--tyre paper|absolute] [--rows N] [--estimator friction|pipeline|mass_grade|tyre_id]
 *           [--mg-config recommended|seed]
 *
 * --estimator pipeline: the composed pipeline of a production car's sensors (rfe/pipeline.h,
 * rfe/pipeline_q31.h) instead of the friction estimator: the parameters, the observer's
 * parameters (its obs_* keys) and the ESC samples exactly as `mu_replay --velocity observer`
 * steps them, float (`--real float`: rfe_replay_params_f32, rfe_replay_velocity_params_f32,
 * rfe_replay_esc_input) and, under PIL_Q31, fixed point (`--real q31`:
 * rfe_replay_observer_params_q31, rfe_replay_esc_input_q31).
 *
 * --estimator mass_grade / tyre_id (the tyre identifier float32 only: it has no fixed-point
 * twin, its data file holds nothing under PIL_Q31): the mass and grade estimator's parameters as mu_replay
 * derives them (rfe_param_set_mass_grade with --mg-config, the log's metadata,
 * rfe_replay_mass_grade_params_f32), or the tyre identifier's vehicle (rfe_replay_params_f32
 * of --preset and the log's metadata; the identifier's own parameters are its defaults, set
 * on the target), and the samples of host/pil/aux_input.h (shared with bench/bench_aux.c);
 * for the mass and grade estimator also the fixed-point arm (PIL_Q31): those float
 * parameters converted by rfe_mass_grade_params_to_q31_f32 and the samples rounded to their
 * Q formats (rfe_aux_mg_input_q31).
 *
 * Parameters: the library preset, then the log's `# key = value` metadata, then --filter and
 * --tyre (mu_replay's order). Float: rfe_replay_params_f32 (the keys' doubles rounded to
 * float); fixed point: rfe_replay_params_q31 (double path, then rfe_params_to_q31_f64). Samples:
 * float = (float)value as replay_real.c; fixed = rfe_replay_sample_q31 (replay_q31.c). Floats
 * are written as hexadecimal literals and Q values as integers, so the target sees the very
 * bits the host replay uses. Structs are written with positional initialisers, member by
 * member in declaration order, which the target compiler lays out for its own ABI (the
 * Cortex-M build has 1-byte enums and 4-byte size_t; the host has neither).
 */
#include <inttypes.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "host/csv_log.h"
#include "host/param_file.h"
#include "host/replay_q31.h"
#include "host/replay_real.h"
#include "host/pil/aux_input.h"
#include "rfe/component/params_conv.h"
#include "rfe/params.h"

/* The enum members of rfe_params_t: written as integers, every other 4-byte word as a float. */
static int is_enum_offset(size_t off)
{
    return off == offsetof(rfe_params_t, tyre.mode) || off == offsetof(rfe_params_t, filter.kind) ||
           off == offsetof(rfe_params_t, filter.structure);
}

/* Positional initialiser of one 4-byte-word sub-struct of rfe_params_t. */
static void put_float_block(FILE *f, const rfe_params_t *p, size_t start, size_t size)
{
    size_t off;
    fputs("    {", f);
    for (off = start; off < start + size; off += 4u) {
        if (is_enum_offset(off)) {
            int32_t v;
            memcpy(&v, (const char *)p + off, sizeof v);
            fprintf(f, "%s%" PRId32, off == start ? "" : ", ", v);
        } else {
            float v;
            memcpy(&v, (const char *)p + off, sizeof v);
            fprintf(f, "%s%af", off == start ? "" : ", ", (double)v);
        }
    }
    fputs("},\n", f);
}

/* The four sub-structs of rfe_params_t, each a positional initialiser (the images' float
 * parameters: friction, pipeline, tyre identifier). */
static void put_float_params(FILE *f, const rfe_params_t *p)
{
    put_float_block(f, p, offsetof(rfe_params_t, vehicle), sizeof(rfe_vehicle_t));
    put_float_block(f, p, offsetof(rfe_params_t, tyre), sizeof(rfe_tyre_params_t));
    put_float_block(f, p, offsetof(rfe_params_t, filter), sizeof(rfe_filter_params_t));
    put_float_block(f, p, offsetof(rfe_params_t, monitor), sizeof(rfe_monitor_params_t));
}

static void put_q31_block(FILE *f, const rfe_params_q31_t *q, size_t start, size_t size)
{
    size_t off;
    fputs("    {", f);
    for (off = start; off < start + size; off += 4u) {
        int32_t v;
        memcpy(&v, (const char *)q + off, sizeof v);
        fprintf(f, "%s%" PRId32, off == start ? "" : ", ", v);
    }
    fputs("},\n", f);
}

/* The data of the friction estimator's image: fixed point under PIL_Q31, else float;
 * returns how many values saturated in the Q formats. */
static uint32_t put_friction(FILE *f, const rfe_params_t *p, const rfe_params_q31_t *q,
                             const rfe_sensor_log_t *log, size_t rows)
{
    uint32_t in_sat = 0u;
    size_t i, w;
    fputs("#if defined(PIL_Q31)\nconst rfe_params_q31_t pil_params = {\n", f);
    put_q31_block(f, q, offsetof(rfe_params_q31_t, vehicle), sizeof(rfe_vehicle_q31_t));
    put_q31_block(f, q, offsetof(rfe_params_q31_t, tyre), sizeof(rfe_tyre_params_q31_t));
    put_q31_block(f, q, offsetof(rfe_params_q31_t, filter), sizeof(rfe_filter_params_q31_t));
    put_q31_block(f, q, offsetof(rfe_params_q31_t, monitor), sizeof(rfe_monitor_params_q31_t));
    fputs("};\n\nconst rfe_sample_q31_t pil_samples[] = {\n", f);
    for (i = 0u; i < rows; ++i) {
        rfe_sample_q31_t s;
        in_sat += rfe_replay_sample_q31(&log->rows[i], &s);
        fprintf(f, "    {%" PRId32 ", %" PRId32 ", %" PRId32 ", %" PRId32 ", %" PRId32 ", %" PRId32 ", %" PRId32 ", {",
                s.delta, s.vx, s.vy, s.yaw_rate, s.yaw_acc, s.ax, s.ay);
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            fprintf(f, "%s%" PRId32, w == 0u ? "" : ", ", s.omega[w]);
        }
        fputs("}},\n", f);
    }
    fputs("};\n#else\nconst rfe_params_t pil_params = {\n", f);
    put_float_params(f, p);
    fputs("};\n\nconst rfe_sample_t pil_samples[] = {\n", f);
    for (i = 0u; i < rows; ++i) {
        const rfe_sensor_row_t *r = &log->rows[i];
        fprintf(f, "    {%af, %af, %af, %af, %af, %af, %af, {", (double)(float)r->delta, (double)(float)r->vx,
                (double)(float)r->vy, (double)(float)r->yaw_rate, (double)(float)r->yaw_acc,
                (double)(float)r->ax, (double)(float)r->ay);
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            fprintf(f, "%s%af", w == 0u ? "" : ", ", (double)(float)r->omega[w]);
        }
        fputs("}},\n", f);
    }
    fputs("};\n#endif\n", f);
    return in_sat;
}

/* The fixed-point data of the pipeline image (PIL_PIPELINE with PIL_Q31): parameters,
 * observer parameters (rfe_velocity_params_q31_t: driven and lat_every (uint32_t), then int32
 * words only;
 * checked in main) and the ESC samples as rfe_replay_run_observer_q31 steps them
 * (rfe_replay_esc_input_q31); returns how many values saturated in the Q formats. */
static uint32_t put_pipeline_q31(FILE *f, const rfe_params_q31_t *q, const rfe_velocity_params_q31_t *vq,
                                 const rfe_sensor_log_t *log, size_t rows)
{
    uint32_t in_sat = 0u;
    size_t i, w, off;
    fputs("#if defined(PIL_Q31)\nconst rfe_params_q31_t pil_params = {\n", f);
    put_q31_block(f, q, offsetof(rfe_params_q31_t, vehicle), sizeof(rfe_vehicle_q31_t));
    put_q31_block(f, q, offsetof(rfe_params_q31_t, tyre), sizeof(rfe_tyre_params_q31_t));
    put_q31_block(f, q, offsetof(rfe_params_q31_t, filter), sizeof(rfe_filter_params_q31_t));
    put_q31_block(f, q, offsetof(rfe_params_q31_t, monitor), sizeof(rfe_monitor_params_q31_t));
    fprintf(f, "};\n\nconst rfe_velocity_params_q31_t pil_velocity_params = {%" PRIu32 "u, %" PRIu32 "u",
            vq->driven, vq->lat_every);
    for (off = sizeof vq->driven + sizeof vq->lat_every; off < sizeof *vq; off += sizeof(int32_t)) {
        int32_t v;
        memcpy(&v, (const char *)vq + off, sizeof v);
        fprintf(f, ", %" PRId32, v);
    }
    fputs("};\n\nconst rfe_velocity_input_q31_t pil_inputs[] = {\n", f);
    for (i = 0u; i < rows; ++i) {
        rfe_velocity_input_q31_t in;
        in_sat += rfe_replay_esc_input_q31(log, i, i - 1u, &in); /* i = 0: SIZE_MAX */
        fprintf(f, "    {%" PRId32 ", %" PRId32 ", %" PRId32 ", %" PRId32 ", %" PRId32 ", %" PRId32 ", {",
                in.dt, in.delta, in.steer_wheel, in.yaw_rate, in.ax, in.ay);
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            fprintf(f, "%s%" PRId32, w == 0u ? "" : ", ", in.omega[w]);
        }
        fputs("}, {", f);
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            fprintf(f, "%s%" PRId32, w == 0u ? "" : ", ", in.p_brake[w]);
        }
        fputs("}, {", f);
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            fprintf(f, "%s%" PRId32, w == 0u ? "" : ", ", in.torque[w]);
        }
        fprintf(f, "}, %" PRId32 ", %" PRIu32 "u},\n", in.grade, in.has);
    }
    fputs("};\n", f);
    return in_sat;
}

/* One float per element (hexadecimal literal: the exact bits). */
static void put_floats(FILE *f, const float *v, size_t n)
{
    size_t k;
    fputs("{", f);
    for (k = 0u; k < n; ++k) {
        fprintf(f, "%s%af", k == 0u ? "" : ", ", (double)v[k]);
    }
    fputs("}", f);
}

/* The float data of the pipeline image (PIL_PIPELINE without PIL_Q31): parameters, observer
 * parameters and the ESC samples; rfe_velocity_params_t is driven and lat_every (uint32_t)
 * followed by floats only (checked in main). */
static void put_pipeline(FILE *f, const rfe_params_t *p, const rfe_velocity_params_t *vp,
                         const rfe_sensor_log_t *log, size_t rows)
{
    size_t i, off;
    fputs("#else\nconst rfe_params_t pil_params = {\n", f);
    put_float_params(f, p);
    fprintf(f, "};\n\nconst rfe_velocity_params_t pil_velocity_params = {%" PRIu32 "u, %" PRIu32 "u",
            vp->driven, vp->lat_every);
    for (off = sizeof vp->driven + sizeof vp->lat_every; off < sizeof *vp; off += sizeof(float)) {
        float v;
        memcpy(&v, (const char *)vp + off, sizeof v);
        fprintf(f, ", %af", (double)v);
    }
    fputs("};\n\nconst rfe_velocity_input_t pil_inputs[] = {\n", f);
    for (i = 0u; i < rows; ++i) {
        rfe_velocity_input_t in;
        rfe_replay_esc_input(log, i, i - 1u, &in); /* i = 0: SIZE_MAX, none */
        fprintf(f, "    {%af, %af, %af, %af, %af, %af, ", (double)in.dt, (double)in.delta,
                (double)in.steer_wheel, (double)in.yaw_rate, (double)in.ax, (double)in.ay);
        put_floats(f, in.omega, (size_t)RFE_WHEELS);
        fputs(", ", f);
        put_floats(f, in.p_brake, (size_t)RFE_WHEELS);
        fputs(", ", f);
        put_floats(f, in.torque, (size_t)RFE_WHEELS);
        fprintf(f, ", %af, %" PRIu32 "u},\n", (double)in.grade, in.has);
    }
    fputs("};\n#endif\n", f);
}

/* The mass and grade image's data (PIL_MASS_GRADE): its parameters (every member a float
 * but the two uint32_t flags adaptive and use_ax, 4 bytes each: checked in main) and the
 * samples. */
static void put_mass_grade(FILE *f, const rfe_mass_grade_params_t *mp, const rfe_sensor_log_t *log,
                           size_t rows)
{
    size_t i, off;
    fputs("#if defined(PIL_MASS_GRADE) && !defined(PIL_Q31)\nconst rfe_mass_grade_params_t pil_mg_params = {", f);
    for (off = 0u; off < sizeof *mp; off += 4u) {
        if (off == offsetof(rfe_mass_grade_params_t, adaptive) || off == offsetof(rfe_mass_grade_params_t, use_ax)) {
            uint32_t u;
            memcpy(&u, (const char *)mp + off, sizeof u);
            fprintf(f, "%s%" PRIu32 "u", off == 0u ? "" : ", ", u);
        } else {
            float v;
            memcpy(&v, (const char *)mp + off, sizeof v);
            fprintf(f, "%s%af", off == 0u ? "" : ", ", (double)v);
        }
    }
    fputs("};\n\nconst rfe_mass_grade_input_t pil_mg_inputs[] = {\n", f);
    for (i = 0u; i < rows; ++i) {
        rfe_mass_grade_input_t in;
        rfe_aux_mg_input(log, i, (double)mp->R, &in);
        fprintf(f, "    {%af, %af, %af, %af, %af, %af, %af, %" PRId32 ", %" PRIu32 "u, %" PRIu32 "u},\n",
                (double)in.dt, (double)in.v, (double)in.torque, (double)in.p_brake, (double)in.ax,
                (double)in.vx, (double)in.ay, in.gear, in.brake, in.has);
    }
    fputs("};\n#endif\n", f);
}

/* The fixed-point arm of the mass and grade image's data (PIL_MASS_GRADE with PIL_Q31): the
 * float parameters converted by rfe_mass_grade_params_to_q31 (every member a 4-byte word,
 * the flags adaptive, use_ax and pause_grade unsigned: checked in main) and the samples of rfe_aux_mg_input_q31; returns the samples' saturations. */
static uint32_t put_mass_grade_q31(FILE *f, const rfe_mass_grade_params_q31_t *q, double R,
                                   const rfe_sensor_log_t *log, size_t rows)
{
    size_t i, off;
    uint32_t sat = 0u;
    fputs("#if defined(PIL_MASS_GRADE) && defined(PIL_Q31)\nconst rfe_mass_grade_params_q31_t pil_mg_params = {", f);
    for (off = 0u; off < sizeof *q; off += 4u) {
        if (off == offsetof(rfe_mass_grade_params_q31_t, adaptive) ||
            off == offsetof(rfe_mass_grade_params_q31_t, use_ax) ||
            off == offsetof(rfe_mass_grade_params_q31_t, pause_grade)) {
            uint32_t u;
            memcpy(&u, (const char *)q + off, sizeof u);
            fprintf(f, "%s%" PRIu32 "u", off == 0u ? "" : ", ", u);
        } else {
            int32_t v;
            memcpy(&v, (const char *)q + off, sizeof v);
            fprintf(f, "%s%" PRId32, off == 0u ? "" : ", ", v);
        }
    }
    fputs("};\n\nconst rfe_mass_grade_input_q31_t pil_mg_inputs[] = {\n", f);
    for (i = 0u; i < rows; ++i) {
        rfe_mass_grade_input_q31_t in;
        rfe_aux_mg_input_q31(log, i, R, &in, &sat);
        fprintf(f, "    {%" PRId32 ", %" PRId32 ", %" PRId32 ", %" PRId32 ", %" PRId32 ", %" PRId32 ", %" PRId32
                   ", %" PRId32 ", %" PRIu32 "u, %" PRIu32 "u},\n",
                in.dt, in.v, in.torque, in.p_brake, in.ax, in.vx, in.ay, in.gear, in.brake, in.has);
    }
    fputs("};\n#endif\n", f);
    return sat;
}

/* The tyre identifier's image's data (PIL_TYRE_ID): the vehicle's parameters and the
 * samples. */
static void put_tyre_id(FILE *f, const rfe_params_t *p, const rfe_sensor_log_t *log, size_t rows)
{
    size_t i;
    fputs("#if defined(PIL_TYRE_ID) && !defined(PIL_Q31)\nconst rfe_params_t pil_params = {\n", f);
    put_float_params(f, p);
    fputs("};\n\nconst rfe_tyre_id_sample_t pil_tid_samples[] = {\n", f);
    for (i = 0u; i < rows; ++i) {
        rfe_tyre_id_sample_t s;
        rfe_aux_tid_sample(log, i, &s);
        fprintf(f, "    {%af, %af, %af, %af, %af, %af},\n", (double)s.dt, (double)s.delta, (double)s.vx,
                (double)s.yaw_rate, (double)s.ay, (double)s.ax);
    }
    fputs("};\n#endif\n", f);
}

static int usage(const char *msg)
{
    fprintf(stderr, "pil_gen: %s\nusage: pil_gen --in LOG.csv --out DATA.c [--preset paper|default] "
                    "[--filter sckf|ckf] [--tyre paper|absolute] [--rows N] "
                    "[--estimator friction|pipeline|mass_grade|tyre_id] [--mg-config recommended|seed]\n", msg);
    return 2;
}

int main(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *preset = "paper", *filter = NULL, *tyre = NULL;
    const char *estimator = "friction", *mg_config = "recommended";
    int pipeline, mass_grade, tyre_id;
    rfe_mass_grade_params_t mp;
    rfe_mass_grade_params_q31_t mq;
    rfe_velocity_params_t vp;
    rfe_velocity_params_q31_t vq;
    size_t rows = 0u;
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_preset_t pid;
    rfe_io_error_t err;
    rfe_params_t p;
    rfe_params_q31_t q;
    uint32_t in_sat = 0u;
    FILE *f;
    int a;

    for (a = 1; a + 1 < argc; a += 2) {
        if (strcmp(argv[a], "--in") == 0) { in = argv[a + 1]; }
        else if (strcmp(argv[a], "--out") == 0) { out = argv[a + 1]; }
        else if (strcmp(argv[a], "--preset") == 0) { preset = argv[a + 1]; }
        else if (strcmp(argv[a], "--filter") == 0) { filter = argv[a + 1]; }
        else if (strcmp(argv[a], "--tyre") == 0) { tyre = argv[a + 1]; }
        else if (strcmp(argv[a], "--estimator") == 0) { estimator = argv[a + 1]; }
        else if (strcmp(argv[a], "--mg-config") == 0) { mg_config = argv[a + 1]; }
        else if (strcmp(argv[a], "--rows") == 0) { rows = (size_t)strtoul(argv[a + 1], NULL, 10); }
        else { return usage("unknown option"); }
    }
    if (a != argc || in == NULL || out == NULL) {
        return usage("--in and --out are required");
    }
    pipeline = strcmp(estimator, "pipeline") == 0;
    mass_grade = strcmp(estimator, "mass_grade") == 0;
    tyre_id = strcmp(estimator, "tyre_id") == 0;
    if (!pipeline && !mass_grade && !tyre_id && strcmp(estimator, "friction") != 0) {
        return usage("bad --estimator");
    }
    if (strcmp(mg_config, "recommended") != 0 && strcmp(mg_config, "seed") != 0) {
        return usage("bad --mg-config");
    }
    if (rfe_preset_parse(preset, &pid) != 0) {
        return usage("bad --preset");
    }
    memset(&log, 0, sizeof log);
    if (rfe_sensor_log_read(in, &log, &err) != 0) {
        fprintf(stderr, "pil_gen: %s:%zu: %s\n", in, err.line, err.msg);
        return 1;
    }
    (void)rfe_param_set_preset_f64(&ps, pid);
    if (mass_grade) {
        /* mu_replay --mass-grade aukf: the seed's configuration before the metadata */
        (void)rfe_param_set_mass_grade_f64(&ps, RFE_MG_CAR, strcmp(mg_config, "seed") == 0 ? RFE_MG_SEED : RFE_MG_RECOMMENDED);
    }
    if (rfe_param_set_apply_meta(&ps, &log, in, &err) != 0) {
        fprintf(stderr, "pil_gen: %s: %s\n", in, err.msg);
        return 1;
    }
    if (filter != NULL && rfe_filter_kind_parse(filter, &ps.filter) != 0) {
        return usage("bad --filter");
    }
    if (tyre != NULL && rfe_tyre_mode_parse(tyre, &ps.tyre) != 0) {
        return usage("bad --tyre");
    }
    if (pipeline && (log.omega_linear != 0 || log.has_swa != 0)) {
        /* mu_replay converts these from the parameters first; the PIL logs need not */
        fprintf(stderr, "pil_gen: %s: wheel speeds in km/h or a steering-wheel angle: not "
                        "supported for --estimator pipeline\n", in);
        return 1;
    }
    if (mass_grade && (!log.has_drive_torque || rfe_replay_mass_grade_params_f32(&ps, &mp, NULL) != RFE_OK ||
                       sizeof mp.adaptive != 4u || sizeof mp % 4u != 0u ||
                       rfe_mass_grade_params_to_q31(&mp, &mq) != RFE_OK ||
                       sizeof mq != 46u * 4u)) { /* 46 words: the mismatch monitor (2) since 44, the grade's two-level walk (5) since 39 */
        fprintf(stderr, "pil_gen: %s: no drive_torque, or the mass and grade parameters are rejected\n", in);
        return 1;
    }
    if (rfe_replay_params_f32(&ps, &p, NULL) != RFE_OK ||
        (pipeline ? rfe_replay_velocity_params_f32(&ps, &vp, NULL) : rfe_replay_params_q31(&ps, &q, NULL)) != RFE_OK ||
        (pipeline && rfe_replay_observer_params_q31(&ps, &q, &vq, NULL) != RFE_OK)) {
        fprintf(stderr, "pil_gen: %s: the parameters are rejected\n", in);
        return 1;
    }
    if (rows == 0u || rows > log.n_rows) {
        rows = log.n_rows;
    }
    /* Every member of both parameter structs is 4 bytes on the host (checked here), so the
     * structs are walked word by word, sub-struct by sub-struct. */
    if (sizeof(rfe_params_t) != sizeof(rfe_vehicle_t) + sizeof(rfe_tyre_params_t) + sizeof(rfe_filter_params_t) +
                                    sizeof(rfe_monitor_params_t) ||
        sizeof(rfe_params_q31_t) != sizeof(rfe_vehicle_q31_t) + sizeof(rfe_tyre_params_q31_t) + sizeof(rfe_filter_params_q31_t) +
                                        sizeof(rfe_monitor_params_q31_t) ||
        sizeof(float) != 4u || sizeof(rfe_tyre_mode_t) != 4u || sizeof(rfe_params_t) % 4u != 0u ||
        sizeof(rfe_params_q31_t) % 4u != 0u || offsetof(rfe_velocity_params_t, driven) != 0u ||
        offsetof(rfe_velocity_params_t, lat_every) != sizeof(float) ||
        sizeof vp.driven != sizeof(float) || sizeof vp.lat_every != sizeof(float) ||
        sizeof vp % sizeof(float) != 0u || offsetof(rfe_velocity_params_q31_t, driven) != 0u ||
        offsetof(rfe_velocity_params_q31_t, lat_every) != sizeof(int32_t) ||
        sizeof vq.driven != sizeof(int32_t) || sizeof vq.lat_every != sizeof(int32_t) ||
        sizeof vq % sizeof(int32_t) != 0u) {
        fprintf(stderr, "pil_gen: unexpected parameter struct layout on the host\n");
        return 1;
    }

    f = fopen(out, "w");
    if (f == NULL) {
        perror(out);
        return 1;
    }
    fprintf(f, "/* Generated by firmware/pil/pil_gen.c from %s (preset %s, filter %s, tyre %s): do not edit. */\n",
            in, preset, rfe_filter_kind_str(ps.filter), rfe_tyre_mode_str(ps.tyre));
    fputs("#include \"pil_data.h\"\n\n", f);
    fprintf(f, "const uint32_t pil_n_samples = %zuu;\n\n", rows);
    if (mass_grade) {
        put_mass_grade(f, &mp, &log, rows);
        in_sat = put_mass_grade_q31(f, &mq, (double)mp.R, &log, rows);
    } else if (tyre_id) {
        put_tyre_id(f, &p, &log, rows);
    } else if (pipeline) {
        in_sat = put_pipeline_q31(f, &q, &vq, &log, rows);
        put_pipeline(f, &p, &vp, &log, rows);
    } else {
        in_sat = put_friction(f, &p, &q, &log, rows);
    }
    if (fclose(f) != 0) {
        perror(out);
        return 1;
    }
    fprintf(stderr, "pil_gen: %s: %zu samples -> %s (%" PRIu32 " values saturated in Q formats)\n", in,
            rows, out, in_sat);
    rfe_sensor_log_free(&log);
    return 0;
}
