/**
 * @file test_vehicle_mass_q31.c
 * @brief The fixed-point vehicle mass set at run time (rfe_params_set_mass_q31,
 *        rfe_friction_set_mass_q31, rfe_pipeline_set_mass_q31): statuses and the untouched state on error, the
 *        recomputed constants against their values computed here in double, and that the
 *        estimator keeps nothing else derived from the mass.
 *
 * Tolerance of the constants: rfe_params_set_mass_q31 recomputes each with 30-bit mantissas
 * (at most five roundings of 2^-30 relative each: below 2^-26 relative, rfe/params_q31.h)
 * and rounds it to its Q format (half an LSB), so |constant - exact| <= exact 2^-26 + 1 LSB.
 */
#include "test_common.h"

#include <math.h>
#include <string.h>

#include "host/fixed_conv.h"
#include "rfe/friction_q31.h"
#include "rfe/pipeline_q31.h"

static rfe_params_q31_t preset(void)
{
    rfe_params_q31_t p;
    memset(&p, 0, sizeof p); /* the estimator copies it, padding included: keep it defined */
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    return p;
}

static rfe_fix_t mass_q(double kg)
{
    uint32_t sat = 0u;
    const rfe_fix_t m = rfe_fix_from_double(kg, RFE_FIX_Q_MASS, &sat);
    assert_int_equal(sat, 0u);
    return m;
}

/* |stored - exact 2^q| <= exact 2^q 2^-26 + 1 (the file comment). */
static void assert_constant(rfe_fix_t stored, double exact, unsigned int q, const char *what)
{
    const double want = ldexp(exact, (int)q);
    const double tol = (want * ldexp(1.0, -26)) + 1.0;
    if (!(fabs((double)stored - want) <= tol)) {
        fail_msg("%s: %d, want %.3f (tolerance %.3f)", what, stored, want, tol);
    }
}

/* REQ-EST-017 */
static void test_params_set_mass_q31_constants(void **state)
{
    static const double masses[4] = {1000.0, 1500.0, 2312.5, 3500.0};
    size_t i;
    (void)state;
    for (i = 0u; i < 4u; ++i) {
        rfe_params_q31_t p = preset();
        const rfe_vehicle_q31_t *v = &p.vehicle;
        double m, g, lf, lr, bf, br, hg, la;
        assert_int_equal(rfe_params_set_mass_q31(&p, mass_q(masses[i])), RFE_OK);
        m = rfe_fix_to_double(v->m, RFE_FIX_Q_MASS);
        g = rfe_fix_to_double(v->g, RFE_FIX_Q_ACC);
        lf = rfe_fix_to_double(v->Lf, RFE_FIX_Q_LEN);
        lr = rfe_fix_to_double(v->Lr, RFE_FIX_Q_LEN);
        bf = rfe_fix_to_double(v->Bf, RFE_FIX_Q_LEN);
        br = rfe_fix_to_double(v->Br, RFE_FIX_Q_LEN);
        hg = rfe_fix_to_double(v->hg, RFE_FIX_Q_LEN);
        la = lf + lr;
        assert_true(m == masses[i]); /* each mass above is a multiple of 2^-16 kg */
        assert_constant(v->inv_m, 1.0 / m, RFE_FIX_Q_INV, "inv_m");
        assert_constant(v->fz_static_f, m * g * lr / (2.0 * la), RFE_FIX_Q_FORCE, "fz_static_f");
        assert_constant(v->fz_static_r, m * g * lf / (2.0 * la), RFE_FIX_Q_FORCE, "fz_static_r");
        assert_constant(v->k_pitch, m * hg / (2.0 * la), RFE_FIX_Q_KLOAD, "k_pitch");
        assert_constant(v->k_roll_f, m * hg * lr / (la * bf), RFE_FIX_Q_KLOAD, "k_roll_f");
        assert_constant(v->k_roll_r, m * hg * lf / (la * br), RFE_FIX_Q_KLOAD, "k_roll_r");
    }
}

