#!/usr/bin/env bash
# squama batch throughput: the same small manifest of synthetic photos fitted four ways on
# this machine, in rows per minute: one row at a time on 1 thread and on every core, two
# local jobs of cores/2 threads, and (when squama has MPI and mpirun is here) 2 MPI ranks of
# cores/2 threads. Ends with:
#   RESULT batch rows=N evals=E cores=C rpm_1t=... rpm_all=... rpm_jobs2=... rpm_mpi2=...
#          scaling_all=... scaling_jobs2=... scaling_mpi2=... s_per_row_1t=... cpu_s_per_row=...
#          evals_per_cpu_s=... mpi_overhead_s=... load=...
# cpu_s_per_row and evals_per_cpu_s (CPU time of the 1-thread run, preparation and outputs
# included) do not depend on other work sharing the machine; the rows per minute and their
# scaling do: `load` is the 1-minute load average at the end (above the cores: shared).
# scaling_X = rpm_X / rpm_1t (ideal: the cores used); mpi_overhead_s = the wall time of
# 'mpirun -np 1' over the same run without mpirun (startup and the work queue).
# Usage: bench/batch.sh SQUAMA [--rows N] [--evals E] [--out DIR]
set -euo pipefail
SQ=$1; shift
rows=6 evals=400 out=build-bench/batch
while [ $# -gt 0 ]; do
  case $1 in
    --rows) rows=$2; shift 2 ;;
    --evals) evals=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) echo "bench/batch.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
SRC=$(cd "$(dirname "$0")/.." && pwd)
cores=$(nproc)
half=$(( cores / 2 > 0 ? cores / 2 : 1 ))
rm -rf "$out" && mkdir -p "$out/photos"
presets=("$SRC"/presets/thesis/table_4_*.json "$SRC"/presets/thesis/d11_*.json)
echo "id,photo,mask,expected" >"$out/manifest.csv"
for i in $(seq 0 $((rows - 1))); do
  p=${presets[$((i % ${#presets[@]}))]}
  "$SQ" photo "$p" -o "$out/photos/r$i.jpg" --size 320x240 --seed $((i + 1)) >/dev/null
  cat=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['preset']['Pattern_Type'])" "$out/photos/r${i}_truth.json")
  echo "r$i,photos/r$i.jpg,photos/r${i}_mask.png,$cat" >>"$out/manifest.csv"
done
FIT=(--evals "$evals" --size 128 --categories none,longitudinal,transversal,spots,other_simple)

# runs NAME [launcher...] -- [batch options...]: prints wall seconds, CPU seconds (user +
# system of every process it started), rows fitted and evaluations
measure() {
  local name=$1; shift
  local pre=()
  while [ "$1" != -- ]; do pre+=("$1"); shift; done
  shift
  python3 - "$out/$name.json" "$out/$name.err" "$out/$name/catalogue.csv" "${pre[@]}" "$SQ" batch \
      "$out/manifest.csv" -o "$out/$name" "${FIT[@]}" --json "$@" <<'PY'
import csv, json, resource, subprocess, sys, time
t = time.time()
subprocess.call(sys.argv[4:], stdout=open(sys.argv[1], "w"), stderr=open(sys.argv[2], "w"))
wall = time.time() - t
u = resource.getrusage(resource.RUSAGE_CHILDREN)
last = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])
evals = sum(int(r["evaluations"] or 0) for r in csv.DictReader(open(sys.argv[3], newline="")))
print(f"{wall:.2f} {u.ru_utime + u.ru_stime:.2f} {last['fitted_now']} {evals}")
PY
}

echo "squama batch: $rows synthetic photos, --evals $evals, $cores cores"
read -r w1 c1 n1 e1 < <(measure one_thread -- --threads 1)
echo "  1 row at a time, 1 thread:            $n1 rows in $w1 s ($c1 CPU s)"
read -r wa _ na _ < <(measure all_cores -- --threads "$cores")
echo "  1 row at a time, $cores threads:            $na rows in $wa s"
read -r wj _ nj _ < <(measure jobs2 -- --jobs 2 --threads "$half")
echo "  2 jobs of $half thread(s):                 $nj rows in $wj s"
wm=0 nm=0 ov=nan
if command -v mpirun >/dev/null && [ "$("$SQ" batch --help | grep -c mpirun)" -gt 0 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  read -r wm _ nm _ < <(measure mpi2 mpirun --oversubscribe -np 2 -- --threads "$half")
  grep -q '"rank":1' "$out/mpi2.json" || echo "  (squama was built without MPI: mpirun ran two separate batches)"
  echo "  2 MPI ranks of $half thread(s):            $nm rows in $wm s"
  # the launcher and queue's cost: mpirun -np 1 against the plain run (rows done: resumed)
  read -r wr _ _ _ < <(measure one_thread -- --threads 1)
  read -r wq _ _ _ < <(measure one_thread mpirun -np 1 -- --threads 1)
  ov=$(python3 -c "print(f'{$wq - $wr:.2f}')")
  echo "  mpirun -np 1 over a plain run (nothing to fit): $ov s"
fi
load=$(cut -d' ' -f1 /proc/loadavg)
python3 - "$rows" "$evals" "$cores" "$w1" "$n1" "$e1" "$wa" "$na" "$wj" "$nj" "$wm" "$nm" "$ov" "$c1" "$load" <<'PY'
import sys
rows, evals, cores = sys.argv[1:4]
w1, n1, e1, wa, na, wj, nj, wm, nm = map(float, sys.argv[4:13])
ov, c1, load = sys.argv[13], float(sys.argv[14]), sys.argv[15]
rpm = lambda n, w: 60 * n / w if w > 0 and n > 0 else float("nan")
r1, ra, rj, rm = rpm(n1, w1), rpm(na, wa), rpm(nj, wj), rpm(nm, wm)
print(f"RESULT batch rows={rows} evals={evals} cores={cores} rpm_1t={r1:.3f} rpm_all={ra:.3f} rpm_jobs2={rj:.3f} "
      f"rpm_mpi2={rm:.3f} scaling_all={ra / r1:.2f} scaling_jobs2={rj / r1:.2f} scaling_mpi2={rm / r1:.2f} "
      f"s_per_row_1t={w1 / n1:.1f} cpu_s_per_row={c1 / n1:.1f} evals_per_cpu_s={e1 / c1:.1f} "
      f"mpi_overhead_s={ov} load={load}")
PY
