#!/usr/bin/env bash
# SPDX-License-Identifier: AGPL-3.0-or-later
# Runs every palpa_fuzz_<target> of BUILD_DIR for SECONDS each (default 60), on
# a working corpus in BUILD_DIR/fuzz/corpus/<target> seeded from
# fuzz/corpus/<target>. Inputs that crash, leak, hang over 1 s or allocate more
# than 2 GB are saved in BUILD_DIR/fuzz/artifacts/<target>/ (copy them into
# fuzz/regressions/<target>/ once fixed: the unit tests replay that folder).
# Prints one line per target: executions, coverage features, corpus size,
# findings. Exit status 1 if any target found something. FUZZ_TARGETS="csv obj"
# runs only those.
#
# The fuzzers start from the seeds and from the corpus that earlier campaigns
# grew (fuzz/campaign/<target>, kept in the repository). FUZZ_MERGE=1 adds to
# that folder the inputs of this run that add coverage to it (libFuzzer's
# -merge=1; nothing is removed, so the repository only gains files);
# FUZZ_MERGE=minimize rebuilds it as the smallest set that keeps all the
# coverage. Record the run in fuzz/CAMPAIGNS.md.
set -u
build=${1:?usage: fuzz/run.sh BUILD_DIR [SECONDS]}
seconds=${2:-60}
src=$(cd "$(dirname "$0")" && pwd)
status=0
printf '%-10s %12s %10s %8s  %s\n' target executions features corpus findings
for prog in "$build"/fuzz/palpa_fuzz_*; do
  t=${prog##*/palpa_fuzz_}
  if [ -n "${FUZZ_TARGETS:-}" ] && [[ " $FUZZ_TARGETS " != *" $t "* ]]; then continue; fi
  work="$build/fuzz/corpus/$t"
  art="$build/fuzz/artifacts/$t"
  mkdir -p "$work" "$art"
  log="$build/fuzz/$t.log"
  grown="$src/campaign/$t"
  inputs=("$work" "$src/corpus/$t")
  [ -d "$grown" ] && inputs+=("$grown")
  "$prog" -max_total_time="$seconds" -timeout=1 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
    -max_len=1048576 -print_final_stats=1 -artifact_prefix="$art/" "${inputs[@]}" >"$log" 2>&1
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo 0)
  merge_flags=(-merge=1 -timeout=1 -rss_limit_mb=2048 -malloc_limit_mb=2048 -max_len=1048576 -artifact_prefix="$art/")
  if [ "${FUZZ_MERGE:-0}" = 1 ]; then
    mkdir -p "$grown"
    "$prog" "${merge_flags[@]}" "$grown" "$work" "$src/corpus/$t" >"$build/fuzz/$t.merge.log" 2>&1
  elif [ "${FUZZ_MERGE:-0}" = minimize ]; then
    merged="$build/fuzz/merged/$t"
    rm -rf "$merged" && mkdir -p "$merged"
    "$prog" "${merge_flags[@]}" "$merged" "${inputs[@]}" >"$build/fuzz/$t.merge.log" 2>&1
    rm -rf "$grown" && mkdir -p "$grown" && cp "$merged"/* "$grown"/ 2>/dev/null
  fi
  found=$(find "$art" -type f | wc -l)
  [ "$found" -gt 0 ] && status=1
  printf '%-10s %12s %10s %8s  %s\n' "$t" "${execs:-0}" "${ft:-0}" "$(ls "$work" | wc -l)" \
    "$([ "$found" -gt 0 ] && echo "$found in $art (log: $log)" || echo none)"
done
exit $status
