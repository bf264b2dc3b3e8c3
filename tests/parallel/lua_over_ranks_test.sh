#!/bin/sh
# `mpirun -np N granule run SCENE.lua`: one scene spread over N ranks gives the
# one-process run's state bit for bit. Usage:
#   lua_over_ranks_test.sh GRANULE SOURCE_DIR MPIRUN
# - five scenes (3D dense box with Hertz-Mindlin, 3D drum with a turning
#   cylinder, 3D JKR cloud, 2D Walton-Braun drum, 3D shear cell periodic
#   along x with rolling and twisting resistance, its ghosts across the period, 2D pile bonded with parallel bonds
#   and tumbled until some break, 3D pile on a triangle-mesh floor the scene
#   writes to a file and reads back), each with callbacks that
#   query the whole scene and set a particle's velocity (the shear cell's
#   also a wall's velocity every 3 steps, the shares kept), time-triggered
#   snapshots, checkpoints and a stop check, on 1-4 ranks against a plain run
#   in canonical order: every particle's state, the stats, the callbacks'
#   readings (with the last step's contacts from sim:contacts() and
#   sim:contact_arrays(), in order, and the bond counts), the final contact
#   list, the bond counts and the walls'
#   forces equal bit for bit;
# - a checkpoint written on 2 ranks continued on 3 ends in the same state
#   (the box, the sparse box whose callback removes a particle every 250
#   steps and whose friction ramps down over 40 steps, the 2D drum, the
#   periodic shear cell and the bonded pile), and the
#   sparse box's plain run continues its own checkpoint;
# - the 2D Mechanofusion base case with its diagnostics (steps they look at
#   taken whole) on 2, 3 and 4 ranks: the same /results, diagnostics series
#   and final snapshot as on 1;
# - a contact going on across two runs keeps its peaks on 1-3 ranks;
# - ranks other than 0 write nothing where the scene says (their scratch
#   folders are removed);
# - the REPL under mpirun (rank 0 reads, every rank runs each line) prints
#   what the plain REPL prints, bit for bit, on 2 and 3 ranks.
set -eu
granule=$1
src=$2
mpirun="$3 --allow-run-as-root --oversubscribe"
scene=$src/tests/parallel/scenes/over_ranks.lua
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
mkdir scratch
export TMPDIR="$work/scratch" OMP_NUM_THREADS=1
# A killed rank's scratch (its process gone) is removed by the next run's
# ranks; a folder of a live process (this shell's) is left alone.
dead=$(sh -c 'echo $$')
mkdir -p scratch/granule-rank1-$dead/sub scratch/granule-rank2-$$
same() {  # every line bit for bit: particles, stats, the callbacks' readings, the walls' forces
  /usr/bin/python3 - "$1" "$2" <<'PY'
import sys
a, b = (open(p).read().split("\n") for p in sys.argv[1:3])
assert len(a) == len(b), f"{sys.argv[1]}: {len(a)} lines, {sys.argv[2]}: {len(b)}"
assert sum(l.startswith("state") for l in a) > 100, "too few particles printed"
for x, y in zip(a, b):
    assert x == y, f"{sys.argv[1]} / {sys.argv[2]} differ:\n{x[:200]}\n{y[:200]}"
PY
}
for case in box sparse drum jkr wb shear bonds mesh; do
  if [ "$case" = drum ]; then  # after the box's mpirun runs
    test ! -e scratch/granule-rank1-$dead || { echo "a dead rank's scratch was kept"; exit 1; }
    test -d scratch/granule-rank2-$$ || { echo "a live process's folder was removed"; exit 1; }
    rmdir scratch/granule-rank2-$$
  fi
  "$granule" run "$scene" -D case=$case -D canonical=1 -D checkpoint=plain_$case.chk.h5 \
    -o plain_$case.h5 --quiet > plain_$case.txt
  for n in 1 2 3 4; do
    $mpirun -np $n "$granule" run "$scene" -D case=$case -D checkpoint=np${n}_$case.chk.h5 \
      -o np${n}_$case.h5 --quiet > np${n}_$case.txt
    same plain_$case.txt np${n}_$case.txt
  done
  echo "$case: 1-4 ranks bit-identical to the plain run"
