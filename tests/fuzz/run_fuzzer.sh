#!/usr/bin/env bash
# Runs one libFuzzer target for a bounded time, starting from the seed corpus (scenes/) and the
# committed regression inputs, in a scratch folder. Prints libFuzzer's tally ("Done N runs in S
# second(s)"). A crash input is left in the scratch folder and the test fails: fix the bug, then
# keep the input in tests/fuzz/regressions/<target>/.
#   run_fuzzer.sh <fuzzer> <seconds> <source dir> <scratch dir>
set -uo pipefail
fuzzer=$1 seconds=$2 src=$3 work=$4
rm -rf "$work" && mkdir -p "$work/corpus" || exit 1
cp "$src"/scenes/*.toml "$src"/tests/fuzz/regressions/*/* "$work/corpus/"
cd "$work" || exit 1
"$fuzzer" -max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=10 -max_len=16384 \
  -dict="$src/tests/fuzz/toml.dict" -print_final_stats=1 corpus >log.txt 2>&1
rc=$?
grep -E '^Done [0-9]+ runs|^stat::number_of_executed_units|ERROR|SUMMARY|Test unit written' log.txt
[ "$rc" -ne 0 ] && tail -n 40 log.txt
exit "$rc"
