#!/bin/sh
# SIGTERM and SIGHUP (what `timeout` and batch schedulers send, and a closed
# terminal) stop a run as Ctrl-C does: a checkpoint at the next chunk boundary,
# a message naming the signal, exit status 128 + the signal (143, 129); the
# checkpoint continues with --restart. A second signal more than half a second
# after the first ends the program at once. `granule sweep` passes SIGTERM on to
# its running case and records the case as interrupted in its summary.
# Usage: signals_test.sh GRANULE SOURCE_DIR
set -eu
granule=$1
scene=$2/tests/scenes/restart.lua
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
fail() {
  echo "FAILED: $*"
  for f in *.txt; do echo "--- $f"; cat "$f"; done
  exit 1
}
# The step a checkpoint holds (integers/meta: version, dimension, step, ...).
checkpoint_step() {
  /usr/bin/python3 -c 'import sys, h5py; print(int(h5py.File(sys.argv[1], "r")["checkpoint/integers/meta"][2]))' "$1"
}
# Waits until the run has started stepping (its output file exists), then 2 s more.
wait_running() {
  for _ in $(seq 300); do
    [ -f "$1" ] && break
    sleep 0.1
  done
  sleep 2
}
# Runs the long scene in the background, sends it the signal(s) $2.. and checks:
# exit status $1, the checkpoint written, the message naming the signal $3.
stop_with() {
  want=$1 signal=$2 name=$3 restart=${4:-}
  rm -f signals.chk.h5
  # A restart continues the first run's output (here in place), so that one stays.
  [ -n "$restart" ] || rm -f long.h5
  "$granule" run "$scene" -D checkpoint=signals.chk.h5 -D checkpoint_every=1000000 \
    -D stage2_steps=4000000 -o long.h5 --quiet $restart > "$name.txt" 2>&1 &
  pid=$!
  wait_running long.h5
  # Twice in a row: a launcher signals the program and its process group, and that echo
  # (within half a second) must not turn the clean stop into a kill.
  kill -s "$signal" $pid
  kill -s "$signal" $pid 2> /dev/null || true  # it may have stopped already
  status=0
  wait $pid || status=$?
  [ "$status" -eq "$want" ] || fail "$name: expected exit status $want, got $status"
  [ -f signals.chk.h5 ] || fail "$name: no checkpoint written"
  grep -q "run interrupted" "$name.txt" || fail "$name: no 'run interrupted' message"
  grep -q "stopped by $name (exit status $want)" "$name.txt" || fail "$name: the message does not name $name"
}

stop_with 143 TERM SIGTERM
first=$(checkpoint_step signals.chk.h5)
[ "$first" -gt 0 ] || fail "the SIGTERM checkpoint is at step $first"
# The checkpoint continues: the restarted run goes on from it and SIGHUP stops it later.
cp signals.chk.h5 first.chk.h5
stop_with 129 HUP SIGHUP "--restart first.chk.h5"
second=$(checkpoint_step signals.chk.h5)
[ "$second" -gt "$first" ] || fail "the restarted run did not go on: step $second after $first"
echo "SIGTERM at step $first, restarted, SIGHUP at step $second"

# A second signal later than the echo window ends the program at once, even while the
# scene waits in a call the run loop cannot interrupt.
printf 'os.execute("sleep 30 > /dev/null 2>&1")\n' > wait.lua
"$granule" run wait.lua > hard.txt 2>&1 &
pid=$!
sleep 1
kill -TERM $pid
sleep 1
kill -TERM $pid
start=$(date +%s)
status=0
wait $pid || status=$?
took=$(( $(date +%s) - start ))
[ "$status" -eq 143 ] || fail "a second SIGTERM: expected death by SIGTERM (143), got $status"
[ "$took" -lt 10 ] || fail "a second SIGTERM took $took s to end the program"
if grep -q "stopped by" hard.txt; then fail "a second SIGTERM should kill, not stop cleanly"; fi

# granule sweep: SIGTERM to the sweep reaches its running case, which stops cleanly; the
# summary says so and the sweep exits 143.
case_scene=$2/tests/scenes/sweep_case.lua
"$granule" sweep "$case_scene" -D speed=1,2 -D busy=20 -o sweep > sweep.txt 2>&1 &
pid=$!
for _ in $(seq 300); do
  [ -f sweep/sweep_case_speed=1.log ] && grep -q threads sweep/sweep_case_speed=1.log && break
  sleep 0.1
done
sleep 0.5
kill -TERM $pid
status=0
wait $pid || status=$?
[ "$status" -eq 143 ] || fail "sweep: expected exit status 143 after SIGTERM, got $status"
/usr/bin/python3 - sweep/sweep_case.sweep.csv <<'PY' || fail "sweep: summary"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
status = [r["status"] for r in rows]
assert status == ["interrupted", "not run"], status
assert "SIGTERM" in rows[0]["error"], rows[0]["error"]
PY
grep -q "stopped by SIGTERM" sweep/sweep_case_speed=1.log || fail "sweep: the case did not stop cleanly"
echo "signals stop cleanly"
