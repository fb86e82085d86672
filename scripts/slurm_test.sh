#!/usr/bin/env bash
# The real Slurm test: a single-node Slurm cluster on this machine runs `ffdtool batch` as a
# job array, and the union of its shards must equal a local batch byte for byte.
#
#   scripts/slurm_test.sh            (as root; installs slurm-wlm and munge when missing)
#
# 1. Installs `slurm-wlm` and `munge` from Debian's packages when missing (apt is not
#    touched when both are there) and creates /etc/munge/munge.key when there is none.
# 2. Starts munged (as the munge user), slurmctld and slurmd (as root) directly, no
#    systemd, with a slurm.conf of its own in a temporary folder: one node (this host's
#    short name, all its cores), no cgroups, no accounting, its own munge socket and its
#    own ports, so a cluster or munged already on the machine is neither used nor touched.
# 3. Waits for the node to be idle and submits `sbatch --array=0-2 --wait` of the users'
#    example, scripts/slurm/batch.sbatch: `ffdtool batch` with no --shard (each task takes
#    its shard from SLURM_ARRAY_TASK_ID/COUNT) over a folder of small meshes. Runs the same
#    batch locally without Slurm, and checks that the three shards' files equal the local
#    batch's (cmp), that there are exactly three results-I-of-3.jsonl and that the shards'
#    items are disjoint and cover all.
# 4. Times an array of no-op tasks: prints `slurm: per-task overhead X s`.
# 5. Stops only the daemons it started (by their recorded PIDs) and removes its folder.
#
# Environment: FFDTOOL (default build/apps/ffdtool/ffdtool), FFD_SHARED_MESHES (default
# ../shared/meshes: meshes under 2 MB from there join the test set when the folder exists),
# SLURM_TEST_TIMEOUT (seconds per sbatch, default 300), SLURM_TEST_OVERHEAD_TASKS (default
# 6), SLURM_TEST_KEEP=1 keeps the temporary folder (logs, outputs) for a post-mortem.
# Exit 0 when every check passed; the last line is `slurm_test: N passed, M failed`.
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
repo="$(pwd)"

