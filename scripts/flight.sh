#!/usr/bin/env bash
# The flight-ready check: builds the Cortex-M4F test image (firmware/) for
# thumbv7em-none-eabihf, runs it under QEMU's netduinoplus2 (an STM32F405,
# the Crazyflie 2.x's CPU), and compares every output word with the host's
# f32 results of the same inputs; then reports and checks what the laws
# cost there (instructions per update, .text, stack).
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
read -r pe _ <<< "$(addr gpc_position_update)"
read -r ae _ <<< "$(addr gpc_attitude_update)"
read -r pw pws <<< "$(addr firmware::position)"
read -r aw aws <<< "$(addr firmware::attitude)"
fifo=$(mktemp -u) && mkfifo "$fifo"
counts=$root/target/firmware/exact-counts.txt
# mawk has no hex arithmetic: addresses compare as fixed-width hex strings.
awk -v pe="$pe" -v ae="$ae" -v pw="$pw" -v pwe="$(printf '%08x' $((16#$pw + 16#$pws)))" \
    -v aw="$aw" -v awe="$(printf '%08x' $((16#$aw + 16#$aws)))" '
    { split($4, f, "/"); pc = f[2]
      if (pc == pe) { inp = 1; n = 0 } else if (pc == ae) { ina = 1; m = 0 }
      if (inp) { if (pc >= pw && pc < pwe) { inp = 0; ps += n; pn++; if (n > pmax) pmax = n; if (!pmin || n < pmin) pmin = n } else n++ }
      if (ina) { if (pc >= aw && pc < awe) { ina = 0; as += m; an++; if (m > amax) amax = m; if (!amin || m < amin) amin = m } else m++ } }
    END { printf "position %d %d %.1f %d\nattitude %d %d %.1f %d\n", pn, pmin, ps / (pn ? pn : 1), pmax, an, amin, as / (an ? an : 1), amax }' \
    "$fifo" > "$counts" &
timeout 600 "${qemu[@]}" -machine netduinoplus2 -cpu cortex-m4 -nographic -monitor none \
    -semihosting-config enable=on,target=native -icount shift=0 -singlestep -d exec,nochain -D "$fifo" \
    -kernel "$elf" > /dev/null
wait
rm -f "$fifo"
printf '%-10s %6s %10s %10s %10s\n' update calls min mean max
awk '{printf "%-10s %6d %10d %10.1f %10d\n", $1, $2, $3, $4, $5}' "$counts"
read -r _ calls _ _ pmax < <(grep '^position' "$counts")
if [ "$calls" -ne "$(grep -c '^R ' "$out")" ] || [ "$pmax" -gt 3360 ]; then
    echo "exact count: $calls position calls traced, at most $pmax instructions (budget 3360)"
    exit 1
fi
echo "every position-mode update within 3 360 instructions (1 % of a 500 Hz tick at 168 MHz)"

stage "sizes"
size_tool=$(command -v llvm-size-22 || command -v llvm-size || command -v rust-size || true)
if [ -z "$size_tool" ]; then
    echo "no llvm-size on PATH: sizes not measured"
    exit 1
fi
text=$("$size_tool" -A "$elf" | awk '$1 == ".text" {print $2}')
controller=$("$nm_tool" -S -C --size-sort --radix=d "$elf" \
    | awk '$3 ~ /^[tT]$/ && $0 ~ /(gpc_|geopid_control::|controllers::|lie::|libm::)/ {s += $2} END {print s + 0}')
echo "image .text: $text B; the controller's functions (gpc_*, controllers, lie, libm): $controller B; heap: none (no allocator in the image)"
if [ "$controller" -gt 49152 ]; then
    echo "the controller's .text exceeds 48 KB"
    exit 1
fi
stage "done"
