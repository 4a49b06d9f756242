/**
 * @file mu_replay.c
 * @brief mu_replay: run the friction estimator over a sensor log (docs DATA.md), write the
 *        estimate log, and score it against the truth columns when the log has them.
 *
 * Exit status: 0 success, 1 malformed input or failed run (one line
 * `mu_replay: FILE:LINE:COL: message` on stderr), 2 bad usage.
 * Parameter precedence: --preset (the library's default or paper set) < log metadata <
 * --params file < --filter/--tyre flags.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "csv_log.h"
#include "log_timing.h"
#include "rfe/config.h"
#include "metrics.h"
#include "param_file.h"
#include "replay_q31.h"
#include "replay_mem.h"
#include "replay_real.h"
#include "text_io.h"

#define PROG "mu_replay"

/* The tyre identifier's particle count RFE_TID_N (rfe/config.h) as text, for the metadata,
 * the summary and the JSON. */
#define TEXT2_(x) #x
#define TEXT_(x) TEXT2_(x)
#define RFE_TID_N_TEXT TEXT_(RFE_TID_N)

/** Exit statuses. */
enum { EXIT_OK = 0, EXIT_INPUT = 1, EXIT_USAGE = 2 };

static const char k_usage[] =
    "usage: " PROG " --in SENSOR.csv --out ESTIMATE.csv [--preset default|paper]\n"
    "                 [--params FILE] [--filter sckf|ckf] [--tyre paper|absolute|magic]\n"
    "                 [--real float|double|q31] [--velocity auto|observer|measured]\n"
    "                 [--mass-grade ukf|aukf|off] [--mass-grade-vehicle car|truck]\n"
    "                 [--tyre-id apf|sir|sckf|off]\n"
    "                 [--metrics FILE.json] [--strict]\n"
    "                 [--require-params] [--quiet] [--help]\n"
    "\n"
    "Runs the road-friction estimator over a sensor log (docs DATA.md) and writes the\n"
    "estimate log. Parameters: the --preset set < the log's '# key = value' metadata <\n"
    "--params file < --filter/--tyre. When the log has truth columns mu_fl..mu_rr, prints\n"
    "an accuracy table (and writes it as JSON with --metrics); with util_fl..util_rr too,\n"
    "the valid share where the tyres are excited.\n"
    "\n"
    "  --in FILE        sensor log to read\n"
    "  --out FILE       estimate log to write\n"
    "  --preset NAME    base parameter set of the library: default (default) or paper\n"
    "  --params FILE    parameter file ('key = value' lines; unknown keys are errors;\n"
    "                   the keys are those of docs DATA.md and docs/ESTIMATOR.md)\n"
    "  --filter KIND    sckf (default) or ckf (the paper's baseline: --preset paper)\n"
    "  --tyre MODE      paper, absolute (Dugoff) or magic (Magic Formula; default:\n"
    "                   the preset's)\n"
    "  --real TYPE      float (default) or double arithmetic, or q31: the fixed-point\n"
    "                   estimator, observer and mass and grade estimator (samples\n"
    "                   rounded to their Q formats; saturation counts in the estimate\n"
    "                   log's metadata, the JSON and the summary)\n"
    "  --velocity WHERE where vx, vy and the yaw acceleration come from: measured (the\n"
    "                   log's vx, vy, yaw_acc columns, a test car's sensors), observer\n"
    "                   (estimated from steer, yaw rate, ax, ay, wheel speeds and the\n"
    "                   optional p_*, torque_*, grade columns: docs/OBSERVER.md, in every\n"
    "                   --real; the estimate log gains vx_est .. sd_beta), or auto\n"
    "                   (default): measured when the log has the columns, else observer\n";
/* the rest of the usage (one string would exceed the 4095 characters C99 guarantees) */
static const char k_usage_rest[] =
    "  --mass-grade CFG the vehicle mass and road-grade estimator (docs/MASS_GRADE.md),\n"
    "                   run on a log with a drive_torque column (N m at the wheels;\n"
    "                   optional brake 0/1, brake_pressure Pa, gear) from the speed\n"
    "                   (omega_fl + omega_fr + omega_rl + omega_rr) / 4 * R, the torque\n"
    "                   and ax: ukf (default) starts its mg_* keys from the library's\n"
    "                   car preset RFE_MG_RECOMMENDED (plain UKF, accelerometer row:\n"
    "                   mg_adaptive = 0, mg_use_ax = 1), aukf from RFE_MG_SEED (the\n"
    "                   seed's adaptive UKF on speed and torque: mg_adaptive = 1,\n"
    "                   mg_use_ax = 0, mg_m_rot = 0, mg_t_adapt = 0); then the log's\n"
    "                   metadata and --params set mg_* keys, and the flag, when given,\n"
    "                   sets mg_adaptive last. The estimate log gains mass_est, sd_mass,\n"
    "                   grade_est, sd_grade, mg_status and mass_used, the friction\n"
    "                   estimator's mass: after an update (mg_status 0) with sd_mass <=\n"
    "                   mg_feed_sd_rel * mass_est (key; default 0.02, 0: never) and\n"
    "                   enough |ax| since its start (mg_feed_excitation) it\n"
    "                   takes that mass_est before that sample's step, and keeps it\n"
    "                   until the next such update (the observer too); with the\n"
    "                   observer and no grade column the observer takes each sample's\n"
    "                   estimated grade (that sample's); with mass_true, grade_true the summary and --metrics\n"
    "                   give the mass error at the end and the grade's RMSE. off: not\n"
    "                   run (the columns are ignored). With --real q31 its fixed-point\n"
    "                   twin runs (docs/FIXED_POINT.md \"Mass and grade\")\n"
    "  --mass-grade-vehicle V  car (default) or truck: the vehicle whose preset the mg_*\n"
    "                   keys start from (docs/MASS_GRADE.md §6: the simulator's car, or\n"
    "                   the seed's 5 758 kg truck); the log's metadata and --params\n"
    "                   still set each key. R and g stay vehicle keys\n"
    "  --tyre-id FILTER the online tyre identifier (docs/TYRE_ID.md) beside the\n"
    "                   friction estimator: apf (auxiliary particle filter), sir\n"
    "                   (bootstrap filter) or sckf (sigma-point filter, §15)\n"
    "                   sets tid_filter; off (default): not run.\n"
    "                   It takes delta, yaw_rate, ay, ax and the velocity's vx (the\n"
    "                   observer's behind it), the friction estimator's vehicle and tyre\n"
    "                   data and the tid_* keys (tid_seed its stream's seed; the particle\n"
    "                   count is fixed at compile time). The estimate log gains mu_id_f,\n"
    "                   mu_id_r, sd_mu_id_f, sd_mu_id_r, B_f .. E_r, tid_status and\n"
    "                   tid_flags; the summary and --metrics its status counts. Float\n"
    "                   and double only: not with --real q31. The key tid_feed_sd_rel\n"
    "                   (default 0: never) feeds its curve to the friction estimator\n"
    "                   after an update whose cornering stiffness is known within that\n"
    "                   relative sd, once the friction estimator has spent\n"
    "                   tid_feed_evidence seconds (default 0) at a mu bound or in model\n"
    "                   mismatch (docs/TYRE_ID.md §14; measured velocities only)\n"
    "  --metrics FILE   write run summary and accuracy as JSON\n"
    "  --strict         stop at the first empty, nan/inf or out-of-range cell (exit 1);\n"
    "                   by default such a cell goes to the estimator as NaN/Inf, which\n"
    "                   rejects that sample (status 17) and holds its estimate, and the\n"
    "                   run ends with a count per cause\n"
    "  --require-params make every vehicle parameter (m, Lf, Lr, Bf, Br, R, J, hg) that\n"
    "                   neither the log's metadata nor --params gives an error; by\n"
    "                   default the preset's values are used and a warning names them\n"
    "  --quiet, -q      print nothing on success\n"
    "  --help, -h       print this help and exit\n"
    "\n"
    "Exit status: 0 success, 1 malformed input or failed run, 2 bad usage.\n";

/** Command-line options; NULL = not given. */
typedef struct {
    const char *in;
    const char *out;
    const char *preset;
    rfe_preset_t preset_id;  /**< --preset parsed (RFE_PRESET_DEFAULT when not given) */
    const char *params;
    const char *metrics;
    const char *filter;
    const char *tyre;
    const char *real;
    const char *velocity;
    const char *mass_grade; /**< --mass-grade ukf|aukf|off */
    const char *tyre_id;    /**< --tyre-id apf|sir|sckf|off */
    const char *mg_vehicle; /**< --mass-grade-vehicle car|truck */
    int quiet;
    int help;
    int strict; /**< --strict: a bad cell is an input error */
    int require_params; /**< --require-params: no vehicle parameters is an input error */
    const char *params_text; /**< the in-memory run's parameters, `key = value` lines applied
                                  where a --params file is (after it); NULL: none */
    rfe_io_error_t *err_out; /**< the in-memory run (rfe_mu_replay_open): errors go here,
                                  not to stderr; NULL: printed */
} options_t;

/** Everything one run produces. */
typedef struct {
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_est_row_t *rows;
    rfe_replay_stats_t stats;
    rfe_replay_q31_stats_t q31;  /**< the q31 run's counters (is_q31) */
    int is_double;
    int is_q31;
    int use_observer;  /**< vx, vy, r-dot from the velocity observer (--velocity) */
    int mg_ran;        /**< the mass and grade estimator ran (the rows carry its columns) */
    int tid_ran;       /**< the tyre identifier ran (the rows carry its columns) */
    int preset_vehicle; /**< a vehicle key from no file: the preset's value (check_vehicle) */
    int has_metrics;
    rfe_metrics_t metrics;
} run_t;

typedef rfe_status_t (*replay_fn_t)(const rfe_param_set_t *, const rfe_sensor_log_t *,
                                    rfe_est_row_t *, rfe_replay_stats_t *, size_t *);

