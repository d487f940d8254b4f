#!/usr/bin/env bash
# Mutation testing of the numerical core with cargo-mutants (not in CI: a
# full pass over these files is 4 276 mutants, hours on two cores).
#
#   scripts/mutants.sh list            # how many mutants, per file
#   scripts/mutants.sh sample OUT      # the sample of docs/mutants.md
#   scripts/mutants.sh rerun OUT.json  # re-test what a run did not catch
#
# The sample is two round-robin shards of twelve (every 12th mutant of the
# list in source order): shard 8, drawn by Python's
# random.Random(34).randrange(12), and shard 5, the first draw of
# random.Random(35) other than 8. `rerun` takes the mutants a run missed
# or timed out on (scripts/mutants-table.py --list) and tests them again
# with every feature on, as CI tests them (the SIMD lanes included).
# Mutants are tested in place: run it in a clean worktree of its own
# (`git worktree add ../mut HEAD`), not in the one you edit.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v cargo-mutants >/dev/null || cargo install cargo-mutants
FILES=(lie/src/so3.rs lie/src/se3.rs lie/src/series.rs lie/src/quat.rs lie/src/convert.rs
       lie/src/rotation.rs lie/src/group.rs lie/src/bundle.rs
       controllers/src/attitude_pid.rs controllers/src/position_pid.rs
       controllers/src/mode_scheduler.rs controllers/src/mode.rs
       dynamics/src/vehicles.rs dynamics/src/multirotor.rs dynamics/src/wind.rs
       integrators/src/rk.rs integrators/src/lgvi.rs integrators/src/dopri.rs
       integrators/src/dense.rs integrators/src/stepper.rs
       scenarios/src/sim/events.rs scenarios/src/sim/closed_loop.rs
       studies/src/montecarlo/mod.rs studies/src/montecarlo/experiments.rs)
F=()
for f in "${FILES[@]}"; do F+=(-f "$f"); done
# No debug info: the builds are for running tests, and linking is faster.
export CARGO_PROFILE_DEV_DEBUG=false
# Exact names as cargo-mutants' --re arguments (regex metacharacters escaped).
as_re() { python3 -c '
import sys
meta = set("\\.+*?()|[]{}^$#&-~")
for line in sys.stdin:
    name = line.rstrip("\n")
    if name:
        print("-F"); print("^" + "".join("\\" + c if c in meta else c for c in name) + "$")'; }
case "${1:-}" in
list)
    cargo mutants --list "${F[@]}" | cut -d: -f1 | sort | uniq -c ;;
sample)
    out=${2:?output directory}
    for k in 8 5; do cargo mutants --list --shard "$k/12" --sharding round-robin "${F[@]}"; done \
        | sort -u | as_re > "$out.args"
    mapfile -t ARGS < "$out.args"
    cargo mutants --in-place --no-shuffle --minimum-test-timeout 30 -o "$out" "${ARGS[@]}" "${F[@]}" ;;
rerun)
    json=${2:?outcomes.json of an earlier run}
    python3 scripts/mutants-table.py "$json" --list | cut -c10- | as_re > "$json.rerun.args"
    mapfile -t ARGS < "$json.rerun.args"
    cargo mutants --in-place --no-shuffle --all-features --minimum-test-timeout 30 \
        -o "$(dirname "$json")/rerun" "${ARGS[@]}" "${F[@]}" ;;
*)
    sed -n '2,17p' "$0"; exit 2 ;;
esac
