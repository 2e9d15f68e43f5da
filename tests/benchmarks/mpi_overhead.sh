#!/usr/bin/env bash
# What MPI costs on one machine (issue 19; README, "Experiments on MPI"):
#   1. launching: `lightbench integrators` alone and under mpirun -np 2;
#   2. per run: an experiment of many tiny runs (60 runs of 8 spp at 32x24)
#      in one process with 1 thread, and on -np 2 (rank 0 coordinates, one
#      worker with 1 thread): the difference divided by the runs is what
#      handing out a run and sending back its rows and images costs;
#   3. the time from the last run's end to the finished report (the runner's
#      "finish:" line), both ways;
#   4. rank 0's own work per run (the runner's "rank 0:" line: decoding a
#      run's result, writing its images and rows) at 128x96 and 1280x720,
#      which bounds how many workers one rank 0 keeps busy.
# Run it alone (nothing else on the machine): bash tests/benchmarks/mpi_overhead.sh [build]
set -euo pipefail
cd "$(dirname "$0")/../.."
BIN="${1:-build}/lightbench"
MPIRUN=(mpirun --oversubscribe)
[ "$(id -u)" -eq 0 ] && MPIRUN+=(--allow-run-as-root)
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
sed -e "s|../../scenes/|$PWD/scenes/|" -e "s|repeats: 2|repeats: 20|" tests/data/mpi-tiny.yaml > "$WORK/many.yaml"

now() { date +%s.%N; }
calc() { /usr/bin/python3 -c "print($1)"; }
elapsed() { calc "$2 - $1"; }

t0=$(now); for i in 1 2 3 4 5; do "$BIN" integrators >/dev/null; done; t1=$(now)
for i in 1 2 3 4 5; do "${MPIRUN[@]}" -np 2 "$BIN" integrators >/dev/null; done; t2=$(now)
printf "launch: alone %.3f s, mpirun -np 2 %.3f s (mean of 5)\n" "$(calc "($t1 - $t0) / 5")" "$(calc "($t2 - $t1) / 5")"

# The reference once, so that both runs below only run.
"$BIN" run "$WORK/many.yaml" --results "$WORK/warm" --no-report --threads 1 >/dev/null 2>&1
cp -r "$WORK/warm/references" "$WORK/one-refs"

for mode in single mpi; do
  rm -rf "$WORK/r" && mkdir -p "$WORK/r" && cp -r "$WORK/one-refs" "$WORK/r/references"
  t0=$(now)
  if [ $mode = single ]; then
    "$BIN" run "$WORK/many.yaml" --results "$WORK/r" --threads 1 2> "$WORK/$mode.err"
  else
    "${MPIRUN[@]}" -np 2 "$BIN" run "$WORK/many.yaml" --results "$WORK/r" --threads 1 2> "$WORK/$mode.err"
  fi
  t1=$(now)
  read -r runs render < <(/usr/bin/python3 -c "
import csv,sys
rows=[r for r in csv.DictReader(open(sys.argv[1])) if r['final']=='1' and ' + ' not in r['label']]
print(len(rows), sum(float(r['time_s']) for r in rows))" "$WORK"/r/many/*/log.csv)
  printf "%-6s: %d runs, wall %.2f s, of which rendering %.2f s; %s; %s\n" $mode "$runs" "$(elapsed $t0 $t1)" "$render" \
    "$(grep '^finish:' "$WORK/$mode.err")" "$(grep '^rank 0:' "$WORK/$mode.err" || true)"
done

for size in 128x96 1280x720; do
  w=${size%x*}; h=${size#*x}
  cat > "$WORK/size.yaml" <<YAML
scenes:
  - scene: $PWD/scenes/cornell-box.yaml
    resolution: [$w, $h]
    reference: {integrator: path, spp: 1, chunk_spp: 1}
    crop: [8, 8, 72, 56]
configurations:
  - {label: path, integrator: path}
budget: {spp: 1}
snapshots: {count: 1}
repeats: 6
YAML
  rm -rf "$WORK/s"
  "${MPIRUN[@]}" -np 2 "$BIN" run "$WORK/size.yaml" --results "$WORK/s" --threads 1 --no-report 2> "$WORK/size.err"
  echo "$size: $(grep '^rank 0:' "$WORK/size.err")"
done
