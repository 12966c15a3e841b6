#!/usr/bin/env bash
# Whether a change to the main job kept its output: every sample and corpus program through
# every sample machine model, on one thread and two, with the binary before and after; the
# written program, the report on stdout (the --json summary: every figure to ten digits),
# the messages and the exit code must be the same byte for byte. A speed change is kept
# only when this prints nothing but its last line.
#   bench/same-output.sh OLD_CCOMP NEW_CCOMP [EXTRA_PROGRAM...]
# (e.g. a copy of build/src/ccomp from before the change, and build/src/ccomp; a long
# program such as the bench's finishing pass as an extra).
source "$(dirname "$0")/common.sh"
old=$(realpath "${1:?usage: same-output.sh OLD_CCOMP NEW_CCOMP [PROGRAM...]}")
new=$(realpath "${2:?usage: same-output.sh OLD_CCOMP NEW_CCOMP [PROGRAM...]}")
shift 2
out="$work/same-output"
rm -rf "$out"
mkdir -p "$out/old" "$out/new"
mapfile -t programs < <(find samples/programs tests/data/corpus -name '*.ngc' | sort)
programs+=("$@")
runs=0
for model in samples/machines/*.yaml; do
  name=$(basename "$model" .yaml)
  sensors=()
  grep -q '^sensors:' "$model" && sensors=(--sensor bed=24 --sensor column=23 --sensor spindle=31 --time 3600)
  for program in "${programs[@]}"; do
    key="$name.$(tr / _ <<< "$program")"
    for threads in 1 2; do
      for side in old new; do
        bin=$old
        [ "$side" = new ] && bin=$new
        rc=0
        # (written to one place for both binaries, as the summary names it, then moved)
        "$bin" "$program" -m "$model" -o "$out/written.ngc" --tool-table samples/tools.tbl \
          "${sensors[@]}" --force --json --threads "$threads" > "$out/$side/$key.$threads.stdout" \
          2> "$out/$side/$key.$threads.stderr" || rc=$?
        if [ -e "$out/written.ngc" ]; then mv "$out/written.ngc" "$out/$side/$key.$threads.ngc"; fi
        echo "$rc" > "$out/$side/$key.$threads.rc"
      done
      runs=$((runs + 1))
    done
  done
done
if diff -rq "$out/old" "$out/new"; then
  echo "same-output: the same in all $runs runs (${#programs[@]} programs, $(ls samples/machines/*.yaml | wc -l) models, 1 and 2 threads)"
else
  echo "same-output: the files above differ (in $out)" >&2
  exit 1
fi
