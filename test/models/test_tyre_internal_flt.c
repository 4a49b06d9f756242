/**
 * @file test_tyre_internal_flt.c
 * @brief The tyre model's internal split (src/models/tyre_internal.h) behind the cheaper
 *        float/double step: the load-scaled evaluation split into its friction-independent
 *        part and the rest, against the public function it replaces (rfe_tyre_dugoff_abs,
 *        rfe_tyre_magic_abs), bit for bit and status for status, on finite, non-finite and
 *        out-of-range inputs from a fixed-seed generator (test_draws.h), and its argument
 *        check.
 */
#include "test_light.h"
#include "test_common.h"

#include <stdint.h>
#include <string.h>

#include "rfe/params.h"
#include "rfe/component/tyre.h"

#include "models/tyre_internal.h"
#include "test_draws.h"

#define N_CASES 20000
#define RFE_R(x) ((rfe_real_t)(x))

/* REQ: the split evaluation of a load-scaled tyre is the public function's (Dugoff:
 * rfe_tyre_dugoff_abs, magic: rfe_tyre_magic_abs), bits and statuses. */
/* REQ-TYRE-003 REQ-TYRE-007 */
static void test_dugoff_split(void **state)
{
    rfe_params_t p;
    int n;
    (void)state;
    draw_seed(0xD06FF5ull);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    for (n = 0; n < N_CASES; n += (int)rfe_test_stride(10u)) {
        const rfe_real_t kappa = draw_special(1.2);
        const rfe_real_t alpha = draw_special(0.6);
        const rfe_real_t fz = draw_special(9000.0);
        const rfe_real_t vwx = draw_special(60.0);
        const rfe_real_t mu = draw_special(2.0);
        rfe_real_t f1[2] = {RFE_R(7.0), RFE_R(7.0)};
        rfe_real_t f2[2] = {RFE_R(7.0), RFE_R(7.0)};
        rfe_dugoff_pre_t pre;
        rfe_tyre_params_t tp = p.tyre;
        if ((n % 3) == 1) {
            tp.cx = (rfe_real_t)draw_uniform(0.0, 60.0);
            tp.cy = (rfe_real_t)draw_uniform(0.0, 60.0);
            tp.eps = (rfe_real_t)draw_uniform(0.0, 0.05);
        }
        tp.mode = (((n / (int)rfe_test_stride(10u)) % 2) == 0) ? RFE_TYRE_MAGIC : RFE_TYRE_ABSOLUTE;
        rfe_tyre_dugoff_pre(&tp, kappa, alpha, vwx, &pre);
        assert_int_equal(rfe_tyre_dugoff_abs_pre(&tp, &pre, kappa, alpha, fz, vwx, mu,
                                                         &f2[0], &f2[1]),
                         (tp.mode == RFE_TYRE_MAGIC)
                             ? rfe_tyre_magic_abs(&tp, kappa, alpha, fz, vwx, mu, &f1[0],
                                                  &f1[1])
                             : rfe_tyre_dugoff_abs(&tp, kappa, alpha, fz, vwx, mu, &f1[0],
                                                   &f1[1]));
        assert_memory_equal(f1, f2, sizeof(f1));
    }
    {
        rfe_dugoff_pre_t pre;
        rfe_real_t f[2];
        rfe_tyre_dugoff_pre(&p.tyre, RFE_R(0.1), RFE_R(0.0), RFE_R(20.0), &pre);
        assert_int_equal(rfe_tyre_dugoff_abs_pre(NULL, &pre, RFE_R(0.1), RFE_R(0.0),
                                                         RFE_R(1.0), RFE_R(20.0), RFE_R(1.0),
                                                         &f[0], &f[1]),
                         RFE_ERR_NULL);
    }
}

/* REQ: the forces' derivatives (rfe_tyre_pre_jac) give the forces of the split evaluation
 * (rfe_tyre_dugoff_abs_pre) bit for bit in the load-scaled modes, its statuses on
 * non-finite and out-of-range inputs, and reject missing arguments, nothing written. */
