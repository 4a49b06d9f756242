/**
 * @file test_param_file.c
 * @brief Tests of the parameter set: presets, parameter files, log metadata, precedence.
 *
 * Run from the repository root (fixtures under test/host/data/). In a parameter file the
 * COL of an error is the character position of the offending key or value. The sets start
 * from the paper preset, whose values are fixed (the default preset may change between
 * library versions; test_replay checks both against the library).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "csv_log.h"
#include "param_file.h"
#include "replay_real.h"

#define DATA "test/host/data/"

/* Applies @p text as a parameter file through a temporary stream. */
static int apply_text(rfe_param_set_t *ps, const char *text, rfe_io_error_t *err)
{
    FILE *f = tmpfile();
    int rc;
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1u, strlen(text), f), strlen(text));
    rewind(f);
    rc = rfe_param_set_apply_stream(ps, f, "mem.par", err);
    fclose(f);
    return rc;
}

/* The parameter set of the paper preset (double library). */
static void paper_set(rfe_param_set_t *ps)
{
    assert_int_equal(rfe_param_set_preset_f64(ps, RFE_PRESET_PAPER), 0);
}

/* REQ-PARF-001 REQ-PARAMS-001 */
static void test_rfe_param_set_paper_values(void **state)
{
    rfe_param_set_t ps;
    (void)state;
    paper_set(&ps);
    assert_int_equal(ps.preset, RFE_PRESET_PAPER);
    /* MODEL.md §2 / DATA.md paper values, spot-checked in every group. */
    assert_true(ps.value[RFE_PK_m] == 1830.0);
    assert_true(ps.value[RFE_PK_Lr] == 1.65);
    assert_true(ps.value[RFE_PK_hg] == 0.54);
    assert_true(ps.value[RFE_PK_Cy_n] == 15.0);
    assert_true(ps.value[RFE_PK_eps] == 0.015);
    assert_true(ps.value[RFE_PK_alpha_max] == 1.4);
    assert_true(ps.value[RFE_PK_q_mu] == 0.003);
    assert_true(ps.value[RFE_PK_mu_max] == 1.2);
    assert_true(ps.value[RFE_PK_v_est_min] == 3.0);
    assert_int_equal(ps.tyre, RFE_TYRE_PAPER);
    assert_int_equal(ps.filter, RFE_FILTER_SCKF);
    assert_int_equal(ps.structure, RFE_STRUCT_WHEELS);
    /* docs/ESTIMATOR.md: every addition off in the paper preset. */
    assert_true(ps.value[RFE_PK_sd0_common] == 0.0 && ps.value[RFE_PK_q_common] == 0.0);
    assert_true(ps.value[RFE_PK_tau_v] == 0.0 && ps.value[RFE_PK_info_min] == 0.0);
    assert_true(ps.value[RFE_PK_sd_max] == 0.0 && ps.value[RFE_PK_sd_valid] == 0.0);
    assert_true(ps.value[RFE_PK_dt] == 0.01);
    assert_null(ps.origin[RFE_PK_m].file);
}

/* REQ-PARF-001 */
static void test_rfe_param_find_every_table_key(void **state)
{
    size_t k;
    (void)state;
    for (k = 0u; k < (size_t)RFE_PK_COUNT; ++k) {
        const rfe_param_info_t *info = rfe_param_info(k);
        assert_non_null(info);
        assert_int_equal(rfe_param_find(info->key), k);
        assert_true(strlen(info->unit) > 0u);
        assert_true(strlen(info->doc) > 0u);
    }
    assert_int_equal(rfe_param_find("tyre"), RFE_PK_TYRE);
    assert_int_equal(rfe_param_find("filter"), RFE_PK_FILTER);
    assert_int_equal(rfe_param_find("structure"), RFE_PK_STRUCTURE);
    assert_int_equal(rfe_param_find("sd_floor_rel"), RFE_PK_sd_floor_rel);
    assert_int_equal(rfe_param_find("mass"), RFE_PK_NONE);
    assert_null(rfe_param_info(RFE_PK_NONE));
}

/* REQ-PARF-001 */
static void test_rfe_param_set_apply_file_valid(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(rfe_param_set_apply_file(&ps, DATA "params_good.par", &err), 0);
    assert_true(ps.value[RFE_PK_m] == 1500.0); /* inline comment stripped */
    assert_true(ps.value[RFE_PK_Lf] == 1.2);   /* no blanks around '=' */
    assert_true(ps.value[RFE_PK_mu0] == 0.7);
    assert_true(ps.value[RFE_PK_Lr] == 1.65);  /* untouched */
    assert_int_equal(ps.tyre, RFE_TYRE_ABSOLUTE);
    assert_int_equal(ps.filter, RFE_FILTER_CKF);
    assert_string_equal(ps.origin[RFE_PK_m].file, DATA "params_good.par");
    assert_int_equal(ps.origin[RFE_PK_m].line, 2);
    assert_int_equal(ps.origin[RFE_PK_TYRE].line, 5);
    assert_null(ps.origin[RFE_PK_Lr].file);
}

