#!/usr/bin/env bash
# The flight-ready check: builds the Cortex-M4F test image (firmware/) for
# thumbv7em-none-eabihf, runs it under QEMU's netduinoplus2 (an STM32F405,
# the Crazyflie 2.x's CPU) on the laws' inputs and a recorded IMU and
# motion-capture stream for the filters, compares every output word with
# the host's f32 results of the same inputs; then reports and checks what
# the laws and filters cost there (instructions per call, .text, stack).
#
# Installs what it needs: the target's toolchain (rustup's target if the
# runner has one, else Debian's rustc-web with -Zbuild-std=core) and QEMU
# (Debian's qemu-system-arm, unpacked into target/qemu when installing it
# would remove an installed package). The rustup toolchain stays first on
# PATH; only the image's build sees Debian's.
#
# Usage: scripts/flight.sh [--no-compare]. The bit-for-bit comparison with
# the host is the test `cargo test -p geopid-control --test firmware`, which reads
# target/firmware/qemu.txt; without --no-compare this script runs it last
# (CI runs the script first and the test inside `cargo test --workspace`).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
compare=1
[ "${1:-}" = "--no-compare" ] && compare=0
target=thumbv7em-none-eabihf
start=$SECONDS
stage() { echo "-- $1 ($((SECONDS - start)) s)"; }
apt_updated=
apt() {
    if [ -z "$apt_updated" ]; then apt-get update -q >/dev/null; apt_updated=1; fi
    DEBIAN_FRONTEND=noninteractive apt-get "$@"
}

stage "toolchain for $target"
if rustup target list --installed 2>/dev/null | grep -qx "$target"; then
    echo "rustup's $target standard library: plain cargo build"
    build_image() { cargo build --release; }
else
    if ! { [ -x /usr/bin/rustc ] && [ -d /usr/lib/rustlib/src/rust/library ] && command -v ld.lld-22 >/dev/null; }; then
        echo "installing Debian's rustc-web, cargo-web, rust-web-src and lld-22"
        apt install -y -q rustc-web cargo-web rust-web-src lld-22 >/dev/null
    fi
    echo "rustup has no $target here: Debian's $(/usr/bin/rustc --version), core built from rust-web-src (-Zbuild-std=core), linked by ld.lld-22"
    build_image() {
        env PATH="/usr/bin:$PATH" RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1 \
            CARGO_TARGET_THUMBV7EM_NONE_EABIHF_LINKER=ld.lld-22 \
            /usr/bin/cargo build --release -Zbuild-std=core
    }
fi

stage "QEMU"
if command -v qemu-system-arm >/dev/null; then
    qemu=(qemu-system-arm)
elif ! apt-get install -s qemu-system-arm 2>/dev/null | grep -q '^Remv'; then
    apt install -y -q qemu-system-arm >/dev/null
    qemu=(qemu-system-arm)
