#!/usr/bin/env bash
# Runs the cargo-fuzz targets of fuzz/ one after another, FUZZ_S seconds each, and prints a table
# of executions, exec/s, corpus size and findings per target (docs/development.md, "Fuzzing").
#
#   scripts/fuzz.sh                      every target, FUZZ_S (default 60) seconds each
#   FUZZ_S=600 FUZZ_TARGETS="bvh_parse model_file" scripts/fuzz.sh
#
# Settings (environment):
#   FUZZ_S          seconds per target (default 60)
#   FUZZ_TARGETS    targets to run, in order (default: all eight)
#   FUZZ_MALLOC_MB  allocation budget in MiB: one allocation or the live heap past it is a finding
#                   (default 256; given to libFuzzer as -malloc_limit_mb and to the targets'
#                   own allocator, which enforces it: see fuzz/src/lib.rs)
#   FUZZ_RSS_MB     libFuzzer's -rss_limit_mb for the whole process (default 1024)
#   FUZZ_TIMEOUT_S  one input taking longer is a hang (-timeout, default 10)
#   FUZZ_MAX_LEN    -max_len (default: libFuzzer's, the largest seed or 4096)
#   FUZZ_NO_CMP     targets built with --no-trace-compares, into fuzz/target-notc (default:
#                   load_pipeline long_takes; "" for none). Its time goes to the numeric crates under the
#                   methods (burn's matmul, kiddo, nalgebra): their comparisons' hooks took 60 % of
#                   it, for no guidance worth having — the bytes it mutates are the BVH grammar's,
#                   whose comparisons bvh_parse and bvh_grammar trace. Without them it runs ~3× faster.
#
# One fuzzer process at a time (no -jobs/-workers: the machines have two cores, shared). Builds
# with RUSTC_BOOTSTRAP=1 on the stable toolchain (cargo-fuzz needs nightly flags) into
# fuzz/target, never into the main crate's target folder, with --sanitizer none: the code under
# test is safe Rust, so AddressSanitizer would only cost throughput. Debug assertions are on
# (-a), so an integer overflow is a finding too. Exits 1 if any target had a finding.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
export PATH="${HOME}/.cargo/bin:${PATH}"

CARGO_FUZZ_VERSION=0.13.2
ALL_TARGETS="bvh_parse bvh_grammar load_pipeline long_takes labels_import segmentation_json model_file project_file asf_amc"
FUZZ_S="${FUZZ_S:-60}"
FUZZ_TARGETS="${FUZZ_TARGETS:-$ALL_TARGETS}"
FUZZ_MALLOC_MB="${FUZZ_MALLOC_MB:-256}"
FUZZ_RSS_MB="${FUZZ_RSS_MB:-1024}"
FUZZ_TIMEOUT_S="${FUZZ_TIMEOUT_S:-10}"
FUZZ_MAX_LEN="${FUZZ_MAX_LEN:-}"
FUZZ_NO_CMP="${FUZZ_NO_CMP-load_pipeline long_takes}"

for t in $FUZZ_TARGETS; do
    [[ " $ALL_TARGETS " == *" $t "* ]] || { echo "unknown fuzz target '$t' (known: $ALL_TARGETS)" >&2; exit 2; }
done

# cargo-fuzz, pinned; installed only when missing or another version.
have="$(cargo fuzz --version 2>/dev/null || true)"
if [[ "$have" != "cargo-fuzz $CARGO_FUZZ_VERSION" ]]; then
    echo "installing cargo-fuzz $CARGO_FUZZ_VERSION (found: ${have:-none})"
    cargo install cargo-fuzz --locked --version "$CARGO_FUZZ_VERSION"
fi

# The fuzz crate builds into fuzz/target (its instrumented build must not touch the main cache).
unset CARGO_TARGET_DIR
export RUSTC_BOOTSTRAP=1
triple="$(rustc -vV | sed -n 's/^host: //p')"
echo "building the fuzz targets ($FUZZ_TARGETS) with --sanitizer none, debug assertions on"
no_cmp() { [[ " $FUZZ_NO_CMP " == *" $1 "* ]]; }
bin_dir_of() { if no_cmp "$1"; then echo "fuzz/target-notc/$triple/release"; else echo "fuzz/target/$triple/release"; fi; }
for t in $FUZZ_TARGETS; do
    if no_cmp "$t"; then
        cargo fuzz build --sanitizer none --debug-assertions --no-trace-compares --target-dir fuzz/target-notc "$t"
    else
        cargo fuzz build --sanitizer none --debug-assertions "$t"
    fi
