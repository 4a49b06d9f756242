#!/usr/bin/env bash
# Runs the binary named by $VALGRIND_WRAP_BIN under valgrind memcheck with the given
# arguments; `make valgrind` passes this script to test/host/test_cli.sh in place of mu_replay.
# The CLI's own exit codes (0, 1, 2) pass through unchanged; valgrind reports an error with
# exit code 99, which the script also records (with the arguments) in $VALGRIND_WRAP_LOG so
# the make target fails even if the CLI check happened to expect a failure.
# (--read-inline-info=no as the Makefile's VALGRIND: a fifth of each start, ~300 starts)
set -u
BIN=${VALGRIND_WRAP_BIN:?set VALGRIND_WRAP_BIN to the mu_replay binary}
valgrind --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite,indirect -q \
    --read-inline-info=no \
    "$BIN" "$@"
rc=$?
if [ "$rc" -eq 99 ]; then
    echo "valgrind_wrap: memcheck error in: $BIN $*" >&2
    if [ -n "${VALGRIND_WRAP_LOG:-}" ]; then
        echo "valgrind: memcheck error in: $BIN $*" >>"$VALGRIND_WRAP_LOG"
    fi
fi
exit "$rc"