static int usage_error(const options_t *o, const char *fmt, const char *arg);
static const char **option_slot(options_t *o, const char *name);
static int *flag_slot(options_t *o, const char *name);
static void print_bad_cells(FILE *f, const run_t *r);
static int parse_args(int argc, char **argv, options_t *o);
static int check_option_words(options_t *o);
static int same_file(const char *a, const char *b);
static int load_params(const options_t *o, run_t *r);
static int prepare_log(const options_t *o, run_t *r);
static int check_period(const options_t *o, run_t *r);
static int check_vehicle(const options_t *o, run_t *r);
static void warn_preset_vehicle(const options_t *o, const run_t *r);
static int run_estimator(const options_t *o, run_t *r);
static int write_estimates(const options_t *o, const run_t *r);
static void compute_metrics(run_t *r);
static int write_metrics_json(const options_t *o, const run_t *r);
static void print_status_counts(const run_t *r);
static const char *base_name(const char *path);
static const char *q31_converter_name(const run_t *r, size_t k);
static const char *validator_name(size_t k);
static const char *real_name(const run_t *r);
static const char *mg_config_name(const run_t *r);
static size_t saturation_meta(const run_t *r, rfe_kv_t *meta, char vals[][RFE_NUM_BUF]);
static int fail(const options_t *o, const rfe_io_error_t *err);
static void read_opts(const options_t *o, rfe_read_opts_t *ro);
static int resolve_params(const options_t *o, run_t *r);
static int start_error(const options_t *o, const run_t *r, rfe_status_t st, size_t bad);
static int apply_params_text(rfe_param_set_t *ps, const char *text, rfe_io_error_t *err);
static int mass_grade_flags(const options_t *o, run_t *r);
static void print_mass_grade(const run_t *r);
static void write_mass_grade_json(FILE *f, const run_t *r);
static void tyre_id_flag(const options_t *o, run_t *r);
static void print_tyre_id(const run_t *r);
static void write_tyre_id_json(FILE *f, const run_t *r);

int main(int argc, char **argv)
{
    options_t o;
    run_t r;
    int rc;
    memset(&r, 0, sizeof r);
    memset(&o, 0, sizeof o);
    rc = parse_args(argc, argv, &o);
    if ((rc != 0) || o.help) {
        fputs(k_usage, (rc != 0) ? stderr : stdout);
        fputs(k_usage_rest, (rc != 0) ? stderr : stdout);
        return (rc != 0) ? EXIT_USAGE : EXIT_OK;
    }
    rc = load_params(&o, &r);
    if (rc == 0) {
        rc = check_vehicle(&o, &r);
    }
    if (rc == 0) {
        rc = prepare_log(&o, &r);
    }
    if (rc == 0) {
        rc = run_estimator(&o, &r);
    }
    if (rc == 0) {
        rc = write_estimates(&o, &r);
    }

    if ((rc == 0) && r.log.has_truth) {
        compute_metrics(&r);
    }
    if ((rc == 0) && (o.metrics != NULL)) {
        rc = write_metrics_json(&o, &r);
    }
    if ((rc == 0) && !o.quiet) {
        if (r.has_metrics) {
            rfe_metrics_print_table(stdout, &r.metrics);
        }
        print_status_counts(&r);
        /* A table lost to a full disk or closed pipe must not look like success. */
        if ((fflush(stdout) != 0) || ferror(stdout)) {
            fprintf(stderr, "%s: stdout: write failed\n", PROG);
            rc = -1;
        }
    }
    if (rc == 0) {
        warn_preset_vehicle(&o, &r); /* once the run succeeded: errors stay one line */
    }
    free(r.rows);
    rfe_sensor_log_free(&r.log);
    return (rc == 0) ? EXIT_OK : EXIT_INPUT;
}

/* ------------------------------------------------------------ command line */

/* One-line reason on stderr (or into o->err_out); the caller then prints the usage. */
static int usage_error(const options_t *o, const char *fmt, const char *arg)
{
    if (o->err_out != NULL) {
        rfe_io_error_set(o->err_out, NULL, 0u, 0u, fmt, arg);
        return -1;
    }
    fprintf(stderr, "%s: ", PROG);
    fprintf(stderr, fmt, arg);
    fputc('\n', stderr);
    return -1;
}

/* Where the value of a value-taking option goes, or NULL for an unknown name. */
static const char **option_slot(options_t *o, const char *name)
{
    static const char *const names[] = {"in",         "out",     "params",  "metrics",
                                        "filter",     "tyre",    "real",    "preset",
                                        "velocity",   "mass-grade", "tyre-id",
                                        "mass-grade-vehicle"};
    const char **slots[sizeof names / sizeof names[0]];
    size_t i;
    slots[0] = &o->in;
    slots[1] = &o->out;
    slots[2] = &o->params;
    slots[3] = &o->metrics;
    slots[4] = &o->filter;
    slots[5] = &o->tyre;
    slots[6] = &o->real;
    slots[7] = &o->preset;
    slots[8] = &o->velocity;
    slots[9] = &o->mass_grade;
    slots[10] = &o->tyre_id;
    slots[11] = &o->mg_vehicle;
    for (i = 0u; i < sizeof names / sizeof names[0]; ++i) {
        if (strcmp(names[i], name) == 0) {
            return slots[i];
        }
    }
    return NULL;
}

/* Where an option without a value goes, or NULL when @p name is not one. */
static int *flag_slot(options_t *o, const char *name)
{
    if (strcmp(name, "help") == 0) {
        return &o->help;
    }
    if (strcmp(name, "quiet") == 0) {
        return &o->quiet;
    }
    if (strcmp(name, "strict") == 0) {
        return &o->strict;
    }
    if (strcmp(name, "require-params") == 0) {
        return &o->require_params;
    }
    return NULL;
}

/* Accepts `--opt VALUE` and `--opt=VALUE`. Returns 0, or -1 after a one-line message. */
static int parse_args(int argc, char **argv, options_t *o)
{
    int i;
    for (i = 1; i < argc; ++i) { /* o zeroed by the caller (and err_out set) */
        char name[24]; /* the longest option, mass-grade-vehicle, and its NUL */
        const char *arg = argv[i];
        const char *eq = strchr(arg, '=');
        size_t n = (eq != NULL) ? (size_t)(eq - arg) : strlen(arg);
        const char **slot;
        if ((strcmp(arg, "-h") == 0) || (strcmp(arg, "-q") == 0)) {
            *((arg[1] == 'h') ? &o->help : &o->quiet) = 1; /* the usual short forms */
            continue;
        }
        if ((strncmp(arg, "--", 2u) != 0) || (n < 3u) || (n - 2u >= sizeof name)) {
            return usage_error(o, "unexpected argument '%s'", arg);
        }
        memcpy(name, arg + 2, n - 2u);
        name[n - 2u] = '\0';
        if (flag_slot(o, name) != NULL) {
            if (eq != NULL) {
                return usage_error(o, "option '%s' takes no value", arg);
            }
            *flag_slot(o, name) = 1;
            continue;
        }
        slot = option_slot(o, name);
        if (slot == NULL) {
            return usage_error(o, "unknown option '%s'", arg);
        }
        if (*slot != NULL) {
            return usage_error(o, "option '--%s' given twice", name);
        }
        *slot = (eq != NULL) ? eq + 1 : ((i + 1 < argc) ? argv[++i] : NULL);
        if ((*slot == NULL) || (**slot == '\0') || (strncmp(*slot, "--", 2u) == 0)) {
            return usage_error(o, "option '--%s' needs a value", name);
        }
    }
    return o->help ? 0 : check_option_words(o);
}

/* Required options present, word values known (the preset kept parsed), output not
 * clobbering an input. */
static int check_option_words(options_t *o)
{
    rfe_filter_kind_t fk;
    rfe_tyre_mode_t tm;
    if ((o->in == NULL) || (o->out == NULL)) {
        return usage_error(o, "%s", "--in and --out are required");
    }
    o->preset_id = RFE_PRESET_DEFAULT;
    if ((o->preset != NULL) && (rfe_preset_parse(o->preset, &o->preset_id) != 0)) {
        return usage_error(o, "--preset must be default or paper, not '%s'", o->preset);
    }
    if ((o->filter != NULL) && (rfe_filter_kind_parse(o->filter, &fk) != 0)) {
        return usage_error(o, "--filter must be sckf or ckf, not '%s'", o->filter);
    }
    if ((o->filter != NULL) && (fk == RFE_FILTER_CKF) && (o->preset_id != RFE_PRESET_PAPER)) {
        return usage_error(o, "%s", "--filter ckf: the CKF baseline needs --preset paper (it runs "
                                 "only the paper subset of the parameters)");
    }
    if ((o->tyre != NULL) && (rfe_tyre_mode_parse(o->tyre, &tm) != 0)) {
        return usage_error(o, "--tyre must be paper, absolute or magic, not '%s'", o->tyre);
    }
    if ((o->real != NULL) && (strcmp(o->real, "float") != 0) && (strcmp(o->real, "double") != 0) &&
        (strcmp(o->real, "q31") != 0)) {
        return usage_error(o, "--real must be float, double or q31, not '%s'", o->real);
    }
    if ((o->velocity != NULL) && (strcmp(o->velocity, "auto") != 0) &&
        (strcmp(o->velocity, "observer") != 0) && (strcmp(o->velocity, "measured") != 0)) {
        return usage_error(o, "--velocity must be auto, observer or measured, not '%s'", o->velocity);
    }
    if ((o->mass_grade != NULL) && (strcmp(o->mass_grade, "ukf") != 0) &&
        (strcmp(o->mass_grade, "aukf") != 0) && (strcmp(o->mass_grade, "off") != 0)) {
        return usage_error(o, "--mass-grade must be ukf, aukf or off, not '%s'", o->mass_grade);
    }
    if ((o->mg_vehicle != NULL) && (strcmp(o->mg_vehicle, "car") != 0) &&
        (strcmp(o->mg_vehicle, "truck") != 0)) {
        return usage_error(o, "--mass-grade-vehicle must be car or truck, not '%s'",
                           o->mg_vehicle);
    }
    if ((o->tyre_id != NULL) && (strcmp(o->tyre_id, "apf") != 0) &&
        (strcmp(o->tyre_id, "sir") != 0) && (strcmp(o->tyre_id, "sckf") != 0) &&
        (strcmp(o->tyre_id, "off") != 0)) {
        return usage_error(o, "--tyre-id must be apf, sir, sckf or off, not '%s'", o->tyre_id);
    }
    if ((o->tyre_id != NULL) && (strcmp(o->tyre_id, "off") != 0) && (o->real != NULL) &&
        (strcmp(o->real, "q31") == 0)) {
        return usage_error(o, "--tyre-id %s: the tyre identifier is float and double only (no "
                           "fixed-point twin: docs/TYRE_ID.md §12); use --real float or double, "
                           "or --tyre-id off",
                           o->tyre_id);
    }
    if (same_file(o->out, o->in) || ((o->params != NULL) && same_file(o->out, o->params)) ||
        ((o->metrics != NULL) && (same_file(o->metrics, o->in) || same_file(o->metrics, o->out)))) {
        return usage_error(o, "%s", "an output file (--out, --metrics) is also an input or the other output");
    }
    return 0;
}