done
# The output records the ranks; its series (every 100 steps: totals reduced
# over the ranks, the shares kept) and snapshots are the plain run's bits.
# The ghosts' states by messages, the way between machines, instead of the
# memory the ranks of one machine share (GRANULE_MPI_SHARED=0): the same bits.
for case in wb shear; do
  GRANULE_MPI_SHARED=0 $mpirun -x GRANULE_MPI_SHARED -np 2 "$granule" run "$scene" -D case=$case \
    -D checkpoint=msg_$case.chk.h5 -o msg_$case.h5 --quiet > msg_$case.txt
  same plain_$case.txt msg_$case.txt
done
echo "messages: bit-identical to shared memory and to the plain run"
/usr/bin/python3 - <<'PY'
import h5py
bonded = 0
e = h5py.File("np3_box.h5", "r")["scene/effects"].attrs
assert e["ranks"] == 3 and "rcb" in str(e["decomposition"]), dict(e)
assert "ghosts by shared memory" in str(e["decomposition"]), dict(e)
m = h5py.File("msg_wb.h5", "r")["scene/effects"].attrs
assert "ghosts by messages" in str(m["decomposition"]), dict(m)
assert h5py.File("plain_box.h5", "r")["scene/effects"].attrs["ranks"] == 1
for case in ("box", "wb", "bonds"):
    a, b = h5py.File(f"plain_{case}.h5", "r"), h5py.File(f"np3_{case}.h5", "r")
    names = list(a["series"].keys())
    assert len(names) > 5 and len(a["series/time"]) > 20, names
    for n in names:
        assert a["series"][n][:].tobytes() == b["series"][n][:].tobytes(), (case, n)
    count = a["snapshots"].attrs["count"]
    assert count == b["snapshots"].attrs["count"] and count > 5
    for k in range(count):
        for q in ("id", "position", "velocity", "spin"):
            assert a["snapshots/%06d/%s" % (k, q)][:].tobytes() == b["snapshots/%06d/%s" % (k, q)][:].tobytes()
        if case == "bonds" and "bonds" in a["snapshots/%06d" % k]:
            for q in ("a", "b", "broken"):
                assert a["snapshots/%06d/bonds/%s" % (k, q)][:].tobytes() == b["snapshots/%06d/bonds/%s" % (k, q)][:].tobytes(), (k, q)
            bonded += 1
assert bonded > 2, "too few snapshots with bonds"

print("series and snapshots bit-identical")
PY
# A checkpoint from 2 ranks, continued on 3 (and on 1).
for case in box sparse wb shear bonds; do
  $mpirun -np 3 "$granule" run "$scene" -D case=$case -D checkpoint=np2_$case.chk.h5 \
    --restart np2_$case.chk.h5 -o restarted3_$case.h5 --quiet > restarted3_$case.txt
  same plain_$case.txt restarted3_$case.txt
  "$granule" run "$scene" -D case=$case -D checkpoint=np2_$case.chk.h5 \
    --restart np2_$case.chk.h5 -o restarted1_$case.h5 --quiet > restarted1_$case.txt
  same plain_$case.txt restarted1_$case.txt
done
# The plain run's own checkpoint (the sparse case's written after a removal) continued.
"$granule" run "$scene" -D case=sparse -D canonical=1 -D checkpoint=plain_sparse.chk.h5 \
  --restart plain_sparse.chk.h5 -o restarted_plain_sparse.h5 --quiet > restarted_plain_sparse.txt
same plain_sparse.txt restarted_plain_sparse.txt
echo "restart: 2 ranks' checkpoints continued on 3 ranks and on one process"
# The 2D Mechanofusion base case with its diagnostics.
mf=$src/scenarios/mechanofusion.lua
$mpirun -np 1 "$granule" run "$mf" -D duration=0.002 -o mf1.h5 --quiet > mf1.txt
for n in 2 3 4; do
  $mpirun -np $n "$granule" run "$mf" -D duration=0.002 -o mf$n.h5 --quiet | sed s/mf$n.h5/mf.h5/ > mf$n.txt
  sed s/mf1.h5/mf.h5/ mf1.txt | cmp - mf$n.txt
done
/usr/bin/python3 - <<'PY'
import h5py
for n in (2, 3, 4):
  a, b = h5py.File("mf1.h5", "r"), h5py.File(f"mf{n}.h5", "r")
  ra, rb = dict(a["results"].attrs), dict(b["results"].attrs)
  assert ra.keys() == rb.keys() and len(ra) > 5, (ra.keys(), rb.keys())
  for k in ra:
    assert (ra[k] == rb[k]).all() if hasattr(ra[k], "all") else ra[k] == rb[k], (n, k)
  def last(f):
    g = f["snapshots/%06d" % (f["snapshots"].attrs["count"] - 1)]
    return {k: g[k][:].tobytes() for k in ("id", "position", "velocity", "spin")}
  assert last(a) == last(b), n
  series = []
  a["diagnostics"].visit(lambda s: series.append(s) if isinstance(a["diagnostics"][s], h5py.Dataset) else None)
  assert series, "no diagnostics written"
  for s in series:
    assert a["diagnostics"][s][:].tobytes() == b["diagnostics"][s][:].tobytes(), (n, s)
