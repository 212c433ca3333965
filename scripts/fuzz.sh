#!/usr/bin/env bash
# libFuzzer (issue 14): builds the harnesses of fuzz/ with clang in build-fuzz/ (-fsanitize=fuzzer,
# address,undefined; the rest of tricot linked from the ordinary build/) and runs each for
# FUZZ_SECONDS (default 600; wall time, the CPU time is reported beside it) from the seed corpus fuzz/corpus/<name>/. New inputs go to
# build-fuzz/corpus/<name>/, crashes to build-fuzz/artifacts/<name>/. `make fuzz` runs this; CI does not.
#   scripts/fuzz.sh                      # every harness, 10 minutes each
#   FUZZ_SECONDS=60 scripts/fuzz.sh csv log
#   FUZZ_CPU_SECONDS=600 scripts/fuzz.sh  # each harness until it has had 600 s of CPU (a busy machine)
# A crash fails the run; reproduce with build-fuzz/fuzz/<name>_fuzz ARTIFACT and add it as a regression
# test in the unit tests (tests/project/fuzz_regression_test.cpp).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build-fuzz}
PREBUILT=${PREBUILT:-build}
SECONDS_EACH=${FUZZ_SECONDS:-600}
JOBS=${JOBS:-2}
harnesses=(${@:-config csv image json log})

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
[ -f "$PREBUILT/build.ninja" ] || cmake -S . -B "$PREBUILT" -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}"
cmake --build "$PREBUILT" -j "$JOBS" --target tricot_project  # the libraries the harnesses link
cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DTRICOT_FUZZ=ON \
  -DTRICOT_FUZZ_PREBUILT="$(realpath "$PREBUILT")" "${launcher[@]}" >/dev/null
cmake --build "$BUILD" -j "$JOBS" --target "${harnesses[@]/%/_fuzz}"

export OPENCV_IO_MAX_IMAGE_PIXELS=16777216  # a header claiming a huge image is refused, not an OOM
status=0
printf '%-8s %8s %8s %7s %12s %10s %8s %s\n' harness wall_s cpu_s rounds executions exec/cpu_s corpus result
for h in "${harnesses[@]}"; do
  corpus="$BUILD/corpus/$h" artifacts="$BUILD/artifacts/$h/"
  mkdir -p "$corpus" "$artifacts"
  log="$BUILD/$h.log"
  result=ok
  # In rounds of FUZZ_SECONDS (wall) until the harness has had FUZZ_CPU_SECONDS of CPU (default: one
  # round); each round goes on from the corpus the last one left.
  cpu=0 execs=0 wall=0 rounds=0
  while :; do
    start=$(date +%s)
    /usr/bin/time -f '%U %S' -o "$BUILD/$h.time" "$BUILD/fuzz/${h}_fuzz" -max_total_time="$SECONDS_EACH" -max_len=4096 -rss_limit_mb=2048 -timeout=10 \
      -print_final_stats=1 -artifact_prefix="$artifacts" "$corpus" "fuzz/corpus/$h" >"$log" 2>&1 || { result="CRASH (see $log)"; status=1; }
    wall=$((wall + $(date +%s) - start)) rounds=$((rounds + 1))
    n=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    execs=$((execs + ${n:-0}))
    cpu=$(tail -1 "$BUILD/$h.time" | awk -v c="$cpu" '{printf "%.0f", c + $1 + $2}')  # the harness's own CPU, user + sys
    [ "$result" = ok ] && [ "$cpu" -lt "${FUZZ_CPU_SECONDS:-0}" ] || break
  done
  rate=$(awk -v e="$execs" -v c="$cpu" 'BEGIN {printf "%.0f", (c > 0 ? e / c : 0)}')  # per CPU second
  printf '%-8s %8s %8s %7s %12s %10s %8s %s\n' "$h" "$wall" "$cpu" "$rounds" "$execs" "$rate" "$(ls "$corpus" | wc -l)" "$result"
done
exit $status