/* Same path string, or the same existing file under another name. */
static int same_file(const char *a, const char *b)
{
    struct stat sa;
    struct stat sb;
    if (strcmp(a, b) == 0) {
        return 1;
    }
    if ((stat(a, &sa) != 0) || (stat(b, &sb) != 0)) {
        return 0;
    }
    return (sa.st_dev == sb.st_dev) && (sa.st_ino == sb.st_ino);
}

/* ------------------------------------------------------------ the run */

static int fail(const options_t *o, const rfe_io_error_t *err)
{
    if (o->err_out != NULL) {
        *o->err_out = *err;
    } else {
        rfe_io_error_print(stderr, PROG, err);
    }
    return -1;
}

/* Reads the log, then parameters: preset < metadata < --params < flags. The preset values
 * come from the double library (exact decimals; a float run rounds them as any value). */
static int load_params(const options_t *o, run_t *r)
{
    rfe_io_error_t err;
    rfe_read_opts_t ro;
    read_opts(o, &ro);
    if (rfe_sensor_log_read_opts(o->in, &ro, &r->log, &err) != 0) {
        return fail(o, &err);
    }
    if (!o->quiet && ((r->log.bad_rows != 0u) || (r->log.bad_ignored != 0u))) {
        fprintf(stderr, "%s: note: %s: ", PROG, o->in);
        print_bad_cells(stderr, r);
    }
    return resolve_params(o, r);
}

/* How the options read a log: bad cells, the mass and grade columns, the inputs used. */
static void read_opts(const options_t *o, rfe_read_opts_t *ro)
{
    memset(ro, 0, sizeof *ro);
    ro->cells = o->strict ? RFE_CELLS_STRICT : RFE_CELLS_KEEP;
    /* off: its columns are extra columns, not read */
    ro->mass_grade_off = (o->mass_grade != NULL) && (strcmp(o->mass_grade, "off") == 0);
    /* the columns --velocity uses: the measured ones needed (named with any other missing
     * column), the bad cells of the unused ones apart */
    ro->inputs = (o->velocity == NULL)                     ? RFE_INPUTS_AUTO
                : (strcmp(o->velocity, "measured") == 0) ? RFE_INPUTS_MEASURED
                : (strcmp(o->velocity, "observer") == 0) ? RFE_INPUTS_OBSERVER
                                                          : RFE_INPUTS_AUTO;
}

/* The parameters of the log read: preset < metadata < --params < flags; the run's precision
 * and velocity source. */
static int resolve_params(const options_t *o, run_t *r)
{
    rfe_io_error_t err;
    (void)rfe_param_set_preset_f64(&r->ps, o->preset_id); /* cannot fail: parsed preset */
    {
        /* the mg_* keys' base: the vehicle's preset of the configuration (MASS_GRADE.md §6) */
        const rfe_mg_vehicle_t v = ((o->mg_vehicle != NULL) && (strcmp(o->mg_vehicle, "truck") == 0))
                                       ? RFE_MG_TRUCK
                                       : RFE_MG_CAR;
        const rfe_mg_config_t c = ((o->mass_grade != NULL) && (strcmp(o->mass_grade, "aukf") == 0))
                                      ? RFE_MG_SEED
                                      : RFE_MG_RECOMMENDED;
        (void)rfe_param_set_mass_grade_f64(&r->ps, v, c); /* cannot fail: checked words */
    }
    if (rfe_param_set_apply_meta(&r->ps, &r->log, o->in, &err) != 0) {
        return fail(o, &err);
    }
    if ((o->params != NULL) && (rfe_param_set_apply_file(&r->ps, o->params, &err) != 0)) {
        return fail(o, &err);
    }
    if ((o->params_text != NULL) && (apply_params_text(&r->ps, o->params_text, &err) != 0)) {
        return fail(o, &err);
    }
    /* Words were checked in parse_args; the flags win over every file. */
    if ((o->filter != NULL) && (rfe_filter_kind_parse(o->filter, &r->ps.filter) == 0)) {
        r->ps.origin[RFE_PK_FILTER].file = "command line";
        r->ps.origin[RFE_PK_FILTER].line = 0u;
    }
    if ((o->tyre != NULL) && (rfe_tyre_mode_parse(o->tyre, &r->ps.tyre) == 0)) {
        r->ps.origin[RFE_PK_TYRE].file = "command line";
        r->ps.origin[RFE_PK_TYRE].line = 0u;
    }
    r->is_double = (o->real != NULL) && (strcmp(o->real, "double") == 0);
    r->is_q31 = (o->real != NULL) && (strcmp(o->real, "q31") == 0);
    if (mass_grade_flags(o, r) != 0) {
        return -1;
    }
    tyre_id_flag(o, r);
    if ((o->velocity != NULL) && (strcmp(o->velocity, "measured") == 0) && !r->log.has_velocity) {
        rfe_io_error_set(&err, o->in, 0u, 0u, "%s",
                         "--velocity measured needs the columns vx, vy, yaw_acc; this log has "
                         "none (a production car's log: use --velocity observer)");
        return fail(o, &err);
    }
    r->use_observer = ((o->velocity != NULL) && (strcmp(o->velocity, "observer") == 0)) ||
                      (((o->velocity == NULL) || (strcmp(o->velocity, "auto") == 0)) &&
                       !r->log.has_velocity);
    return 0;
}

/* The mass and grade estimator runs on a log with drive_torque unless off (then the reader
 * left its columns out: has_drive_torque 0), in every --real (q31: its fixed-point twin). An
 * explicit ukf or aukf sets mg_adaptive over every file, as --filter does. A drive_torque that
 * is not at the wheels (driveline_torque_at other than wheels) is an input error. */
static int mass_grade_flags(const options_t *o, run_t *r)
{
    const char *at = rfe_sensor_log_meta(&r->log, "driveline_torque_at");
    rfe_io_error_t err;
    r->ps.mass_grade = r->log.has_drive_torque;
    if (r->ps.mass_grade && (at != NULL) && (strcmp(at, "wheels") != 0)) {
        rfe_io_error_set(&err, o->in, 0u, 0u,
                         "driveline_torque_at = %s: the mass and grade estimator takes the torque "
                         "at the wheels, which the replay does not compute from the drive line; "
                         "convert drive_torque first, or --mass-grade off", at);
        return fail(o, &err);
    }
    if ((o->mass_grade != NULL) && (strcmp(o->mass_grade, "off") != 0)) {
        r->ps.mg[RFE_PK_mg_adaptive - RFE_PK_MG_FIRST] =
            (strcmp(o->mass_grade, "aukf") == 0) ? 1.0 : 0.0;
        r->ps.origin[RFE_PK_mg_adaptive].file = "command line";
        r->ps.origin[RFE_PK_mg_adaptive].line = 0u;
    }
    return 0;
}

/* The tyre identifier runs only when --tyre-id names a filter (off by default, until it
 * earns its place in a preset); the flag sets tid_filter over every file, as --mass-grade
 * sets mg_adaptive. */
static void tyre_id_flag(const options_t *o, run_t *r)
{
    rfe_tid_filter_t f;
    r->ps.tyre_id = (o->tyre_id != NULL) && (rfe_tid_filter_parse(o->tyre_id, &f) == 0);
    if (r->ps.tyre_id) {
        r->ps.tid[RFE_PK_tid_filter - RFE_PK_TID_FIRST] = (double)f;
        r->ps.origin[RFE_PK_tid_filter].file = "command line";
        r->ps.origin[RFE_PK_tid_filter].line = 0u;
    }
}

/* Whether vehicle key @p k (m .. hg) came from no file: neither the log's metadata nor a
 * --params file gave it, so the preset's value stands in. */
static int vehicle_key_preset(const run_t *r, size_t k)
{
    return r->ps.origin[k].file == NULL;
}

/* The vehicle keys (m .. hg of the key table; g is nature's) that neither the log's metadata
 * nor a parameter file gives: the preset's values stand in for them, which a user must know
 * (a warning naming every one with its value), or may forbid (--require-params: an input
 * error naming them). One key given does not stand for the others: a log with only m runs on
 * the preset's wheelbase, track, radius, inertia and CoG height. */
static int check_vehicle(const options_t *o, run_t *r)
{
    rfe_io_error_t err;
    char list[128];
    size_t used = 0u;
    size_t n = 0u;
    size_t k;
    list[0] = '\0';
    for (k = (size_t)RFE_PK_m; k <= (size_t)RFE_PK_hg; ++k) {
        if (vehicle_key_preset(r, k) && (used < sizeof list)) {
            const int w = snprintf(list + used, sizeof list - used, "%s%s", (n > 0u) ? ", " : "",
                                   rfe_param_info(k)->key);
            used += (w > 0) ? (size_t)w : 0u;
            ++n;
        }
    }
    if (n == 0u) {
        return 0;
    }
    if (o->require_params && (n == (size_t)RFE_PK_hg - (size_t)RFE_PK_m + 1u)) {
        rfe_io_error_set(&err, o->in, 0u, 0u, "%s",
                         "no vehicle parameters (m, Lf, Lr, Bf, Br, R, J, hg) in the log's "
                         "metadata and no --params file (--require-params)");
        return fail(o, &err);
    }
    if (o->require_params) {
        rfe_io_error_set(&err, o->in, 0u, 0u,
                         "vehicle parameter%s %s in neither the log's metadata nor a --params "
                         "file (--require-params)", (n > 1u) ? "s" : "", list);
        return fail(o, &err);
    }
    r->preset_vehicle = 1;
    return 0;
}

