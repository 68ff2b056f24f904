#!/bin/sh
# SPDX-License-Identifier: Apache-2.0
# Runs a SocketCAN test binary inside a qemu VM booted from Debian's kernel, for hosts whose
# kernel has no AF_CAN (docs/nav-protocols.md §13.4). One boot: vcan0/vcan1 up, the test binary
# against candump/cansend, optionally an slcan bridge on ttyS1 to a host unix socket.
#
#   run-vm-can.sh --test-binary <gtest exe> --work-dir <dir under the build dir> [--timeout s]
#                 [--no-slcan] [--accel tcg|kvm|auto]
#
# Acceleration: tcg (default) is qemu's software CPU: it boots and runs the tests in seconds and
# works on every host. kvm is faster where nested virtualisation works, but on some hosts a
# writable /dev/kvm still leaves the guest stuck at "Booting from ROM"; auto probes KVM with a
# short boot (10 s at most) and falls back to TCG. MIRAGE_VM_ACCEL sets the default.
#
# Exit 0 = all tests passed, 1 = failure, 77 = skipped (qemu, busybox-static, can-utils or the
# kernel package unavailable). The kernel package is downloaded once into <work-dir>/cache, so
# reruns work offline.
set -u

SKIP=77
binary=""
work=""
timeout_s=120
slcan=1
accel=${MIRAGE_VM_ACCEL:-tcg}
while [ $# -gt 0 ]; do
    case "$1" in
        --test-binary) binary="$2"; shift 2 ;;
        --work-dir) work="$2"; shift 2 ;;
        --timeout) timeout_s="$2"; shift 2 ;;
        --no-slcan) slcan=0; shift ;;
        --accel) accel="$2"; shift 2 ;;
        *) echo "vm-can: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
case "$accel" in tcg|kvm|auto) ;; *) echo "vm-can: --accel must be tcg, kvm or auto" >&2; exit 2 ;; esac
[ -n "$binary" ] && [ -n "$work" ] || { echo "vm-can: --test-binary and --work-dir are required" >&2; exit 2; }
[ -x "$binary" ] || { echo "vm-can: test binary '$binary' not found" >&2; exit 1; }

skip() { echo "SKIP vm-can: $*"; exit $SKIP; }
need() { command -v "$1" >/dev/null 2>&1 || skip "'$1' not found ($2)"; }

need qemu-system-x86_64 "apt-get install qemu-system-x86"
need busybox "apt-get install busybox-static"
need candump "apt-get install can-utils"
need cansend "apt-get install can-utils"
need dpkg-deb "a Debian host is needed to unpack the kernel package"
need gzip "gzip"
need timeout "coreutils"
busybox_bin=$(command -v busybox)
if ldd "$busybox_bin" >/dev/null 2>&1; then
    skip "$busybox_bin is dynamically linked (apt-get install busybox-static)"
fi
if [ "$slcan" = 1 ]; then
    command -v slcand >/dev/null 2>&1 && command -v socat >/dev/null 2>&1 || {
        echo "vm-can: slcand or socat missing, slcan bridge check skipped"; slcan=0; }
fi

mkdir -p "$work/cache" || exit 1
cache=$(cd "$work/cache" && pwd)
work=$(cd "$work" && pwd)

# --- (a) Debian's kernel, once --------------------------------------------------------------
pkg=""
if command -v apt-cache >/dev/null 2>&1; then
    pkg=$(apt-cache depends linux-image-amd64 2>/dev/null |
          awk '/Depends: linux-image-[0-9]/{print $2; exit}')
fi
deb=""
[ -n "$pkg" ] && deb=$(ls "$cache"/"${pkg}"_*.deb 2>/dev/null | head -n 1)
if [ -z "$deb" ] && [ -n "$pkg" ] && command -v apt-get >/dev/null 2>&1; then
    echo "vm-can: downloading $pkg (about 70 MB, once) into $cache"
    (cd "$cache" && apt-get download "$pkg") 2>&1 | sed 's/^/vm-can: apt-get: /'
    deb=$(ls "$cache"/"${pkg}"_*.deb 2>/dev/null | head -n 1)
fi
# Offline, or the ABI moved on and the mirror is unreachable: any cached kernel will do.
[ -z "$deb" ] && deb=$(ls "$cache"/linux-image-*-amd64_*.deb 2>/dev/null | head -n 1)
[ -n "$deb" ] || skip "no Debian kernel package: 'apt-get download ${pkg:-linux-image-6.1.0-NN-amd64}' failed (no network to the Debian mirror?)"