/* REQ-EST-017 */
static void test_params_set_mass_q31_refused(void **state)
{
    rfe_params_q31_t p = preset();
    rfe_params_q31_t before;
    (void)state;
    assert_int_equal(rfe_params_set_mass_q31(NULL, mass_q(1500.0)), RFE_ERR_NULL);
    memcpy(&before, &p, sizeof before);
    assert_int_equal(rfe_params_set_mass_q31(&p, 0), RFE_ERR_PARAM);
    assert_int_equal(rfe_params_set_mass_q31(&p, -mass_q(1500.0)), RFE_ERR_PARAM);
    /* below 1 kg: fewer than 16 significant bits in Q16 */
    assert_int_equal(rfe_params_set_mass_q31(&p, mass_q(0.9)), RFE_ERR_PARAM);
    /* 100 kg: 1/m = 0.01 leaves Q38 (its bound 2^-7, m >= 128 kg) */
    assert_int_equal(rfe_params_set_mass_q31(&p, mass_q(100.0)), RFE_ERR_PARAM);
    /* 30 t: the static front load m g Lr / (2 La) > 65536 N leaves Q15 */
    assert_int_equal(rfe_params_set_mass_q31(&p, mass_q(30000.0)), RFE_ERR_PARAM);
    assert_memory_equal(&p, &before, sizeof p);
    /* a set that is invalid elsewhere is refused whatever the mass, untouched */
    p.vehicle.J = -1;
    memcpy(&before, &p, sizeof before);
    assert_int_equal(rfe_params_set_mass_q31(&p, mass_q(1500.0)), RFE_ERR_PARAM);
    assert_memory_equal(&p, &before, sizeof p);
}

/* A braking sample at 20 m/s with 4 % slip (Q formats). */
static rfe_sample_q31_t braking(size_t k)
{
    rfe_sample_q31_t u;
    uint32_t sat = 0u;
    size_t w;
    memset(&u, 0, sizeof u);
    u.vx = rfe_fix_from_double(20.0, RFE_FIX_Q_SPEED, &sat);
    u.ax = rfe_fix_from_double(-4.0 - (0.01 * (double)(k % 7u)), RFE_FIX_Q_ACC, &sat);
    for (w = 0u; w < 4u; ++w) {
        u.omega[w] = rfe_fix_from_double(20.0 * 0.96 / 0.325, RFE_FIX_Q_OMEGA, &sat);
    }
    assert_int_equal(sat, 0u);
    return u;
}

/* REQ-EST-017 */
static void test_friction_set_mass_q31(void **state)
{
    rfe_params_q31_t p = preset();
    rfe_params_q31_t p2;
    rfe_friction_q31_t a; /* set to 1500 kg after K steps */
    rfe_friction_q31_t b; /* a's state, with the parameters of rfe_params_set_mass_q31 */
    rfe_friction_q31_t c; /* never set */
    rfe_friction_q31_t before;
    rfe_estimate_q31_t ea;
    rfe_estimate_q31_t eb;
    rfe_estimate_q31_t ec;
    size_t k;
    const size_t K = 150u;
    int differs = 0;
    (void)state;
    memset(&ea, 0, sizeof ea); /* compared as bytes below */
    memset(&eb, 0, sizeof eb);
    memset(&ec, 0, sizeof ec);
    memset(&a, 0, sizeof a);
    assert_int_equal(rfe_friction_set_mass_q31(NULL, mass_q(1500.0)), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_set_mass_q31(&a, mass_q(1500.0)), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_friction_init_q31(&a, &p), RFE_OK);
    memset(&c, 0, sizeof c);
    assert_int_equal(rfe_friction_init_q31(&c, &p), RFE_OK);
    for (k = 0u; k < K; ++k) {
        const rfe_sample_q31_t u = braking(k);
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&a, &u, &ea)));
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&c, &u, &ec)));
    }
    memcpy(&before, &a, sizeof before); /* bytes, padding included */
    assert_int_equal(rfe_friction_set_mass_q31(&a, 0), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_mass_q31(&a, mass_q(30000.0)), RFE_ERR_RANGE);
    assert_memory_equal(&a, &before, sizeof a);
    /* b: a's state with the parameters rfe_params_set_mass_q31 gives for 1500 kg */
    p2 = p;
    assert_int_equal(rfe_params_set_mass_q31(&p2, mass_q(1500.0)), RFE_OK);
    memcpy(&b, &a, sizeof b);
    b.params = p2;
    assert_int_equal(rfe_friction_set_mass_q31(&a, mass_q(1500.0)), RFE_OK);
    assert_memory_equal(&a, &b, sizeof a);
    for (k = K; k < (2u * K); ++k) {
        const rfe_sample_q31_t u = braking(k);
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&a, &u, &ea)));
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&b, &u, &eb)));
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&c, &u, &ec)));
        assert_memory_equal(&ea, &eb, sizeof ea);
        differs |= (memcmp(&ea.mu, &ec.mu, sizeof ea.mu) != 0) ? 1 : 0;
    }
    assert_true(differs); /* the mass reaches the model: 1500 kg is not the preset's */
}