/* The warning of a run on the preset's vehicle values (check_vehicle), once the run
 * succeeded: every one used, with its value. */
static void warn_preset_vehicle(const options_t *o, const run_t *r)
{
    char val[RFE_NUM_BUF];
    size_t k;
    size_t n = 0u;
    const char *sep = "";
    if (!r->preset_vehicle || o->quiet) {
        return;
    }
    for (k = (size_t)RFE_PK_m; k <= (size_t)RFE_PK_hg; ++k) {
        n += vehicle_key_preset(r, k) ? 1u : 0u;
    }
    if (n == (size_t)RFE_PK_hg - (size_t)RFE_PK_m + 1u) {
        fprintf(stderr, "%s: warning: %s: no vehicle parameters in the metadata and no --params: "
                        "the %s preset's car is used:", PROG, o->in, rfe_preset_str(r->ps.preset));
    } else {
        fprintf(stderr, "%s: warning: %s: vehicle parameter%s in neither the metadata nor "
                        "--params: using the %s preset's", PROG, o->in, (n > 1u) ? "s" : "",
                rfe_preset_str(r->ps.preset));
    }
    for (k = (size_t)RFE_PK_m; k <= (size_t)RFE_PK_hg; ++k) {
        if (vehicle_key_preset(r, k)) {
            rfe_param_format(&r->ps, k, val);
            fprintf(stderr, "%s %s = %s %s", sep, rfe_param_info(k)->key, val,
                    rfe_param_info(k)->unit);
            sep = ",";
        }
    }
    fprintf(stderr, " (--require-params makes this an error)\n");
}

/* A recorded car's log in the library's terms, once the parameters are known: wheel speeds
 * in km/h through the rolling radius R, the steering-wheel angle through obs_steer_ratio
 * (the observer applies it itself), the sample period against dt. */
static int prepare_log(const options_t *o, run_t *r)
{
    rfe_io_error_t err;
    const size_t k_ratio = (size_t)RFE_PK_obs_steer_ratio;
    const double ratio = r->ps.obs[k_ratio - RFE_PK_OBS_FIRST];
    if ((r->log.omega_linear != 0) &&
        (rfe_sensor_log_wheel_radius(&r->log, r->ps.value[RFE_PK_R]) != 0)) {
        rfe_io_error_set(&err, o->in, 0u, 0u, "the wheel speeds are circumferential speeds and "
                         "need a positive rolling radius R (R = %.17g)", r->ps.value[RFE_PK_R]);
        return fail(o, &err);
    }
    if (r->log.has_swa != 0) {
        /* The default ratio is only a typical car's: a log of the steering-wheel angle must
         * say its own, or every slip angle is silently off by the ratio's error. */
        if (r->ps.origin[k_ratio].file == NULL) {
            rfe_io_error_set(&err, o->in, 0u, 0u, "%s",
                             "the log gives the steering-wheel angle (swa): declare the "
                             "car's obs_steer_ratio in its metadata or a --params file");
            return fail(o, &err);
        }
        if (!r->use_observer && (rfe_sensor_log_steer_ratio(&r->log, ratio) != 0)) {
            rfe_io_error_set(&err, (r->ps.origin[k_ratio].file != NULL) ? r->ps.origin[k_ratio].file
                                                                       : o->in,
                             r->ps.origin[k_ratio].line, 0u,
                             "obs_steer_ratio = %.17g: must be a positive number", ratio);
            return fail(o, &err);
        }
    }
    return check_period(o, r);
}

/* The friction estimator's input filter assumes the period dt; a log at another rate (a car
 * logged at 50 Hz) must say so. dt not given: it becomes the time stamps' median period.
 * Given: it must match that median within 1 % (loggers' clocks drift < 0.1 %; the median
 * ignores jitter and gaps; a 50 Hz log read as 100 Hz is off by 100 %). A period longer than
 * two medians is a gap, reported with what the run does over it (DATA.md "The sample
 * period"); shorter jitter is accepted without a word. */
static int check_period(const options_t *o, run_t *r)
{
    rfe_io_error_t err;
    rfe_log_period_t per;
    const rfe_param_origin_t *src = &r->ps.origin[RFE_PK_dt];
    const double dt = r->ps.value[RFE_PK_dt];
    const double dt_max = r->ps.obs[(size_t)RFE_PK_obs_dt_max - RFE_PK_OBS_FIRST];
    size_t gaps;
    size_t i;
    double t_gap = 0.0;
    if (rfe_log_period(&r->log, &per) != 0) {
        return 0; /* one row: no period to check */
    }
    if (src->file == NULL) {
        r->ps.value[RFE_PK_dt] = per.median;
        r->ps.origin[RFE_PK_dt].file = "the log's time stamps";
        /* the preset's dt matching to the 1 % of a given one is no news (a 100 Hz log's
         * median period is 0.01 only to the stamps' rounding) */
        if (!o->quiet && !(fabs(dt - per.median) <= 0.01 * per.median)) {
            fprintf(stderr, "%s: note: dt = %.6g s, the median period of the time stamps (the "
                            "preset's %.6g s does not match this log)\n",
                    PROG, per.median, dt);
        }
    } else if (!(fabs(dt - per.median) <= 0.01 * per.median)) {
        rfe_io_error_set(&err, src->file, src->line, 0u,
                         "dt = %.6g s, but the log's time stamps have a median period of %.6g s "
                         "(%.6g .. %.6g s; they may differ by 1 %%): correct dt, or drop it to "
                         "take the time stamps'",
                         dt, per.median, per.min, per.max);
        return fail(o, &err);
    } else {
        /* dt as given: it matches */
    }
    gaps = rfe_log_gaps(&r->log, rfe_log_gap_limit(per.median));
    for (i = 1u; i < r->log.n_rows; ++i) {
        if ((r->log.rows[i].t - r->log.rows[i - 1u].t) == per.max) {
            t_gap = r->log.rows[i].t;
            break;
        }
    }
    if (!o->quiet && (gaps != 0u)) {
        fprintf(stderr, "%s: note: %zu gap(s) longer than 2 periods (2 x %.6g s), the longest "
                        "%.6g s before t = %.6g s: ",
                PROG, gaps, per.median, per.max, t_gap);
        if (r->use_observer) {
            fprintf(stderr, "behind the observer the friction estimator makes the time updates "
                            "of the missed periods at once and restarts its input filter; the "
                            "observer steps with the real period and starts afresh after %zu "
                            "gap(s) longer than obs_dt_max = %.6g s (rfe/pipeline.h)",
                    rfe_log_gaps(&r->log, dt_max), dt_max);
        } else {
            fprintf(stderr, "the friction estimator makes the time updates of the missed "
                            "periods at once and restarts its input filter (rfe_friction_skip)");
        }
        fputc('\n', stderr);
    }
    if (!o->quiet && r->use_observer) {
        size_t shorter = 0u;
        for (i = 1u; i < r->log.n_rows; ++i) {
            shorter += ((r->log.rows[i].t - r->log.rows[i - 1u].t) < 0.5 * per.median) ? 1u : 0u;
        }
        if (shorter != 0u) {
            fprintf(stderr, "%s: note: %zu period(s) shorter than half of dt = %.6g s: behind "
                            "the observer such a sample is refused (status 18; the friction "
                            "estimator would take it as a whole period, rfe/pipeline.h)\n",
                    PROG, shorter, per.median);
        }
    }
    return 0;
}

/* Steps the estimator; an invalid parameter set is reported where its value came from. */
static int run_estimator(const options_t *o, run_t *r)
{
    replay_fn_t run = r->use_observer
                          ? (r->is_double ? rfe_replay_run_observer_f64 : rfe_replay_run_observer_f32)
                          : (r->is_double ? rfe_replay_run_f64 : rfe_replay_run_f32);
    size_t bad = RFE_PK_NONE;
    rfe_status_t st;
    r->rows = rfe_xrealloc(NULL, r->log.n_rows, sizeof *r->rows);
    if (r->is_q31) {
        st = r->use_observer ? rfe_replay_run_observer_q31(&r->ps, &r->log, r->rows, &r->q31, NULL, &bad)
                             : rfe_replay_run_q31(&r->ps, &r->log, r->rows, &r->q31, NULL, &bad);
        r->stats = r->q31.base;
    } else {
        st = run(&r->ps, &r->log, r->rows, &r->stats, &bad);
    }
    r->mg_ran = (st == RFE_OK) && (r->log.n_rows > 0u) && (r->rows[0].has_mass_grade != 0);
    r->tid_ran = (st == RFE_OK) && (r->log.n_rows > 0u) && (r->rows[0].has_tyre_id != 0);
    return (st == RFE_OK) ? 0 : start_error(o, r, st, bad);
}

/* The message of a run that could not start (@p st, the key @p bad blamed): an invalid
 * parameter set is reported where its value came from. */