/* REQ-PARF-003 */
static void test_rfe_param_set_apply_file_unknown_key(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(rfe_param_set_apply_file(&ps, DATA "params_unknown_key.par", &err), -1);
    assert_string_equal(err.file, DATA "params_unknown_key.par");
    assert_int_equal(err.line, 3);
    assert_int_equal(err.col, 1);
    assert_non_null(strstr(err.msg, "unknown parameter key 'mass'"));
}

/* REQ-PARF-003 */
static void test_rfe_param_set_apply_file_case_typo_hint(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(apply_text(&ps, "\n   lf = 1.3\n", &err), -1);
    assert_int_equal(err.line, 2);
    assert_int_equal(err.col, 4);
    assert_non_null(strstr(err.msg, "did you mean 'Lf'?"));
}

/* REQ-PARF-003 */
static void test_rfe_param_set_apply_file_bad_number_position(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(rfe_param_set_apply_file(&ps, DATA "params_bad_number.par", &err), -1);
    assert_int_equal(err.line, 3);
    assert_int_equal(err.col, 7); /* "Lr =  1,65": the value starts at character 7 */
    assert_non_null(strstr(err.msg, "value of 'Lr'"));
    assert_non_null(strstr(err.msg, "'1,65'"));
}

/* REQ-PARF-003 */
static void test_rfe_param_set_apply_file_missing_equals(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(rfe_param_set_apply_file(&ps, DATA "params_no_equals.par", &err), -1);
    assert_int_equal(err.line, 2);
    assert_int_equal(err.col, 1);
    assert_non_null(strstr(err.msg, "expected 'key = value'"));
}

/* REQ-PARF-003 */
static void test_rfe_param_set_apply_file_missing_key(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(apply_text(&ps, "  = 3\n", &err), -1);
    assert_int_equal(err.line, 1);
    assert_int_equal(err.col, 3);
    assert_non_null(strstr(err.msg, "missing key"));
}

/* REQ-PARF-003 */
static void test_rfe_param_set_apply_file_duplicate_key(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(rfe_param_set_apply_file(&ps, DATA "params_duplicate.par", &err), -1);
    assert_int_equal(err.line, 3);
    assert_non_null(strstr(err.msg, "'m' given twice (first at line 1)"));
}

/* REQ-PARF-003 */
static void test_rfe_param_set_apply_file_nan_value(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(rfe_param_set_apply_file(&ps, DATA "params_nan.par", &err), -1);
    assert_int_equal(err.line, 1);
    assert_int_equal(err.col, 8);
    assert_non_null(strstr(err.msg, "finite"));
    assert_true(ps.value[RFE_PK_q_mu] == 0.003); /* unchanged */
}

/* REQ-PARF-003 */
static void test_rfe_param_set_apply_file_empty_value(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(apply_text(&ps, "m =   # nothing\n", &err), -1);
    assert_int_equal(err.col, 4);
    assert_non_null(strstr(err.msg, "empty field"));
}

/* REQ-PARF-003 */
static void test_rfe_param_set_apply_file_bad_word(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(rfe_param_set_apply_file(&ps, DATA "params_bad_word.par", &err), -1);
    assert_int_equal(err.line, 1);
    assert_int_equal(err.col, 8);
    assert_non_null(strstr(err.msg, "'pacejka'"));
    assert_int_equal(ps.tyre, RFE_TYRE_PAPER);
}

/* REQ-PARF-003 */
static void test_rfe_param_set_apply_file_nonexistent(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(rfe_param_set_apply_file(&ps, DATA "nope.par", &err), -1);
    assert_int_equal(err.line, 0);
    assert_non_null(strstr(err.msg, "cannot open"));
}

/* REQ-PARF-003 */
static void test_rfe_param_set_apply_file_directory_is_read_error(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(rfe_param_set_apply_file(&ps, DATA, &err), -1);
    assert_int_equal(err.line, 1);
    assert_non_null(strstr(err.msg, "read error"));
}

/* REQ-PARF-003 */
static void test_rfe_param_set_apply_stream_nul_byte(void **state)
{
    static const char text[] = "m = 1\nLf = 1\0.2\n";
    rfe_param_set_t ps;
    rfe_io_error_t err;
    FILE *f = tmpfile();
    (void)state;
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1u, sizeof text - 1u, f), sizeof text - 1u);
    rewind(f);
    paper_set(&ps);
    assert_int_equal(rfe_param_set_apply_stream(&ps, f, "nul.par", &err), -1);
    fclose(f);
    assert_int_equal(err.line, 2);
    assert_non_null(strstr(err.msg, "NUL"));
}

