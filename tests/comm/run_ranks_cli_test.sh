#!/usr/bin/env bash
# `mpirun -np N unisph run` against `unisph run` (the 2D dam break at dx 0.05 to t = 1, par):
#   run_ranks_cli_test.sh UNISPH CASES_DIR WORK_DIR MPIEXEC NP [mpiexec flags...]
#  * the observers of every row agree with the run on one process within 1e-9 relative (mass,
#    energies, front, the probes), in the same number of rows;
#  * each snapshot is one .pvtp joining one piece per rank, which VTK reads as one data set
#    with every fluid particle once (python3-vtk9, where installed);
#  * the log names the ranks, their particles and the transport;
#  * a checkpoint written on NP ranks at t = 0.5 restarts on one process and on NP ranks (and
#    on 2 where NP is 4), and a checkpoint of one process restarts on NP ranks: each restarted
#    run ends (t = 1) with every fluid particle's position, velocity, density and pressure the
#    same bits as the run on one process without a restart (python3-vtk9, where installed);
#  * the piston flume (moving paddle, gauges, velocity probe, loads) and Poiseuille flow
#    (periodic along x): observers and loads within 1e-9 of one process.
set -u
exe=$1; cases=$2; work=$3; mpiexec=$4; np=$5; shift 5
rm -rf "$work"; mkdir -p "$work"
status=0
fail() { echo "FAIL $*"; status=1; }
ok() { echo "ok   $*"; }
# Every row of two CSV files (observers, loads) within 1e-9 relative, the same columns and rows.
same_csv() {  # label file_one file_ranks
  /usr/bin/python3 - "$2" "$3" <<'PY' && ok "$1 within 1e-9 on $np ranks" || fail "$1 differs on $np ranks"
import csv, sys
def rows(path):
    lines = [l for l in open(path) if not l.startswith('#')]
    r = list(csv.reader(lines))
    return r[0], [[float(v) for v in row] for row in r[1:]]
h1, a = rows(sys.argv[1]); h2, b = rows(sys.argv[2])
assert h1 == h2, (h1, h2)
assert len(a) == len(b) and len(a) > 1, (len(a), len(b))
worst = 0.0
for ra, rb in zip(a, b):
    for x, y in zip(ra, rb):
        worst = max(worst, abs(x - y) / max(abs(x), 1e-300) if x != 0 else abs(y))
print(f"  {len(a)} rows of {len(h1)} columns, largest relative difference {worst:.3g}")
assert worst <= 1e-9
PY
}
args=("$cases/dambreak_2d.toml" --dx 0.05 --end-time 1 --policy par --quiet)

"$exe" run "${args[@]}" --output "$work/one" || fail "the run on one process"
"$mpiexec" -np "$np" "$@" "$exe" run "${args[@]}" --output "$work/ranks" || fail "the run on $np ranks"

same_csv "observers" "$work/one/observers.csv" "$work/ranks/observers.csv"

# Two more cases against one process: the piston flume (a moving paddle, wave gauges, a
# velocity probe, wall loads, a damping zone) and Poiseuille flow (periodic along x): every
# observer and load within 1e-9 (gauges and velocity probes: the same values).
for c in "piston_flume_2d:--dx 0.05 --end-time 1" "poiseuille_2d:--end-time 0.5"; do
  name=${c%%:*}; read -r -a extra <<< "${c#*:}"
  more=("$cases/$name.toml" "${extra[@]}" --policy par --quiet)
  "$exe" run "${more[@]}" --output "$work/${name}_one" || fail "$name on one process"
  "$mpiexec" -np "$np" "$@" "$exe" run "${more[@]}" --output "$work/${name}_ranks" || fail "$name on $np ranks"
  same_csv "$name: observers" "$work/${name}_one/observers.csv" "$work/${name}_ranks/observers.csv"
  [ -f "$work/${name}_one/loads.csv" ] &&
    same_csv "$name: loads" "$work/${name}_one/loads.csv" "$work/${name}_ranks/loads.csv"
done

ls "$work/ranks"/Water_000001_r*.vtp > /dev/null 2>&1 || fail "no per-rank pieces"
[ "$(ls "$work/ranks"/Water_000001_r*.vtp | wc -l)" = "$np" ] && ok "$np pieces per snapshot" || fail "not $np pieces"
grep -q 'Water_000001.pvtp' "$work/ranks/dambreak_2d.pvd" && ok "the collection lists the .pvtp" || fail "the collection does not list Water_000001.pvtp"
if /usr/bin/python3 -c "import vtk" 2> /dev/null; then
  /usr/bin/python3 - "$work/ranks/Water_000001.pvtp" "$work/one/Water_000001.vtp" <<'PY' && ok "VTK reads the .pvtp as one data set" || fail "the .pvtp does not read as the whole fluid"
