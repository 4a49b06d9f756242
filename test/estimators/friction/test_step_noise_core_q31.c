/**
 * @file test_step_noise_core_q31.c
 * @brief The fixed-point step noise's internal entry rfe_step_noise_sqrt_core_q31
 *        (src/estimators/friction/step_noise_internal_q31.h; the estimator's: nominal columns
 *        of the wheels an input does not reach reused), against the public
 *        rfe_step_noise_sqrt_q31 and against a reference built here from the public
 *        measurement model exactly as docs/ESTIMATOR.md step 4 writes it (a full evaluation of
 *        h at u, the public input derivative rfe_meas_input_jac_q31), bit for bit, saturation counts
 *        included, in magic, absolute and paper tyre mode. The pieces it is built on are
 *        tested with their modules: test/models/test_tyre_internal_q31.c (the tyre's split),
 *        test/models/test_meas_q31.c (the per-wheel columns and cached terms).
 * Inputs: integer samples from a fixed-seed generator (test_draws_q31.h), over the typical
 * range, the int32 extremes (saturating the kinematics, forces, H and z) and rolling wheels;
 * mu from below 0 to 4. In valgrind's light mode every tenth case (every path is still taken).
 */
#include "test_light.h"
#include "test_common.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rfe/component/step_noise_q31.h"
#include "rfe/fixed.h"
#include "rfe/component/fxmath.h"
#include "rfe/component/meas_q31.h"
#include "rfe/params_q31.h"
#include "rfe/component/qr_q31.h"

#include "estimators/friction/step_noise_internal_q31.h"
#include "test_draws_q31.h"

#define N_CASES 20000

static rfe_params_q31_t preset(void)
{
    rfe_params_q31_t p;
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    return p;
}

/* ---- the step noise: reference from the public measurement model ------------------------- */

static rfe_status_t ref_h(const rfe_params_q31_t *p, const rfe_sample_q31_t *u,
                          const rfe_fix_t mu[4], rfe_fix_t z[3], uint32_t *count)
{
    rfe_meas_q31_t h;
    rfe_status_t st = rfe_meas_setup_q31(&h, &p->vehicle, &p->tyre, u, count);
    if (st == RFE_OK) {
        st = rfe_meas_eval_q31(&h, &p->vehicle, &p->tyre, mu, z, count);
    }
    return st;
}

/* v^2 exactly (a Q24 value's square in Q48, RFE_MON_Q31_QP) */
static uint64_t sq48(rfe_fix_t v)
{
    const uint64_t m = (uint64_t)llabs((long long)v);
    return m * m;
}

/* docs/ESTIMATOR.md step 4 as written: S_R = Tria([S_R0, g_1 ..]), h0 a full evaluation
 * (set-up and eval) of the public measurement model, g_j its public input derivative. */
static rfe_status_t ref_step_noise(const rfe_params_q31_t *p, const rfe_sample_q31_t *u,
                            const rfe_fix_t mu[4], rfe_fix_t SR[9], uint32_t *sat,
                            uint64_t pers[3])
{
    const rfe_filter_params_q31_t *fp = &p->filter;
    const rfe_fix_t sd[8] = {fp->sd_in_delta, fp->sd_in_vx,    fp->sd_in_vy,
                             fp->sd_in_yaw_rate, fp->sd_in_omega, fp->sd_in_omega,
                             fp->sd_in_omega, fp->sd_in_omega};
    const rfe_fix_t r[3] = {fp->r_ax, fp->r_ay, fp->r_yaw_acc};
    rfe_fix_t A[3 * 11];
    rfe_fix_t h0[3];
    size_t cols = 3u;
    uint32_t count = 0u;
    size_t i;
    size_t j;
    rfe_status_t st = ref_h(p, u, mu, h0, &count);
    if (st != RFE_OK) {
        return st;
    }
    memset(A, 0, sizeof(A));
    for (i = 0; i < 3; ++i) {
        rfe_fix_t v[2];
        v[0] = r[i];
        v[1] = rfe_fix_mul(fp->r_model_rel, rfe_fix_abs(h0[i], &count), RFE_FIX_Q_SD, &count);
        assert_int_equal(rfe_fix_norm(v, 2u, &A[i * 11u + i], &count), RFE_OK);
        pers[i] = sq48(v[1]); /* e^2, exact in Q48 */
    }
    /* g_j = sd_j dh/du_j (docs/ESTIMATOR.md step 4) from the public derivative on a set-up
     * of its own, whose saturations ref_h counted already (rfe_meas_input_jac_q31 is tested
     * against the double build in test_meas_q31.c) */
    {
        rfe_meas_q31_t hs;
        rfe_fix_t G[3 * 8];
        uint32_t scratch = 0u;
        st = rfe_meas_setup_q31(&hs, &p->vehicle, &p->tyre, u, &scratch);
        if (st == RFE_OK) {
            st = rfe_meas_input_jac_q31(&hs, &p->vehicle, &p->tyre, u, mu, sd, G, &count);
        }
        if (st != RFE_OK) {
            return st;
        }
        for (j = 0; j < 8; ++j) {
            if (sd[j] <= 0) {
                continue;
            }
            for (i = 0; i < 3; ++i) {
                A[i * 11u + cols] = G[i * 8u + j];
                if ((j == 1u) || (j == 2u)) { /* vx, vy: the low-passed inputs */
                    pers[i] += sq48(A[i * 11u + cols]);
                }
            }
            ++cols;
        }
    }
    st = rfe_qr_tria_q31(A, 3u, cols, 11u, &count);
    if (st != RFE_OK) {
        return st;
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            SR[i * 3u + j] = (j <= i) ? A[i * 11u + j] : 0;
        }
    }
    *sat += count;
    return RFE_OK;
}

