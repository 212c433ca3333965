#!/usr/bin/env bash
# Issue 15, ctest `mpi_identify` (label mpi): `mpirun -np N tricot identify` gives the one-process
# answer on 2 and 4 ranks (over-subscribed on CI's 2 cores, on the loopback), and its error paths
# end with the contract's exit code instead of hanging.
#   mpi_identify.sh TRICOT MPIEXEC PYTHON3 SOURCE_DIR WORK_DIR
set -euo pipefail
tricot=$1 mpiexec=$2 python=$3 src=$4 work=$5
# CI runs as root; Open MPI's mpirun refuses to unless told.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_WAIT_POLICY=passive
mpirun() { timeout 120 "$mpiexec" --oversubscribe "$@"; }

rm -rf "$work"
mkdir -p "$work"
cp "$src/project.toml" "$work/"
"$tricot" synth "$src/experiment.toml" -o "$work/experiment" -q
"$tricot" identify "$work/project.toml" -o "$work/np1" -q --no-plots
for n in 2 4; do
  mpirun -np $n "$tricot" identify "$work/project.toml" -o "$work/np$n" -q --no-plots
done
"$python" - "$work" <<'PY'
import json, sys
# The ranks run each test's arithmetic unchanged, so the answer is the same to the last bit; the
# contract asks for 1e-12 relative.
TOL = 1e-12
work = sys.argv[1]
one = json.load(open(f"{work}/np1/result.json"))
ok = True
for n in (2, 4):
    r = json.load(open(f"{work}/np{n}/result.json"))
    for key in ("iterations", "evaluations", "termination"):
        if r[key] != one[key]:
            print(f"np {n}: {key} {r[key]} != {one[key]}"); ok = False
    if r["ranks"] != n or one["ranks"] != 1:  # result.json records the processes (issue 34)
        print(f"np {n}: result.json ranks {r['ranks']}, one process {one['ranks']}"); ok = False
    pairs = [("objective", r["objective"], one["objective"])]
    pairs += [(f"parameters.{k}", r["parameters"][k], v) for k, v in one["parameters"].items()]
    pairs += [(f"std_error.{k}", r["std_error"][k], v) for k, v in one["std_error"].items()]
    for name, a, b in pairs:
        if abs(a - b) > TOL * abs(b):
            print(f"np {n}: {name} {a!r} != {b!r}"); ok = False
    same = all(a == b for _, a, b in pairs)
    print(f"np {n}: f = {r['objective']!r}, {r['iterations']} iterations, {'bit-identical' if same else 'within 1e-12'}")
sys.exit(0 if ok else 1)
PY

# A project missing on every rank: rank 0 says so, exit 3, no rank left waiting.
set +e
mpirun -np 2 "$tricot" identify "$work/missing.toml" -o "$work/x" -q 2> "$work/err1"
rc=$?
set -e
[ $rc -eq 3 ] || { echo "missing project: exit $rc, expected 3"; cat "$work/err1"; exit 1; }
grep -q "^tricot: error: .*missing.toml: file not found" "$work/err1"
# A rank that cannot build the objective while rank 0 can (its files differ, e.g. on another node):
# rank 0 reports that rank's error, exit 3.
sed 's/^dir = "experiment"/dir = "nowhere"/' "$work/project.toml" > "$work/bad.toml"
set +e
mpirun -np 1 "$tricot" identify "$work/project.toml" -o "$work/y" -q : -np 1 "$tricot" identify "$work/bad.toml" -o "$work/y" -q 2> "$work/err2"
rc=$?
set -e
[ $rc -eq 3 ] || { echo "rank 1's bad project: exit $rc, expected 3"; cat "$work/err2"; exit 1; }
grep -q "^tricot: error: .*experiment.dir: experiment folder not found.*(on MPI rank 1)$" "$work/err2"
[ ! -e "$work/y/result.json" ]
echo "mpi_identify: ok"
