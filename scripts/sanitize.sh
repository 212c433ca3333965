#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer (issue 14): builds tricot and the unit tests in
# build-sanitize/ (TRICOT_SANITIZE=address,undefined) and runs the unit tests and the examples under
# them, with stack-use-after-return detection on. `make sanitize` runs this; CI does not (it would not
# fit its 30 minutes on 2 cores). Any sanitizer report fails the run.
#   scripts/sanitize.sh                 # build-sanitize/, baseline x86-64 (see docs/validation.md)
#   BUILD=dir TRICOT_NATIVE=ON JOBS=4 scripts/sanitize.sh
#   scripts/sanitize.sh --no-tests      # the examples only
# The build is baseline x86-64 (TRICOT_NATIVE=OFF) by default: portable, and the SEGV reported under
# stack-use-after-return (issue 14) was seen only with -march=native; TRICOT_NATIVE=ON checks the
# native build (docs/validation.md §8).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build-sanitize}
JOBS=${JOBS:-2}
NATIVE=${TRICOT_NATIVE:-OFF}
run_tests=1
[ "${1:-}" = "--no-tests" ] && run_tests=0

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
t0=$(date +%s)
cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTRICOT_SANITIZE=address,undefined \
  -DTRICOT_NATIVE="$NATIVE" "${launcher[@]}" ${CMAKE_FLAGS:-} >/dev/null
targets=(tricot)
if [ $run_tests = 1 ]; then
  mapfile -t units < <(cmake --build "$BUILD" --target help | sed -n 's/^\([a-z_]*_unit_tests\):.*/\1/p')
  targets+=("${units[@]}")
fi
cmake --build "$BUILD" -j "$JOBS" --target "${targets[@]}"
t1=$(date +%s)
echo "sanitize: built ${#targets[@]} targets in $((t1 - t0)) s"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_stack_use_after_return=1:detect_leaks=1:abort_on_error=1:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
if [ $run_tests = 1 ]; then
  (cd "$BUILD" && ctest -L unit -j "$JOBS" --output-on-failure)
fi
t2=$(date +%s)

# The examples: every case simulated, the paper's synthetic experiment made and identified, and the
# lab chain (synth with images and logs, dic, experiment).
bin="$BUILD/tricot"
out="$BUILD/examples-out"
rm -rf "$out"
for c in examples/*/case.toml; do
  name=$(basename "$(dirname "$c")")
  "$bin" simulate "$c" -q -o "$out/$name"
done
mkdir -p "$out/uniaxial-mooney"
cp examples/uniaxial-mooney/project.toml "$out/uniaxial-mooney/project.toml"
"$bin" synth examples/uniaxial-mooney/experiment.toml -q -o "$out/uniaxial-mooney/experiment"
"$bin" identify "$out/uniaxial-mooney/project.toml" -q --no-plots -o "$out/uniaxial-mooney/identify"
lab="$out/lab-uniaxial"
mkdir -p "$lab"
cp examples/lab-uniaxial/*.toml "$lab/"
"$bin" synth "$lab/experiment.toml" -q -o "$lab/raw"
"$bin" dic "$lab/dic.toml" "$lab"/raw/tension/images/frame_*.png -q -o "$lab/raw/dic"
"$bin" experiment "$lab/lab.toml" -q -o "$lab/experiment"
t3=$(date +%s)
echo "sanitize: clean. build $((t1 - t0)) s, unit tests $((t2 - t1)) s, examples $((t3 - t2)) s (ASAN_OPTIONS=$ASAN_OPTIONS)"
