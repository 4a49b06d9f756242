/**
 * @file test_light.h
 * @brief Light mode for the long back-to-back tests: `make valgrind` sets RFE_TEST_LIGHT=1,
 *        because memcheck runs ~40x slower than native and its purpose is memory errors, not
 *        input coverage. In light mode a test walks a subset of its logs / random inputs
 *        (some take fewer branches: see COV_LIGHT_TESTS in the Makefile); `make test-c` and `make sanitize` always run the
 *        full set, `make coverage` the light subsets of the tests in COV_LIGHT_TESTS (Makefile:
 *        with them it covers the same lines and branches as with every full set).
 */
#ifndef RFE_TEST_LIGHT_H
#define RFE_TEST_LIGHT_H

#include <stdlib.h>

/** 1 when the environment asks for the light mode (RFE_TEST_LIGHT set, not "0"). */
static inline int rfe_test_light(void)
{
    const char *e = getenv("RFE_TEST_LIGHT");
    return (e != NULL) && (e[0] != '\0') && !((e[0] == '0') && (e[1] == '\0'));
}

/** Stride over a list: 1 normally, @p light_stride in light mode. */
static inline size_t rfe_test_stride(size_t light_stride)
{
    return rfe_test_light() ? light_stride : 1u;
}

#endif /* RFE_TEST_LIGHT_H */
