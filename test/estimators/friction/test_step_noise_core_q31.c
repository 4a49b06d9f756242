/**
 * @file test_step_noise_core_q31.c
 * @brief The internal pieces behind the cheaper fixed-point step (src/models/tyre_internal_q31.h,
 *        src/models/meas_internal_q31.h, src/estimators/friction/step_noise_internal_q31.h) against the public functions they
 *        replace, bit for bit, saturation counts included:
 *  - one wheel's kinematics, kappa alone, and the load-scaled tyre evaluation (absolute
 *    Dugoff and Magic Formula) split into its friction-independent part and the rest, against
 *    rfe_tyre_kinematics_q31, rfe_tyre_dugoff_abs_q31 and rfe_tyre_magic_abs_q31;
 *  - one wheel's column of H and the exact column sums, against rfe_obsmat_build_q31 and
 *    rfe_obsmat_apply_q31(H, ones) (the load-scaled chain of rfe_meas_eval_q31, absolute and
 *    magic mode), also when eval is given other tyre parameters than the set-up (other
 *    stiffness, eps or alpha_max: the cached terms are then not used; another load-scaled
 *    mode or other shape factors: the cached terms, which do not depend on them, are used);
 *  - the step noise's internal entry rfe_step_noise_sqrt_core_q31 (the estimator's: nominal
 *    columns of the wheels an input does not reach reused), against the public
 *    rfe_step_noise_sqrt_q31 and against a reference built here from the public measurement
 *    model exactly as docs/ESTIMATOR.md step 4 writes it (a full evaluation of h at u and at
 *    u +- sd_j e_j for every input), in magic, absolute and paper tyre mode.
 * Inputs: integer samples from a fixed-seed generator (test_draws_q31.h), over the typical range, the int32
 * extremes (saturating the kinematics, forces, H and z) and rolling wheels; mu from below 0
 * to 4. In valgrind's light mode every tenth case (every path is still taken).
 */
#include "test_light.h"
#include "test_common.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "rfe/component/step_noise_q31.h"
#include "rfe/fixed.h"
#include "rfe/component/fxmath.h"
#include "rfe/component/meas_q31.h"
#include "rfe/component/obsmat_q31.h"
#include "rfe/params_q31.h"
#include "rfe/component/qr_q31.h"
#include "rfe/component/tyre_q31.h"

#include "estimators/friction/step_noise_internal_q31.h"
#include "models/tyre_internal_q31.h"
#include "test_draws_q31.h"

#define N_CASES 20000

static rfe_params_q31_t preset(void)
{
    rfe_params_q31_t p;
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    return p;
}

/* REQ: one wheel's kinematics and the split Dugoff and Magic Formula evaluations are
 * rfe_tyre_kinematics_q31's, rfe_tyre_dugoff_abs_q31's and rfe_tyre_magic_abs_q31's bits and
 * counts. */
