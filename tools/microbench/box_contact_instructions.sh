#!/bin/sh
# Instructions per call (callgrind) of box_contact_benchmark's families:
# hedra's contact() cold and warm, on the box path and on the general
# polytope path, and Bullet's btBoxBoxDetector. Each count is one family's
# 1000 frames in one mode less the same run doing nothing (the setup),
# divided by 1000.
#   tools/microbench/box_contact_instructions.sh [build/bin/box_contact_benchmark] [FAMILY ...]
set -eu
bin=${1:-build/bin/box_contact_benchmark}
[ $# -gt 0 ] && shift
families=${*:-"unit/1mm/still unit/1mm/slide plates/1mm/still plates/1mm/slide small/1mm/still small/1mm/slide rounded/1mm/still rounded/1mm/slide"}
count() {
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" --once "$1" "$2" 2>&1 |
    sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
echo "| family | general cold | general warm | cold | warm | btBoxBoxDetector |"
echo "|---|---|---|---|---|---|"
for f in $families; do
  base=$(count "$f" none)
  row="| $f"
  for mode in general-cold general-warm cold warm bullet; do
    row="$row | $(( ($(count "$f" "$mode") - base) / 1000 ))"
  done
  echo "$row |"
done
