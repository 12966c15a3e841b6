#!/usr/bin/env bash
# Shop-floor batch: compensate every program in a folder into another folder, in parallel,
# and say plainly what happened: one ccomp per program (JOBS at once), a line for each program
# ccomp did not compensate, and a count of those it did, from ccomp's exit codes. Exit code:
# 0 all done; otherwise the highest of ccomp's codes (3 a program is wrong, 5 the model, 6 a
# file, 7 refused as unsafe), see `ccomp --help`. A refused program's earlier output, if one
# is in OUT_DIR, is left as it was and named in its line: do not send it.
#
#   ccomp-batch.sh IN_DIR OUT_DIR MODEL.yaml [TOOL_TABLE]
#
# Environment: CCOMP (the ccomp binary, default: ccomp on PATH), JOBS (default: all cores).
set -uo pipefail
in_dir=${1:?usage: ccomp-batch.sh IN_DIR OUT_DIR MODEL.yaml [TOOL_TABLE]}
out_dir=${2:?usage: ccomp-batch.sh IN_DIR OUT_DIR MODEL.yaml [TOOL_TABLE]}
model=${3:?usage: ccomp-batch.sh IN_DIR OUT_DIR MODEL.yaml [TOOL_TABLE]}
tools=${4:-}
ccomp=${CCOMP:-ccomp}
jobs=${JOBS:-$(nproc)}

shopt -s nullglob nocaseglob
programs=("$in_dir"/*.ngc "$in_dir"/*.nc "$in_dir"/*.tap)
if [ ${#programs[@]} -eq 0 ]; then
  echo "ccomp-batch: no programs (*.ngc, *.nc, *.tap) in $in_dir" >&2
  exit 0
fi
mkdir -p "$out_dir" || exit 6
log="$out_dir/ccomp-batch.log"
status_dir=$(mktemp -d) || exit 6
trap 'rm -rf "$status_dir"' EXIT

# One ccomp per program, JOBS at once, each leaving its exit code in status_dir/<index>: the
# count comes from what ccomp said of each program, not from which outputs exist (a refused
# program leaves an earlier run's output, if any, as it was).
export CCOMP_BATCH_BIN=$ccomp CCOMP_BATCH_MODEL=$model CCOMP_BATCH_TOOLS=$tools CCOMP_BATCH_OUT=$out_dir \
  CCOMP_BATCH_STATUS=$status_dir
for i in "${!programs[@]}"; do printf '%s\0%s\0' "$i" "${programs[$i]}"; done |
  xargs -0 -n 2 -P "$jobs" bash -c '
    args=(-m "$CCOMP_BATCH_MODEL" --out-dir "$CCOMP_BATCH_OUT")
    [ -n "$CCOMP_BATCH_TOOLS" ] && args+=(--tool-table "$CCOMP_BATCH_TOOLS")
    "$CCOMP_BATCH_BIN" "$2" "${args[@]}"
    echo $? >"$CCOMP_BATCH_STATUS/$1"' _ 2>&1 | tee "$log" >&2

status=0
done_count=0
for i in "${!programs[@]}"; do
  p=${programs[$i]}
  code=$(cat "$status_dir/$i" 2>/dev/null) || code=
  [ -n "$code" ] || code=70  # no status: the worker did not run ccomp to its end
  if [ "$code" -eq 0 ]; then
    done_count=$((done_count + 1))
  else
    out="$out_dir/$(basename "$p")"
    stale=""
    [ -e "$out" ] && stale=" ($out is an earlier run's output, not this program's)"
    echo "ccomp-batch: $p not compensated (exit $code)$stale" | tee -a "$log"
  fi
  [ "$code" -gt "$status" ] && status=$code
done
echo "ccomp-batch: $done_count of ${#programs[@]} programs compensated into $out_dir (exit $status; messages in $log)"
exit "$status"