/* REQ-FXP-007 REQ-FXP-008 */
static void test_tyre_internal_q31(void **state)
{
    rfe_params_q31_t p = preset();
    int n;
    (void)state;
    draw_seed(0x7E1EC0DEull);
    for (n = 0; n < N_CASES; n += (int)rfe_test_stride(10u)) {
        rfe_sample_q31_t u;
        rfe_fix_t mu[4];
        rfe_wheel_kin_q31_t kin;
        rfe_wheel_kin_q31_t kin_ex;
        rfe_tyre_kin_extra_q31_t extra;
        rfe_fix_t s = 0;
        rfe_fix_t c = 0;
        uint32_t sat = 0u;
        uint32_t sum = 0u;
        size_t i;
        p = preset();
        if ((n % 3) == 1) {
            draw_tyre_q31(&p.tyre);
        }
        draw_sample_q31(&p, &u, mu, n);
        assert_int_equal(rfe_tyre_kinematics_q31(&p.vehicle, &p.tyre, &u, &kin, &sat), RFE_OK);
        assert_int_equal(rfe_tyre_kinematics_ex_q31(&p.vehicle, &p.tyre, &u, &kin_ex, &extra),
                         RFE_OK);
        assert_memory_equal(&kin, &kin_ex, sizeof(kin));
        assert_int_equal(rfe_fix_sincos(u.delta, &s, &c), RFE_OK);
        assert_int_equal(extra.cos_delta, c);
        assert_int_equal(extra.sin_delta, s);
        for (i = 0; i < 4; ++i) {
            rfe_fix_t vwx = 0;
            rfe_fix_t alpha = 0;
            rfe_fix_t kappa = 0;
            rfe_fix_t fx = 0;
            rfe_fix_t fy = 0;
            rfe_fix_t gx = 0;
            rfe_fix_t gy = 0;
            uint32_t cw = 0u;
            uint32_t c1 = 0u;
            uint32_t c2 = 0u;
            rfe_dugoff_pre_q31_t pre;
            rfe_dugoff_pre_q31_t pre_t;
            sum += extra.sat_vwx[i] + extra.sat_fz[i];
            rfe_tyre_wheel_kin_q31(&p.vehicle, &p.tyre, &u, c, s, i, &vwx, &alpha, &kappa, &cw);
            assert_int_equal(vwx, kin.vwx[i]);
            assert_int_equal(alpha, kin.alpha[i]);
            assert_int_equal(kappa, kin.kappa[i]);
            assert_int_equal(cw, extra.sat_vwx[i]);
            assert_int_equal(rfe_tyre_wheel_kappa_q31(&p.vehicle, &p.tyre, &u, c, s, i),
                             kin.kappa[i]);
            assert_int_equal(rfe_tyre_dugoff_abs_q31(&p.tyre, kin.kappa[i], kin.alpha[i],
                                                     kin.fz[i], kin.vwx[i], mu[i], &fx, &fy,
                                                     &c1),
                             RFE_OK);
            rfe_tyre_dugoff_pre_q31(&p.tyre, kin.kappa[i], kin.alpha[i], kin.vwx[i], &pre);
            rfe_tyre_dugoff_mu_q31(&pre, mu[i], kin.fz[i], &gx, &gy, &c2);
            assert_int_equal(gx, fx);
            assert_int_equal(gy, fy);
            assert_int_equal(c2, c1);
            rfe_tyre_dugoff_pre_tan_q31(&p.tyre, kin.kappa[i], pre.tan_a, kin.vwx[i], &pre_t);
            assert_memory_equal(&pre_t, &pre, sizeof(pre));
            /* the Magic Formula on the same terms */
            c1 = c2 = 0u;
            assert_int_equal(rfe_tyre_magic_abs_q31(&p.tyre, kin.kappa[i], kin.alpha[i],
                                                    kin.fz[i], kin.vwx[i], mu[i], &fx, &fy,
                                                    &c1),
                             RFE_OK);
            rfe_tyre_magic_mu_q31(&p.tyre, &pre, mu[i], kin.fz[i], &gx, &gy, &c2);
            assert_int_equal(gx, fx);
            assert_int_equal(gy, fy);
            assert_int_equal(c2, c1);
        }
        assert_int_equal(sum, sat);
    }
    {
        rfe_tyre_params_q31_t bad = p.tyre;
        assert_int_equal(rfe_tyre_dugoff_params_ok_q31(&p.tyre), 1);
        bad.shape_Cx = 0; /* the Dugoff check does not look at the shape */
        assert_int_equal(rfe_tyre_dugoff_params_ok_q31(&bad), 1);
        bad = p.tyre;
        bad.eps = -1;
        assert_int_equal(rfe_tyre_dugoff_params_ok_q31(&bad), 0);
        bad = p.tyre;
        bad.alpha_max = 0;
        assert_int_equal(rfe_tyre_dugoff_params_ok_q31(&bad), 0);
        bad = p.tyre;
        bad.v_min = 0;
        {
            rfe_wheel_kin_q31_t kin;
            rfe_tyre_kin_extra_q31_t extra;
            rfe_sample_q31_t u;
            memset(&u, 0, sizeof(u));
            assert_int_equal(rfe_tyre_kinematics_ex_q31(&p.vehicle, &bad, &u, &kin, &extra),
                             RFE_ERR_PARAM);
        }
    }
}

