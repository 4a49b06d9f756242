/**
 * @file test_meas_nominal_q31.c
 * @brief The step noise's one-pass entry rfe_meas_nominal_input_jac_q31
 *        (models/meas_internal_q31.h, issue 21) against the two calls it replaces,
 *        rfe_meas_nominal_q31 then rfe_meas_input_jac_q31.
 *
 * An exact claim (the same integer operations in another order): z, G and the
 * saturation count bit for bit, statuses equal, for the Magic Formula with the set-up's tyre
 * (paper, Dugoff and another stiffness are refused: the caller makes the two calls), on drawn driving samples
 * (vx 3 .. 45 m/s, wheel slips -20 .. +10 %, steer +-0.3 rad, |ay| up to 9 m/s^2) and on a
 * heavy vehicle at mu 3.9 whose forces clamp (the counts then differ from 0). No tolerance:
 * every comparison is exact.
 */
#include "test_light.h"
#include "test_common.h"

#include <stdint.h>
#include <string.h>

#include "q31_rows.h"
#include "rfe/component/meas_q31.h"
#include "rfe/component/params_conv.h"
#include "rfe/params.h"
#include "models/meas_internal_q31.h"

static rfe_params_q31_t pq[3]; /* paper, absolute (Dugoff), magic: the default preset's */

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;

/* a uniform draw in [lo, hi) (xorshift64*, deterministic) */
static double draw(double lo, double hi)
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return lo + ((hi - lo) * (double)((rng_state * 0x2545F4914F6CDD1Dull) >> 11) /
                 9007199254740992.0);
}

static int setup(void **state)
{
    rfe_params_t pd;
    int m;
    (void)state;
    for (m = 0; m < 3; ++m) {
        if (rfe_params_default_f64(&pd) != RFE_OK) {
            return -1;
        }
        pd.tyre.mode = (m == 0) ? RFE_TYRE_PAPER : ((m == 1) ? RFE_TYRE_ABSOLUTE : RFE_TYRE_MAGIC);
        if (rfe_params_to_q31_f64(&pd, &pq[m]) != RFE_OK) {
            return -1;
        }
    }
    return (pq[2].tyre.mode == RFE_TYRE_MAGIC) ? 0 : -1;
}

/* A driving sample (n = 0 of every 40: the clamping one, mu 3.9) and its friction, Q29. */
static void draw_point(int n, rfe_params_q31_t *p, rfe_sample_q31_t *u, rfe_fix_t mu[4])
{
    const double vx = draw(3.0, 45.0);
    const double R = (double)p->vehicle.R / 536870912.0; /* Q29 */
    size_t i;
    memset(u, 0, sizeof(*u));
    u->delta = q31_rows_toq(draw(-0.3, 0.3), RFE_FIX_Q_ANGLE);
    u->vx = q31_rows_toq(vx, RFE_FIX_Q_SPEED);
    u->vy = q31_rows_toq(draw(-0.08, 0.08) * vx, RFE_FIX_Q_SPEED);
    u->yaw_rate = q31_rows_toq(draw(-0.6, 0.6), RFE_FIX_Q_YAWRATE);
    u->ax = q31_rows_toq(draw(-8.0, 4.0), RFE_FIX_Q_ACC);
    u->ay = q31_rows_toq(draw(-9.0, 9.0), RFE_FIX_Q_ACC);
    for (i = 0u; i < 4u; ++i) {
        u->omega[i] = q31_rows_toq(vx * (1.0 + draw(-0.2, 0.1)) / R, RFE_FIX_Q_OMEGA);
        mu[i] = q31_rows_toq(draw(0.05, 1.3), RFE_FIX_Q_MU);
    }
    if ((n % 40) == 0) {
        /* a heavy load on a strong road: forces beyond +-65536 N clamp (counted) */
        for (i = 0u; i < 4u; ++i) {
            mu[i] = q31_rows_toq(3.9, RFE_FIX_Q_MU);
        }
        u->delta = q31_rows_toq(0.3, RFE_FIX_Q_ANGLE);
        u->vy = q31_rows_toq(-0.3 * vx, RFE_FIX_Q_SPEED);
        p->vehicle.fz_static_f = RFE_FIX_MAX / 2;
        p->vehicle.fz_static_r = RFE_FIX_MAX / 2;
    }
}

/* REQ: where rfe_meas_one_pass_ok_q31 (a Magic Formula set-up with its own tyre),
 * rfe_meas_nominal_input_jac_q31 is rfe_meas_nominal_q31 followed by rfe_meas_input_jac_q31,
 * bit for bit (z, G, the count) and status for status; elsewhere (paper, Dugoff, another
 * stiffness) RFE_ERR_PARAM with nothing written; NULL arguments rejected. */