ffdtool="${FFDTOOL:-build/apps/ffdtool/ffdtool}"
case "$ffdtool" in /*) ;; *) ffdtool="$repo/$ffdtool" ;; esac
shared_meshes="${FFD_SHARED_MESHES:-$repo/../shared/meshes}"
sbatch_timeout="${SLURM_TEST_TIMEOUT:-300}"
overhead_tasks="${SLURM_TEST_OVERHEAD_TASKS:-6}"
shards=3

passed=0
failed=0
tmp=""
policy_rc_created=""
munged_pid=""
slurmctld_pid=""
slurmd_pid=""
cluster_up=""

say() { echo "slurm_test: $*"; }
pass() { passed=$((passed + 1)); echo "  ok    $*"; }
fail() { failed=$((failed + 1)); echo "  FAIL  $*"; }
# A failure after which nothing else can be checked.
die() { fail "$*"; exit 1; }

show_logs() {
  [ -n "$tmp" ] || return 0
  local f
  for f in "$tmp"/munge/munged.log "$tmp"/log/slurmctld.log "$tmp"/log/slurmd.log "$tmp"/log/task-*; do
    [ -s "$f" ] || continue
    echo "---- last lines of ${f#"$tmp"/}"
    tail -n 15 "$f"
  done
}

alive() { [ -n "$1" ] && kill -0 "$1" 2>/dev/null; }

# Runs a long command in the background and waits for it, so that a signal to this script
# runs its trap at once (bash defers traps until a foreground child returns).
child=""
run_bg() {
  local rc
  "$@" &
  child=$!
  wait "$child"
  rc=$?
  child=""
  return "$rc"
}

# Sends TERM to one recorded PID, waits up to 10 s, then KILL. $2 names the process, and the
# PID is signalled only while /proc says it is still that program (PIDs are reused).
stop_pid() {
  local pid="$1" name="$2" i
  alive "$pid" || return 0
  [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = "$name" ] || return 0
  kill -TERM "$pid" 2>/dev/null
  for i in $(seq 1 100); do alive "$pid" || break; sleep 0.1; done
  if alive "$pid"; then
    echo "  $name (pid $pid) ignored TERM; sending KILL"
    kill -KILL "$pid" 2>/dev/null
    sleep 0.2
  fi
  wait "$pid" 2>/dev/null || true
}

# Job steps live in slurmstepd processes that outlast slurmd; ours are the ones whose job
# ran in our folder or whose slurmd spool is ours.
our_stepds() {
  local p
  [ -n "$tmp" ] || return 0
  for p in /proc/[0-9]*; do
    case "$(cat "$p/cmdline" 2>/dev/null | tr '\0' ' ')" in slurmstepd:*) ;; *) continue ;; esac
    if ls -l "$p/cwd" "$p/fd" 2>/dev/null | grep -q "$tmp"; then echo "${p#/proc/}"; fi
  done
}

# Sets $left to the PIDs still alive afterwards.
stop_cluster() {
  local i pids
  left=""
  if [ -n "$cluster_up" ] && alive "$slurmctld_pid"; then
    # Cancel whatever is still queued on our cluster (only ours: SLURM_CONF is ours).
    if [ -n "$(squeue -h -o %i 2>/dev/null)" ]; then
      scancel --full $(squeue -h -o %A 2>/dev/null) 2>/dev/null || true
      for i in $(seq 1 50); do [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break; sleep 0.2; done
    fi
  fi
  stop_pid "$slurmd_pid" slurmd
  stop_pid "$slurmctld_pid" slurmctld
  pids="$(our_stepds)"
  if [ -n "$pids" ]; then
    echo "  stopping leftover slurmstepd: $pids"
    kill -KILL $pids 2>/dev/null || true
  fi
  stop_pid "$munged_pid" munged
  for i in "$slurmd_pid" "$slurmctld_pid" "$munged_pid" $pids; do
    if alive "$i"; then left="$left $i"; fi
  done
}

remove_policy_rc() {
  if [ -n "$policy_rc_created" ]; then rm -f /usr/sbin/policy-rc.d; policy_rc_created=""; fi
}

finish() {
  local rc=$?
  trap - EXIT INT TERM
  exec 1>&7 2>&8   # a signal may come while a command's output is redirected
  remove_policy_rc
  if alive "$child"; then kill -TERM "$child" 2>/dev/null; wait "$child" 2>/dev/null; fi
  if [ -n "$munged_pid$slurmctld_pid$slurmd_pid" ]; then
    [ "$failed" -gt 0 ] && show_logs
    stop_cluster
    if [ -n "$tmp" ] && [ -d "$tmp" ] && [ "${SLURM_TEST_KEEP:-}" != 1 ]; then rm -rf "$tmp"; fi
    if [ -z "${left// /}" ]; then
      pass "stopped the daemons this test started (pids: ${munged_pid:-} ${slurmctld_pid:-} ${slurmd_pid:-})"
    else
      fail "still running after stop: pids$left"
    fi
  fi
  if [ -n "$tmp" ] && [ -d "$tmp" ]; then
    if [ "${SLURM_TEST_KEEP:-}" = 1 ]; then say "kept $tmp"; else rm -rf "$tmp"; fi
  fi
  [ "$failed" -eq 0 ] && [ "$rc" -ne 0 ] && failed=1
  echo "slurm_test: $passed passed, $failed failed"
  [ "$failed" -eq 0 ] && exit 0
  exit 1
}
exec 7>&1 8>&2
trap '' PIPE   # a reader that goes away (| head) must not kill us before the cleanup
trap finish EXIT
trap 'exec 1>&7 2>&8; fail "interrupted by a signal"; exit 130' INT TERM

# ---------------------------------------------------------------------------------------
say "ffdtool: $ffdtool"
[ -x "$ffdtool" ] || die "no ffdtool binary at $ffdtool (run scripts/build.sh, or set FFDTOOL)"
for c in batch report; do
  "$ffdtool" "$c" --help 2>&1 | grep -Eq "^Usage: [^ ]+ $c( |\$)" \
    || die "$ffdtool has no '$c' command ('ffdtool $c --help' shows no usage of it)"
done
[ "$(id -u)" -eq 0 ] || die "must run as root (slurmd and slurmctld run as root here; munged as munge)"
command -v python3 >/dev/null || die "python3 is needed to read the results files (scripts/setup.sh installs it)"

# 1. Packages ----------------------------------------------------------------------------
packages=(slurm-wlm munge)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  say "packages present: ${packages[*]}"
else
  say "installing ${missing[*]}"
  # Keep the packages' maintainer scripts from starting munge/slurm services: this test
  # starts its own daemons and leaves none behind.
  if [ ! -e /usr/sbin/policy-rc.d ]; then
    printf '#!/bin/sh\nexit 101\n' > /usr/sbin/policy-rc.d
    chmod 755 /usr/sbin/policy-rc.d
    policy_rc_created=1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq || die "apt-get update failed"
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null \
    || die "apt-get install ${missing[*]} failed"
  remove_policy_rc
fi
for c in munged munge unmunge slurmctld slurmd sbatch sinfo squeue scancel; do
  command -v "$c" >/dev/null || die "$c not found after installing ${packages[*]}"
done
id munge >/dev/null 2>&1 || die "no munge user (the munge package creates it)"
say "$(slurmctld -V), $(munged --version 2>&1 | head -n 1)"

# 2. Munge key and daemon ------------------------------------------------------------------
key=/etc/munge/munge.key
if [ ! -s "$key" ]; then
  say "creating $key"
  install -d -o munge -g munge -m 0700 /etc/munge
  if command -v mungekey >/dev/null; then
    mungekey --create --keyfile="$key" --force || die "mungekey failed"
  else
    dd if=/dev/urandom of="$key" bs=1 count=1024 status=none || die "could not write $key"
  fi
  chown munge:munge "$key"
  chmod 0400 "$key"
fi

tmp="$(mktemp -d /tmp/ffd-slurm.XXXXXX)" || die "mktemp failed"
chmod 0755 "$tmp"   # munged (as munge) must reach its socket folder inside
mkdir -p "$tmp/log" "$tmp/state" "$tmp/spool" "$tmp/meshes" "$tmp/local" "$tmp/slurm" "$tmp/ts"
install -d -o munge -g munge -m 0755 "$tmp/munge"
[ "$(stat -c %U "$tmp/munge")" = munge ] || die "$tmp/munge is not owned by munge"
socket="$tmp/munge/munge.socket"

runuser -u munge -- munged --force 7>&- 8>&- \
  --key-file="$key" --socket="$socket" --pid-file="$tmp/munge/munged.pid" \
  --log-file="$tmp/munge/munged.log" --seed-file="$tmp/munge/munged.seed" \
  || die "munged did not start (see $tmp/munge/munged.log)"
for i in $(seq 1 50); do [ -s "$tmp/munge/munged.pid" ] && [ -S "$socket" ] && break; sleep 0.1; done
munged_pid="$(cat "$tmp/munge/munged.pid" 2>/dev/null)"
alive "$munged_pid" || die "munged is not running (see its log below)"
[ "$(stat -c %U "/proc/$munged_pid")" = munge ] || die "munged (pid $munged_pid) does not run as munge"
if munge -n -S "$socket" | unmunge -S "$socket" >/dev/null; then
  pass "munged runs as munge (pid $munged_pid), a credential round-trips through $socket"
else
  die "munge | unmunge through $socket failed"
fi

# 3. slurm.conf and the Slurm daemons ------------------------------------------------------
host="$(hostname -s)"
port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
ctld_port=""
for p in $(seq 16817 2 16899); do
  if port_free "$p" && port_free $((p + 1)); then ctld_port=$p; break; fi
done
[ -n "$ctld_port" ] || die "no free port pair in 16817..16900"
slurmd_port=$((ctld_port + 1))

# The node line: what slurmd sees on this machine (sockets, cores, threads), without memory.
node_hw="$(slurmd -C 2>/dev/null | head -n 1 | tr ' ' '\n' | grep -E '^(CPUs|Boards|SocketsPerBoard|CoresPerSocket|ThreadsPerCore)=' | tr '\n' ' ')"
case "$node_hw" in *CPUs=*) ;; *) node_hw="CPUs=$(nproc)" ;; esac

export SLURM_CONF="$tmp/slurm.conf"
cat > "$SLURM_CONF" <<EOF
# Written by scripts/slurm_test.sh: a throwaway single-node cluster.
ClusterName=ffdtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
MailProg=/bin/true
MaxArraySize=1001
NodeName=$host NodeAddr=127.0.0.1 $node_hw State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF

slurmctld -D -i -f "$SLURM_CONF" > "$tmp/log/slurmctld.out" 2>&1 7>&- 8>&- &
slurmctld_pid=$!
cluster_up=1
for i in $(seq 1 100); do
  alive "$slurmctld_pid" || break
  scontrol ping 2>/dev/null | grep -q UP && break
  sleep 0.2
done
alive "$slurmctld_pid" || { cat "$tmp/log/slurmctld.out"; die "slurmctld exited at start"; }
slurmd -D -N "$host" -f "$SLURM_CONF" > "$tmp/log/slurmd.out" 2>&1 7>&- 8>&- &
slurmd_pid=$!

state=""
for i in $(seq 1 150); do
  alive "$slurmd_pid" || break
  state="$(sinfo -h -N -n "$host" -o %T 2>/dev/null | head -n 1)"
  [ "$state" = idle ] && break
  sleep 0.2
done
alive "$slurmd_pid" || { cat "$tmp/log/slurmd.out"; die "slurmd exited at start"; }
if [ "$state" = idle ]; then
  pass "single-node cluster up: node $host idle ($node_hw), slurmctld pid $slurmctld_pid port $ctld_port, slurmd pid $slurmd_pid"
else
  scontrol show node "$host" 2>&1 | sed 's/^/    /'
  die "node $host is '${state:-unknown}', not idle, after 30 s"
fi

# 4. Test meshes and script -----------------------------------------------------------------
cp test_data/bunny.obj test_data/grid.obj "$tmp/meshes/"
if [ -d "$shared_meshes" ]; then
  for f in "$shared_meshes"/*.obj "$shared_meshes"/*.off; do
    [ -f "$f" ] && [ "$(stat -c %s "$f")" -lt 2000000 ] && cp "$f" "$tmp/meshes/"
  done
fi
cat > "$tmp/meshes/cube.off" <<'EOF'
OFF
8 12 0
0 0 0
1 0 0
1 1 0
0 1 0
0 0 1
1 0 1
1 1 1
0 1 1
3 0 2 1
3 0 3 2
3 4 5 6
3 4 6 7
3 0 1 5
3 0 5 4
3 1 2 6
3 1 6 5
3 2 3 7
3 2 7 6
3 3 0 4
3 3 4 7
EOF
cat > "$tmp/meshes/octahedron.obj" <<'EOF'
v 1 0 0
v -1 0 0
v 0 1 0
v 0 -1 0
v 0 0 1
v 0 0 -1
f 1 3 5
f 3 2 5
f 2 4 5
f 4 1 5
f 3 1 6
f 2 3 6
f 4 2 6
f 1 4 6
EOF
# A 24 x 12 torus as OFF and a 16 x 8 one as OBJ with quads.
awk -v n=24 -v m=12 'BEGIN { pi = atan2(0, -1); print "OFF"; print n*m, n*m*2, 0
  for (i = 0; i < n; i++) for (j = 0; j < m; j++) { u = 2*pi*i/n; v = 2*pi*j/m
    printf "%.6f %.6f %.6f\n", (2 + cos(v)) * cos(u), (2 + cos(v)) * sin(u), sin(v) }
  for (i = 0; i < n; i++) for (j = 0; j < m; j++) { a = i*m + j; b = ((i+1)%n)*m + j
    c = ((i+1)%n)*m + (j+1)%m; d = i*m + (j+1)%m
    print 3, a, b, c; print 3, a, c, d } }' > "$tmp/meshes/torus.off"
awk -v n=16 -v m=8 'BEGIN { pi = atan2(0, -1)
  for (i = 0; i < n; i++) for (j = 0; j < m; j++) { u = 2*pi*i/n; v = 2*pi*j/m
    printf "v %.6f %.6f %.6f\n", (3 + cos(v)) * cos(u), (3 + cos(v)) * sin(u), 0.5 * sin(v) }
  for (i = 0; i < n; i++) for (j = 0; j < m; j++) { a = i*m + j; b = ((i+1)%n)*m + j
    c = ((i+1)%n)*m + (j+1)%m; d = i*m + (j+1)%m
    print "f", a+1, b+1, c+1, d+1 } }' > "$tmp/meshes/ring.obj"
n_items="$(ls "$tmp/meshes" | wc -l)"

# Scale-free, so it suits every mesh: widen and twist the upper middle of a fitted lattice,
# save that stage, then tilt the top layer.
cat > "$tmp/deform.json" <<'EOF'
{
  "version": 1,
  "steps": [
    {"op": "lattice", "name": "box", "basis": "bspline", "degree": 3,
     "box": {"fit": "aabb", "padding": 0.05}, "cells": [5, 5, 5]},
    {"op": "move", "lattice": "box", "select": {"indices": [[2, 2, 3], [3, 2, 3], [2, 3, 3], [3, 3, 3]]},
     "transform": {"scale": [1.3, 1.3, 1], "rotate": {"axis": [0, 0, 1], "degrees": 15}}},
    {"op": "save", "path": "widened.obj"},
    {"op": "move", "lattice": "box", "select": {"indices": [[2, 2, 3], [3, 2, 3], [2, 3, 3], [3, 3, 3]]},
     "transform": {"rotate": {"axis": [1, 0, 0], "degrees": 10}}}
  ]
}
EOF
say "$n_items meshes: $(ls "$tmp/meshes" | tr '\n' ' ')"

# 5. The same batch locally, without Slurm ----------------------------------------------------
no_slurm=(env -u SLURM_ARRAY_TASK_ID -u SLURM_ARRAY_TASK_COUNT -u SLURM_ARRAY_JOB_ID -u SLURM_JOB_ID -u JOB_COMPLETION_INDEX)
if run_bg "${no_slurm[@]}" "$ffdtool" batch "$tmp/deform.json" "$tmp/meshes" -o "$tmp/local" \
     > "$tmp/log/local.out" 2> "$tmp/log/local.err"; then
  pass "local batch (no Slurm) exit 0"
else
  fail "local batch exit $? ($(tail -n 3 "$tmp/log/local.err" | tr '\n' ' '))"
fi
if [ -s "$tmp/local/results.jsonl" ]; then pass "local batch wrote results.jsonl"; else fail "local batch wrote no results.jsonl"; fi

# 6. The array job: the example users get, scripts/slurm/batch.sbatch, with the
# command line's options over its #SBATCH lines (3 tasks of 1 CPU here) -----------------------
t0="$(date +%s.%N)"
if run_bg timeout "$sbatch_timeout" sbatch --array=0-$((shards - 1)) --wait --parsable --job-name=ffd-batch \
     --cpus-per-task=1 --time=10 --chdir="$tmp" \
     --export="ALL,FFDTOOL=$ffdtool,FFD_SCRIPT=$tmp/deform.json,FFD_INPUT=$tmp/meshes,FFD_OUT=$tmp/slurm" \
     --output="$tmp/log/task-%a.out" --error="$tmp/log/task-%a.err" scripts/slurm/batch.sbatch > "$tmp/log/sbatch.out" 2>&1; then
  t1="$(date +%s.%N)"
  pass "sbatch --array=0-$((shards - 1)) --wait scripts/slurm/batch.sbatch (ffdtool batch, no --shard): job $(head -n 1 "$tmp/log/sbatch.out"), every task exit 0 ($(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }') s)"
else
  rc=$?
  if [ "$rc" -eq 124 ]; then fail "sbatch --wait did not return within $sbatch_timeout s"
  else fail "sbatch --wait exit $rc (a task failed; sbatch said: $(tr '\n' ' ' < "$tmp/log/sbatch.out"))"; fi
  squeue 2>&1 | sed 's/^/    /'
fi

# Each task's first stderr line names its shard.
for i in $(seq 0 $((shards - 1))); do
  first="$(head -n 1 "$tmp/log/task-$i.err" 2>/dev/null)"
  if echo "$first" | grep -Eq "(^|[^0-9])$i ?(/|of) ?$shards([^0-9]|$)"; then
    pass "task $i's first stderr line names shard $i/$shards: $first"
  else
    fail "task $i's first stderr line does not name shard $i/$shards: '${first}'"
  fi
done

# 7. Results files: exactly N shard files, disjoint shards covering every item ----------------
shard_files=("$tmp"/slurm/results-*-of-"$shards".jsonl)
n_files=0; for f in "${shard_files[@]}"; do [ -f "$f" ] && n_files=$((n_files + 1)); done
others="$(cd "$tmp/slurm" 2>/dev/null && ls results*.jsonl 2>/dev/null | grep -v -E "^results-[0-9]+-of-$shards\.jsonl$")"
if [ "$n_files" -eq "$shards" ] && [ -z "$others" ] \
   && (for i in $(seq 0 $((shards - 1))); do [ -f "$tmp/slurm/results-$i-of-$shards.jsonl" ] || exit 1; done); then
  pass "exactly $shards results files: $(cd "$tmp/slurm" && ls results*.jsonl | tr '\n' ' ')"
else
  fail "expected results-0..$((shards - 1))-of-$shards.jsonl only; found: $(cd "$tmp/slurm" 2>/dev/null && ls results*.jsonl 2>/dev/null | tr '\n' ' ')"
fi

if python3 - "$tmp/slurm" "$tmp/local/results.jsonl" "$shards" <<'EOF'
import json, os, sys
slurm, local, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
def rows(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [json.loads(l) for l in f if l.strip()]
problems = []
want = [r["input"] for r in rows(local)]
if len(set(want)) != len(want):
    problems.append("the local batch lists an input twice")
shard_items = {}
for i in range(n):
    p = os.path.join(slurm, "results-%d-of-%d.jsonl" % (i, n))
    shard_items[i] = [r["input"] for r in rows(p)] if os.path.exists(p) else []
    bad = [r["input"] + ": " + str(r.get("status")) for r in rows(p) if r.get("status") != "ok"] if os.path.exists(p) else []
    if bad:
        problems.append("shard %d: not ok: %s" % (i, ", ".join(bad)))
seen = {}
for i, items in shard_items.items():
    for x in items:
        if x in seen:
            problems.append("%s is in shard %d and shard %d" % (x, seen[x], i))
        seen[x] = i
missing = sorted(set(want) - set(seen))
extra = sorted(set(seen) - set(want))
if missing: problems.append("no shard holds: " + ", ".join(missing))
if extra: problems.append("not in the local batch: " + ", ".join(extra))
# Items are sorted by path and shard i takes index = i (mod n).
order = sorted(want)
for k, x in enumerate(order):
    if x in seen and seen[x] != k % n:
        problems.append("%s (item %d) is in shard %d, not %d" % (x, k, seen[x], k % n))
bad_local = [r["input"] for r in rows(local) if r.get("status") != "ok"]
if bad_local: problems.append("local batch not ok: " + ", ".join(bad_local))
for p in problems: print("    " + p)
print("    shards: " + "; ".join("%d: %s" % (i, " ".join(os.path.basename(x) for x in v)) for i, v in shard_items.items()))
sys.exit(1 if problems else 0)
EOF
then
  pass "the shards' items are disjoint, cover all $n_items, follow index mod $shards, every status ok"
else
  fail "the shards' items do not partition the local batch's"
fi

# 8. Byte for byte: every file the shards wrote against the local batch's ----------------------
list_outputs() { (cd "$1" && find . -type f ! -name 'results*.jsonl' | LC_ALL=C sort); }
list_outputs "$tmp/slurm" > "$tmp/slurm.files" 2>/dev/null
list_outputs "$tmp/local" > "$tmp/local.files" 2>/dev/null
n_out="$(wc -l < "$tmp/local.files")"
if [ "$n_out" -gt 0 ] && cmp -s "$tmp/slurm.files" "$tmp/local.files"; then
  differ=""
  while read -r f; do cmp -s "$tmp/slurm/$f" "$tmp/local/$f" || differ="$differ ${f#./}"; done < "$tmp/local.files"
  if [ -z "$differ" ]; then
    pass "the shards' $n_out output files equal the local batch's byte for byte (cmp)"
  else
    fail "outputs differ from the local batch's:$differ"
  fi
else
  fail "the shards' files and the local batch's are not the same list ($n_out local):"
  diff "$tmp/slurm.files" "$tmp/local.files" | sed 's/^/    /' | head -n 20
fi
saves="$(grep -c '/widened.obj$' "$tmp/slurm.files")"
if [ "$saves" -eq "$n_items" ]; then pass "every item's save file is in OUTDIR/name/ ($saves)"
else fail "$saves save files for $n_items items"; fi

if "$ffdtool" report "$tmp/slurm" > "$tmp/log/report.out" 2>&1; then
  pass "ffdtool report merges the shards' results (exit 0)"
else
  fail "ffdtool report exit $?: $(head -n 5 "$tmp/log/report.out" | tr '\n' ' ')"
fi

# 9. Slurm's per-task overhead: an array of no-op tasks that write timestamps -------------------
t0="$(date +%s.%N)"
if run_bg timeout "$sbatch_timeout" sbatch --array=0-$((overhead_tasks - 1)) --wait --parsable --job-name=ffd-noop \
     --cpus-per-task=1 --time=1 --chdir="$tmp" --output=/dev/null \
     --wrap="date +%s.%N > $tmp/ts/start-\$SLURM_ARRAY_TASK_ID; /bin/true; date +%s.%N > $tmp/ts/end-\$SLURM_ARRAY_TASK_ID" \
     > "$tmp/log/sbatch-noop.out" 2>&1; then
  t1="$(date +%s.%N)"
  n_ts="$(find "$tmp/ts" -name "end-*" | wc -l)"
  if [ "$n_ts" -eq "$overhead_tasks" ]; then
    cpus="$(nproc)"
    read -r first last <<<"$(cat "$tmp"/ts/start-* | sort -n | head -n 1) $(cat "$tmp"/ts/end-* | sort -n | tail -n 1)"
    awk -v t0="$t0" -v t1="$t1" -v a="$first" -v b="$last" -v n="$overhead_tasks" -v c="$cpus" 'BEGIN {
      printf "slurm: %d no-op tasks, %d at a time: first started %.2f s after submission, last ended %.2f s after (that / tasks: the overhead below); sbatch --wait returned after %.2f s (%.2f s per task; --wait polls)\n", n, c, a - t0, b - t0, t1 - t0, (t1 - t0) / n
      printf "slurm: per-task overhead %.2f s\n", (b - t0) / n }'
    pass "no-op array of $overhead_tasks tasks timed"
  else
    fail "no-op array: $n_ts of $overhead_tasks tasks left timestamps"
  fi
else
  fail "no-op array: sbatch --wait exit $?: $(tr '\n' ' ' < "$tmp/log/sbatch-noop.out")"
fi

# 10. Stop the cluster: done by finish (the EXIT trap), which also counts that check.
exit 0
