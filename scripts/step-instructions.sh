#!/bin/bash
# Instructions per simulation step under callgrind: a run of 2 s minus a
# run of 1 s, over the difference in steps, so that start-up and parsing
# cancel. For comparing a hot-path change built before and after.
#
# Usage: scripts/step-instructions.sh GEOPID_BINARY SCENE INTEGRATOR [BACKEND]
set -euo pipefail
bin=$1 scene=$2 integrator=$3 backend=${4:-glam}
declare -A ir steps
for d in 1 2; do
    out=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null \
        "$bin" run "$scene" --integrator "$integrator" --backend "$backend" --duration "$d" 2> "${TMPDIR:-/tmp}/step-instructions.err")
    ir[$d]=$(grep -E "Collected" "${TMPDIR:-/tmp}/step-instructions.err" | awk '{print $NF}')
    steps[$d]=$(grep -oE "[0-9]+ steps" <<< "$out" | head -1 | awk '{print $1}')
done
echo "$scene $integrator $backend: $(( (ir[2] - ir[1]) / (steps[2] - steps[1]) )) instructions per step"
