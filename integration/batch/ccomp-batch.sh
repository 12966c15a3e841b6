#!/usr/bin/env bash
# Shop-floor batch: compensate every program in a folder into another folder, in parallel,
# and say plainly what happened. Exit code: 0 all done; otherwise ccomp's highest code
# (3 a program is wrong, 5 the model, 6 a file, 7 refused as unsafe), see `ccomp --help`.
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
mkdir -p "$out_dir"
args=(-m "$model" --out-dir "$out_dir" -j "$jobs")
[ -n "$tools" ] && args+=(--tool-table "$tools")
log="$out_dir/ccomp-batch.log"
"$ccomp" "${programs[@]}" "${args[@]}" 2> >(tee "$log" >&2)
status=$?
done_count=0
for p in "${programs[@]}"; do [ -f "$out_dir/$(basename "$p")" ] && done_count=$((done_count + 1)); done
echo "ccomp-batch: $done_count of ${#programs[@]} programs compensated into $out_dir (exit $status; messages in $log)"
exit $status
