#!/usr/bin/env bash
# Instructions per step of `tumble run SCENE` (callgrind's count, the load subtracted: a run of one
# step taken from a run of DURATION seconds), a measure of the step's work that a busy machine does
# not change; the CSV output written every sample_every steps is included.
#
#   tools/step_instructions.sh TUMBLE_BINARY SCENE.toml [DURATION]
#
# Needs valgrind (apt-get install valgrind).
set -euo pipefail
bin=$1 scene=$2 duration=${3:-2}
count() {
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" run "$scene" --quiet --duration "$1" \
        --out "$(mktemp -d)/out.csv" 2>&1 | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
dt=$(sed -n 's/^dt *= *\([0-9.e-]*\).*/\1/p' "$scene" | head -1)
one=$(count "$dt")
many=$(count "$duration")
python3 -c "print('%-28s %9.1f thousand instructions per step' % ('$(basename "$scene")', ($many - $one) / (($duration - $dt) / $dt) / 1000))"
