#!/usr/bin/env bash
# SPDX-License-Identifier: AGPL-3.0-or-later
# Runs every benchmark binary of a build folder; each prints JSON lines.
set -euo pipefail
build=${1:-build/release}
found=0
for b in "$build"/bench/palpa_bench_*; do
  [[ -x "$b" ]] || continue
  found=1
  "$b"
done
# A cohort design on one process and over MPI ranks (whole commands).
if [[ -x "$build/apps/palpa/palpa" ]] && command -v mpirun >/dev/null; then
  /usr/bin/python3 "$(dirname "$0")/cohort_ranks.py" --palpa "$build/apps/palpa/palpa"
fi
# The Python module's call overhead, when the module was built.
if [[ -d "$build/python/palpa" ]]; then
  PYTHONPATH="$build/python" /usr/bin/python3 "$(dirname "$0")/python_overhead.py"
fi
if (( found == 0 )); then
  echo "bench: no benchmark binaries in $build/bench" >&2
  exit 1
fi
