"""The counter-based random stream of the tyre identifier (docs/TYRE_ID.md §6).

Philox4x64-10 (Salmon, Moraes, Dror, Shaw, "Parallel random numbers: as easy as 1, 2, 3",
SC11), the generator NumPy ships as numpy.random.Philox: a block of four 64-bit words is a
pure function of a 256-bit counter (four words c0..c3) and a 128-bit key (k0, k1).  The
blocks come from NumPy's implementation (fast, and independent of this project); `block_ref`
is a plain-integer implementation of the published rounds, and the tests pin both to the
Random123 known-answer vectors, so the stream is the standard's, not a NumPy version's.

From words to numbers (§6.2), identical in C:
    uniform   u = ((w >> 12) + 0.5) * 2^-52       in [2^-53, 1 - 2^-53], exact in double
    normal    Box-Muller on the two uniforms of a pair of words (u_a, u_b):
              rho = sqrt(-2 log u_a), th = TWO_PI * u_b,  z_a = rho cos th, z_b = rho sin th
Normal n of a stream is pair n // 2 (words 2(n//2), 2(n//2)+1, i.e. block n // 4), cosine
for even n, sine for odd n.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["MASK64", "TWO_PI", "block_ref", "words", "uniforms_from_words",
           "normals_from_words", "Stream"]

MASK64 = (1 << 64) - 1
TWO_PI = 6.283185307179586          # the double nearest 2*pi (= 2.0 * math.pi exactly)
_M0, _M1 = 0xD2E7470EE14C6C93, 0xCA5A826395121157   # Philox4x64 multipliers
_W0, _W1 = 0x9E3779B97F4A7C15, 0xBB67AE8584CAA73B   # Weyl key increments


def block_ref(counter, key, rounds=10):
    """One Philox4x64 block from Python integers: counter (4 words), key (2 words)."""
    c0, c1, c2, c3 = (int(x) & MASK64 for x in counter)
    k0, k1 = (int(x) & MASK64 for x in key)
    for r in range(rounds):
        if r > 0:
            k0 = (k0 + _W0) & MASK64
            k1 = (k1 + _W1) & MASK64
        p0 = _M0 * c0
        p1 = _M1 * c2
        c0, c1, c2, c3 = ((p1 >> 64) ^ c1 ^ k0, p1 & MASK64, (p0 >> 64) ^ c3 ^ k1, p0 & MASK64)
    return [c0, c1, c2, c3]


def words(key, c1, c2, c3, n_words):
    """The first n_words words of the blocks with counters (j, c1, c2, c3), j = 0, 1, ...
    in order (block j's words 4j .. 4j+3), as a uint64 array, from numpy.random.Philox.

    NumPy's generator adds 1 to its 256-bit counter before each block, so it is started one
    below (j = 0, c1, c2, c3), with the borrow carried through the words."""
    v = (c1 << 64 | c2 << 128 | c3 << 192) - 1
    v %= 1 << 256
    start = np.array([(v >> (64 * i)) & MASK64 for i in range(4)], dtype=np.uint64)
    bg = np.random.Philox(counter=start, key=np.array(key, dtype=np.uint64))
    n_blocks = (n_words + 3) // 4
    return bg.random_raw(4 * n_blocks)[:n_words]


def uniforms_from_words(w):
    """u = ((w >> 12) + 0.5) * 2^-52: the top 52 bits, centred, never 0 or 1."""
    return ((np.asarray(w, dtype=np.uint64) >> np.uint64(12)).astype(np.float64) + 0.5) \
        * 2.220446049250313e-16


def normals_from_words(w, fn):
    """Box-Muller on consecutive word pairs; fn: the elementary functions (log, sqrt, cos,
    sin), numpy's or libm's (tyre_id.Backend).  len(w) must be even."""
    u = uniforms_from_words(w)
    ua, ub = u[0::2], u[1::2]
    rho = fn.sqrt(-2.0 * fn.log(ua))
    th = TWO_PI * ub
    z = np.empty(u.shape[0])
    z[0::2] = rho * fn.cos(th)
    z[1::2] = rho * fn.sin(th)
    return z


class Stream:
    """The identifier's draws (§6.3): key (seed, 0); counter (j, step, purpose, 0)."""

    def __init__(self, seed, fn):
        if not 0 <= int(seed) <= MASK64:
            raise ValueError("seed must be a 64-bit unsigned integer")
        self.key = (int(seed), 0)
        self.fn = fn

    def uniforms(self, step, purpose, n):
        """Uniforms 0 .. n-1 of (step, purpose): uniform j is word j."""
        return uniforms_from_words(words(self.key, step, purpose, 0, n))

    def normals(self, step, purpose, n):
        """Normals 0 .. n-1 of (step, purpose): normal j from words 2(j//2), 2(j//2)+1."""
        m = n + (n & 1)
        return normals_from_words(words(self.key, step, purpose, 0, m), self.fn)[:n]


def _self_check():
    # the constant is 2*pi rounded once (math.pi is pi rounded; doubling is exact)
    assert TWO_PI == 2.0 * math.pi


_self_check()