/* The load-scaled chain of the public functions at tyre parameters tp (the curve of tp's
 * mode): z and its count. */
static uint32_t chain(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                      const rfe_tyre_params_q31_t *tp, const rfe_fix_t mu[4], rfe_fix_t z[3])
{
    static const rfe_fix_t ones[4] = {1 << 29, 1 << 29, 1 << 29, 1 << 29};
    rfe_fix_t fx[4];
    rfe_fix_t fy[4];
    rfe_fix_t H[12];
    uint32_t count = 0u;
    assert_int_equal(rfe_tyre_forces_abs_q31(tp, &h->kin, mu, fx, fy, &count), RFE_OK);
    assert_int_equal(rfe_obsmat_build_q31(veh, h->delta, fx, fy, H, &count), RFE_OK);
    assert_int_equal(rfe_obsmat_apply_q31(H, ones, z, &count), RFE_OK);
    return count;
}

/* REQ: the per-wheel columns and their sums are the load-scaled chain (forces, H, H ones) bit
 * for bit with the same count, in magic and absolute mode; eval with other tyre parameters
 * than the set-up's (stiffness, eps, alpha_max, the other load-scaled mode, other shape
 * factors) gives that chain at the other parameters. */
/* REQ-FXP-007 REQ-FXP-008 */
static void test_meas_columns_q31(void **state)
{
    int n;
    long with_sat = 0;
    (void)state;
    draw_seed(0xC01C01ull);
    for (n = 0; n < N_CASES; n += (int)rfe_test_stride(10u)) {
        rfe_params_q31_t p = preset();
        rfe_tyre_params_q31_t other;
        rfe_sample_q31_t u;
        rfe_fix_t mu[4];
        rfe_meas_q31_t h;
        rfe_meas_terms_q31_t nom;
        rfe_fix_t z[3];
        rfe_fix_t zc[3];
        uint32_t sat = 0u;
        uint32_t cnt = 0u;
        uint32_t kin_cnt;
        size_t i;
        if ((n % 3) == 1) {
            draw_tyre_q31(&p.tyre);
        }
        if ((n % 5) == 2) {
            p.tyre.mode = RFE_TYRE_ABSOLUTE;
        }
        draw_sample_q31(&p, &u, mu, n);
        assert_int_equal(rfe_meas_setup_q31(&h, &p.vehicle, &p.tyre, &u, &sat), RFE_OK);
        /* the nominal terms and their sum: the chain's z; the count is the chain's plus the
         * set-up's kinematics counts, which each wheel's terms carry */
        assert_int_equal(rfe_meas_nominal_q31(&h, &p.vehicle, &p.tyre, mu, &nom, z, &cnt),
                         RFE_OK);
        kin_cnt = 0u;
        for (i = 0; i < 4; ++i) {
            kin_cnt += h.sat_vwx[i] + h.sat_fz[i];
        }
        assert_int_equal(chain(&h, &p.vehicle, &p.tyre, mu, zc) + kin_cnt, cnt);
        cnt -= kin_cnt;
        assert_memory_equal(z, zc, sizeof(z));
        sat = 0u;
        assert_int_equal(rfe_meas_eval_q31(&h, &p.vehicle, &p.tyre, mu, z, &sat), RFE_OK);
        assert_int_equal(sat, cnt);
        assert_memory_equal(z, zc, sizeof(z));
        with_sat += (cnt != 0u) ? 1 : 0;
        /* other (valid) tyre parameters at eval: the terms are recomputed for them */
        other = p.tyre;
        switch (n % 6) {
        case 0:
            other.cx = other.cx / 2 + 1;
            break;
        case 1:
            other.cy = other.cy / 3 + 1;
            break;
        case 2:
            other.eps = other.eps / 2;
            break;
        case 3:
            other.alpha_max = other.alpha_max / 2;
            break;
        case 4:
            /* the other load-scaled curve on the same cached terms */
            other.mode = (other.mode == RFE_TYRE_MAGIC) ? RFE_TYRE_ABSOLUTE : RFE_TYRE_MAGIC;
            break;
        default:
            /* other shape factors on the same cached terms */
            other.shape_Cx = (1 << 24) + 1 + (int32_t)(draw_u64() % ((1u << 24) - 1u));
            other.shape_Ey = (int32_t)(draw_u64() % (5u << 24)) - (4 << 24);
            break;
        }
        sat = 0u;
        assert_int_equal(rfe_meas_eval_q31(&h, &p.vehicle, &other, mu, z, &sat), RFE_OK);
        assert_int_equal(sat, chain(&h, &p.vehicle, &other, mu, zc));
        assert_memory_equal(z, zc, sizeof(z));
    }
    printf("columns: %d cases, %ld with saturations\n", N_CASES, with_sat);
    assert_true(with_sat > 10);
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

static rfe_fix_t *slot(rfe_sample_q31_t *u, size_t j)
{
    rfe_fix_t *const s[8] = {&u->delta,    &u->vx,       &u->vy,       &u->yaw_rate,
                             &u->omega[0], &u->omega[1], &u->omega[2], &u->omega[3]};
    return s[j];
}

/* docs/ESTIMATOR.md step 4 as written: S_R = Tria([S_R0, g_1 ..]), every h a full
 * evaluation (set-up and eval) of the public measurement model. */
static rfe_status_t ref_step_noise(const rfe_params_q31_t *p, const rfe_sample_q31_t *u,
                            const rfe_fix_t mu[4], rfe_fix_t SR[9], uint32_t *sat)
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
    }
    for (j = 0; j < 8; ++j) {
        rfe_sample_q31_t up = *u;
        rfe_sample_q31_t um = *u;
        rfe_fix_t zp[3];
        rfe_fix_t zm[3];
        if (sd[j] <= 0) {
            continue;
        }
        *slot(&up, j) = rfe_fix_add(*slot(&up, j), sd[j], &count);
        *slot(&um, j) = rfe_fix_sub(*slot(&um, j), sd[j], &count);
        st = ref_h(p, &up, mu, zp, &count);
        if (st == RFE_OK) {
            st = ref_h(p, &um, mu, zm, &count);
        }
        if (st != RFE_OK) {
            return st;
        }
        for (i = 0; i < 3; ++i) {
            A[i * 11u + cols] = rfe_fix_narrow((int64_t)zp[i] - (int64_t)zm[i], 1u, &count);
        }
        ++cols;
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
 * reference with a full evaluation per perturbed input, in magic, absolute and paper tyre
 * mode, with every input switched on or off. */
/* REQ-FXP-007 REQ-FXP-008 */
static void test_step_noise_core_q31(void **state)
{
    int n;
    long checked = 0;
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
        e2 = ref_step_noise(&p, &u, mu, S2, &s2);
        assert_int_equal(e1, e2);
        if (e1 != RFE_OK) {
            continue;
        }
        assert_memory_equal(S1, S2, sizeof(S1));
        assert_int_equal(s1, s2);
        assert_int_equal(rfe_meas_setup_q31(&h, &p.vehicle, &p.tyre, &u, &scratch), RFE_OK);
        assert_int_equal(rfe_step_noise_sqrt_core_q31(&p, &h, &u, mu, S3, &s3), RFE_OK);
        assert_memory_equal(S3, S2, sizeof(S3));
        assert_int_equal(s3, s2);
        ++checked;
        with_sat += (s1 != 3u) ? 1 : 0;
    }
    printf("step noise: %ld cases bit for bit (%ld with saturations)\n", checked, with_sat);
    assert_true(checked > 1000);
    assert_true(with_sat > 10);
}