static int start_error(const options_t *o, const run_t *r, rfe_status_t st, size_t bad)
{
    rfe_io_error_t err;
    char val[RFE_NUM_BUF];
    if ((st == RFE_ERR_RANGE) && (bad != RFE_PK_NONE)) {
        const rfe_param_origin_t *src = &r->ps.origin[bad];
        rfe_param_format(&r->ps, bad, val);
        rfe_io_error_set(&err, (src->file != NULL) ? src->file : "preset", src->line, 0u,
                         "parameter %s = %s does not fit the fixed-point formats "
                         "(%s, q31 run; docs/FIXED_POINT.md)",
                         rfe_param_info(bad)->key, val,
                         q31_converter_name(r, bad));
    } else if (st == RFE_ERR_RANGE) {
        rfe_io_error_set(&err, o->in, 0u, 0u,
                         "estimator init failed: %s (q31 run: the parameter set or the prior "
                         "does not fit the fixed-point formats, docs/FIXED_POINT.md)",
                         rfe_status_str(st));
    } else if ((bad == (size_t)RFE_PK_FILTER) && (r->ps.filter == RFE_FILTER_CKF)) {
        const rfe_param_origin_t *src = &r->ps.origin[bad];
        rfe_io_error_set(&err, (src->file != NULL) ? src->file : "preset", src->line, 0u,
                         "filter = ckf: the CKF baseline needs --preset paper (it runs only "
                         "the paper subset of the parameters)");
    } else if (bad != RFE_PK_NONE) {
        const rfe_param_origin_t *src = &r->ps.origin[bad];
        rfe_param_format(&r->ps, bad, val);
        rfe_io_error_set(&err, (src->file != NULL) ? src->file : "preset", src->line, 0u,
                         "invalid parameter %s = %s (rejected by %s, %s run)",
                         rfe_param_info(bad)->key, val, validator_name(bad),
                         real_name(r));
    } else {
        rfe_io_error_set(&err, o->in, 0u, 0u,
                         "estimator init failed: %s (check the parameter combination: "
                         "mu_min < mu_max, mu0 within them%s%s)",
                         rfe_status_str(st),
                         !r->ps.mass_grade ? ""
                         : r->is_q31       ? "; mass and grade: mg_m_min < mg_m0 < mg_m_max, "
                                             "|mg_theta0| < mg_theta_max, mg_ut_* with 1 < n + "
                                             "lambda < 16 and w_c,0 >= 0 in fixed point, "
                                             "docs/FIXED_POINT.md \"Mass and grade\""
                                           : "; mass and grade: mg_m_min < mg_m0 < mg_m_max, "
                                             "|mg_theta0| < mg_theta_max, mg_ut_* with n + lambda "
                                             "> 0, docs/MASS_GRADE.md §6",
                         r->ps.tyre_id ? "; tyre identifier: tid_mu0, shape_Cy, cy and shape_Ey "
                                         "within their tid_* bounds, docs/TYRE_ID.md §2"
                                       : "");
    }
    return fail(o, &err);
}

/* The converter that found key @p k beyond its Q format (q31 runs): R and g, which the mass
 * and grade estimator takes too, in either of two when it runs. */
static const char *q31_converter_name(const run_t *r, size_t k)
{
    if (rfe_param_is_obs(k) != 0) {
        return "rfe_velocity_params_to_q31";
    }
    if (rfe_param_is_mg(k) != 0) {
        return "rfe_mass_grade_params_to_q31";
    }
    return (r->ps.mass_grade && ((k == (size_t)RFE_PK_R) || (k == (size_t)RFE_PK_g)))
               ? "rfe_params_to_q31 or rfe_mass_grade_params_to_q31"
               : "rfe_params_to_q31";
}

/* The library function that refused key @p k. (R and g, which the mass and grade estimator
 * takes too, are checked by rfe_params_validate first, on the same conditions.) */
static const char *validator_name(size_t k)
{
    if (k == (size_t)RFE_PK_mg_feed_sd_rel) {
        return "mu_replay: a relative sd >= 0";
    }
    if (k == (size_t)RFE_PK_mg_feed_excitation) {
        return "mu_replay: a finite excitation >= 0 m/s";
    }
    if (k == (size_t)RFE_PK_mg_feed_ax_min) {
        return "mu_replay: a finite acceleration >= 0 m/s^2";
    }
    if ((k == (size_t)RFE_PK_mg_feed_slip_max) || (k == (size_t)RFE_PK_mg_feed_band)) {
        return "mu_replay: a finite share >= 0";
    }
    if (k == (size_t)RFE_PK_tid_seed) {
        return "mu_replay: an integer 0 .. 2^53";
    }
    if (k == (size_t)RFE_PK_tid_feed_evidence) {
        return "mu_replay: a time >= 0 s";
    }
    if (k == (size_t)RFE_PK_tid_feed_ax_max) {
        return "mu_replay: a finite acceleration >= 0 m/s^2";
    }
    if (k == (size_t)RFE_PK_tid_feed_refresh) {
        return "mu_replay: a finite time >= 0 s";
    }
    if (k == (size_t)RFE_PK_tid_feed_outlier_k) {
        return "mu_replay: a finite multiple >= 0 of tid_sd_ay";
    }
    if (k == (size_t)RFE_PK_tid_feed_sd_rel) {
        return "mu_replay: a relative sd >= 0, and 0 behind the velocity observer, whose "
               "pipeline has no lateral tyre setter";
    }
    if (rfe_param_is_tid(k) != 0) {
        return "rfe_tyre_id_params_validate";
    }
    if (rfe_param_is_mg(k) != 0) {
        return "rfe_mass_grade_params_validate";
    }
    return (rfe_param_is_obs(k) != 0) ? "rfe_velocity_params_validate" : "rfe_params_validate";
}

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return (slash != NULL) ? slash + 1 : path;
}

/* The mass and grade configuration that ran, by its mg_adaptive: "aukf" or "ukf". */
static const char *mg_config_name(const run_t *r)
{
    return (r->ps.mg[RFE_PK_mg_adaptive - RFE_PK_MG_FIRST] != 0.0) ? "aukf" : "ukf";
}

static const char *real_name(const run_t *r)
{
    return r->is_q31 ? "q31" : (r->is_double ? "double" : "float");
}

/* q31 runs: the saturation counters as metadata pairs (values formatted into vals); returns
 * how many (0 for float and double runs). */
static size_t saturation_meta(const run_t *r, rfe_kv_t *meta, char vals[][RFE_NUM_BUF])
{
    static const char *const keys[5] = {"saturation_estimator_total", "saturation_estimator_steps",
                                        "saturation_estimator_max_per_step",
                                        "saturation_input_values", "saturation_input_rows"};
    const unsigned long long v[5] = {
        (unsigned long long)r->q31.est_sat, (unsigned long long)r->q31.est_sat_rows,
        (unsigned long long)r->q31.est_sat_max, (unsigned long long)r->q31.input_sat,
        (unsigned long long)r->q31.input_sat_rows};
    size_t i;
    if (!r->is_q31) {
        return 0u;
    }
    for (i = 0u; i < 5u; ++i) {
        snprintf(vals[i], RFE_NUM_BUF, "%llu", v[i]);
        meta[i].key = keys[i];
        meta[i].value = vals[i];
    }
    return 5u;
}

/* Metadata: generator, preset, filter, tyre, [velocity], structure, real, input,
 * [param_file], then every numeric key (the obs_* keys when the observer ran). */
static int write_estimates(const options_t *o, const run_t *r)
{
    rfe_kv_t meta[17u + RFE_PK_COUNT];
    char vals[RFE_PK_COUNT][RFE_NUM_BUF];
    char sat_vals[5][RFE_NUM_BUF];
    size_t n = 0u;
    size_t k;
    rfe_io_error_t err;
    meta[n].key = "generator";
    meta[n++].value = PROG;
    meta[n].key = "preset";
    meta[n++].value = rfe_preset_str(r->ps.preset);
    meta[n].key = "filter";
    meta[n++].value = rfe_filter_kind_str(r->ps.filter);
    meta[n].key = "tyre";
    meta[n++].value = rfe_tyre_mode_str(r->ps.tyre);
    if (r->use_observer) { /* only then: estimate logs of measured runs stay as they were */
        meta[n].key = "velocity";
        meta[n++].value = "observer";
    }
    if (r->mg_ran) { /* only then: other estimate logs stay as they were */
        meta[n].key = "mass_grade";
        meta[n++].value = mg_config_name(r);
        meta[n].key = "mass_grade_vehicle";
        meta[n++].value = (r->ps.mg_vehicle == RFE_MG_TRUCK) ? "truck" : "car";
    }
    if (r->tid_ran) { /* as the mass and grade estimator's */
        meta[n].key = "tyre_id";
        meta[n++].value = rfe_tid_filter_str((rfe_tid_filter_t)r->ps.tid[RFE_PK_tid_filter - RFE_PK_TID_FIRST]);
        meta[n].key = "tid_n"; /* RFE_TID_N: information, not a key */
        meta[n++].value = RFE_TID_N_TEXT;
    }
    meta[n].key = "structure";
    meta[n++].value = rfe_structure_str(r->ps.structure);
    meta[n].key = "real";
    meta[n++].value = real_name(r);
    meta[n].key = "input";
    meta[n++].value = base_name(o->in);
    if (o->params != NULL) {
        meta[n].key = "param_file";
        meta[n++].value = base_name(o->params);
    }
    for (k = 0u; k < (size_t)RFE_PK_COUNT; ++k) {
        /* numbers only (the words are above); the observer's keys when it ran */
        if ((rfe_param_is_word(k) == 0) && (r->use_observer || (rfe_param_is_obs(k) == 0)) &&
            (r->mg_ran || (rfe_param_is_mg(k) == 0)) && (r->tid_ran || (rfe_param_is_tid(k) == 0))) {
            rfe_param_format(&r->ps, k, vals[k]);
            meta[n].key = rfe_param_info(k)->key;
            meta[n++].value = vals[k];
        }
    }
    n += saturation_meta(r, &meta[n], sat_vals);
    /* q31: the Q values converted exactly to double, written in the shortest form that
     * reads back as the same double, so the log holds them bit for bit. */
    if (rfe_estimate_log_write(o->out, meta, n, r->rows, r->log.n_rows,
                               (r->is_double || r->is_q31) ? RFE_NUMFMT_DOUBLE : RFE_NUMFMT_FLOAT,
                               &err) != 0) {
        return fail(o, &err);
    }
    return 0;
}