/* REQ-PARF-002 */
static void test_rfe_param_set_apply_meta_known_keys_only(void **state)
{
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "good_small.csv", &log, &err), 0);
    paper_set(&ps);
    /* scenario and description are information: ignored, no error. */
    assert_int_equal(rfe_param_set_apply_meta(&ps, &log, "good_small.csv", &err), 0);
    assert_true(ps.value[RFE_PK_mu0] == 0.6);
    assert_int_equal(ps.tyre, RFE_TYRE_ABSOLUTE);
    assert_string_equal(ps.origin[RFE_PK_mu0].file, "good_small.csv");
    assert_int_equal(ps.origin[RFE_PK_mu0].line, 5);
    rfe_sensor_log_free(&log);
}

/* REQ-PARF-002 REQ-PARF-003 */
static void test_rfe_param_set_apply_meta_malformed_known_key(void **state)
{
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "bad_meta.csv", &log, &err), 0);
    paper_set(&ps);
    assert_int_equal(rfe_param_set_apply_meta(&ps, &log, "bad_meta.csv", &err), -1);
    assert_string_equal(err.file, "bad_meta.csv");
    assert_int_equal(err.line, 2);
    assert_non_null(strstr(err.msg, "metadata 'm'"));
    assert_non_null(strstr(err.msg, "'heavy'"));
    rfe_sensor_log_free(&log);
}

/* REQ-PARF-002 */
static void test_rfe_param_set_precedence_file_over_metadata(void **state)
{
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "good_small.csv", &log, &err), 0);
    paper_set(&ps);
    assert_int_equal(rfe_param_set_apply_meta(&ps, &log, "good_small.csv", &err), 0);
    assert_int_equal(apply_text(&ps, "mu0 = 0.55\n", &err), 0);
    assert_true(ps.value[RFE_PK_mu0] == 0.55);        /* file beats metadata */
    assert_int_equal(ps.tyre, RFE_TYRE_ABSOLUTE);      /* metadata beats default */
    assert_true(ps.value[RFE_PK_m] == 1830.0);         /* default where nobody spoke */
    assert_string_equal(ps.origin[RFE_PK_mu0].file, "mem.par");
    rfe_sensor_log_free(&log);
}

/* REQ-PARF-001 */
static void test_rfe_param_format_numbers_and_words(void **state)
{
    rfe_param_set_t ps;
    char buf[RFE_NUM_BUF];
    (void)state;
    paper_set(&ps);
    rfe_param_format(&ps, RFE_PK_q_mu, buf);
    assert_string_equal(buf, "0.003");
    ps.filter = RFE_FILTER_CKF;
    rfe_param_format(&ps, RFE_PK_FILTER, buf);
    assert_string_equal(buf, "ckf");
    rfe_param_format(&ps, RFE_PK_TYRE, buf);
    assert_string_equal(buf, "paper");
    rfe_param_format(&ps, RFE_PK_STRUCTURE, buf);
    assert_string_equal(buf, "wheels");
}

/* REQ-PARF-003 */
static void test_rfe_param_set_text_rejects_out_of_range_key(void **state)
{
    rfe_param_set_t ps;
    (void)state;
    paper_set(&ps);
    assert_int_equal(rfe_param_set_text(&ps, RFE_PK_NONE, "1"), RFE_NUM_SYNTAX);
    assert_int_equal(rfe_param_set_text(&ps, RFE_PK_FILTER, "ekf"), RFE_NUM_SYNTAX);
    assert_int_equal(rfe_param_set_text(&ps, RFE_PK_FILTER, "ckf"), RFE_NUM_OK);
    assert_int_equal(ps.filter, RFE_FILTER_CKF);
    assert_int_equal(rfe_param_set_text(&ps, RFE_PK_STRUCTURE, "axles"), RFE_NUM_SYNTAX);
    assert_int_equal(rfe_param_set_text(&ps, RFE_PK_STRUCTURE, "sides"), RFE_NUM_OK);
    assert_int_equal(ps.structure, RFE_STRUCT_SIDES);
}

/* REQ-PARF-001 */
static void test_rfe_enum_words_round_trip(void **state)
{
    rfe_tyre_mode_t t = RFE_TYRE_PAPER;
    rfe_filter_kind_t f = RFE_FILTER_SCKF;
    (void)state;
    assert_int_equal(rfe_tyre_mode_parse("absolute", &t), 0);
    assert_string_equal(rfe_tyre_mode_str(t), "absolute");
    assert_int_equal(rfe_tyre_mode_parse("magic", &t), 0);
    assert_int_equal(t, RFE_TYRE_MAGIC);
    assert_string_equal(rfe_tyre_mode_str(t), "magic");
    assert_int_equal(rfe_tyre_mode_parse("paper", &t), 0);
    assert_int_equal(t, RFE_TYRE_PAPER);
    assert_int_equal(rfe_tyre_mode_parse("Paper", &t), -1); /* words are case-sensitive */
    assert_int_equal(rfe_filter_kind_parse("ckf", &f), 0);
    assert_string_equal(rfe_filter_kind_str(f), "ckf");
    assert_string_equal(rfe_filter_kind_str((rfe_filter_kind_t)7), "?");
    assert_string_equal(rfe_tyre_mode_str((rfe_tyre_mode_t)7), "?");
}