print(f"mechanofusion: {len(ra)} results and {len(series)} diagnostic columns bit-identical on 1 and 2-4 ranks")
PY
# A contact going on across the end of one run and the start of the next keeps
# its beginning and peaks (its track travels with its history) on 1-3 ranks.
peaks=$src/tests/parallel/scenes/peaks_across_runs.lua
"$granule" run "$peaks" --quiet > peaks_plain.txt
grep -q "mean_peak_force_all 0.3" peaks_plain.txt
for n in 1 2 3; do
  $mpirun -np $n "$granule" run "$peaks" -D split=40 --quiet | cmp - peaks_plain.txt
done
echo "contact peaks across runs: the same on 1-3 ranks as on one process"
# A checkpoint into a missing folder: refused on every rank where the scene names
# it (the ranks other than 0 would write into scratch), each ending with the
# reason and its scratch folder removed, no hang and no abort.
if timeout 120 $mpirun -np 2 "$granule" run "$scene" -D case=wb -D checkpoint=missing/x.chk.h5 \
     -o failing.h5 --quiet > failing.txt 2> failing.err; then
  echo "a checkpoint into a missing folder did not fail"; exit 1
fi
# The same error on both ranks: printed once, naming them.
grep -q "all 2 ranks: error: .*checkpoint missing/x.chk.h5: the folder missing does not exist" failing.err ||
  { cat failing.err; exit 1; }
rm -f failing.h5 failing.xmf failing_walls.xmf
test "$(grep -c "the folder missing does not exist" failing.err)" = 1 || { cat failing.err; exit 1; }
! grep -q "MPI_ABORT" failing.err || { echo "a failure on every rank aborted"; cat failing.err; exit 1; }
echo "a failure on every rank ends them all"
# Nothing but rank 0's files where the scene writes; no scratch folder left.
test -z "$(ls scratch)" || { echo "scratch left behind: $(ls scratch)"; exit 1; }
for f in *.h5; do
  case $f in plain_*|np?_*|msg_*|restarted?_*|restarted_plain_*|mf?.h5|repl_*) ;; *) echo "unexpected file $f"; exit 1 ;; esac
done
# The REPL under mpirun: rank 0 reads the lines and every rank runs them, so
# the scene and the runs typed at the prompt spread over the ranks; what the
# prompt prints (values, errors) is the plain REPL's, bit for bit.
cat > repl_in.txt <<'LUA'
sim:run { steps = 400 }
st = sim:stats()
string.format("%a %d %d", st.kinetic_energy, st.contacts_particle, #sim:contacts())
no_such_name
for _, id in ipairs(sim:particles()) do local q = sim:particle(id) print(id, string.format("%a %a %a", q.position[1], q.velocity[2], q.force[3])) end
sim:run { steps = 200 }
string.format("%a", sim:wall("floor").force[2])
LUA
"$granule" repl "$scene" -D case=box -D canonical=1 -D steps=300 -D checkpoint=repl_plain.chk.h5 \
  -o repl_plain.h5 --quiet < repl_in.txt > repl_plain.txt 2> repl_plain.err && {
  echo "the plain REPL's failing line did not fail the session"; exit 1; }
for n in 2 3; do
  if $mpirun -np $n "$granule" repl "$scene" -D case=box -D steps=300 -D checkpoint=repl_np$n.chk.h5 \
       -o repl_np$n.h5 --quiet < repl_in.txt > repl_np$n.txt 2> repl_np$n.err; then
    echo "the REPL on $n ranks did not fail the session with its failing line"; exit 1
  fi
  cmp repl_plain.txt repl_np$n.txt || { diff repl_plain.txt repl_np$n.txt | head; exit 1; }
done
grep -q "no_such_name is not defined" repl_plain.txt
test "$(grep -c '^[0-9]' repl_plain.txt)" -gt 800  # the prompt's lines, a particle each
test -z "$(ls scratch)" || { echo "scratch left behind: $(ls scratch)"; exit 1; }
echo "repl: 2 and 3 ranks print the plain REPL's lines bit for bit"
echo "lua_over_ranks ok"
