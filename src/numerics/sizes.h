/**
 * @file sizes.h
 * @brief Sizes derived from the compile-time maxima (rfe/config.h) as size_t, shared by the
 *        float and the fixed-point sources (no number type; not installed).
 */
#ifndef RFE_NUMERICS_SIZES_H
#define RFE_NUMERICS_SIZES_H

#include <stddef.h>

#include "rfe/config.h"

/** RFE_TRIA_COLS_MAX as a size_t, built from casts of the single constants (a cast of the
 *  composite int expression would break MISRA C:2012 Rule 10.8). Same formula, checked: */
#if RFE_TRIA_COLS_MAX != ((2 * RFE_N_MAX) + ((RFE_N_MAX > RFE_M_MAX) ? RFE_N_MAX : RFE_M_MAX))
#error "RFE_TRIA_COLS_SZ restates RFE_TRIA_COLS_MAX (config.h): keep the two formulas equal"
#endif
#define RFE_TRIA_COLS_SZ                                                                       \
    ((2u * (size_t)RFE_N_MAX) +                                                                \
     (((size_t)RFE_N_MAX > (size_t)RFE_M_MAX) ? (size_t)RFE_N_MAX : (size_t)RFE_M_MAX))

/** RFE_TRIA_ROWS_MAX and RFE_TRIA_COLS_LIMIT (config.h) as size_t, from casts of the single
 *  constants as above; the same formulas, checked: */
#if (RFE_TRIA_ROWS_MAX != ((RFE_N_MAX > RFE_TID_SCKF_N) ? RFE_N_MAX : RFE_TID_SCKF_N)) ||      \
    (RFE_TRIA_COLS_LIMIT !=                                                                    \
     ((2 * RFE_TRIA_ROWS_MAX) + ((RFE_TRIA_ROWS_MAX > RFE_M_MAX) ? RFE_TRIA_ROWS_MAX : RFE_M_MAX)))
#error "RFE_TRIA_ROWS_SZ / RFE_TRIA_COLS_LIMIT_SZ restate config.h: keep the formulas equal"
#endif
#define RFE_TRIA_ROWS_SZ                                                                       \
    (((size_t)RFE_N_MAX > (size_t)RFE_TID_SCKF_N) ? (size_t)RFE_N_MAX : (size_t)RFE_TID_SCKF_N)
#define RFE_TRIA_COLS_LIMIT_SZ                                                                 \
    ((2u * RFE_TRIA_ROWS_SZ) +                                                                 \
     ((RFE_TRIA_ROWS_SZ > (size_t)RFE_M_MAX) ? RFE_TRIA_ROWS_SZ : (size_t)RFE_M_MAX))

#endif /* RFE_NUMERICS_SIZES_H */
