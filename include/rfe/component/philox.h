/**
 * @file philox.h
 * @brief The counter-based random stream of the tyre identifier (docs/TYRE_ID.md §6):
 *        Philox4x64-10 (Salmon, Moraes, Dror, Shaw, SC11 2011), uniforms and Box-Muller
 *        normals from its words, the same numbers as the reference (scripts/reference/
 *        philox.py) bit for bit in double.
 *
 * A block of four 64-bit words is a pure function of a 256-bit counter (c0..c3) and a
 * 128-bit key (k0, k1): any draw can be made in any order, so a particle's noise depends
 * only on (sample, purpose, particle). Portable C99: the 64 x 64 -> 128 bit products are
 * formed from 32-bit halves (no compiler extension).
 *
 * A stream (rfe_philox_t) fixes the key (seed, 0) and the counter words c1, c2 (c3 = 0);
 * its word n is word n mod 4 of the block with c0 = n / 4. It caches the last block, so
 * reading the words in order costs one block per four words.
 */
#ifndef RFE_PHILOX_H
#define RFE_PHILOX_H

#include "rfe/types.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. The block
 * itself has no real type; it carries the suffix so that both libraries link into one
 * program (docs/LAYOUT.md "Names"). */
#if defined(RFE_REAL_DOUBLE)
#define rfe_philox_block       rfe_philox_block_f64
#define rfe_philox_stream      rfe_philox_stream_f64
#define rfe_philox_word        rfe_philox_word_f64
#define rfe_philox_uniform     rfe_philox_uniform_f64
#define rfe_philox_normal_pair rfe_philox_normal_pair_f64
#else
#define rfe_philox_block       rfe_philox_block_f32
#define rfe_philox_stream      rfe_philox_stream_f32
#define rfe_philox_word        rfe_philox_word_f32
#define rfe_philox_uniform     rfe_philox_uniform_f32
#define rfe_philox_normal_pair rfe_philox_normal_pair_f32
#endif

/** Words per Philox4x64 block. */
/* cppcheck-suppress misra-c2012-2.4 ; MISRA-FP-01: an anonymous enum has no tag */
enum { RFE_PHILOX_WORDS = 4 };

/** One stream: key (seed, 0), counter (j, c1, c2, 0), and the last block computed. */
typedef struct {
    uint64_t key[2];                /**< k0 = seed, k1 = 0 */
    uint64_t c1;                    /**< counter word c1 (the tyre identifier: the sample) */
    uint64_t c2;                    /**< counter word c2 (the tyre identifier: the purpose) */
    uint64_t block;                 /**< c0 of the cached block */
    uint64_t w[RFE_PHILOX_WORDS];   /**< the cached block's words */
    uint32_t cached;                /**< 1 when w holds block `block` */
} rfe_philox_t;

/**
 * One Philox4x64-10 block.
 * @param[in]  ctr  the counter c0..c3.
 * @param[in]  key  the key k0, k1.
 * @param[out] out  the four words.
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_philox_block(const uint64_t ctr[RFE_PHILOX_WORDS],
                                            const uint64_t key[2],
                                            uint64_t out[RFE_PHILOX_WORDS]);

/**
 * Sets up the stream of key (seed, 0) and counter words c1, c2 (c3 = 0); nothing cached.
 * @param[out] s  the stream.
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_philox_stream(rfe_philox_t *s, uint64_t seed, uint64_t c1,
                                             uint64_t c2);

/**
 * Word n of the stream: word n mod 4 of the block with c0 = n / 4.
 * @param[in,out] s  the stream (its cache is updated).
 * @param[out]    w  the word.
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_philox_word(rfe_philox_t *s, uint64_t n, uint64_t *w);

/**
 * Uniform n of the stream (TYRE_ID.md §6.2), from word n: in double
 * u = ((w >> 12) + 0.5) 2^-52, in float u = ((w >> 41) + 0.5) 2^-23; exact, never 0 or 1.
 * @param[in,out] s  the stream.
 * @param[out]    u  the uniform.
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_philox_uniform(rfe_philox_t *s, uint64_t n, rfe_real_t *u);

/**
 * Normals 2p and 2p + 1 of the stream (TYRE_ID.md §6.2) by Box-Muller on the uniforms of
 * words 2p, 2p + 1 (u_a, u_b): rho = sqrt(-2 log u_a), th = TWO_PI u_b, z[0] = rho cos th,
 * z[1] = rho sin th (TWO_PI the double nearest 2 pi, rounded to float in the float build).
 * @param[in,out] s  the stream.
 * @param[out]    z  the two normals.
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_philox_normal_pair(rfe_philox_t *s, uint64_t p,
                                                  rfe_real_t z[2]);

#endif /* RFE_PHILOX_H */
