"""Tests of scripts/firmware/firmware_pil.py's call stack (next_stack), which the inclusive
counts of make pil-profile are built on."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import firmware_pil as fp  # noqa: E402

MAIN, STEP, F, G = 0, 1, 2, 3


def test_call_and_return():
    s = fp.next_stack((), MAIN, False)            # the step starts inside main
    s = fp.next_stack(s, STEP, True)              # call
    s = fp.next_stack(s, F, True)                 # call
    assert s == (MAIN, STEP, F)
    assert fp.next_stack(s, F, False) == s        # another block of F
    assert fp.next_stack(s, STEP, False) == (MAIN, STEP)   # return
    assert fp.next_stack(s, MAIN, False) == (MAIN,)        # two returns at once (a tail call's)


def test_tail_call_returns_to_the_callers_caller():
    s = fp.next_stack((MAIN, STEP, F), G, True)   # F ends with b G: G pushed above F
    assert s == (MAIN, STEP, F, G)
    assert fp.next_stack(s, STEP, False) == (MAIN, STEP)    # G's return lands in STEP


def test_recursion_pops_to_the_innermost_frame():
    s = fp.next_stack((MAIN, F), F, True)         # F calls itself
    s = fp.next_stack(s, G, True)
    assert fp.next_stack(s, F, False) == (MAIN, F, F)
