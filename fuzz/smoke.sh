#!/usr/bin/env bash
# SPDX-License-Identifier: AGPL-3.0-or-later
# A few seconds of fuzzing of one target, as the unit tests run it in the
# sanitizer build: PROGRAM (palpa_fuzz_smoke) mutates the target's seeds, its
# grown corpus and its regression inputs for SECONDS, in a fresh WORK folder.
# Exit status 0 when nothing was found; otherwise the input that crashed, leaked
# or hung is in WORK and its path is printed (copy it into
# fuzz/regressions/TARGET/ once fixed).
set -u
prog=${1:?usage: fuzz/smoke.sh PROGRAM TARGET SECONDS WORK}
target=${2:?}
seconds=${3:?}
work=${4:?}
src=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work/corpus"
inputs=("$work/corpus")
for d in "$src/corpus/$target" "$src/campaign/$target" "$src/regressions/$target"; do
  [ -d "$d" ] && inputs+=("$d")
done
PALPA_FUZZ_TARGET=$target "$prog" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
  -malloc_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$work/" "${inputs[@]}" \
  >"$work/log" 2>&1
status=$?
execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$work/log" | grep -o '[0-9]*$')
found=$(find "$work" -maxdepth 1 -type f ! -name log)
if [ $status -ne 0 ] || [ -n "$found" ]; then
  tail -n 40 "$work/log"
  echo "fuzz smoke: $target found ${found:-a failure} (exit $status); log: $work/log"
  exit 1
fi
echo "fuzz smoke: $target, ${execs:-0} inputs in ${seconds} s, nothing found"