/* REQ: a set-up in absolute mode with invalid Dugoff parameters (eps < 0) keeps zero
 * friction-independent terms, and the evaluation rejects the tyre (as the public chain does);
 * in magic mode with a shape factor outside its domain the set-up succeeds (its terms do not
 * depend on the shape) and the evaluation rejects the tyre;
 * rfe_fix_div's long division stops as soon as the quotient must saturate (operands that
 * take the long path: shift + 1 > 32), saturating to INT32_MAX, counted. */
/* REQ-FXP-008 REQ-MEAS-002 */
static void test_meas_pre_invalid_tyre_and_div_saturation_q31(void **state)
{
    rfe_params_q31_t p = preset();
    rfe_sample_q31_t u;
    rfe_fix_t mu[4];
    rfe_fix_t z[3];
    rfe_meas_q31_t h;
    rfe_fix_t q = 0;
    uint32_t sat = 0u;
    size_t i;
    (void)state;
    draw_seed(0xD1CEull);
    draw_sample_q31(&p, &u, mu, 0);
    u.vx = 20 << 23;
    u.delta = 0;
    for (i = 0; i < 4; ++i) {
        u.omega[i] = (int32_t)((((int64_t)u.vx) << 6) / (p.vehicle.R >> 20));
        mu[i] = 1 << 28;
    }
    p.tyre.mode = RFE_TYRE_ABSOLUTE;
    p.tyre.eps = -1;
    assert_int_equal(rfe_meas_setup_q31(&h, &p.vehicle, &p.tyre, &u, &sat), RFE_OK);
    for (i = 0; i < 4; ++i) {
        const rfe_dugoff_pre_q31_t zero = {0, 0, 0, 0, 0, 0, 0u};
        assert_memory_equal(&h.pre[i], &zero, sizeof zero);
    }
    assert_int_not_equal(rfe_meas_eval_q31(&h, &p.vehicle, &p.tyre, mu, z, &sat), RFE_OK);
    /* magic mode, C = 2 (outside 1 < C < 2) */
    p = preset();
    p.tyre.shape_Cy = 2 << 24;
    sat = 0u;
    assert_int_equal(rfe_meas_setup_q31(&h, &p.vehicle, &p.tyre, &u, &sat), RFE_OK);
    for (i = 0; i < 4; ++i) {
        rfe_dugoff_pre_q31_t fresh;
        rfe_tyre_dugoff_pre_q31(&p.tyre, h.kin.kappa[i], h.kin.alpha[i], h.kin.vwx[i], &fresh);
        assert_memory_equal(&h.pre[i], &fresh, sizeof fresh);
    }
    memset(z, 0x5A, sizeof z);
    assert_int_equal(rfe_meas_eval_q31(&h, &p.vehicle, &p.tyre, mu, z, &sat), RFE_ERR_PARAM);
    assert_int_equal(z[0], 0x5A5A5A5A);
    assert_int_equal(sat, 0u);
    p.tyre.mode = RFE_TYRE_ABSOLUTE; /* the Dugoff curve does not use the shape */
    assert_int_equal(rfe_meas_eval_q31(&h, &p.vehicle, &p.tyre, mu, z, &sat), RFE_OK);
    /* division: a = INT32_MAX, b = 1, shift 40: 2^71, far beyond int32 */
    sat = 0u;
    assert_int_equal(rfe_fix_div(INT32_MAX, 1, 40, &q, &sat), RFE_OK);
    assert_int_equal(q, INT32_MAX);
    assert_int_equal(sat, 1u);
    sat = 0u;
    assert_int_equal(rfe_fix_div(-INT32_MAX, 3, 35, &q, &sat), RFE_OK);
    assert_int_equal(q, -INT32_MAX);
    assert_int_equal(sat, 1u);
    /* and just inside: 3 * 2^35 / 2^6 = 3 * 2^29 fits exactly */
    sat = 0u;
    assert_int_equal(rfe_fix_div(3, 1 << 6, 35, &q, &sat), RFE_OK);
    assert_int_equal(q, 3 << 29);
    assert_int_equal(sat, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tyre_internal_q31),
        cmocka_unit_test(test_meas_columns_q31),
        cmocka_unit_test(test_step_noise_core_q31),
        cmocka_unit_test(test_meas_pre_invalid_tyre_and_div_saturation_q31),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
