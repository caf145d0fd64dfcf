#!/usr/bin/env bash
# scripts/test.sh — `make test`: every test, in stages, each one timed (scripts/stage.sh, the times at the end).
#
# The two big compilations share nothing (the native dev-profile tests and the release wasm page are different
# targets and profiles, in different folders of the one build folder, so cargo does not lock one against the other):
# the page bundle and the wasm test binary build in the background while the native tests build and run, and the two
# cores stay busy instead of each build's serial stretches (burn's two largest crates, the final link) leaving one
# idle. The background's output goes to test-output/web.log and is printed when it is waited for.
#   1. setup   scripts/setup.sh
#   2. native  cargo test (make test-native)            ‖  web  the page bundle (make web), then the wasm test
#                                                             binary compiled (make build-test-wasm)
#   3. wasm    the wasm tests in headless Chromium (make test-wasm: nothing left to compile)
#   4. e2e     Playwright against dist/ (make test-e2e)
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
STAGE=scripts/stage.sh
MAKE=${MAKE:-make}
mkdir -p test-output
: >"${STAGE_TIMES:=$PWD/test-output/stage-times.txt}"
export STAGE_TIMES
WEB_LOG=test-output/web.log

"$STAGE" setup scripts/setup.sh || exit 1

# its own process group (set -m), so that a failing native stage can stop it with everything it started
set -m
("$STAGE" web "$MAKE" web && "$STAGE" wasm-build "$MAKE" build-test-wasm) >"$WEB_LOG" 2>&1 &
web=$!
set +m
echo "test: the page bundle and the wasm test binary are building in the background (log: $WEB_LOG)"

"$STAGE" native "$MAKE" test-native
native=$?
if [ "$native" -ne 0 ]; then
    kill -- -"$web" 2>/dev/null
    wait "$web" 2>/dev/null
    echo "test: the native stage failed; the background build was stopped (its log so far: $WEB_LOG)" >&2
    exit "$native"
fi

echo "test: waiting for the page bundle and the wasm test binary (log: $WEB_LOG)"
wait "$web"
built=$?
echo "----- $WEB_LOG -----"
cat "$WEB_LOG"
echo "----- end of $WEB_LOG -----"
[ "$built" -eq 0 ] || { echo "test: building the page bundle or the wasm tests failed (above)" >&2; exit "$built"; }

"$STAGE" wasm "$MAKE" test-wasm || exit 1
"$STAGE" e2e "$MAKE" test-e2e || exit 1

echo
echo "make test: all stages passed (native, web bundle, wasm in headless Chromium, e2e). Times (native and"
echo "web+wasm-build ran at the same time):"
cat "$STAGE_TIMES"