/* REQ-PARF-001 */
static void test_rfe_structure_words_round_trip(void **state)
{
    rfe_structure_t s = RFE_STRUCT_WHEELS;
    (void)state;
    assert_int_equal(rfe_structure_parse("sides", &s), 0);
    assert_int_equal(s, RFE_STRUCT_SIDES);
    assert_string_equal(rfe_structure_str(s), "sides");
    assert_int_equal(rfe_structure_parse("wheels", &s), 0);
    assert_int_equal(s, RFE_STRUCT_WHEELS);
    assert_string_equal(rfe_structure_str(s), "wheels");
    assert_int_equal(rfe_structure_parse("Sides", &s), -1); /* case-sensitive */
    assert_int_equal(s, RFE_STRUCT_WHEELS);                 /* untouched on failure */
    assert_string_equal(rfe_structure_str((rfe_structure_t)7), "?");
}

/* REQ-PARF-001 */
static void test_rfe_preset_words_round_trip(void **state)
{
    rfe_preset_t p = RFE_PRESET_DEFAULT;
    (void)state;
    assert_int_equal(rfe_preset_parse("paper", &p), 0);
    assert_int_equal(p, RFE_PRESET_PAPER);
    assert_string_equal(rfe_preset_str(p), "paper");
    assert_int_equal(rfe_preset_parse("default", &p), 0);
    assert_int_equal(p, RFE_PRESET_DEFAULT);
    assert_string_equal(rfe_preset_str(p), "default");
    assert_int_equal(rfe_preset_parse("Paper", &p), -1); /* case-sensitive */
    assert_int_equal(rfe_preset_parse("", &p), -1);
    assert_int_equal(p, RFE_PRESET_DEFAULT);             /* untouched on failure */
    assert_string_equal(rfe_preset_str((rfe_preset_t)7), "?");
}

/* "preset" is a command-line choice, not a parameter key: unknown in a parameter file. */
/* REQ-PARF-003 */
static void test_rfe_param_set_apply_file_preset_is_not_a_key(void **state)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    (void)state;
    paper_set(&ps);
    assert_int_equal(rfe_param_find("preset"), RFE_PK_NONE);
    assert_int_equal(apply_text(&ps, "preset = paper\n", &err), -1);
    assert_non_null(strstr(err.msg, "unknown parameter key 'preset'"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_param_set_paper_values),
        cmocka_unit_test(test_rfe_param_find_every_table_key),
        cmocka_unit_test(test_rfe_param_set_apply_file_valid),
        cmocka_unit_test(test_rfe_param_set_apply_file_unknown_key),
        cmocka_unit_test(test_rfe_param_set_apply_file_case_typo_hint),
        cmocka_unit_test(test_rfe_param_set_apply_file_bad_number_position),
        cmocka_unit_test(test_rfe_param_set_apply_file_missing_equals),
        cmocka_unit_test(test_rfe_param_set_apply_file_missing_key),
        cmocka_unit_test(test_rfe_param_set_apply_file_duplicate_key),
        cmocka_unit_test(test_rfe_param_set_apply_file_nan_value),
        cmocka_unit_test(test_rfe_param_set_apply_file_empty_value),
        cmocka_unit_test(test_rfe_param_set_apply_file_bad_word),
        cmocka_unit_test(test_rfe_param_set_apply_file_nonexistent),
        cmocka_unit_test(test_rfe_param_set_apply_file_directory_is_read_error),
        cmocka_unit_test(test_rfe_param_set_apply_stream_nul_byte),
        cmocka_unit_test(test_rfe_param_set_apply_meta_known_keys_only),
        cmocka_unit_test(test_rfe_param_set_apply_meta_malformed_known_key),
        cmocka_unit_test(test_rfe_param_set_precedence_file_over_metadata),
        cmocka_unit_test(test_rfe_param_format_numbers_and_words),
        cmocka_unit_test(test_rfe_param_set_text_rejects_out_of_range_key),
        cmocka_unit_test(test_rfe_enum_words_round_trip),
        cmocka_unit_test(test_rfe_structure_words_round_trip),
        cmocka_unit_test(test_rfe_preset_words_round_trip),
        cmocka_unit_test(test_rfe_param_set_apply_file_preset_is_not_a_key),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
