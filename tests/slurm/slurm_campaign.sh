#!/usr/bin/env bash
# Issue 34, ctest `slurm_campaign` (label slurm): examples/knit-campaign/campaign.slurm under a real
# single-node Slurm. Starts munged, slurmctld and `slurmd -N localhost` from Debian's packages with a
# minimal generated slurm.conf (2 CPUs, no cgroups, no accounting) in a temporary folder; then, as a
# job user that is not root, runs README.md's "Running campaigns on a cluster" lines on a folder laid
# out as the repository (this folder's Table 1-scale stand-ins in place of the knit campaign's
# projects) and checks:
#   - every task of the two-project array (2 MPI ranks each) exits 0, and f, the coefficients, the
#     iterations and evaluations equal a plain one-process run's; result.json says 2 ranks × 1 thread;
#     the same with the script's other launcher (LAUNCHER=srun: srun --mpi=pmix) on one project;
#   - a plain `srun -n 2 tricot identify` is refused: one line, exit 2, nothing written;
#   - a project that does not converge ends its task with 0 and a `did not converge` line, or with 4
#     under STRICT_CONVERGENCE=1;
#   - the script submitted from another folder names what is missing (exit 2).
# Stops the daemons by their PIDs. Exit 77 (ctest SKIP_RETURN_CODE) only where the daemons cannot start
# at all: not root, a program missing, or a daemon that exits at start; the reason is printed.
#   slurm_campaign.sh TRICOT PYTHON3 SOURCE_DIR
set -euo pipefail
tricot=$1 python=$2 src=$3
here=$src/tests/slurm
export PATH=$PATH:/usr/sbin:/sbin  # slurmctld, slurmd, munged, useradd
job_user=tricot-slurm
started=$SECONDS

say() { echo "slurm_campaign: [$((SECONDS - started)) s] $*"; }
skip() {
  say "SKIPPED: $*"
  exit 77
}
[ "$(id -u)" -eq 0 ] || skip "not root: slurmd must run as root to start jobs as another user (CI runs as root)"
for p in munged slurmctld slurmd sbatch srun scontrol sinfo mpirun runuser useradd; do
  command -v "$p" > /dev/null || skip "$p not found (scripts/install-deps installs slurm-wlm, munge and openmpi-bin)"
done