/* An ESC sample: braking at about 20 m/s, the wheels 4 % slower, a little steering. */
static rfe_velocity_input_q31_t esc(size_t k)
{
    rfe_velocity_input_q31_t in;
    uint32_t sat = 0u;
    size_t w;
    memset(&in, 0, sizeof in);
    in.dt = rfe_fix_from_double(0.01, RFE_FIX_Q_DT, &sat);
    in.delta = rfe_fix_from_double(0.01, RFE_FIX_Q_ANGLE, &sat);
    in.ax = rfe_fix_from_double(-4.0 - (0.01 * (double)(k % 7u)), RFE_FIX_Q_ACC, &sat);
    in.yaw_rate = rfe_fix_from_double(0.05, RFE_FIX_Q_YAWRATE, &sat);
    for (w = 0u; w < 4u; ++w) {
        in.omega[w] = rfe_fix_from_double((20.0 - (0.04 * (double)k)) * 0.96 / 0.325,
                                          RFE_FIX_Q_OMEGA, &sat);
    }
    assert_int_equal(sat, 0u);
    return in;
}

static void pipeline_at(rfe_pipeline_q31_t *pl, const rfe_params_q31_t *p)
{
    rfe_velocity_params_q31_t vp;
    memset(&vp, 0, sizeof vp);
    assert_int_equal(rfe_velocity_params_default_q31(&vp), RFE_OK);
    memset(pl, 0, sizeof *pl); /* padding defined: compared as bytes */
    assert_int_equal(rfe_pipeline_init_q31(pl, p, &vp), RFE_OK);
}

/* Both estimators take the mass and its constants: the pipeline set to 1500 kg after K steps
 * equals, from then on, the same state with the parameters rfe_params_set_mass_q31 gives. */
/* REQ-EST-017 */
static void test_pipeline_set_mass_q31(void **state)
{
    static rfe_pipeline_q31_t a;
    static rfe_pipeline_q31_t b;
    static rfe_pipeline_q31_t before;
    rfe_pipeline_out_q31_t oa;
    rfe_pipeline_out_q31_t ob;
    rfe_params_q31_t p = preset();
    rfe_params_q31_t p2;
    size_t k;
    const size_t K = 100u;
    (void)state;
    memset(&oa, 0, sizeof oa);
    memset(&ob, 0, sizeof ob);
    assert_int_equal(rfe_pipeline_set_mass_q31(NULL, mass_q(1500.0)), RFE_ERR_NULL);
    memset(&a, 0, sizeof a);
    assert_int_equal(rfe_pipeline_set_mass_q31(&a, mass_q(1500.0)), RFE_ERR_NOT_INITIALISED);
    pipeline_at(&a, &p);
    for (k = 0u; k < K; ++k) {
        const rfe_velocity_input_q31_t in = esc(k);
        assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&a, &in, &oa)));
    }
    memcpy(&before, &a, sizeof before);
    assert_int_equal(rfe_pipeline_set_mass_q31(&a, -1), RFE_ERR_RANGE);
    assert_int_equal(rfe_pipeline_set_mass_q31(&a, mass_q(30000.0)), RFE_ERR_RANGE);
    assert_memory_equal(&a, &before, sizeof a);
    p2 = p;
    assert_int_equal(rfe_params_set_mass_q31(&p2, mass_q(1500.0)), RFE_OK);
    memcpy(&b, &a, sizeof b); /* the rest (the input noise the steps set) a's */
    b.friction.params.vehicle = p2.vehicle;
    b.velocity.veh = p2.vehicle;
    assert_int_equal(rfe_pipeline_set_mass_q31(&a, mass_q(1500.0)), RFE_OK);
    assert_memory_equal(&a, &b, sizeof a);
    for (k = K; k < (2u * K); ++k) {
        const rfe_velocity_input_q31_t in = esc(k);
        assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&a, &in, &oa)));
        assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&b, &in, &ob)));
        assert_memory_equal(&oa, &ob, sizeof oa);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_params_set_mass_q31_constants),
        cmocka_unit_test(test_params_set_mass_q31_refused),
        cmocka_unit_test(test_friction_set_mass_q31),
        cmocka_unit_test(test_pipeline_set_mass_q31),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