else
    # Installing it would remove a package (Debian's qemu-utils from
    # backports, here): its .deb and the libraries it lacks, unpacked.
    dir=$root/target/qemu
    if [ ! -x "$dir/root/usr/bin/qemu-system-arm" ]; then
        mkdir -p "$dir"
        (cd "$dir" && apt download qemu-system-arm libfdt1 libcapstone4 libpmem1 librdmacm1 \
            libibverbs1 libslirp0 libvdeplug2 libndctl6 libdaxctl1 libnl-3-200 libnl-route-3-200 >/dev/null \
            && for deb in ./*.deb; do dpkg-deb -x "$deb" root; done)
    fi
    libs="$dir/root/usr/lib/x86_64-linux-gnu:$dir/root/lib/x86_64-linux-gnu"
    qemu=(env "LD_LIBRARY_PATH=$libs" "$dir/root/usr/bin/qemu-system-arm")
    echo "qemu-system-arm unpacked into target/qemu (installing it would remove a package)"
fi
"${qemu[@]}" --version | head -1

stage "fmt and clippy of the firmware crate (clippy checks it for the host: a no_std, no_main crate checks there)"
cargo fmt --manifest-path firmware/Cargo.toml -- --check
CARGO_TARGET_DIR="$root/target/firmware-host" \
    cargo clippy -q --manifest-path firmware/Cargo.toml --target x86_64-unknown-linux-gnu -- -D warnings

stage "build the image"
(cd firmware && CARGO_TARGET_DIR="$root/target/firmware" build_image)
elf=$root/target/firmware/$target/release/firmware

stage "run it under QEMU (netduinoplus2, Cortex-M4, -icount shift=0: one instruction per virtual ns)"
out=$root/target/firmware/qemu.txt
timeout 300 "${qemu[@]}" -machine netduinoplus2 -cpu cortex-m4 -nographic -monitor none \
    -semihosting-config enable=on,target=native -icount shift=0 -kernel "$elf" > "$out"
echo "the image exited 0 after $(grep -c '^R ' "$out") records"

echo "what the image printed about its costs (SysTick; the exact counts follow):"
grep -E '^(C|S) ' "$out"

if [ "$compare" = 1 ]; then
    stage "compare with the host (cargo test -p geopid-control --test firmware)"
    cargo test -q -p geopid-control --test firmware -- --nocapture
else
    echo "(--no-compare: the comparison with the host is left to cargo test -p geopid-control --test firmware)"
fi

stage "exact instruction counts: the run again, single-stepped, every executed instruction traced"
# With -singlestep each translated block is one instruction, so the trace
# has one line per instruction executed: from the entry of a gpc_* update
# to the return into the image's wrapper is exactly what the call cost.
# (The SysTick counts above include the wrapper's few instructions around
# the call and are quantised to 6 instructions; these are exact.)
addr() { "$nm_tool" -S -C "$elf" | awk -v s="$1" '$4 == s && NF == 4 {print $1, $2}'; }
nm_tool=$(command -v llvm-nm-22 || command -v llvm-nm || command -v rust-nm || true)
[ -n "$nm_tool" ] || { echo "no llvm-nm on PATH"; exit 1; }
# Each traced call: its name, the C function, the image's wrapper around
# it, and its budget in instructions (0: reported, no budget).
#   position: a full position-mode update in 1 % of a 500 Hz tick at 168 MHz;
#   iekf-imu: the invariant EKF's predict, 25 000 (15 % of a 1 kHz tick);
#   complementary-*: 2 000, what a Crazyflie-class loop spends on attitude.
calls="position gpc_position_update firmware::position 3360
attitude gpc_attitude_update firmware::attitude 0
iekf-imu gpc_iekf_imu firmware::estimators::iekf_imu 25000
iekf-mocap gpc_iekf_mocap firmware::estimators::iekf_mocap 0
complementary-imu gpc_complementary_imu firmware::estimators::complementary_imu 2000
complementary-mocap gpc_complementary_mocap firmware::estimators::complementary_mocap 2000"
spec=$(while read -r name fn wrapper budget; do
    read -r e _ <<< "$(addr "$fn")"
    read -r w ws <<< "$(addr "$wrapper")"
    [ -n "$e" ] && [ -n "$w" ] || { echo "no symbol $fn or $wrapper in the image" >&2; exit 1; }
    echo "$name $e $w $(printf '%08x' $((16#$w + 16#$ws))) $budget"
done <<< "$calls")
fifo=$(mktemp -u) && mkfifo "$fifo"
counts=$root/target/firmware/exact-counts.txt
# mawk has no hex arithmetic: addresses compare as fixed-width hex strings.
# A call counts from its entry until the trace is back in its wrapper.
awk -v spec="$spec" '
    BEGIN { k = split(spec, lines, "\n")
            for (i = 1; i <= k; i++) { split(lines[i], f, " "); name[i] = f[1]; entry[i] = f[2]; lo[i] = f[3]; hi[i] = f[4] } }
    { split($4, f, "/"); pc = f[2]
      for (i = 1; i <= k; i++) {
        if (pc == entry[i]) { on[i] = 1; n[i] = 0 }
        if (on[i]) {
          if (pc >= lo[i] && pc < hi[i]) { on[i] = 0; sum[i] += n[i]; cnt[i]++; if (n[i] > max[i]) max[i] = n[i]; if (!min[i] || n[i] < min[i]) min[i] = n[i] }
          else n[i]++ } } }
    END { for (i = 1; i <= k; i++) printf "%s %d %d %.1f %d\n", name[i], cnt[i], min[i], sum[i] / (cnt[i] ? cnt[i] : 1), max[i] }' \
    "$fifo" > "$counts" &
timeout 600 "${qemu[@]}" -machine netduinoplus2 -cpu cortex-m4 -nographic -monitor none \
    -semihosting-config enable=on,target=native -icount shift=0 -singlestep -d exec,nochain -D "$fifo" \
    -kernel "$elf" > /dev/null
wait
rm -f "$fifo"
printf '%-20s %6s %10s %10s %10s %8s\n' call calls min mean max budget
failed=0
while read -r name calls min mean max; do
    budget=$(awk -v n="$name" '$1 == n {print $5}' <<< "$spec")
    printf '%-20s %6d %10d %10.1f %10d %8s\n' "$name" "$calls" "$min" "$mean" "$max" "${budget/#0/-}"
    if [ "$calls" -eq 0 ] || { [ "$budget" -gt 0 ] && [ "$max" -gt "$budget" ]; }; then
        echo "  $name: $calls calls traced, at most $max instructions (budget $budget)"
        failed=1
    fi
done < "$counts"
read -r _ pcalls _ < <(grep '^position' "$counts")
if [ "$pcalls" -ne "$(grep -c '^R ' "$out")" ]; then
    echo "exact count: $pcalls position calls traced, $(grep -c '^R ' "$out") records"
    failed=1
fi
[ "$failed" = 0 ] || exit 1
echo "every traced call within its budget"

stage "sizes"
size_tool=$(command -v llvm-size-22 || command -v llvm-size || command -v rust-size || true)
if [ -z "$size_tool" ]; then
    echo "no llvm-size on PATH: sizes not measured"
    exit 1
fi
text=$("$size_tool" -A "$elf" | awk '$1 == ".text" {print $2}')
# The filters' functions (their C entry points, the ABI's conversions
# for them and the sensors crate) are counted apart from the laws'.
read -r controller filters < <("$nm_tool" -S -C --size-sort --radix=d "$elf" \
    | awk '$3 ~ /^[tT]$/ {
        if ($0 ~ /(gpc_iekf|gpc_complementary|geopid_control::estimators|sensors::)/) f += $2
        else if ($0 ~ /(gpc_|geopid_control::|controllers::|lie::|libm::)/) c += $2 }
      END {print c + 0, f + 0}')
echo "image .text: $text B; the laws' functions (gpc_*, controllers, lie, libm): $controller B; the filters' (gpc_iekf_*, gpc_complementary_*, sensors): $filters B; heap: none (no allocator in the image)"
if [ "$controller" -gt 49152 ]; then
    echo "the controller's .text exceeds 48 KB"
    exit 1
fi
stage "done"