kx="$cache/kx-$(basename "$deb" .deb)"
if [ ! -d "$kx" ]; then
    echo "vm-can: unpacking the kernel and the CAN modules of $(basename "$deb")"
    mkdir -p "$kx.tmp" &&
    dpkg-deb --fsys-tarfile "$deb" | tar -x -C "$kx.tmp" --wildcards \
        './boot/vmlinuz-*' '*/kernel/net/can/can.ko' '*/kernel/net/can/can-raw.ko' \
        '*/kernel/drivers/net/can/dev/can-dev.ko' '*/kernel/drivers/net/can/vcan.ko' \
        '*/kernel/drivers/net/can/slcan/slcan.ko' &&
    mv "$kx.tmp" "$kx" || { rm -rf "$kx.tmp"; echo "vm-can: cannot unpack $deb"; exit 1; }
fi
vmlinuz=$(ls "$kx"/boot/vmlinuz-* | head -n 1)
kver=${vmlinuz##*/vmlinuz-}
mods="$kx/lib/modules/$kver/kernel"

# --- (b) the initramfs -----------------------------------------------------------------------
root="$work/rootfs"
rm -rf "$root"
mkdir -p "$root/bin" "$root/lib/modules" "$root/proc" "$root/sys" "$root/dev" "$root/tmp" \
         "$root/lib64" "$root/etc" || exit 1
cp "$busybox_bin" "$root/bin/busybox"
for app in sh mount insmod ip sleep cat poweroff echo ls uname grep wc sed head; do
    ln -s busybox "$root/bin/$app"
done
cp "$mods/net/can/can.ko" "$mods/net/can/can-raw.ko" "$mods/drivers/net/can/dev/can-dev.ko" \
   "$mods/drivers/net/can/vcan.ko" "$mods/drivers/net/can/slcan/slcan.ko" "$root/lib/modules/"

# A binary and the shared libraries it needs (can-utils need libc and ld.so only).
add_binary() {
    cp "$1" "$root/bin/" || exit 1
    ldd "$1" 2>/dev/null | awk '/=> \//{print $3} /^\t\/lib/{print $1}' | while read -r lib; do
        mkdir -p "$root$(dirname "$lib")"
        [ -e "$root$lib" ] || cp -L "$lib" "$root$lib"
    done
}
add_binary "$(command -v candump)"
add_binary "$(command -v cansend)"
[ "$slcan" = 1 ] && add_binary "$(command -v slcand)"
add_binary "$binary"
test_name=$(basename "$binary")

cat > "$root/init" <<EOF
#!/bin/sh
export PATH=/bin
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
for m in can can-raw can-dev vcan slcan; do
    insmod /lib/modules/\$m.ko || echo "MIRAGE-VM: insmod \$m failed"
done
ip link set up lo
ip link add dev vcan0 type vcan && ip link set up vcan0
ip link add dev vcan1 type vcan && ip link set up vcan1
echo "MIRAGE-VM: kernel \$(uname -r), vcan0 and vcan1 up"
candump -L vcan0 > /tmp/candump.log &
dump=\$!
SLCAN=$slcan
if [ "\$SLCAN" = 1 ]; then
    # slcan bridge (§13.4): the host speaks Lawicel ASCII (§9) on the unix socket behind ttyS1.
    slcand -o -c -s6 /dev/ttyS1 can0
    i=0
    while [ \$i -lt 50 ] && [ ! -e /sys/class/net/can0 ]; do sleep 0.1; i=\$((i + 1)); done
    ip link set up can0 && echo "MIRAGE-VM: slcan can0 up" || echo "MIRAGE-VM: slcand failed"
    candump -L can0 > /tmp/slcan.log &
    slcan_dump=\$!
fi
MIRAGE_VCAN=vcan0 MIRAGE_VCAN_SPARE=vcan1 /bin/$test_name --gtest_color=no
rc=\$?
if [ "\$SLCAN" = 1 ]; then
    # The host connects and sends first, so it is listening when the guest answers.
    echo "MIRAGE-VM: slcan ready"
    i=0
    while [ \$i -lt 150 ] && ! grep -q '607#F8207800CEFF' /tmp/slcan.log; do
        sleep 0.1; i=\$((i + 1))
    done
    cansend can0 123#DEADBEEF
    sleep 0.3
    kill \$slcan_dump
    sed 's/^/MIRAGE-VM-SLCAN: /' /tmp/slcan.log
fi
kill \$dump
sed 's/^/MIRAGE-VM-CANDUMP: /' /tmp/candump.log
echo "MIRAGE-VM-RESULT rc=\$rc"
poweroff -f
EOF
chmod +x "$root/init"
(cd "$root" && find . | busybox cpio -o -H newc 2>/dev/null | gzip -1 > "$work/initrd.gz") || exit 1

# --- (c) boot ----------------------------------------------------------------------------------
# KVM only when it boots: a probe initramfs that prints a marker and powers off at once.
kvm_boots() {
    [ -w /dev/kvm ] || { echo "vm-can: /dev/kvm not writable"; return 1; }
    probe="$work/probe"
    rm -rf "$probe" && mkdir -p "$probe/bin" || return 1
    cp "$busybox_bin" "$probe/bin/busybox" && ln -s busybox "$probe/bin/sh" &&
        ln -s busybox "$probe/bin/poweroff" || return 1
    printf '#!/bin/sh\necho MIRAGE-VM-PROBE-OK\npoweroff -f\n' > "$probe/init"
    chmod +x "$probe/init"
    (cd "$probe" && find . | busybox cpio -o -H newc 2>/dev/null | gzip -1 > "$work/probe.gz")
    timeout 10 qemu-system-x86_64 -accel kvm -m 128 -nographic -no-reboot -kernel "$vmlinuz" \
        -initrd "$work/probe.gz" -append 'console=ttyS0 quiet panic=-1' </dev/null \
        > "$work/probe.log" 2>&1
    grep -q MIRAGE-VM-PROBE-OK "$work/probe.log"
}
if [ "$accel" = auto ]; then
    if kvm_boots; then accel=kvm; else
        echo "vm-can: KVM did not boot a probe kernel within 10 s; using TCG"; accel=tcg; fi
fi
console="$work/console.log"
sock="$work/ttyS1.sock"
rm -f "$sock" "$console" "$work/slcan-host.log"
echo "vm-can: booting $kver ($accel) with $test_name, timeout ${timeout_s}s"
start=$(date +%s.%N)
timeout "$timeout_s" qemu-system-x86_64 -accel "$accel" -m 512 -nographic -no-reboot \
    -kernel "$vmlinuz" -initrd "$work/initrd.gz" \
    -append 'console=ttyS0 quiet panic=-1' \
    -serial mon:stdio -serial "unix:$sock,server=on,wait=off" </dev/null >"$console" 2>&1 &
qemu=$!

# The host end of the slcan bridge: wait for the guest's go, send one OxTS 0x607 frame as
# Lawicel text, and record what the guest's cansend puts on the line.
if [ "$slcan" = 1 ]; then
    i=0
    while [ $i -lt "$((timeout_s * 10))" ] && kill -0 $qemu 2>/dev/null &&
          ! grep -q 'MIRAGE-VM: slcan ready' "$console" 2>/dev/null; do
        sleep 0.1; i=$((i + 1))
    done
    if grep -q 'MIRAGE-VM: slcan ready' "$console" 2>/dev/null; then
        # Stay connected until the VM powers off (socat ends when qemu closes the socket).
        { printf 't6076F8207800CEFF\r'; while kill -0 $qemu 2>/dev/null; do sleep 0.2; done; } |
            socat - "UNIX-CONNECT:$sock" > "$work/slcan-host.log" 2>/dev/null &
        bridge=$!
    fi
fi
wait $qemu
qemu_rc=$?
[ -n "${bridge:-}" ] && wait "$bridge"
end=$(date +%s.%N)
sed 's/\r$//' "$console"
secs=$(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.1f", b - a}')

# --- (d) verdict --------------------------------------------------------------------------------
fail=0
grep -q 'MIRAGE-VM-RESULT rc=0' "$console" || { echo "vm-can: FAIL: the test binary failed or did not finish (qemu exit $qemu_rc)"; fail=1; }
passed=$(sed -n 's/.*\[  PASSED  \] \([0-9]*\) test.*/\1/p' "$console" | tail -n 1)
[ -n "$passed" ] || { echo "vm-can: FAIL: no gtest summary on the console"; fail=1; }
if grep -q '\[  SKIPPED \]' "$console"; then echo "vm-can: FAIL: tests skipped inside the VM"; fail=1; fi
if grep -q '\[  FAILED  \]' "$console"; then echo "vm-can: FAIL: gtest failures"; fail=1; fi
# Independent of the test binary: the background candump saw the bus's OxTS frame.
grep -q 'MIRAGE-VM-CANDUMP: (.*) vcan0 607#F8207800CEFF' "$console" ||
    { echo "vm-can: FAIL: background candump did not log 607#F8207800CEFF"; fail=1; }
if [ "$slcan" = 1 ]; then
    if grep -q 'MIRAGE-VM-SLCAN: (.*) can0 607#F8207800CEFF' "$console" &&
       tr '\r' '\n' < "$work/slcan-host.log" | grep -q '^t1234DEADBEEF$'; then
        echo "vm-can: slcan bridge: host->guest t6076F8207800CEFF seen by candump on can0," \
             "guest cansend 123#DEADBEEF seen on the host as t1234DEADBEEF"
    else
        echo "vm-can: FAIL: slcan bridge frames not seen both ways"; fail=1
    fi
fi
if [ "$fail" = 0 ]; then
    echo "vm-can: PASS: ${passed:-?} tests in the VM, boot + tests ${secs} s wall"
    exit 0
fi
echo "vm-can: FAIL after ${secs} s (console: $console)"
exit 1