/* Columns out of the row structs, then the metrics with their default definition. */
static void compute_metrics(run_t *r)
{
    const size_t n = r->log.n_rows;
    /* Columns: t, then per wheel truth, est, sd [, util]. */
    const size_t n_cols = 1u + (r->log.has_util ? 4u : 3u) * RFE_WHEELS;
    double *buf = rfe_xrealloc(NULL, n, n_cols * sizeof *buf);
    unsigned char *valid = rfe_xrealloc(NULL, n, RFE_WHEELS * sizeof *valid);
    rfe_metrics_input_t in;
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    size_t i;
    size_t w;
    memset(&in, 0, sizeof in);
    in.t = buf;
    in.n = n;
    for (w = 0u; w < RFE_WHEELS; ++w) {
        double *truth = &buf[(1u + w) * n];
        double *est = &buf[(1u + RFE_WHEELS + w) * n];
        double *sd = &buf[(1u + 2u * RFE_WHEELS + w) * n];
        double *util = r->log.has_util ? &buf[(1u + 3u * RFE_WHEELS + w) * n] : NULL;
        for (i = 0u; i < n; ++i) {
            truth[i] = r->log.rows[i].mu_true[w];
            est[i] = r->rows[i].mu[w];
            sd[i] = r->rows[i].sd[w];
            valid[w * n + i] = r->rows[i].valid[w];
            if (util != NULL) {
                util[i] = r->log.rows[i].util_true[w];
            }
        }
        in.truth[w] = truth;
        in.est[w] = est;
        in.sd[w] = sd;
        in.valid[w] = &valid[w * n];
        in.util[w] = util;
    }
    for (i = 0u; i < n; ++i) {
        buf[i] = r->rows[i].t;
    }
    /* Fails only for n == 0, which the reader rules out. */
    r->has_metrics = (rfe_metrics_compute(&in, &cfg, &r->metrics) == 0);
    free(valid);
    free(buf);
}

/* {"generator", "input", "preset", "filter", "tyre", "real", ["saturation"],
 *  "bad_cells_ignored", "steps", "bad_cells", "gaps",
 *  "status_counts", "metrics"} */
static int write_metrics_json(const options_t *o, const run_t *r)
{
    rfe_io_error_t err;
    FILE *f = fopen(o->metrics, "w");
    size_t s;
    const char *sep = "";
    int bad;
    if (f == NULL) {
        rfe_io_error_set(&err, o->metrics, 0u, 0u, "cannot open for writing: %s", strerror(errno));
        return fail(o, &err);
    }
    fputs("{\n  \"generator\": \"" PROG "\",\n  \"input\": ", f);
    rfe_json_write_string(f, base_name(o->in));
    fprintf(f, ",\n  \"preset\": \"%s\",\n  \"filter\": \"%s\",\n  \"tyre\": \"%s\",\n"
               "  \"real\": \"%s\",\n",
            rfe_preset_str(r->ps.preset), rfe_filter_kind_str(r->ps.filter), rfe_tyre_mode_str(r->ps.tyre),
            real_name(r));
    if (r->is_q31) {
        fprintf(f, "  \"saturation\": {\"estimator_total\": %llu, \"estimator_steps\": %zu, "
                   "\"estimator_max_per_step\": %lu, \"input_values\": %llu, \"input_rows\": %zu},\n",
                (unsigned long long)r->q31.est_sat, r->q31.est_sat_rows,
                (unsigned long)r->q31.est_sat_max, (unsigned long long)r->q31.input_sat,
                r->q31.input_sat_rows);
    }
    /* bad_cells below: the cells given to the estimator (each rejects its row); these are
     * the bad cells of the input columns this run does not use, which reject nothing */
    fprintf(f, "  \"bad_cells_ignored\": {\"cells\": %zu, \"columns\": ", r->log.bad_ignored);
    if (r->log.unused_cols != NULL) {
        rfe_json_write_string(f, r->log.unused_cols);
    } else {
        fputs("null", f);
    }
    fputs("},\n", f);
    fprintf(f, "  \"steps\": %zu,\n  \"bad_cells\": {\"empty\": %zu, \"nonfinite\": %zu, "
               "\"range\": %zu, \"rows\": %zu},\n  \"gaps\": {\"count\": %zu, "
               "\"missed_periods\": %llu",
            r->stats.n_steps, r->log.bad_cells[RFE_CELL_EMPTY], r->log.bad_cells[RFE_CELL_NONFINITE],
            r->log.bad_cells[RFE_CELL_RANGE], r->log.bad_rows, r->stats.n_gaps,
            (unsigned long long)r->stats.n_skipped);
    if (r->use_observer) {
        fprintf(f, ", \"observer_restarts\": %zu", r->stats.n_restarts);
    }
    fputs("},\n  \"status_counts\": {", f);
    for (s = 0u; s < RFE_REPLAY_STATUS_SLOTS; ++s) {
        if (r->stats.status_count[s] != 0u) {
            fprintf(f, "%s\"%zu\": %zu", sep, s, r->stats.status_count[s]);
            sep = ", ";
        }
    }
    fputs("},\n", f);
    write_mass_grade_json(f, r);
    write_tyre_id_json(f, r);
    fputs("  \"metrics\": ", f);
    if (r->has_metrics) {
        rfe_metrics_write_json(f, &r->metrics, 2);
    } else {
        fputs("null", f);
    }
    fputs("\n}\n", f);
    bad = ferror(f);
    if ((fclose(f) != 0) || (bad != 0)) {
        rfe_io_error_set(&err, o->metrics, 0u, 0u, "write failed");
        return fail(o, &err);
    }
    return 0;
}

/* The bad cells the run kept (csv_log.h RFE_CELLS_KEEP), per cause, those of the columns it
 * uses (each rejects its row) apart from those of the columns it does not use (ignored:
 * they reject nothing): one line, or nothing. */
static void print_bad_cells(FILE *f, const run_t *r)
{
    const rfe_sensor_log_t *lg = &r->log;
    /* --strict stops at the first bad cell of either kind */
    const int used_first = (lg->bad_rows != 0u) &&
                           ((lg->bad_ignored == 0u) ||
                            (lg->bad_first_line < lg->bad_ignored_first_line) ||
                            ((lg->bad_first_line == lg->bad_ignored_first_line) &&
                             (lg->bad_first_col < lg->bad_ignored_first_col)));
    size_t c;
    if ((lg->bad_rows == 0u) && (lg->bad_ignored == 0u)) {
        return;
    }
    if (lg->bad_rows != 0u) {
        fprintf(f, "bad cells (given to the estimator as NaN/Inf, the row rejected):");
        for (c = 0u; c < (size_t)RFE_CELL_CAUSES; ++c) {
            fprintf(f, " %s %zu%s", rfe_cell_cause_str((rfe_cell_cause_t)c), lg->bad_cells[c],
                    (c + 1u < (size_t)RFE_CELL_CAUSES) ? "," : "");
        }
        fprintf(f, "; in %zu row(s), the first at line %zu column %zu%s", lg->bad_rows,
                lg->bad_first_line, lg->bad_first_col, used_first ? " (--strict stops there)" : "");
    } else {
        fprintf(f, "bad cells: none in the columns this run uses");
    }
    if (lg->bad_ignored != 0u) {
        fprintf(f, "; ignored: %zu in the columns this run does not use (%s), the first at line "
                   "%zu column %zu%s",
                lg->bad_ignored, (lg->unused_cols != NULL) ? lg->unused_cols : "?",
                lg->bad_ignored_first_line, lg->bad_ignored_first_col,
                used_first ? "" : " (--strict stops there)");
    }
    fputc('\n', f);
}

static void print_status_counts(const run_t *r)
{
    size_t s;
    printf("steps: %zu\n", r->stats.n_steps);
    print_bad_cells(stdout, r);
    for (s = 0u; s < RFE_REPLAY_STATUS_SLOTS; ++s) {
        if (r->stats.status_count[s] != 0u) {
            const char *name = (s + 1u < RFE_REPLAY_STATUS_SLOTS)
                                   ? rfe_status_str((rfe_status_t)s)
                                   : "other status values";
            printf("  status %2zu %-40s %zu\n", s, name, r->stats.status_count[s]);
        }
    }
    if (r->stats.n_gaps != 0u) {
        printf("gaps: %zu longer than 2 dt, %llu missed sample periods time-updated "
               "(rfe_friction_skip)\n",
               r->stats.n_gaps, (unsigned long long)r->stats.n_skipped);
    }
    if (r->stats.n_restarts != 0u) {
        printf("observer: started afresh at %zu sample(s) after a period beyond obs_dt_max "
               "(rfe_velocity_restart)\n", r->stats.n_restarts);
    }
    print_mass_grade(r);
    print_tyre_id(r);
    if (r->is_q31) {
        printf("saturation (q31): estimator %llu events in %zu steps (at most %lu in one step); "
               "input %llu values in %zu rows\n",
               (unsigned long long)r->q31.est_sat, r->q31.est_sat_rows,
               (unsigned long)r->q31.est_sat_max, (unsigned long long)r->q31.input_sat,
               r->q31.input_sat_rows);
    }
}

/* ------------------------------------------------------------ mass and grade */

/** Accuracy of the mass and grade estimate against the log's truth (DATA.md "Mass and grade
 *  logs"); NaN where a truth column is missing or no sample counts. */
typedef struct {
    size_t first;      /**< the first sample counted: the estimator's first accepted one */
    size_t n;          /**< samples counted: from it to the end of the log */
    double mass_err_end;     /**< mass_est - mass_true at the last sample [kg] */
    double mass_err_end_rel; /**< the same over mass_true */
    double mass_used_err_end_rel; /**< (mass_used - mass_true) / mass_true at the last sample:
                                       the friction estimator's mass (mg_feed_sd_rel) */
    double grade_rmse;       /**< RMSE of grade_est - grade_true over the samples counted [rad] */
    double grade_max_abs;    /**< max |grade_est - grade_true| over them [rad] */
} mg_accuracy_t;

/* The figures of mg_accuracy_t: every sample from the estimator's first accepted one (before
 * it there is no estimate, the rows hold 0) to the end, held ones included: what a user of
 * the estimate would have read. */
