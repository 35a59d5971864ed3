#!/usr/bin/env bash
# Instructions per mj_step (callgrind, only inside mj_step) of every scene
# with hedra, MuJoCo's single-point MPR and MuJoCo with multiccd: repeatable
# where wall times are not (docs/mujoco.md).
#   tools/mujoco/callgrind_steps.sh build/bin/hedra_mujoco [SECONDS]
set -euo pipefail
program=$1
seconds=${2:-1}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=$(mktemp -d)
printf '| scene | hedra | mujoco-multiccd | mujoco | hedra / multiccd | hedra / MPR |\n|---|---|---|---|---|---|\n'
declare -A per_step
for scene in "$here"/scenes/*.xml; do
  for run in hedra mujoco multiccd; do
    args=(--narrowphase "$run")
    if [[ $run == multiccd ]]; then args=(--narrowphase mujoco --multiccd); fi
    valgrind --tool=callgrind --toggle-collect=mj_step --callgrind-out-file="$out/cg" \
      "$program" "$scene" --seconds "$seconds" "${args[@]}" --json > "$out/json" 2> /dev/null
    steps=$(grep '"steps"' "$out/json" | tr -dc 0-9)
    callgrind_annotate "$out/cg" > "$out/annotated" 2> /dev/null
    total=$(awk '/PROGRAM TOTALS/ { gsub(",", "", $1); print $1; exit }' "$out/annotated")
    per_step[$run]=$((total / steps))
  done
  awk -v s="$(basename "$scene" .xml)" -v h="${per_step[hedra]}" -v m="${per_step[multiccd]}" -v p="${per_step[mujoco]}" \
    'BEGIN { printf "| %s | %d | %d | %d | %.2f | %.2f |\n", s, h, m, p, h / m, h / p }'
done
rm -rf "$out"
