#!/usr/bin/env bash
# Shop-floor batch: compensate every program in a folder into another folder, in parallel,
# and say plainly what happened: one ccomp per program (JOBS at once), a line for each program
# ccomp did not compensate, and a count of those it did, from ccomp's exit codes. Exit code:
# 0 all done; otherwise the highest of ccomp's codes (1 written but not passed, 3 a program
# is wrong, 5 the model, 6 a file, 7 refused as unsafe), see `ccomp --help`. A refused program's earlier output, if one
# is in OUT_DIR, is left as it was and named in its line: do not send it.
#
#   ccomp-batch.sh IN_DIR OUT_DIR MODEL.yaml [TOOL_TABLE] [--] [CCOMP_OPTION...]
#
# Every argument after the model (and the tool table, when the first is not an option) goes
# to each ccomp as it is: --sensor bed=21 --dialect fanuc --work-offset G54=X0,Y0,Z-400 ...
# Environment: CCOMP (the ccomp binary, default: ccomp on PATH), JOBS (default: all cores).
set -uo pipefail
usage="usage: ccomp-batch.sh IN_DIR OUT_DIR MODEL.yaml [TOOL_TABLE] [--] [CCOMP_OPTION...]"
in_dir=${1:?$usage}
out_dir=${2:?$usage}
model=${3:?$usage}
shift 3
tools=
# A fourth argument that is not an option is the tool table (the script's first form).
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then tools=$1; shift; fi
[ "${1:-}" = "--" ] && shift
options=("$@")  # for every ccomp, after the script's own
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
# program leaves an earlier run's output, if any, as it was). The options go to the worker
# as its first arguments (an array does not pass through the environment); xargs appends
# each program's index and path after them.
export CCOMP_BATCH_BIN=$ccomp CCOMP_BATCH_MODEL=$model CCOMP_BATCH_TOOLS=$tools CCOMP_BATCH_OUT=$out_dir \
  CCOMP_BATCH_STATUS=$status_dir
for i in "${!programs[@]}"; do printf '%s\0%s\0' "$i" "${programs[$i]}"; done |
  xargs -0 -n 2 -P "$jobs" bash -c '
    index=${@: -2:1} program=${@: -1}
    args=(-m "$CCOMP_BATCH_MODEL" --out-dir "$CCOMP_BATCH_OUT")
    [ -n "$CCOMP_BATCH_TOOLS" ] && args+=(--tool-table "$CCOMP_BATCH_TOOLS")
    "$CCOMP_BATCH_BIN" "$program" "${args[@]}" "${@:1:$#-2}"
    echo $? >"$CCOMP_BATCH_STATUS/$index"' _ ${options[@]+"${options[@]}"} 2>&1 | tee "$log" >&2

status=0
done_count=0
for i in "${!programs[@]}"; do
  p=${programs[$i]}
  code=$(cat "$status_dir/$i" 2>/dev/null) || code=
  [ -n "$code" ] || code=70  # no status: the worker did not run ccomp to its end
  if [ "$code" -eq 0 ]; then
    done_count=$((done_count + 1))
  elif [ "$code" -eq 1 ]; then
    # Written, but its verdict failed (over the tolerance, or worse than as written).
    echo "ccomp-batch: $p compensated but NOT PASSED (exit 1): check it before cutting" | tee -a "$log"
  else
    out="$out_dir/$(basename "$p")"
    stale=""
    [ -e "$out" ] && stale=" ($out is an earlier run's output, not this program's)"
    echo "ccomp-batch: $p not compensated (exit $code)$stale" | tee -a "$log"
  fi
  [ "$code" -gt "$status" ] && status=$code
done
echo "ccomp-batch: $done_count of ${#programs[@]} programs compensated and passed into $out_dir (exit $status; messages in $log)"
exit "$status"