static void mass_grade_accuracy(const run_t *r, mg_accuracy_t *a)
{
    const size_t n = r->log.n_rows;
    double sum = 0.0;
    size_t i;
    a->first = n;
    for (i = 0u; (i < n) && (a->first == n); ++i) {
        a->first = rfe_status_is_error((rfe_status_t)r->rows[i].mg_status) ? n : i;
    }
    a->n = n - a->first;
    a->mass_err_end = (double)NAN;
    a->mass_err_end_rel = (double)NAN;
    a->mass_used_err_end_rel = (double)NAN;
    a->grade_rmse = (double)NAN;
    a->grade_max_abs = (double)NAN;
    if (a->n == 0u) {
        return;
    }
    if (r->log.has_mass_true) {
        a->mass_err_end = r->rows[n - 1u].mass - r->log.rows[n - 1u].mass_true;
        a->mass_err_end_rel = a->mass_err_end / r->log.rows[n - 1u].mass_true;
        a->mass_used_err_end_rel =
            (r->rows[n - 1u].mass_used - r->log.rows[n - 1u].mass_true) / r->log.rows[n - 1u].mass_true;
    }
    if (r->log.has_grade_true) {
        a->grade_max_abs = 0.0;
        for (i = a->first; i < n; ++i) {
            const double e = r->rows[i].grade - r->log.rows[i].grade_true;
            sum += e * e;
            a->grade_max_abs = (fabs(e) > a->grade_max_abs) ? fabs(e) : a->grade_max_abs;
        }
        a->grade_rmse = sqrt(sum / (double)a->n);
    }
}

/* "mass_grade": {...}, when the estimator ran: its configuration, the last estimate, the
 * status counts and the accuracy against the truth columns (null without them). */
static void write_mass_grade_json(FILE *f, const run_t *r)
{
    const rfe_est_row_t *last = &r->rows[r->log.n_rows - 1u];
    mg_accuracy_t a;
    const char *sep = "";
    size_t s;
    if (!r->mg_ran) {
        return;
    }
    mass_grade_accuracy(r, &a);
    fprintf(f, "  \"mass_grade\": {\"config\": \"%s\", \"vehicle\": \"%s\", \"use_ax\": %d, "
               "\"end\": {\"mass\": ",
            mg_config_name(r), (r->ps.mg_vehicle == RFE_MG_TRUCK) ? "truck" : "car",
            (r->ps.mg[RFE_PK_mg_use_ax - RFE_PK_MG_FIRST] != 0.0) ? 1 : 0);
    rfe_json_write_number(f, last->mass);
    fputs(", \"sd_mass\": ", f);
    rfe_json_write_number(f, last->sd_mass);
    fputs(", \"grade\": ", f);
    rfe_json_write_number(f, last->grade);
    fputs(", \"sd_grade\": ", f);
    rfe_json_write_number(f, last->sd_grade);
    fputs("}, \"status_counts\": {", f);
    for (s = 0u; s < RFE_REPLAY_STATUS_SLOTS; ++s) {
        if (r->stats.mg_status_count[s] != 0u) {
            fprintf(f, "%s\"%zu\": %zu", sep, s, r->stats.mg_status_count[s]);
            sep = ", ";
        }
    }
    fprintf(f, "},\n    \"feed\": {\"sd_rel\": ");
    rfe_json_write_number(f, r->ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST]);
    fputs(", \"excitation\": ", f);
    rfe_json_write_number(f, r->ps.mg[RFE_PK_mg_feed_excitation - RFE_PK_MG_FIRST]);
    fputs(", \"ax_min\": ", f);
    rfe_json_write_number(f, r->ps.mg[RFE_PK_mg_feed_ax_min - RFE_PK_MG_FIRST]);
    fputs(", \"excitation_end\": ", f);
    rfe_json_write_number(f, r->stats.mg_excitation);
    fputs(", \"slip_max\": ", f);
    rfe_json_write_number(f, r->ps.mg[RFE_PK_mg_feed_slip_max - RFE_PK_MG_FIRST]);
    fputs(", \"band\": ", f);
    rfe_json_write_number(f, r->ps.mg[RFE_PK_mg_feed_band - RFE_PK_MG_FIRST]);
    fprintf(f, ", \"n_slip_held\": %zu, \"n_band_refused\": %zu, \"n_mismatch_held\": %zu",
            r->stats.n_feed_slip, r->stats.n_feed_band, r->stats.n_feed_mismatch);
    fprintf(f, ", \"n_fed\": %zu, \"mass_used_end\": ", r->stats.n_mass_fed);
    rfe_json_write_number(f, r->stats.mass_used_last);
    fputs("},\n    \"accuracy\": ", f);
    if (r->log.has_mass_true || r->log.has_grade_true) {
        fprintf(f, "{\"from_t_s\": ");
        rfe_json_write_number(f, (a.n > 0u) ? r->rows[a.first].t : (double)NAN);
        fprintf(f, ", \"n\": %zu, \"mass_err_end\": ", a.n);
        rfe_json_write_number(f, a.mass_err_end);
        fputs(", \"mass_err_end_rel\": ", f);
        rfe_json_write_number(f, a.mass_err_end_rel);
        fputs(", \"mass_used_err_end_rel\": ", f);
        rfe_json_write_number(f, a.mass_used_err_end_rel);
        fputs(", \"grade_rmse\": ", f);
        rfe_json_write_number(f, a.grade_rmse);
        fputs(", \"grade_max_abs_err\": ", f);
        rfe_json_write_number(f, a.grade_max_abs);
        fputs("}", f);
    } else {
        fputs("null", f);
    }
    fputs("},\n", f);
}

/* The summary's mass and grade lines, when the estimator ran. */
static void print_mass_grade(const run_t *r)
{
    const rfe_est_row_t *last = &r->rows[r->log.n_rows - 1u];
    mg_accuracy_t a;
    size_t s;
    if (!r->mg_ran) {
        return;
    }
    mass_grade_accuracy(r, &a);
    printf("mass and grade (%s, %s preset, %s): at the end mass %.1f kg (sd %.1f), grade %.4f "
           "rad (sd %.4f)\n",
           mg_config_name(r), (r->ps.mg_vehicle == RFE_MG_TRUCK) ? "truck" : "car",
           (r->ps.mg[RFE_PK_mg_use_ax - RFE_PK_MG_FIRST] != 0.0) ? "speed, torque and ax"
                                                                : "speed and torque",
           last->mass, last->sd_mass, last->grade, last->sd_grade);
    for (s = 0u; s < RFE_REPLAY_STATUS_SLOTS; ++s) {
        if (r->stats.mg_status_count[s] != 0u) {
            const char *name = (s + 1u < RFE_REPLAY_STATUS_SLOTS)
                                   ? rfe_status_str((rfe_status_t)s)
                                   : "other status values";
            printf("  mg status %2zu %-37s %zu\n", s, name, r->stats.mg_status_count[s]);
        }
    }
    printf("  mass fed to the friction estimator at %zu samples (mg_feed_sd_rel = %g, "
           "mg_feed_excitation = %g m/s of |ax| >= %g m/s^2, %.2f m/s at the end); "
           "its mass at the end %.1f kg\n",
           r->stats.n_mass_fed, r->ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST],
           r->ps.mg[RFE_PK_mg_feed_excitation - RFE_PK_MG_FIRST],
           r->ps.mg[RFE_PK_mg_feed_ax_min - RFE_PK_MG_FIRST], r->stats.mg_excitation,
           r->stats.mass_used_last);
    printf("  feed held at %zu updates by wheel slip (mg_feed_slip_max = %g), refused at %zu "
           "samples outside the band (mg_feed_band = %g around m)\n",
           r->stats.n_feed_slip, r->ps.mg[RFE_PK_mg_feed_slip_max - RFE_PK_MG_FIRST],
           r->stats.n_feed_band, r->ps.mg[RFE_PK_mg_feed_band - RFE_PK_MG_FIRST]);
    printf("  feed held at %zu samples by the model-mismatch flag (mg_mm_e)\n",
           r->stats.n_feed_mismatch);
    if (r->log.has_mass_true && (a.n > 0u)) {
        printf("  mass error at the end %+.1f kg (%+.2f %%)\n", a.mass_err_end,
               100.0 * a.mass_err_end_rel);
    }
    if (r->log.has_grade_true && (a.n > 0u)) {
        printf("  grade RMSE %.5f rad, max error %.5f rad, over %zu samples from t = %.3f s\n",
               a.grade_rmse, a.grade_max_abs, a.n, r->rows[a.first].t);
    }
}

/* ------------------------------------------------------------ tyre identifier */

/* The names of the tyre identifier's status bits, RFE_TID_UPDATED (bit 0) .. RFE_TID_LOST. */
static const char *const k_tid_flag_names[RFE_REPLAY_TID_FLAGS] = {"updated", "resampled", "held",
                                                                   "first", "lost"};

/* "tyre_id": {...}, when the identifier ran: its configuration, the status and flag counts,
 * the restarts and the last estimate. */