# Everything in one folder that the job user can enter (the build tree may sit under /root).
tmp=$(mktemp -d /tmp/tricot-slurm.XXXXXX)
chmod 755 "$tmp"
pids=()
stop_daemons() {
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2> /dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2> /dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2> /dev/null || true
  done
  pids=()
}
show_logs() {
  [ -f "$tmp/slurm.conf" ] && SLURM_CONF=$tmp/slurm.conf squeue -o "%i %T %r" 2> /dev/null || true
  for f in "$tmp"/munge/munged.log "$tmp"/slurmctld.log "$tmp"/slurmd.log "$tmp"/site/*.log; do
    [ -f "$f" ] && { echo "---- $f"; tail -n 25 "$f"; }
  done
}
cleanup() {
  local rc=$?
  stop_daemons
  [ $rc -eq 0 ] || [ $rc -eq 77 ] || show_logs
  if [ -n "${KEEP_SLURM_TEST:-}" ]; then say "kept $tmp"; else rm -rf "$tmp"; fi
  exit $rc
}
trap cleanup EXIT

# The job user: not root (Open MPI and Slurm as a cluster's users see them).
id -u "$job_user" > /dev/null 2>&1 || useradd --system --no-create-home --shell /usr/sbin/nologin "$job_user"
# Every command under a time limit: a job that pends (a request the node cannot meet) would wait forever.
as_user() { runuser -u "$job_user" -- env SLURM_CONF="$tmp/slurm.conf" PATH="$PATH" timeout 90 "$@"; }

# munged as the munge user, with its own key and socket (munged checks that only it can write them).
mkdir -m 755 "$tmp/munge"
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chmod 600 "$tmp/munge/munge.key"
chown -R munge:munge "$tmp/munge"
# It forks into the background once its socket is up, and writes its own PID.
runuser -u munge -- munged --socket="$tmp/munge/socket" --key-file="$tmp/munge/munge.key" \
  --log-file="$tmp/munge/munged.log" --pid-file="$tmp/munge/munged.pid" --seed-file="$tmp/munge/munged.seed" \
  > "$tmp/munged.out" 2>&1 || { cat "$tmp/munged.out"; skip "munged did not start"; }
pids+=("$(cat "$tmp/munge/munged.pid")")
[ -S "$tmp/munge/socket" ] || { show_logs; skip "munged did not start"; }

# Two free ports on the loopback for slurmctld and slurmd.
read -r ctld_port slurmd_port < <("$python" -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
mkdir "$tmp/ctld" "$tmp/slurmd"
# The node's memory as Slurm counts it (MB), less a tenth: campaign.slurm asks for --mem-per-cpu=1G.
memory_mb=$(awk '/^MemTotal:/ {print int($2 / 1024 * 0.9)}' /proc/meminfo)
cat > "$tmp/slurm.conf" << EOF
ClusterName=tricot-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$tmp/munge/socket
StateSaveLocation=$tmp/ctld
SlurmdSpoolDir=$tmp/slurmd
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
# sbatch --wait polls every 2 s while 2 s < MinJobAge / 2 fails, else it backs off to 32 s.
MinJobAge=4
ReturnToService=2
MailProg=/bin/true
NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 RealMemory=$memory_mb State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$tmp/slurm.conf
slurmctld -D -i > "$tmp/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N localhost > "$tmp/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do
  state=$(sinfo -h -n localhost -o %T 2> /dev/null || true)
  [ "$state" = idle ] && break
  for pid in "${pids[@]}"; do kill -0 "$pid" 2> /dev/null || { show_logs; skip "a daemon (PID $pid) exited at start"; }; done
  sleep 0.2
done
[ "$state" = idle ] || { say "the daemons run but the node never became idle (state '$state') within 20 s"; exit 1; }
say "munged, slurmctld and slurmd up (ports $ctld_port, $slurmd_port)"

# The site: the repository's layout with the stand-in projects, owned by the job user.
site=$tmp/site
mkdir -p "$site/build" "$site/examples/knit-campaign"
cp "$tricot" "$site/build/tricot"
cp "$src/examples/knit-campaign/campaign.slurm" "$site/examples/knit-campaign/"
cp "$here"/experiment.toml "$here"/project-110.toml "$here"/project-150.toml "$here"/project-cut.toml "$here"/project-bind.toml \
  "$site/examples/knit-campaign/"
# The strict run's own copy: two runs at once into one output folder are refused (the folder's lock).
cp "$here"/project-cut.toml "$site/examples/knit-campaign/project-cut-strict.toml"
chown -R "$job_user" "$site"

# README.md's lines: the first sh block of "Running campaigns on a cluster".
awk '/^#+ Running campaigns on a cluster/ {s = 1} s && /^```sh/ {b = 1; next} b && /^```/ {exit} b' \
  "$src/README.md" > "$tmp/readme.sh"
grep -q "sbatch" "$tmp/readme.sh" || { echo "README.md: no sbatch line in 'Running campaigns on a cluster'"; exit 1; }
say "README.md's lines:"
sed 's/^/  /' "$tmp/readme.sh"
( cd "$site" && as_user bash -euo pipefail "$tmp/readme.sh" ) > "$tmp/readme.out" 2>&1 || {
  echo "README.md's lines failed (exit $?):"
  cat "$tmp/readme.out"
  exit 1
}
job=$(sed -n 's/^Submitted batch job \([0-9]*\)$/\1/p' "$tmp/readme.out" | tail -n 1)
[ -n "$job" ] || { echo "no job id in:"; cat "$tmp/readme.out"; exit 1; }
# `sbatch --wait` returned 0 (the block runs under -e): the highest exit code of the array's tasks.
# Each task's log says which project it ran and that tricot exited 0 (the script's `converged` line).
for task in 0 1; do
  p=$( [ $task -eq 0 ] && echo project-110 || echo project-150)
  log=$site/tricot-campaign-${job}_$task.log
  grep -q "^campaign: task $task: examples/knit-campaign/$p.toml on 2 MPI ranks x 1 threads" "$log" &&
    grep -q "^campaign: examples/knit-campaign/$p.toml converged" "$log" ||
    { echo "task $task: no 'converged' line for $p in $log:"; cat "$log"; exit 1; }
done
say "job $job: both tasks exited 0 ($(scontrol show job "$job" 2> /dev/null | grep -o 'ExitCode=[0-9:]*' | paste -sd' '))"

# The same projects in one plain process each (threads = 0: every core), as root outside Slurm.
for p in project-110 project-150; do
  env -u SLURM_CONF "$tricot" identify "$site/examples/knit-campaign/$p.toml" -o "$tmp/plain/$p" -q --no-plots > /dev/null
done
# The script's other launcher, srun --mpi=pmix (Debian's Slurm and Open MPI both have PMIx), on one project.
( cd "$site" && as_user env LAUNCHER=srun OUT=out/srun sbatch --wait --ntasks=2 --array=0 --output=srun-%A_%a.log \
  examples/knit-campaign/campaign.slurm ) > /dev/null ||
  { echo "LAUNCHER=srun: the task failed:"; cat "$site"/srun-*.log; exit 1; }
grep -q "(srun --mpi=pmix --ntasks=2 --cpus-per-task=1)$" "$site"/srun-*.log || { cat "$site"/srun-*.log; exit 1; }
say "LAUNCHER=srun: done"

"$python" - "$site/out" "$tmp/plain" << 'PY'
import json, sys
# The ranks run each test's arithmetic unchanged, so the answer is a plain run's to the last bit; the
# contract (issue 15) asks for 1e-12 relative.
TOL = 1e-12
out, plain = sys.argv[1], sys.argv[2]
ok = True
for launcher, p in (("mpirun", "project-110"), ("mpirun", "project-150"), ("srun", "project-110")):
    r = json.load(open(f"{out}/{'campaign' if launcher == 'mpirun' else 'srun'}/{p}/result.json"))
    one = json.load(open(f"{plain}/{p}/result.json"))
    for key in ("iterations", "evaluations", "termination"):
        if r[key] != one[key]:
            print(f"{p}: {key} {r[key]} != {one[key]}"); ok = False
    if (r["ranks"], r["threads"]) != (2, 1) or one["ranks"] != 1:
        print(f"{p}: ranks × threads {r['ranks']} × {r['threads']} in Slurm, plain {one['ranks']} × {one['threads']}"); ok = False
    pairs = [("objective", r["objective"], one["objective"])]
    pairs += [(f"parameters.{k}", r["parameters"][k], v) for k, v in one["parameters"].items()]
    for name, a, b in pairs:
        if abs(a - b) > TOL * abs(b):
            print(f"{p}: {name} {a!r} != {b!r}"); ok = False
    same = all(a == b for _, a, b in pairs)
    print(f"slurm_campaign: {p} ({launcher}): f = {r['objective']!r}, {r['parameters']}, {r['iterations']} iterations, "
          f"{r['ranks']} ranks x {r['threads']} threads against {one['ranks']} x {one['threads']}: "
          f"{'bit-identical' if same else 'within 1e-12'}")
sys.exit(0 if ok else 1)
PY

# Rank binding: one rank × 2 CPUs inside Slurm (mpirun --map-by slot:PE=2 --bind-to core) may run on
# both (result.json's cpus: its affinity; bound to one core it would run its two threads on it). The
# times beside plain runs of 2 and 1 threads are printed, not asserted: this test shares the machine.
bind=examples/knit-campaign/project-bind.toml
( cd "$site" && as_user env OUT=out/bind sbatch --wait --ntasks=1 --cpus-per-task=2 --array=0 --output=bind-%A_%a.log \
  examples/knit-campaign/campaign.slurm $bind ) > /dev/null || { echo "the binding job failed:"; cat "$site"/bind-*.log; exit 1; }
for t in 2 1; do
  env -u SLURM_CONF OMP_NUM_THREADS=$t "$tricot" identify "$site/$bind" -o "$tmp/bind$t" -q --no-plots > /dev/null
done
"$python" - "$site/out/bind/project-bind/result.json" "$tmp/bind2/result.json" "$tmp/bind1/result.json" << 'PY'
import json, sys
slurm, two, one = (json.load(open(f)) for f in sys.argv[1:4])
print(f"slurm_campaign: binding: 1 rank x {slurm['threads']} threads on {slurm['cpus']} CPUs in Slurm {slurm['wall_seconds']:.2f} s; "
      f"plain {two['threads']} threads {two['wall_seconds']:.2f} s, {one['threads']} thread {one['wall_seconds']:.2f} s")
ok = (slurm["ranks"], slurm["threads"], slurm["cpus"]) == (1, 2, 2) and slurm["iterations"] == two["iterations"]
if not ok:
    print(f"binding: ranks {slurm['ranks']}, threads {slurm['threads']}, cpus {slurm['cpus']}, expected 1, 2, 2")
sys.exit(0 if ok else 1)
PY

# A plain srun of two tasks (MpiDefault=none): refused in one line, exit 2, nothing written.
set +e
( cd "$site" && as_user srun -n 2 build/tricot identify examples/knit-campaign/project-110.toml -o out/duplicated -q ) \
  > "$tmp/dup.out" 2> "$tmp/dup.err"
rc=$?
set -e
[ $rc -eq 2 ] || { echo "srun -n 2: exit $rc, expected 2"; cat "$tmp/dup.out" "$tmp/dup.err"; exit 1; }
[ "$(grep -c '^tricot: error: mpi: Slurm started 2 tasks of tricot and no MPI world joins them' "$tmp/dup.err")" -eq 1 ] &&
  [ "$(grep -c '^tricot: ' "$tmp/dup.err")" -eq 1 ] || { echo "srun -n 2: not one line:"; cat "$tmp/dup.err"; exit 1; }
[ ! -e "$site/out/duplicated" ] || { echo "srun -n 2 wrote out/duplicated"; exit 1; }
say "srun -n 2 refused: $(grep '^tricot: ' "$tmp/dup.err")"

# A project that does not converge: a result (task exit 0) by default, exit 4 with STRICT_CONVERGENCE=1.
# One rank each, so that both run at once on the node's two CPUs.
cut=examples/knit-campaign/project-cut.toml
( cd "$site" && as_user sbatch --wait --ntasks=1 --array=0 --output=cut-%A_%a.log examples/knit-campaign/campaign.slurm $cut ) \
  > /dev/null &
cut_pid=$!
( cd "$site" && as_user env STRICT_CONVERGENCE=1 sbatch --wait --ntasks=1 --array=0 --output=strict-%A_%a.log \
  examples/knit-campaign/campaign.slurm "${cut%.toml}-strict.toml" ) > /dev/null &
strict_pid=$!
rc_cut=0 rc_strict=0
wait $cut_pid || rc_cut=$?
wait $strict_pid || rc_strict=$?
[ $rc_cut -eq 0 ] && grep -q "^campaign: $cut ran but did not converge (tricot exit 4)" "$site"/cut-*.log ||
  { echo "default: sbatch --wait exit $rc_cut, expected 0 with a 'did not converge' line:"; cat "$site"/cut-*.log; exit 1; }
[ $rc_strict -eq 4 ] || { echo "STRICT_CONVERGENCE=1: sbatch --wait exit $rc_strict, expected 4"; cat "$site"/strict-*.log; exit 1; }
say "a project that does not converge: task exit 0, or 4 with STRICT_CONVERGENCE=1"

# Submitted from another folder: the script names what is missing (build/tricot), exit 2.
mkdir "$tmp/elsewhere" && chown "$job_user" "$tmp/elsewhere"
set +e
( cd "$tmp/elsewhere" && as_user sbatch --wait --ntasks=1 --array=0 --output=elsewhere-%A_%a.log "$site/examples/knit-campaign/campaign.slurm" ) > /dev/null
rc=$?
set -e
[ $rc -eq 2 ] && grep -q "^campaign: error: build/tricot: no such program in $tmp/elsewhere" "$tmp"/elsewhere/elsewhere-*.log ||
  { echo "submitted elsewhere: exit $rc"; cat "$tmp"/elsewhere/elsewhere-*.log; exit 1; }
say "submitted elsewhere: $(cat "$tmp"/elsewhere/elsewhere-*.log)"

stop_daemons
say "ok in $((SECONDS - started)) s"
