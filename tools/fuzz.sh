#!/bin/sh
# fuzz.sh BUILD SECONDS [TARGET...] - runs each libFuzzer target of BUILD/fuzz for
# SECONDS on a corpus seeded from the repository's test inputs (`make fuzz`), one
# after the other, and prints each one's executions, speed and result.  A crash, leak,
# timeout or allocation over 2 GB leaves its input in BUILD/crashes/ and makes the exit
# status 1.  $FUZZ_FLAGS goes to every fuzzer (e.g. -malloc_limit_mb=8192).
set -u
build=$1
secs=$2
shift 2
targets=${*:-yaml project rules grid stl obj points layout}
status=0
summary=""
seeds() {
    case $1 in
    yaml) ls tests/bad/*.yaml tests/bad_rules/* tests/data/project/*.yaml projects/*/*.yaml rules/*.yaml ;;
    project) ls tests/bad/*.yaml tests/data/project/*.yaml projects/*/*.yaml ;;
    rules) ls tests/bad_rules/* rules/*.yaml tests/data/project/rules.yaml ;;
    grid) ls tests/data/project/*.asc tests/data/terrain/*.asc ;;
    stl) ls tests/data/project/*.stl tests/data/terrain/*.stl ;;
    obj) ls tests/data/project/*.obj tests/data/terrain/*.obj ;;
    points) ls tests/fuzz/seeds/points/* ;;
    layout) ls tests/fuzz/seeds/layout/* ;;
    esac 2>/dev/null
}
for t in $targets; do
    bin=$build/fuzz/fuzz_$t
    corpus=$build/corpus/$t
    crashes=$build/crashes
    mkdir -p "$corpus" "$crashes" "$build/logs"
    for f in $(seeds "$t"); do
        [ -f "$f" ] && cp "$f" "$corpus/seed-$(basename "$f")"
    done
    log=$build/logs/$t.log
    echo "fuzz_$t: $secs s on $(ls "$corpus" | wc -l) inputs (log $log)"
    # the target's scratch folder, removed here even when libFuzzer exits without
    # running the target's atexit (a crash, an out-of-memory)
    RF_FUZZ_DIR=$(mktemp -d /dev/shm/rf_fuzz.XXXXXX 2>/dev/null || mktemp -d)
    export RF_FUZZ_DIR
    "$bin" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
        -print_final_stats=1 -artifact_prefix="$crashes/$t-" ${FUZZ_FLAGS:-} "$corpus" \
        >"$log" 2>&1
    rc=$?
    rm -rf "$RF_FUZZ_DIR"
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
    if [ $rc -eq 0 ]; then
        result="no crash, leak or timeout"
    else
        result="FAILED (exit $rc): $(grep -m1 -E 'ERROR|SUMMARY|timeout|leak' "$log")"
        status=1
    fi
    line="fuzz_$t: ${execs:-?} executions, ${speed:-?}/s: $result"
    echo "$line"
    summary="$summary$line
"
done
printf '\nfuzz summary (%s s each):\n%s' "$secs" "$summary"
exit $status
