#!/usr/bin/env bash
# What the outputs cost: `hover-disturbed` sampled at 1 kHz for DURATION
# simulated seconds (default one hour), without outputs, with --csv, with
# --mcap and with both, each run ROUNDS times alternately; then `dd` with
# fsync writing as many bytes as both files hold. Prints the medians, the
# outputs' cost (both minus none) and its ratio to dd, and the peak memory.
#
#   scripts/output-cost.sh [DURATION] [ROUNDS]     (XTASK=path/to/xtask to pick the binary)
set -euo pipefail
cd "$(dirname "$0")/.."
dur=${1:-3600}
rounds=${2:-2}
xtask=${XTASK:-target/debug/xtask}
[[ -x $xtask ]] || cargo build -q -p xtask
dir=target/output-cost
mkdir -p "$dir"
declare -A wall mem
run() { # name, flags...
    local name=$1
    shift
    # Each run writes new files, as dd does below: replacing the previous
    # run's files would add the kernel's freeing of their pages (0.6 s for
    # ten minutes' logs here) to the run's time, and dd's file is removed
    # off the clock.
    rm -f "$dir/run.csv" "$dir/run.mcap"
    sync
    /usr/bin/time -f "%e %M" -o "$dir/time" "$xtask" run hover-disturbed --duration "$dur" --sample 0.001 "$@" > /dev/null
    read -r t m < "$dir/time"
    wall[$name]+="$t "
    mem[$name]=$m
}
for _ in $(seq "$rounds"); do
    run none
    run csv --csv "$dir/run.csv"
    run mcap --mcap "$dir/run.mcap"
    run both --csv "$dir/run.csv" --mcap "$dir/run.mcap"
done
csv_bytes=$(stat -c %s "$dir/run.csv")
mcap_bytes=$(stat -c %s "$dir/run.mcap")
bytes=$((csv_bytes + mcap_bytes))
dd_times=""
for _ in $(seq "$rounds"); do
    sync
    start=$(date +%s.%N)
    dd if=/dev/zero of="$dir/dd" bs=1M count=$(((bytes + 1048575) / 1048576)) conv=fsync status=none
    dd_times+="$(python3 -c "import sys; print(float(sys.argv[2]) - float(sys.argv[1]))" "$start" "$(date +%s.%N)") "
    rm -f "$dir/dd"
done
rm -f "$dir/run.csv" "$dir/run.mcap"
python3 - "$dur" "$rounds" "$csv_bytes" "$mcap_bytes" "$dd_times" \
    "${wall[none]}" "${wall[csv]}" "${wall[mcap]}" "${wall[both]}" \
    "${mem[none]}" "${mem[csv]}" "${mem[mcap]}" "${mem[both]}" <<'PY'
import statistics as st, sys
dur, rounds, csv_b, mcap_b = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
dd = st.median(map(float, sys.argv[5].split()))
walls = [list(map(float, w.split())) for w in sys.argv[6:10]]
mems = [int(m) for m in sys.argv[10:14]]
print(f"hover-disturbed, {dur} s at 1 kHz, medians of {rounds} runs each (alternated):")
for name, w, m in zip(["none", "csv", "mcap", "both"], walls, mems):
    print(f"  {name:5} {st.median(w):6.2f} s   peak memory {m // 1024:4d} MB   (runs: {' '.join(f'{x:.2f}' for x in w)})")
cost = st.median(walls[3]) - st.median(walls[0])
print(f"  bytes: CSV {csv_b / 1e9:.3f} GB + MCAP {mcap_b / 1e9:.3f} GB = {(csv_b + mcap_b) / 1e9:.3f} GB; dd with fsync of as many: {dd:.2f} s")
print(f"outputs cost {cost:.2f} s = {cost / dd:.2f}x dd")
PY