/* REQ: the estimator's step-noise entry (the set-up model reused, only the wheels an input
 * reaches evaluated again) gives the S_R and count of the public function and of the
 * reference (a full evaluation of h0, the public input derivative), in magic, absolute and paper tyre
 * mode, with every input switched on or off; asked for the persistent diagonal, the same
 * S_R, and the diagonal within its bound of the reference's. */
/* REQ-FXP-007 REQ-FXP-008 REQ-MON-011 */
static void test_step_noise_core_q31(void **state)
{
    int n;
    long checked = 0;
    long pers_checked = 0;
    long with_sat = 0;
    (void)state;
    draw_seed(0xE1F5EEDull);
    for (n = 0; n < N_CASES; n += (int)rfe_test_stride(10u)) {
        rfe_params_q31_t p = preset();
        rfe_sample_q31_t u;
        rfe_fix_t mu[4];
        rfe_meas_q31_t h;
        rfe_fix_t S1[9];
        rfe_fix_t S2[9];
        rfe_fix_t S3[9];
        rfe_fix_t S4[9];
        uint64_t pers[3];
        uint64_t pref[3];
        uint32_t s4 = 3u;
        uint32_t s1 = 3u;
        uint32_t s2 = 3u;
        uint32_t s3 = 3u;
        uint32_t scratch = 0u;
        rfe_status_t e1;
        rfe_status_t e2;
        if ((n % 3) == 1) {
            draw_tyre_q31(&p.tyre);
        }
        if ((n % 5) == 2) {
            p.filter.sd_in_delta = (int32_t)(draw_u64() % (1u << 26));
            p.filter.sd_in_vx = (int32_t)(draw_u64() % (1u << 26));
            p.filter.sd_in_omega = (int32_t)(draw_u64() % (1u << 26));
            p.filter.sd_in_vy = ((n % 2) == 0) ? 0 : p.filter.sd_in_vy;
            p.filter.sd_in_yaw_rate = ((n % 4) == 3) ? 0 : p.filter.sd_in_yaw_rate;
        }
        if ((n % 7) == 3) {
            p.tyre.mode = RFE_TYRE_PAPER;
        }
        if ((n % 7) == 5) {
            p.tyre.mode = RFE_TYRE_ABSOLUTE;
        }
        draw_sample_q31(&p, &u, mu, n);
        if (rfe_params_validate_q31(&p) != RFE_OK) {
            continue;
        }
        e1 = rfe_step_noise_sqrt_q31(&p, &u, mu, S1, &s1);
        e2 = ref_step_noise(&p, &u, mu, S2, &s2, pref);
        assert_int_equal(e1, e2);
        if (e1 != RFE_OK) {
            continue;
        }
        assert_memory_equal(S1, S2, sizeof(S1));
        assert_int_equal(s1, s2);
        assert_int_equal(rfe_meas_setup_q31(&h, &p.vehicle, &p.tyre, &u, &scratch), RFE_OK);
        assert_int_equal(rfe_step_noise_sqrt_core_q31(&p, &h, &u, mu, S3, NULL, &s3), RFE_OK);
        assert_memory_equal(S3, S2, sizeof(S3));
        assert_int_equal(s3, s2);
        /* with the persistent diagonal (Q48, issue 21): the same S_R and no saturation added
         * (whatever the columns' size), each entry within its derived bound of the exact
         * e^2 + g_vx^2 + g_vy^2: the squares are exact, and e^2 read back as A_ii^2 - r^2,
         * A_ii = sqrt(r^2 + e^2) + d with |d| <= 1/2, is off by |2 d sqrt(r^2 + e^2) + d^2|
         * <= A_ii + 3/4 LSB^2, an integer, so <= A_ii */
        assert_int_equal(rfe_step_noise_sqrt_core_q31(&p, &h, &u, mu, S4, pers, &s4), RFE_OK);
        assert_memory_equal(S4, S3, sizeof(S4));
        assert_int_equal(s4, s3);
        {
            size_t i;
            for (i = 0; i < 3; ++i) {
                /* A_ii <= the row norm of A, which the Tria keeps: that of S_R's row i */
                const double row = sqrt(((double)S2[i * 3u] * S2[i * 3u]) +
                                        ((double)S2[i * 3u + 1u] * S2[i * 3u + 1u]) +
                                        ((double)S2[i * 3u + 2u] * S2[i * 3u + 2u]));
                const uint64_t diff = (pers[i] > pref[i]) ? (pers[i] - pref[i])
                                                          : (pref[i] - pers[i]);
                ASSERT_LE((double)diff, floor(row + 1.0), "persistent diagonal");
            }
            ++pers_checked;
        }
        ++checked;
        with_sat += (s1 != 3u) ? 1 : 0;
    }
    printf("step noise: %ld cases bit for bit (%ld with saturations); persistent diagonal "
           "within its bound on %ld\n", checked, with_sat, pers_checked);
    assert_true(checked > 1000);
    assert_true(pers_checked > 1000);
    assert_true(with_sat > 10);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_step_noise_core_q31),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
