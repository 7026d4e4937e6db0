#!/usr/bin/env bash
# Runs the libFuzzer targets of the readers (tests/fuzz/, built by the `fuzz` preset; docs/fuzzing.md).
#
#   scripts/fuzz.sh seeds                 gathers the seed corpus into build/fuzz/seeds/<target>/
#   scripts/fuzz.sh ci RUNS [TARGET...]   RUNS executions per target from the seeds alone (fixed fuzzer seed);
#                                         what .ci/run does
#   scripts/fuzz.sh run RUNS [TARGET...]  RUNS executions per target (-1: until stopped or a finding), growing
#                                         the kept corpus build/fuzz/corpus/<target>/; for long runs
#
# Every run prints one line per target (executions, exec/s, new inputs) and a closing line; a finding (crash,
# hang over FUZZ_TIMEOUT s, leak, sanitizer report, an input over FUZZ_RSS_MB of memory) is saved under
# build/fuzz/findings/<target>/ and makes the script exit 1. FUZZ_MAX_LEN caps the input size (default 32768),
# FUZZ_SECONDS caps each target's time in `run` (default: none), BUILD the build folder (default build/fuzz).
# The shared test data is taken from $TRIDEX_SHARED_DATA, else ../shared/data beside this checkout or beside
# its main checkout; when none exists the seeds are tridex's own and assets/'s, and a note says so.
set -euo pipefail
cd "$(dirname "$0")/.."

BUILD="${BUILD:-build/fuzz}"
TARGETS_ALL=(off ply obj stl tdx scene display_config recording journal dtrack net falcon sealed shared cluster_wire)
MAX_LEN="${FUZZ_MAX_LEN:-32768}"
TIMEOUT="${FUZZ_TIMEOUT:-10}"
RSS_MB="${FUZZ_RSS_MB:-2048}"
SEED_MAX_BYTES=200000  # shared meshes larger than this (the bunny, Wuson) are left out: too slow to mutate

shared_data() {
    if [ -n "${TRIDEX_SHARED_DATA:-}" ] && [ -d "$TRIDEX_SHARED_DATA" ]; then echo "$TRIDEX_SHARED_DATA"; return; fi
    if [ -d ../shared/data ]; then echo "$(cd ../shared/data && pwd)"; return; fi
    local common
    common="$(git rev-parse --path-format=absolute --git-common-dir 2>/dev/null || true)"
    if [ -n "$common" ] && [ -d "$(dirname "$common")/../shared/data" ]; then
        echo "$(cd "$(dirname "$common")/../shared/data" && pwd)"
    fi
}

# Copies each FILE no larger than SEED_MAX_BYTES into DIR.
copy_small() {
    local dir="$1"; shift
    mkdir -p "$dir"
    for f in "$@"; do
        [ -f "$f" ] || continue
        [ "$(stat -c %s "$f")" -le "$SEED_MAX_BYTES" ] && cp -f "$f" "$dir/"
    done
    return 0
}

gather_seeds() {
    local seeds="$BUILD/seeds"
    rm -rf "$seeds"
    mkdir -p "$seeds"
    "$BUILD/tests/fuzz/fuzz_seeds" "$seeds"
    copy_small "$seeds/off" assets/*.off
    local f
    for f in assets/*.json; do
        case "$f" in *display*) copy_small "$seeds/display_config" "$f" ;; *) copy_small "$seeds/scene" "$f" ;; esac
    done
    local data
    data="$(shared_data)"
    if [ -z "$data" ]; then
        echo "fuzz: note: no shared test data (../shared/data); seeds are tridex's own and assets/'s"
    else
        local ext
        for ext in off ply obj stl; do
            copy_small "$seeds/$ext" "$data"/meshes/*."$ext" "$data"/bad/*."$ext"
        done
    fi
    local t
    for t in "${TARGETS_ALL[@]}"; do mkdir -p "$seeds/$t"; done
    echo "fuzz: seeds in $seeds: $(find "$seeds" -type f | wc -l) files"
}

# run_target MODE RUNS TARGET: one libFuzzer run; prints the target's line; returns 1 on a finding.
run_target() {
    local mode="$1" runs="$2" t="$3"
    local bin="$BUILD/tests/fuzz/fuzz_$t" corpus log findings
    if [ "$mode" = ci ]; then corpus="$BUILD/ci-corpus/$t"; rm -rf "$corpus"; else corpus="$BUILD/corpus/$t"; fi
    findings="$BUILD/findings/$t"
    log="$BUILD/logs/$t.log"
    mkdir -p "$corpus" "$findings" "$(dirname "$log")"
    local args=(-runs="$runs" -max_len="$MAX_LEN" -timeout="$TIMEOUT" -rss_limit_mb="$RSS_MB" -print_final_stats=1
                -artifact_prefix="$findings/")
    [ "$mode" = ci ] && args+=(-seed=1)
    [ "$mode" = run ] && [ -n "${FUZZ_SECONDS:-}" ] && args+=(-max_total_time="$FUZZ_SECONDS")
    local rc=0
    LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0" nice -n 10 "$bin" "${args[@]}" "$corpus" "$BUILD/seeds/$t" >"$log" 2>&1 || rc=$?
    local done_runs secs rate
    done_runs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
    rate="$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)"
    secs="$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1)"
    if [ "$rc" -ne 0 ]; then
        echo "fuzz: $t: FINDING (exit $rc) after ${done_runs:-?} executions; log $log, inputs in $findings/"
        grep -m3 -E 'ERROR|SUMMARY|tridex fuzz:|terminate|Exception' "$log" | sed 's/^/fuzz:   /' || true
        return 1
    fi
    local speed="${secs:-?} s (${rate:-?} exec/s)"
    [ "${secs:-}" = 0 ] && speed="under 1 s"
    echo "fuzz: $t: ${done_runs:-?} executions in $speed, corpus $(find "$corpus" -type f | wc -l) inputs, no findings"
}

main() {
    local cmd="${1:-}"
    case "$cmd" in
        seeds) gather_seeds; return ;;
        ci | run) ;;
        *) sed -n '2,16p' "$0"; exit 2 ;;
    esac
    local runs="${2:?RUNS}"
    shift 2
    local targets=("$@")
    [ ${#targets[@]} -eq 0 ] && targets=("${TARGETS_ALL[@]}")
    gather_seeds
    local t0 failed=() total=0 n
    t0=$(date +%s)
    for t in "${targets[@]}"; do
        run_target "$cmd" "$runs" "$t" || failed+=("$t")
        n="$(sed -n 's/^stat::number_of_executed_units: *//p' "$BUILD/logs/$t.log" | tail -1)"
        total=$((total + ${n:-0}))
    done
    local took=$(( $(date +%s) - t0 ))
    if [ ${#failed[@]} -ne 0 ]; then
        echo "fuzz: FAILED: findings in ${failed[*]} (${#targets[@]} targets, $total executions, $took s)"
        return 1
    fi
    echo "fuzz: passed: ${#targets[@]} targets, $total executions, no findings, $took s"
}

main "$@"
