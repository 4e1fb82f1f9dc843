#!/usr/bin/env bash
# The JupyterLab test under load: `make lab-test` N times (default 5), each with a CPU-bound
# 30-day Mars run looping beside it, as a busy 2-core CI machine would be. Prints one line a
# run (exit code, wall seconds, load average, pytest's last line); logs in _build/lab-under-load/.
# Compare the seconds with a quiet `make lab-test`: the test should stay green and within 1.5x.
# Usage, from the repository root after `make setup`: sh tools/lab_under_load.sh [N]
set -u
n=${1:-5}
out=_build/lab-under-load
mkdir -p "$out"
i=1
while [ "$i" -le "$n" ]; do
  setsid sh -c 'while true; do .venv/bin/python -m xnavlab run mars --days 30 --json >/dev/null 2>&1; done' &
  hog=$!
  start=$(date +%s)
  make lab-test >"$out/run$i.log" 2>&1
  rc=$?
  end=$(date +%s)
  kill -- -"$hog" 2>/dev/null
  wait "$hog" 2>/dev/null
  echo "run $i: exit $rc, $((end - start)) s, load $(cut -d' ' -f1-3 /proc/loadavg), $(tail -n 1 "$out/run$i.log")"
  i=$((i + 1))
done