/* REQ-MEAS-003 REQ-TYRE-007 */
static void test_pre_jac_forces_and_args(void **state)
{
    static const rfe_tyre_mode_t modes[2] = {RFE_TYRE_ABSOLUTE, RFE_TYRE_MAGIC};
    const rfe_slip_dir_t d = {RFE_R(0.01), RFE_R(-0.02), RFE_R(0.1)};
    rfe_params_t p;
    rfe_dugoff_pre_t pre;
    rfe_tyre_jac_t j;
    rfe_tyre_jac_t j0;
    int n;
    (void)state;
    draw_seed(0x7AC0B1ull);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    for (n = 0; n < N_CASES; n += (int)rfe_test_stride(10u)) {
        const rfe_real_t kappa = draw_special(1.2);
        const rfe_real_t alpha = draw_special(0.6);
        const rfe_real_t fz = draw_special(9000.0);
        const rfe_real_t vwx = draw_special(60.0);
        const rfe_real_t mu = draw_special(2.0);
        rfe_real_t fx = RFE_R(7.0);
        rfe_real_t fy = RFE_R(7.0);
        rfe_status_t want;
        p.tyre.mode = modes[n % 2];
        rfe_tyre_dugoff_pre(&p.tyre, kappa, alpha, vwx, &pre);
        want = rfe_tyre_dugoff_abs_pre(&p.tyre, &pre, kappa, alpha, fz, vwx, mu, &fx, &fy);
        memset(&j, 0x5A, sizeof(j));
        j0 = j;
        assert_int_equal(rfe_tyre_pre_jac(&p.tyre, &pre, kappa, alpha, fz, vwx, mu, &d, &j), want);
        if (want == RFE_OK) {
            assert_memory_equal(&j.fx, &fx, sizeof(fx));
            assert_memory_equal(&j.fy, &fy, sizeof(fy));
        } else {
            assert_memory_equal(&j, &j0, sizeof(j));
        }
    }
    rfe_tyre_dugoff_pre(&p.tyre, RFE_R(0.05), RFE_R(0.02), RFE_R(20.0), &pre);
    assert_int_equal(rfe_tyre_pre_jac(NULL, &pre, RFE_R(0.05), RFE_R(0.02), RFE_R(4000.0), RFE_R(20.0), RFE_R(1.0), &d, &j), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_pre_jac(&p.tyre, NULL, RFE_R(0.05), RFE_R(0.02), RFE_R(4000.0), RFE_R(20.0), RFE_R(1.0), &d, &j), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_pre_jac(&p.tyre, &pre, RFE_R(0.05), RFE_R(0.02), RFE_R(4000.0), RFE_R(20.0), RFE_R(1.0), NULL, &j), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_pre_jac(&p.tyre, &pre, RFE_R(0.05), RFE_R(0.02), RFE_R(4000.0), RFE_R(20.0), RFE_R(1.0), &d, NULL), RFE_ERR_NULL);
}

/* REQ: rfe_tyre_magic_basis (the step noise's two unit slip changes of a Magic Formula wheel)
 * refuses a NULL set-up or output with RFE_ERR_NULL and a non-finite friction with
 * RFE_ERR_NONFINITE, and along the unit change of kappa gives what rfe_tyre_pre_jac gives
 * along the same direction (the same functions in the same order: bit for bit). */
/* REQ-MEAS-003 REQ-TYRE-007 */
static void test_magic_basis_args(void **state)
{
    const rfe_slip_dir_t ek = {RFE_R(1.0), RFE_R(0.0), RFE_R(0.0)};
    rfe_params_t p;
    rfe_dugoff_pre_t pre;
    rfe_tyre_jac_t out[2];
    rfe_tyre_jac_t j;
    (void)state;
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    p.tyre.mode = RFE_TYRE_MAGIC;
    rfe_tyre_dugoff_pre(&p.tyre, RFE_R(0.05), RFE_R(0.02), RFE_R(20.0), &pre);
    assert_int_equal(rfe_tyre_magic_basis(&p.tyre, NULL, RFE_R(0.05), RFE_R(0.02), RFE_R(4000.0), RFE_R(20.0), RFE_R(0.8), out),
                     RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_magic_basis(&p.tyre, &pre, RFE_R(0.05), RFE_R(0.02), RFE_R(4000.0), RFE_R(20.0), RFE_R(0.8), NULL),
                     RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_magic_basis(&p.tyre, &pre, RFE_R(0.05), RFE_R(0.02), RFE_R(4000.0), RFE_R(20.0),
                                          (rfe_real_t)NAN, out),
                     RFE_ERR_NONFINITE);
    assert_int_equal(rfe_tyre_magic_basis(&p.tyre, &pre, RFE_R(0.05), RFE_R(0.02), RFE_R(4000.0), RFE_R(20.0), RFE_R(0.8), out),
                     RFE_OK);
    assert_int_equal(rfe_tyre_pre_jac(&p.tyre, &pre, RFE_R(0.05), RFE_R(0.02), RFE_R(4000.0), RFE_R(20.0), RFE_R(0.8), &ek, &j),
                     RFE_OK);
    assert_memory_equal(&out[0].dfx, &j.dfx, sizeof(j.dfx));
    assert_memory_equal(&out[0].dfy, &j.dfy, sizeof(j.dfy));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dugoff_split),
        cmocka_unit_test(test_pre_jac_forces_and_args),
        cmocka_unit_test(test_magic_basis_args),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
