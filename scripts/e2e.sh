#!/usr/bin/env bash
# scripts/e2e.sh [DIST] — serve the built page (default: dist/) on a free loopback port, run the
# Playwright end-to-end tests (every tests/e2e/*.test.mjs, one file after another, each with its
# own browser) against it, and always stop the server. Screenshots and the server log go to
# test-output/. E2E_FILES="labels.test.mjs" runs only the files named; a node --test filter can be
# passed through E2E_NAME (a test name pattern, e.g. E2E_NAME="timeline"). E2E_JOBS=2 runs two files at a time (on
# 2 cores: 5 min 44 s instead of 6 min 36 s, every file slower: docs/benchmarks.md; the default is one at a time).
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
DIST=$(cd "${1:-$ROOT/dist}" && pwd)
OUT="$ROOT/test-output"
mkdir -p "$OUT"

[ -f "$DIST/index.html" ] || { echo "e2e: $DIST/index.html missing: run 'make web' first" >&2; exit 1; }
[ -d "$ROOT/tests/e2e/node_modules/playwright-core" ] || { echo "e2e: playwright-core missing: run 'make setup'" >&2; exit 1; }

# Port 0: the kernel picks a free port; http.server prints it (-u: unbuffered).
LOG="$OUT/e2e-server.log"
# created here, not by the background job's redirect: that job may not have opened it yet when the loop below first
# reads it (a busy machine; `set -e` with pipefail then stopped the run at the first read)
: >"$LOG"
python3 -u -m http.server 0 --bind 127.0.0.1 --directory "$DIST" >"$LOG" 2>&1 &
SERVER_PID=$!
cleanup() {
    kill "$SERVER_PID" 2>/dev/null || true
    wait "$SERVER_PID" 2>/dev/null || true
}
trap cleanup EXIT INT TERM

PORT=""
for _ in $(seq 1 300); do  # up to 30 s: python on a busy machine
    PORT=$(sed -n 's/.* port \([0-9][0-9]*\).*/\1/p' "$LOG" | head -n 1 || true)
    [ -n "$PORT" ] && break
    kill -0 "$SERVER_PID" 2>/dev/null || { cat "$LOG" >&2; echo "e2e: static server died" >&2; exit 1; }
    sleep 0.1
done
[ -n "$PORT" ] || { cat "$LOG" >&2; echo "e2e: static server did not start" >&2; exit 1; }

echo "e2e: serving $DIST on http://127.0.0.1:$PORT/"
cd "$ROOT/tests/e2e"
# a Node ≥ 20 that scripts/setup.sh installed when the system's is older (Debian 12 ships 18)
for bin in "$ROOT"/.tools/node/node_modules/node-linux-*/bin; do
    [ -x "$bin/node" ] && PATH="$bin:$PATH"
done
files=${E2E_FILES:-$(ls *.test.mjs | sort)}
filter=()
[ -n "${E2E_NAME:-}" ] && filter=(--test-name-pattern="$E2E_NAME")
# the native CLI, for the tests that compare the page's numbers with `mocapseg eval` (truth.test.mjs)
export MOCAPSEG_BIN="${MOCAPSEG_BIN:-${CARGO_TARGET_DIR:-$ROOT/target}/debug/mocapseg}"
# each file's wall-clock seconds, into test-output/e2e-times.txt (which files make the stage long)
TIMES="$OUT/e2e-times.txt"
: >"$TIMES"
# E2E_JOBS files at a time (default 1: one after another, output as it comes), each with its own browser; with more
# than one, a file's output is printed whole once every file ended, so that two files' lines do not interleave
JOBS=${E2E_JOBS:-1}
LOGS=$(mktemp -d)
run_file() {
    local f=$1 t0 status=ok
    t0=$(date +%s)
    BASE_URL="http://127.0.0.1:$PORT/" OUT_DIR="$OUT" FIXTURES="$ROOT/tests/fixtures" SAMPLE_BVH="$DIST/www/sample.bvh" \
        node "${filter[@]}" "$f" >"$LOGS/$f.log" 2>&1 || status=FAILED
    { echo "e2e: $f ($status)"; cat "$LOGS/$f.log"; } >"$LOGS/$f.out"
    printf '%-28s %4d s  %s\n' "$f" "$(( $(date +%s) - t0 ))" "$status" >>"$TIMES"
    [ "$status" = ok ]
}
failed=0
running=()
pids=()
for f in $files; do
    if [ "$JOBS" -le 1 ]; then
        echo "e2e: $f"
        t0=$(date +%s)
        status=ok
        BASE_URL="http://127.0.0.1:$PORT/" OUT_DIR="$OUT" FIXTURES="$ROOT/tests/fixtures" SAMPLE_BVH="$DIST/www/sample.bvh" \
            node "${filter[@]}" "$f" || { failed=1; status=FAILED; }
        printf '%-28s %4d s  %s\n' "$f" "$(( $(date +%s) - t0 ))" "$status" >>"$TIMES"
        continue
    fi
    # (not `jobs`/`wait`: the static server is a child too)
    while :; do
        alive=0
        for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null && alive=$((alive + 1)); done
        [ "$alive" -lt "$JOBS" ] && break
        sleep 0.2
    done
    run_file "$f" &
    pids+=($!)
    running+=("$f")
done
if [ "$JOBS" -gt 1 ]; then
    for p in "${pids[@]}"; do wait "$p" || true; done
    for f in "${running[@]}"; do cat "$LOGS/$f.out"; done
    grep -q FAILED "$TIMES" && failed=1
fi
rm -rf "$LOGS"
echo "e2e: seconds per file (slowest first):"
sort -k2 -n -r "$TIMES"
exit "$failed"
