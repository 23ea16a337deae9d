#!/bin/sh
# Longer fuzzing (make fuzz; docs/testing.md): each libFuzzer target of
# build/ctest/fuzz for SECONDS (default 600), one after the other, from the
# committed seeds fuzz/corpus/<target>/ and a working corpus build/fuzz/<target>/
# that is kept from run to run (it grows). Findings: build/fuzz/artifacts/.
#
#   sh fuzz/run_long.sh [SECONDS] [TARGET ...]
#
# Exits non-zero when a target found a crash, UB or a broken property; the
# executions and new inputs of each target are printed.
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
bin=$root/build/ctest/fuzz
out=$root/build/fuzz
secs=${1:-600}
[ $# -gt 0 ] && shift
targets=${*:-fuzz_math fuzz_blocks fuzz_lcl_obs fuzz_drive fuzz_plant fuzz_engine}
mkdir -p "$out/artifacts"
status=0
for t in $targets; do
    if [ ! -x "$bin/$t" ]; then
        echo "$t: not built ($bin/$t): make ctest or make fuzz first" >&2
        status=1
        continue
    fi
    mkdir -p "$out/$t"
    echo "$t: fuzzing for $secs s"
    "$bin/$t" -max_total_time="$secs" -max_len=8192 -timeout=10 -rss_limit_mb=2048 \
        -print_final_stats=1 -artifact_prefix="$out/artifacts/$t-" \
        "$out/$t" "$root/fuzz/corpus/$t" >"$out/$t.log" 2>&1
    rc=$?
    grep -E '^(Done|stat::number_of_executed_units|stat::new_units_added)' "$out/$t.log" |
        sed "s/^/  /"
    if [ $rc -ne 0 ]; then
        echo "$t: FAILED (exit $rc): see $out/$t.log; input in $out/artifacts/" >&2
        status=1
    fi
done
exit $status