import sys, vtk
from vtk.util.numpy_support import vtk_to_numpy
def read(path, reader):
    reader.SetFileName(path); reader.Update(); return reader.GetOutput()
p = read(sys.argv[1], vtk.vtkXMLPPolyDataReader()); o = read(sys.argv[2], vtk.vtkXMLPolyDataReader())
ids_p = sorted(vtk_to_numpy(p.GetPointData().GetArray("ParticleId")).tolist())
ids_o = sorted(vtk_to_numpy(o.GetPointData().GetArray("ParticleId")).tolist())
print(f"  {p.GetNumberOfPoints()} points in the pieces, {o.GetNumberOfPoints()} in the one-process snapshot")
assert ids_p == ids_o
PY
else
  echo "skip VTK read (no python3-vtk9)"
fi
grep -q "^ranks: $np " "$work/ranks/run.log" && grep -q "^rank $((np - 1)): " "$work/ranks/run.log" &&
  ok "run.log names the ranks" || fail "run.log does not name the ranks"

# Checkpoints: written on NP ranks (and on one process), restarted on other rank counts.
half=("$cases/dambreak_2d.toml" --dx 0.05 --end-time 0.5 --policy par --quiet --checkpoint-every 0.5)
"$mpiexec" -np "$np" "$@" "$exe" run "${half[@]}" --output "$work/ck_ranks" || fail "the run on $np ranks with a checkpoint"
"$exe" run "${half[@]}" --output "$work/ck_one" || fail "the run on one process with a checkpoint"
[ -f "$work/ck_ranks/checkpoint.bin" ] && ok "a checkpoint written on $np ranks" || fail "no checkpoint from $np ranks"
restarts=("ck_ranks:1" "ck_ranks:$np" "ck_one:$np")
[ "$np" -gt 2 ] && restarts+=("ck_ranks:2")
for r in "${restarts[@]}"; do
  from=${r%%:*}; n=${r##*:}; out="$work/re_${from}_$n"
  if [ "$n" = 1 ]; then
    "$exe" run "${args[@]}" --restart "$work/$from/checkpoint.bin" --output "$out" || fail "restart of $from on 1 process"
  else
    "$mpiexec" -np "$n" "$@" "$exe" run "${args[@]}" --restart "$work/$from/checkpoint.bin" --output "$out" ||
      fail "restart of $from on $n ranks"
  fi
  if /usr/bin/python3 -c "import vtk" 2> /dev/null; then
    /usr/bin/python3 - "$work/one/dambreak_2d.pvd" "$out/dambreak_2d.pvd" <<'PY' && ok "$from restarted on $n: the same bits at t = 1" || fail "$from restarted on $n differs from the run without restart"
import os, sys, xml.etree.ElementTree as ET, vtk
from vtk.util.numpy_support import vtk_to_numpy
def last_fluid(pvd):
    sets = [d for d in ET.parse(pvd).getroot().iter('DataSet') if d.get('part') == '0']
    d = max(sets, key=lambda d: float(d.get('timestep')))
    path = os.path.join(os.path.dirname(pvd), d.get('file'))
    reader = vtk.vtkXMLPPolyDataReader() if path.endswith('.pvtp') else vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path); reader.Update(); out = reader.GetOutput()
    ids = vtk_to_numpy(out.GetPointData().GetArray("ParticleId")).tolist()
    x = vtk_to_numpy(out.GetPoints().GetData()).tolist()
    arrays = [vtk_to_numpy(out.GetPointData().GetArray(n)).tolist() for n in ("Velocity", "Density", "Pressure")]
    return float(d.get('timestep')), {i: (x[k], [a[k] for a in arrays]) for k, i in enumerate(ids)}
t1, a = last_fluid(sys.argv[1]); t2, b = last_fluid(sys.argv[2])
assert t1 == t2, (t1, t2)
assert sorted(a) == sorted(b), "not the same particles"
differ = sum(1 for i in a if a[i] != b[i])
print(f"  t = {t1}: {len(a)} particles, {differ} differ in x, v, rho or p")
assert differ == 0
PY
  fi
done
exit $status