/* REQ-MEAS-004 REQ-FXP-003 */
static void test_nominal_input_jac_q31(void **state)
{
    int n;
    int fast = 0;
    int clamped = 0;
    (void)state;
    for (n = 0; n < 240; ++n) {
        rfe_params_q31_t p = pq[n % 3];
        rfe_tyre_params_q31_t other;
        rfe_sample_q31_t u;
        rfe_fix_t mu[4];
        rfe_fix_t sd[RFE_INPUTS];
        rfe_meas_q31_t h;
        uint32_t s0 = 0u;
        size_t j;
        int k;
        draw_point(n, &p, &u, mu);
        for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
            /* 0.05 in each input's format, vy's column left out every third sample */
            const unsigned int q[8] = {29u, 23u, 23u, 27u, 22u, 22u, 22u, 22u};
            sd[j] = ((j == (size_t)RFE_IN_VY) && ((n % 3) == 1)) ? 0 : q31_rows_toq(0.05, q[j]);
        }
        other = p.tyre;
        other.cy = (other.cy / 10) * 13;
        if (rfe_meas_setup_q31(&h, &p.vehicle, &p.tyre, &u, &s0) != RFE_OK) {
            continue;
        }
        for (k = 0; k < 2; ++k) {
            const rfe_tyre_params_q31_t *tp = (k == 0) ? &p.tyre : &other;
            rfe_meas_q31_t h1 = h;
            rfe_meas_q31_t h2 = h;
            rfe_meas_terms_q31_t nom;
            rfe_fix_t z[3] = {0, 0, 0};
            rfe_fix_t z2[3] = {0, 0, 0};
            rfe_fix_t G[3 * RFE_INPUTS];
            rfe_fix_t G2[3 * RFE_INPUTS];
            uint32_t c1 = 7u; /* a count already running: added to */
            uint32_t c2 = 7u;
            rfe_status_t want;
            rfe_status_t got;
            memset(G, 0, sizeof(G));
            memset(G2, 0, sizeof(G2));
            want = rfe_meas_nominal_q31(&h1, &p.vehicle, tp, mu, &nom, z, &c1);
            if (want == RFE_OK) {
                want = rfe_meas_input_jac_q31(&h1, &p.vehicle, tp, &u, mu, sd, G, &c1);
            }
            got = rfe_meas_nominal_input_jac_q31(&h2, &p.vehicle, tp, &u, mu, sd, z2, G2, &c2);
            if (rfe_meas_one_pass_ok_q31(&h, tp) == 0) {
                /* paper and Dugoff set-ups, another stiffness: not its case, nothing written */
                const rfe_fix_t zero3[3] = {0, 0, 0};
                assert_true((p.tyre.mode != RFE_TYRE_MAGIC) || (k == 1));
                assert_int_equal(got, RFE_ERR_PARAM);
                assert_memory_equal(z2, zero3, sizeof(z2));
                assert_int_equal(c2, 7u);
                continue;
            }
            assert_int_equal(p.tyre.mode, RFE_TYRE_MAGIC);
            assert_int_equal(k, 0);
            assert_int_equal(got, want);
            if (want == RFE_OK) {
                assert_memory_equal(z2, z, sizeof(z));
                assert_memory_equal(G2, G, sizeof(G));
                assert_int_equal(c2, c1);
                fast += 1;
                clamped += (c1 > 7u) ? 1 : 0;
            } else {
                assert_int_equal(c2, 7u); /* untouched on an error */
            }
        }
    }
    assert_true(fast >= 60);  /* the one pass was compared */
    assert_true(clamped >= 1); /* with clamped forces too */
    {
        rfe_params_q31_t p = pq[2];
        rfe_sample_q31_t u;
        rfe_fix_t mu[4];
        rfe_fix_t sd[RFE_INPUTS] = {0};
        rfe_fix_t z[3];
        rfe_fix_t G[3 * RFE_INPUTS];
        rfe_meas_q31_t h;
        uint32_t s = 0u;
        draw_point(1, &p, &u, mu);
        assert_int_equal(rfe_meas_setup_q31(&h, &p.vehicle, &p.tyre, &u, &s), RFE_OK);
        assert_int_equal(rfe_meas_nominal_input_jac_q31(NULL, &p.vehicle, &p.tyre, &u, mu, sd, z, G, &s), RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac_q31(&h, NULL, &p.tyre, &u, mu, sd, z, G, &s), RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac_q31(&h, &p.vehicle, NULL, &u, mu, sd, z, G, &s), RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac_q31(&h, &p.vehicle, &p.tyre, NULL, mu, sd, z, G, &s), RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac_q31(&h, &p.vehicle, &p.tyre, &u, NULL, sd, z, G, &s), RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac_q31(&h, &p.vehicle, &p.tyre, &u, mu, NULL, z, G, &s), RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac_q31(&h, &p.vehicle, &p.tyre, &u, mu, sd, NULL, G, &s), RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac_q31(&h, &p.vehicle, &p.tyre, &u, mu, sd, z, NULL, &s), RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac_q31(&h, &p.vehicle, &p.tyre, &u, mu, sd, z, G, NULL), RFE_ERR_NULL);
        assert_int_equal(rfe_meas_one_pass_ok_q31(NULL, &p.tyre), 0);
        assert_int_equal(rfe_meas_one_pass_ok_q31(&h, NULL), 0);
        assert_int_equal(rfe_meas_one_pass_ok_q31(&h, &p.tyre), 1);
        {
            /* A Magic Formula shape out of its range (C_x = 1: magic_shape_ok wants 1 < C_x < 2)
             * keeps the set-up's match (it compares the stiffnesses, eps and alpha_max, not the
             * shape), so the one pass is taken and refuses it as the two calls do: RFE_ERR_PARAM,
             * nothing written, the count untouched. */
            rfe_tyre_params_q31_t bad = p.tyre;
            rfe_fix_t z0[3] = {1, 2, 3};
            const rfe_fix_t z0_want[3] = {1, 2, 3};
            uint32_t c = 7u;
            bad.shape_Cx = RFE_FIX_ONE(RFE_FIX_Q_STIFF);
            assert_int_equal(rfe_meas_one_pass_ok_q31(&h, &bad), 1);
            assert_int_equal(rfe_meas_input_jac_q31(&h, &p.vehicle, &bad, &u, mu, sd, G, &c), RFE_ERR_PARAM);
            assert_int_equal(rfe_meas_nominal_input_jac_q31(&h, &p.vehicle, &bad, &u, mu, sd, z0, G, &c),
                             RFE_ERR_PARAM);
            assert_memory_equal(z0, z0_want, sizeof(z0));
            assert_int_equal(c, 7u);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nominal_input_jac_q31),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