done

stamp="$(date -u +%Y-%m-%dT%H:%MZ)"
results="fuzz/artifacts/results-$(date -u +%Y%m%dT%H%M%SZ).txt"
mkdir -p fuzz/artifacts
rows=()
failed=0
for t in $FUZZ_TARGETS; do
    corpus="fuzz/corpus/$t"
    bin_dir="$(bin_dir_of "$t")"
    artifacts="fuzz/artifacts/$t"
    mkdir -p "$corpus" "$artifacts"
    log="fuzz/artifacts/$t.log"
    # Seeds from tests/fixtures and models/ (written by the target itself: fuzz/src/lib.rs), and
    # one pass over the corpus so a seed that fails is seen before the run.
    MOCAPSEG_FUZZ_SEED_DIR="$corpus" MOCAPSEG_FUZZ_MALLOC_MB="$FUZZ_MALLOC_MB" \
        "$bin_dir/$t" -runs=0 -rss_limit_mb="$FUZZ_RSS_MB" -timeout="$FUZZ_TIMEOUT_S" "$corpus" >"$log.seeds" 2>&1 \
        || { echo "$t: a seed fails (see $log.seeds)" >&2; tail -n 30 "$log.seeds" >&2; }
    before="$(find "$artifacts" -type f | wc -l)"
    flags=(
        -max_total_time="$FUZZ_S" -rss_limit_mb="$FUZZ_RSS_MB" -malloc_limit_mb="$FUZZ_MALLOC_MB"
        -timeout="$FUZZ_TIMEOUT_S" -print_final_stats=1 -artifact_prefix="$artifacts/"
    )
    [[ -n "$FUZZ_MAX_LEN" ]] && flags+=(-max_len="$FUZZ_MAX_LEN")
    echo "== $t: ${FUZZ_S} s (log: $log)"
    start=$(date +%s)
    status=0
    MOCAPSEG_FUZZ_MALLOC_MB="$FUZZ_MALLOC_MB" "$bin_dir/$t" "${flags[@]}" "$corpus" >"$log" 2>&1 || status=$?
    seconds=$(( $(date +%s) - start ))
    execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)"
    [[ -n "$execs" ]] || execs="$(grep -o '^#[0-9]*' "$log" | tail -n 1 | tr -d '#')"
    rate="$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n 1)"
    peak="$(sed -n 's/^stat::peak_rss_mb: *//p' "$log" | tail -n 1)"
    size="$(find "$corpus" -type f | wc -l)"
    found=$(( $(find "$artifacts" -type f | wc -l) - before ))
    if (( status != 0 || found > 0 )); then
        failed=1
        echo "$t: FINDING (exit $status); the input is in $artifacts/, the report in $log:"
        grep -E 'ERROR|panicked|budget exceeded|Test unit written' "$log" | head -n 8 || true
    fi
    rows+=("$(printf '| %-17s | %11s | %7s | %6s | %8s | %6s | %8s |' "$t" "${execs:-?}" "${rate:-?}" "$seconds" "$size" "${peak:-?}" "$found")")
done

{
    echo "fuzz run $stamp: FUZZ_S=$FUZZ_S, -rss_limit_mb=$FUZZ_RSS_MB, -malloc_limit_mb=$FUZZ_MALLOC_MB, -timeout=$FUZZ_TIMEOUT_S, --sanitizer none, --no-trace-compares for: ${FUZZ_NO_CMP:-none}"
    echo
    echo "| target            |  executions |  exec/s |      s |   corpus | rss MB | findings |"
    echo "|-------------------|-------------|---------|--------|----------|--------|----------|"
    printf '%s\n' "${rows[@]}"
} | tee "$results"
echo "(also in $results)"
exit "$failed"