static void write_tyre_id_json(FILE *f, const run_t *r)
{
    const rfe_est_row_t *last = &r->rows[r->log.n_rows - 1u];
    const double end[12] = {last->mu_id[0], last->sd_mu_id[0], last->mu_id[1], last->sd_mu_id[1],
                            last->mf_B[0],  last->mf_C[0],     last->mf_D[0],  last->mf_E[0],
                            last->mf_B[1],  last->mf_C[1],     last->mf_D[1],  last->mf_E[1]};
    static const char *const end_names[12] = {"mu_id_f", "sd_mu_id_f", "mu_id_r", "sd_mu_id_r",
                                              "B_f",     "C_f",        "D_f",     "E_f",
                                              "B_r",     "C_r",        "D_r",     "E_r"};
    const char *sep = "";
    char seed[RFE_NUM_BUF];
    size_t s;
    if (!r->tid_ran) {
        return;
    }
    rfe_param_format(&r->ps, (size_t)RFE_PK_tid_seed, seed);
    fprintf(f, "  \"tyre_id\": {\"filter\": \"%s\", \"resample\": \"%s\", \"n\": %s, "
               "\"seed\": %s, \"status_counts\": {",
            rfe_tid_filter_str((rfe_tid_filter_t)r->ps.tid[RFE_PK_tid_filter - RFE_PK_TID_FIRST]),
            rfe_tid_resample_str((rfe_tid_resample_t)r->ps.tid[RFE_PK_tid_resample - RFE_PK_TID_FIRST]), RFE_TID_N_TEXT, seed);
    for (s = 0u; s < RFE_REPLAY_STATUS_SLOTS; ++s) {
        if (r->stats.tid_status_count[s] != 0u) {
            fprintf(f, "%s\"%zu\": %zu", sep, s, r->stats.tid_status_count[s]);
            sep = ", ";
        }
    }
    fputs("},\n    \"flag_counts\": {", f);
    for (s = 0u; s < RFE_REPLAY_TID_FLAGS; ++s) {
        fprintf(f, "%s\"%s\": %zu", (s > 0u) ? ", " : "", k_tid_flag_names[s],
                r->stats.tid_flag_count[s]);
    }
    fprintf(f, "}, \"restarts\": %zu, \"end\": {", r->stats.tid_restarts);
    for (s = 0u; s < 12u; ++s) {
        fprintf(f, "%s\"%s\": ", (s > 0u) ? ", " : "", end_names[s]);
        rfe_json_write_number(f, end[s]);
    }
    fputs("},\n    \"feed\": {\"sd_rel\": ", f);
    rfe_json_write_number(f, r->ps.tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST]);
    fputs(", \"evidence\": ", f);
    rfe_json_write_number(f, r->ps.tid[RFE_PK_tid_feed_evidence - RFE_PK_TID_FIRST]);
    fputs(", \"ax_max\": ", f);
    rfe_json_write_number(f, r->ps.tid[RFE_PK_tid_feed_ax_max - RFE_PK_TID_FIRST]);
    fprintf(f, ", \"n_fed\": %zu, \"refresh\": ", r->stats.n_tyre_fed);
    rfe_json_write_number(f, r->ps.tid[RFE_PK_tid_feed_refresh - RFE_PK_TID_FIRST]);
    fputs(", \"outlier_k\": ", f);
    rfe_json_write_number(f, r->ps.tid[RFE_PK_tid_feed_outlier_k - RFE_PK_TID_FIRST]);
    fprintf(f, ", \"n_reset\": %zu}},\n", r->stats.n_tyre_reset);
}

/* The summary's tyre identifier lines, when it ran. */
static void print_tyre_id(const run_t *r)
{
    const rfe_est_row_t *last = &r->rows[r->log.n_rows - 1u];
    size_t s;
    if (!r->tid_ran) {
        return;
    }
    if ((rfe_tid_filter_t)r->ps.tid[RFE_PK_tid_filter - RFE_PK_TID_FIRST] == RFE_TID_SCKF) {
        /* the sigma-point filter: no particles, no resampling (TYRE_ID.md §15); with delta
         * as its state 22 points (§15.7) */
        const int ds = r->ps.tid[RFE_PK_tid_delta_state_q - RFE_PK_TID_FIRST] > 0.0;
        printf("tyre identifier (sckf, %s cubature points%s): at the end mu_id_f %.3f (sd %.3f), "
               "mu_id_r %.3f (sd %.3f)\n",
               ds ? "22" : "20", ds ? ", delta a state" : "", last->mu_id[0], last->sd_mu_id[0],
               last->mu_id[1], last->sd_mu_id[1]);
    } else {
        printf("tyre identifier (%s, %s, %s particles): at the end mu_id_f %.3f (sd %.3f), mu_id_r "
               "%.3f (sd %.3f)\n",
               rfe_tid_filter_str((rfe_tid_filter_t)r->ps.tid[RFE_PK_tid_filter - RFE_PK_TID_FIRST]),
               rfe_tid_resample_str((rfe_tid_resample_t)r->ps.tid[RFE_PK_tid_resample - RFE_PK_TID_FIRST]), RFE_TID_N_TEXT, last->mu_id[0],
               last->sd_mu_id[0], last->mu_id[1], last->sd_mu_id[1]);
    }
    for (s = 0u; s < RFE_REPLAY_STATUS_SLOTS; ++s) {
        if (r->stats.tid_status_count[s] != 0u) {
            const char *name = (s + 1u < RFE_REPLAY_STATUS_SLOTS)
                                   ? rfe_status_str((rfe_status_t)s)
                                   : "other status values";
            printf("  tid status %2zu %-36s %zu\n", s, name, r->stats.tid_status_count[s]);
        }
    }
    printf("  samples updated %zu, resampled %zu, held %zu, first %zu, lost %zu; started afresh "
           "after a period beyond tid_dt_max: %zu\n",
           r->stats.tid_flag_count[0], r->stats.tid_flag_count[1], r->stats.tid_flag_count[2],
           r->stats.tid_flag_count[3], r->stats.tid_flag_count[4], r->stats.tid_restarts);
    if (last->has_tyre_feed != 0) {
        printf("  lateral curve fed to the friction estimator at %zu samples (tid_feed_sd_rel = %g, "
               "tid_feed_evidence = %g s, tid_feed_ax_max = %g m/s^2); its curve at the end cy "
               "%.2f /rad, C %.3f, E %.3f, r_model_rel %.4f\n",
               r->stats.n_tyre_fed, r->ps.tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST],
               r->ps.tid[RFE_PK_tid_feed_evidence - RFE_PK_TID_FIRST],
               r->ps.tid[RFE_PK_tid_feed_ax_max - RFE_PK_TID_FIRST],
               last->cy_used, last->shape_Cy_used, last->shape_Ey_used, last->r_model_rel_used);
    }
}

/* ------------------------------------------------------------ the run in memory */

/* `key = value` lines from memory, read as a parameter file named "params" (its own reader:
 * the same keys, errors and origins). */
static int apply_params_text(rfe_param_set_t *ps, const char *text, rfe_io_error_t *err)
{
    const size_t n = strlen(text);
    char *buf = rfe_xrealloc(NULL, n + 1u, 1u);
    FILE *f;
    int rc = -1;
    memcpy(buf, text, n + 1u);
    f = (n > 0u) ? fmemopen(buf, n, "r") : NULL;
    if (n == 0u) {
        rc = 0; /* no lines: nothing to apply */
    } else if (f == NULL) {
        rfe_io_error_set(err, "params", 0u, 0u, "cannot read: %s", strerror(errno));
    } else {
        rc = rfe_param_set_apply_stream(ps, f, "params", err);
        (void)fclose(f); /* read-only: nothing to lose on close */
    }
    free(buf);
    return rc;
}

/* Starts the replay state of the run's precision in @p state; on an error its message. */
static int open_state(const options_t *o, const run_t *r, rfe_replay_mem_t *m, void *state)
{
    size_t bad = RFE_PK_NONE;
    rfe_status_t st;
    if (m->real == (int)RFE_MEM_Q31) {
        m->q31 = state;
        st = rfe_replay_begin_q31(m->q31, &r->ps, &r->log, r->use_observer, &bad);
    } else if (m->real == (int)RFE_MEM_DOUBLE) {
        m->f64 = state;
        st = rfe_replay_begin_f64(m->f64, &r->ps, &r->log, r->use_observer, &bad);
    } else {
        m->f32 = state;
        st = rfe_replay_begin_f32(m->f32, &r->ps, &r->log, r->use_observer, &bad);
    }
    if (st != RFE_OK) {
        (void)start_error(o, r, st, bad);
        return (int)st;
    }
    return 0;
}

int rfe_mu_replay_open(rfe_replay_mem_t *m, int argc, char **argv, const char *params_text,
                       const rfe_kv_t *meta, size_t n_meta, const rfe_column_t *cols,
                       size_t n_cols, size_t n_rows, void *state, rfe_io_error_t *err)
{
    options_t o;
    run_t r;
    int rc;
    if ((m == NULL) || (argv == NULL) || (cols == NULL) || (state == NULL) || (err == NULL)) {
        return (int)RFE_ERR_NULL;
    }
    memset(m, 0, sizeof *m);
    memset(&o, 0, sizeof o);
    memset(&r, 0, sizeof r);
    o.err_out = err;
    if ((parse_args(argc, argv, &o) != 0) || o.help) {
        if (o.help) {
            rfe_io_error_set(err, NULL, 0u, 0u, "%s", "--help: no run");
        }
        return RFE_MEM_USAGE;
    }
    o.quiet = 1;             /* notes are not errors: nothing printed */
    o.params_text = params_text;
    (void)snprintf(m->name, sizeof m->name, "%s", o.in);
    read_opts(&o, &m->ro);
    rc = rfe_sensor_log_from_columns(m->name, meta, n_meta, cols, n_cols, n_rows, &m->ro, &r.log,
                                     err);
    if (rc != 0) {
        return (rc > 0) ? rc : RFE_MEM_INPUT;
    }
    /* the columns as given, before prepare_log converts them (a later block is compared to
     * them, then converted the same way) */
    m->shape = r.log;
    m->shape.rows = NULL;
    m->shape.n_rows = 0u;
    m->shape.meta = NULL;
    m->shape.n_meta = 0u;
    rc = resolve_params(&o, &r);
    if (rc == 0) {
        rc = check_vehicle(&o, &r);
    }
    if (rc == 0) {
        rc = prepare_log(&o, &r);
    }
    m->real = r.is_q31 ? (int)RFE_MEM_Q31 : (r.is_double ? (int)RFE_MEM_DOUBLE : (int)RFE_MEM_FLOAT);
    rc = (rc == 0) ? open_state(&o, &r, m, state) : RFE_MEM_INPUT;
    if (rc == 0) {
        m->ps = r.ps;
        m->observer = r.use_observer;
        m->mass_grade = r.ps.mass_grade;
        m->tyre_id = r.ps.tyre_id;
        m->tyre_feed = r.ps.tyre_id && (r.ps.tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST] > 0.0);
        m->dt_given = (r.ps.origin[RFE_PK_dt].file != NULL) &&
                      (strcmp(r.ps.origin[RFE_PK_dt].file, "the log's time stamps") != 0);
        m->preset_vehicle = r.preset_vehicle;
        m->ready = 1;
    }
    rfe_sensor_log_free(&r.log);
    return rc;
}
