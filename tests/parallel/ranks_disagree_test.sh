#!/bin/sh
# Spread runs where the ranks' scenes start empty or their scripts disagree.
# Usage: ranks_disagree_test.sh GRANULE SOURCE_DIR MPIRUN
# - a scene with no particles at the start (a feeder adding them from a
#   callback) runs on 2 and 3 ranks to the plain run's state, bit for bit,
#   printing once what it prints (print, io.write, sim:table) and writing a
#   file through io.output from rank 0 alone;
# - a stop criterion that says stop on one rank only stops every rank at that
#   check (no rank left waiting in a collective);
# - a stop criterion that fails on one rank only ends every rank with that
#   rank's error, not an MPI error alone;
# - SIGTERM sent to rank 1 alone stops every rank, each naming SIGTERM, and
#   the run exits with 143; rank 0 says how to continue, under mpirun.
set -eu
granule=$1
src=$2
mpirun="timeout 120 $3 --allow-run-as-root --oversubscribe"
scene=$src/tests/parallel/scenes/feeder_over_ranks.lua
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
export OMP_NUM_THREADS=1
"$granule" run "$scene" -D canonical=1 -q > plain.txt
test "$(grep -c '^state' plain.txt)" -gt 20 || { cat plain.txt; exit 1; }
for n in 2 3; do
  $mpirun -np $n "$granule" run "$scene" -q > np$n.txt
  cmp plain.txt np$n.txt || { diff plain.txt np$n.txt | head; exit 1; }
  test "$(cat io_output.txt)" = "written by rank 0" || { cat io_output.txt; exit 1; }
done
echo "an empty start: 2 and 3 ranks bit-identical to the plain run"
$mpirun -np 2 "$granule" run "$scene" -D mode=stop_on_rank1 -q > stop.txt
grep -q "^done	500$" stop.txt || { cat stop.txt; exit 1; }
echo "one rank's stop stops them all"
if $mpirun -np 2 "$granule" run "$scene" -D mode=error_on_rank1 -q > error.txt 2> error.err; then
  echo "a criterion failing on one rank did not fail the run"; exit 1
fi
grep -q "rank 1 of 2: error: .*the criterion failed on rank 1" error.err || { cat error.err; exit 1; }
echo "one rank's failing criterion ends them all, with its error"
# SIGTERM to rank 1 alone: every rank stops, naming SIGTERM, with its exit status.
$mpirun -np 2 "$granule" run "$scene" -D mode=long -q > signal.txt 2> signal.err &
launched=$!
pid=
for _ in $(seq 1 200); do
  pid=$(sed -n 's/^pid of rank 1: //p' signal.err)
  [ -n "$pid" ] && break
  sleep 0.1
done
test -n "$pid" || { echo "rank 1 never named its process"; cat signal.err; exit 1; }
sleep 1
kill -TERM "$pid"
status=0
wait $launched || status=$?
test "$status" = 143 || { echo "exit status $status, expected 143"; cat signal.err; exit 1; }
grep -q "rank 0 of 2: .*SIGTERM" signal.err || { cat signal.err; exit 1; }
! grep -q "Ctrl-C" signal.err || { echo "a rank named Ctrl-C"; cat signal.err; exit 1; }
# Rank 0's way to continue names the launcher and the rank count.
grep -q "continue with: mpirun -np 2 granule run " signal.err ||
  { echo "no 'continue with: mpirun -np 2' hint"; cat signal.err; exit 1; }
echo "a signal to one rank stops them all, named"
echo "ranks_disagree ok"
