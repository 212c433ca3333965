#!/usr/bin/env bash
# Issue 14: kill -9 an identification at N moments spread over its run (LM, the stability test, the
# outputs and plots), resume each with --resume, and compare with the uninterrupted run: parameters
# within 1e-10 relative and the same LM iteration count. Prints one line per kill and "k/N".
#   scripts/kill_resume.sh            # 20 kills, build/tricot, in out/kill-resume/
#   N=5 BIN=build/tricot OUT=/tmp/kr scripts/kill_resume.sh
set -euo pipefail
cd "$(dirname "$0")/.."
N=${N:-20}
BIN=$(realpath "${BIN:-build/tricot}")
OUT=${OUT:-out/kill-resume}
rm -rf "$OUT"
mkdir -p "$OUT"
cd "$OUT"

# A strip in force-controlled tension, four Mooney–Rivlin coefficients from half the truth: an
# identification of a few seconds with its stability test and plots.
case_toml() {
  cat <<TOML
[mesh]
width = 20.0
height = 60.0
element = "Q8"
nx = 4
ny = 12

[law]
type = "mooney_rivlin"
[law.mooney_rivlin]
terms = ["C10", "C20", "C21", "C03"]
values = $1

[[test]]
name = "tension"
kind = "uniaxial"
control = "force"
load_max = 5.0
steps = 16
TOML
}
{ case_toml "[0.1, -0.025, 0.015, 0.01]"; printf '\n[synth]\nnx = 5\nny = 14\n'; } > experiment.toml
{ case_toml "[0.05, -0.0125, 0.0075, 0.005]"
  printf '\n[experiment]\ndir = "exp"\n\n'
  for c in C10 C20 C21 C03; do printf '[[parameter]]\nname = "%s"\n' $c; done; } > project.toml
"$BIN" synth experiment.toml -q -o exp

ms() { date +%s%3N; }
T=
for r in 1 2 3; do  # the shortest of three: the kills then fall inside a run on a busy machine too
  rm -rf whole
  t0=$(ms)
  "$BIN" identify project.toml -q -o whole >/dev/null
  t=$(( $(ms) - t0 ))
  [ -z "$T" ] || [ "$t" -lt "$T" ] && T=$t
done
echo "uninterrupted: $T ms, $(python3 -c "import json; j=json.load(open('whole/result.json')); print(j['iterations'], 'LM iterations,', j['termination'])")"

compare() {  # prints "ok" or why not
  python3 - "$1" <<'PY'
import json, sys
a = json.load(open("whole/result.json")); b = json.load(open(sys.argv[1] + "/result.json"))
rel = max(abs(b["parameters"][k] - v) / abs(v) for k, v in a["parameters"].items())
same = b["iterations"] == a["iterations"] and b["termination"] == a["termination"]
print(("ok" if rel <= 1e-10 and same else "DIFFERS"), f"max rel {rel:.1e}, {b['iterations']} iterations")
PY
}

good=0
for i in $(seq 1 "$N"); do
  d=run_$i
  at=$(( T * i * 9 / (10 * (N + 1)) ))  # spread over the first 90 % of the run
  "$BIN" identify project.toml -q -o "$d" >/dev/null 2>&1 &
  pid=$!
  python3 -c "import time; time.sleep($at/1000)"
  kill -9 $pid 2>/dev/null || true
  wait $pid 2>/dev/null || true
  where="finished before the kill"
  if [ -f "$d/.tricot-identify/checkpoint.json" ]; then
    where=$(python3 -c "import json; c=json.load(open('$d/.tricot-identify/checkpoint.json')); print('phase', c['phase'], 'at iteration', c['iterations'])")
    [ "$where" != "${where/done/}" ] && where="$where (outputs)"
  elif [ ! -f "$d/result.json" ]; then
    where="before the first checkpoint"
  fi
  if [ -f "$d/result.json" ] && [ ! -d "$d/.tricot-identify" ]; then
    "$BIN" identify project.toml -q -o "$d" --resume >/dev/null  # a finished run: nothing to do
  elif [ "$where" = "before the first checkpoint" ]; then
    "$BIN" identify project.toml -q -o "$d" >/dev/null  # nothing to resume: run again
  else
    "$BIN" identify project.toml -q -o "$d" --resume >/dev/null
  fi
  verdict=$(compare "$d")
  [ "${verdict%% *}" = ok ] && good=$((good + 1))
  printf 'kill %2d at %5d ms (%s): %s\n' "$i" "$at" "$where" "$verdict"
done
echo "$good/$N resumed to the uninterrupted answer (1e-10 relative, same iterations)"
[ "$good" = "$N" ]
