#!/usr/bin/env bash
# The DeviceNet scanner's SocketCAN backend on a real kernel CAN interface:
# boots Debian's kernel (scripts/vm-kernel) under qemu with an initramfs
# that holds busybox, the kernel's CAN modules, plcrun, dnslave and
# can-utils, runs init.sh in it (the filling cell on vcan0 against dnslave,
# candump logging, cansend injecting), and checks what it printed
# (check_vcan_vm.py). vcan is a kernel CAN interface, not CAN hardware: see
# README.md, "DeviceNet", for what it cannot show.
#
#   tests/devicenet/vcan_vm/run_vcan_vm.sh [BUILD_DIR]     (default: build)
#
# Environment: PLC_VM_ACCEL=kvm|tcg (default: kvm where the CPU has
# hardware virtualisation and /dev/kvm opens, else tcg), PLC_VM_TIMEOUT
# (seconds for the whole boot-to-poweroff, default 360), PLC_VM_KERNEL_DIR
# (default build-vm/kernel), PLC_VM_WORK (default BUILD_DIR/vcan-vm: the
# initramfs, console log, candump log, trace).
# Exit 0: every check passed; 1: a check or the run failed; 77: skipped,
# qemu or the kernel is not there (ctest's SKIP_RETURN_CODE).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
src="$(cd "$here/../../.." && pwd)"
build="$(cd "${1:-$src/build}" && pwd)"
kernel_dir="${PLC_VM_KERNEL_DIR:-$src/build-vm/kernel}"
work="${PLC_VM_WORK:-$build/vcan-vm}"
timeout_s="${PLC_VM_TIMEOUT:-360}"

skip() {
  echo "SKIP: $*"
  exit 77
}
for tool in qemu-system-x86_64 candump cansend cpio objcopy python3; do
  command -v "$tool" >/dev/null || skip "$tool is not installed (scripts/setup installs it)"
done
busybox="$(command -v busybox || true)"
[ -n "$busybox" ] || skip "busybox is not installed (scripts/setup installs busybox-static)"
if ldd "$busybox" >/dev/null 2>&1; then skip "$busybox is not the static one (busybox-static)"; fi
[ -e "$kernel_dir/current" ] || skip "no VM kernel in $kernel_dir (scripts/setup or scripts/vm-kernel fetches it)"
kver="$(readlink "$kernel_dir/current")"
kroot="$kernel_dir/$kver"
vmlinuz="$kroot/boot/vmlinuz-$kver"
[ -f "$vmlinuz" ] || skip "no $vmlinuz (scripts/vm-kernel fetches it)"
for b in plcrun dnslave; do
  [ -x "$build/bin/$b" ] || { echo "FAILED: $build/bin/$b is not built"; exit 1; }
done

t_prep=$(date +%s.%N)
rm -rf "${work:?}"
root="$work/root"
mkdir -p "$root"/{bin,dev,proc,sys,tmp,vm/bin,vm/cell,vm/modules}
cp "$busybox" "$root/bin/busybox"

# An executable and every shared library ldd resolves for it. The ELF loader
# keeps its path (the executables name it); the libraries go into /vm/lib,
# which the VM's LD_LIBRARY_PATH (init.sh) puts before the build tree's
# RUNPATH. Not at their own paths: a build tree under /tmp (a CI clone)
# would be hidden by the tmpfs the VM's init mounts on /tmp.
copy_elf() {
  cp -L "$1" "$root/vm/bin/"
  local lib
  for lib in $(ldd "$1" | awk '$2 == "=>" && $3 ~ /^\// { print $3 }'); do
    [ -e "$root/vm/lib/$(basename "$lib")" ] || cp -L "$lib" "$root/vm/lib/"
  done
  for lib in $(ldd "$1" | awk '$1 ~ /^\// { print $1 }'); do
    [ -e "$root$lib" ] && continue
    mkdir -p "$root$(dirname "$lib")"
    cp -L "$lib" "$root$lib"
  done
}
mkdir -p "$root/vm/lib"
for b in "$build/bin/plcrun" "$build/bin/dnslave" "$(command -v candump)" "$(command -v cansend)"; do
  copy_elf "$b"
done

# The CAN modules and what they depend on (the depends= of each module's
# .modinfo section), in load order: dependencies first.
modpath() { find "$kroot/lib/modules/$kver/kernel" -name "$1.ko" -print -quit; }
moddeps() {
  objcopy -O binary --only-section=.modinfo "$1" /dev/stdout | tr '\0' '\n' |
    sed -n 's/^depends=//p' | tr ',' ' '
}
declare -A loaded=()
order=()
add_module() {
  local name="${1//_/-}" path dep
  [ -n "${loaded[$name]:-}" ] && return 0
  path="$(modpath "$name")"
  [ -n "$path" ] || path="$(modpath "${1//-/_}")"
  [ -n "$path" ] || { echo "FAILED: kernel $kver has no module $1"; exit 1; }
  loaded[$name]=1
  for dep in $(moddeps "$path"); do add_module "$dep"; done
  cp "$path" "$root/vm/modules/$name.ko"
  order+=("$name")
}
for m in can can-raw vcan; do add_module "$m"; done
printf '%s\n' "${order[@]}" >"$root/vm/modules.list"

# The cell and the slaves of the repository, moved onto vcan0, with a
# smaller target weight (2.5 kg, above the fine switch point of 2 kg) so
# that containers count within the run, and with
# times an emulated CPU keeps: under TCG (no KVM) the guest runs 20-100x
# slower than the host, a 1 ms scan and a 200 ms connection timeout do
# not hold there. Scan 10 ms (watchdog 1 s), poll cycle 50 ms, EPR 500 ms
# (connection timeout 2 s), explicit timeout 4 s, the safety module's
# PROFIsafe watchdog F_WD_Time 1 s (100 ms in the cell), and the drive's
# fault reset pulse 500 ms (100 ms): a pulse shorter than the gap between
# two polls, which a late tick stretches to 200 ms and more here, may
# never reach the drive, and the cell would wait in its fault step.
sed -e 's|bus: "udp:127.0.0.1:47800"|bus: "socketcan:vcan0"|' -e 's|hub: true|hub: false|' \
  -e 's|      scale.BusType: 1|      target_kg: 2.5\n      guard.FMOD.F_WD_Time: 1000\n      conveyor.ResetPulse: T#500ms\n      scale.BusType: 1|' \
  -e 's|    period: 1ms|    period: 10ms\n    watchdog: 100|' \
  -e 's|      poll_cycle: 10ms|      poll_cycle: 50ms\n      explicit_timeout: 4s|' \
  -e 's|epr: 50ms|epr: 500ms|' \
  "$src/programs/filling_cell/cell_vf66b_devicenet.yaml" >"$root/vm/cell/cell.yaml"
sed -e 's|bus: "udp:127.0.0.1:47800"|bus: "socketcan:vcan0"|' \
  "$src/programs/filling_cell/dnslave_vf66b.yaml" >"$root/vm/cell/dnslave.yaml"
for edit in 'socketcan:vcan0' 'hub: false' 'target_kg: 2.5' 'F_WD_Time: 1000' 'ResetPulse: T#500ms' \
  'period: 10ms' 'explicit_timeout: 4s'; do
  grep -q "$edit" "$root/vm/cell/cell.yaml" ||
    { echo "FAILED: the cell config has changed ($edit); adapt run_vcan_vm.sh's edits"; exit 1; }
done
if [ "$(grep -c 'epr: 500ms' "$root/vm/cell/cell.yaml")" -ne 2 ] || ! grep -q 'socketcan:vcan0' "$root/vm/cell/dnslave.yaml"; then
  echo "FAILED: the cell configs have changed; adapt run_vcan_vm.sh's edits"
  exit 1
fi

cp "$here/init.sh" "$root/init"
chmod 755 "$root/init"
# Not compressed: under TCG the kernel took 5 s to unpack the 50 MB, and
# 28 s to inflate them from 22 MB of gzip.
(cd "$root" && find . | cpio -o -H newc --quiet) >"$work/initramfs.cpio"
echo "vcan-vm: kernel $kver, initramfs $(du -h "$work/initramfs.cpio" | cut -f1) built in" \
  "$(awk -v a="$t_prep" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }') s, modules: ${order[*]}"

accel="${PLC_VM_ACCEL:-}"
if [ -z "$accel" ]; then
  # /dev/kvm alone is not enough: a nested KVM without the CPU's
  # virtualisation extensions (e.g. a paravirtual kvm-pvm host) opens, but a
  # stock kernel hangs in it at its switch to long mode.
  if [ -r /dev/kvm ] && [ -w /dev/kvm ] && grep -qwE 'vmx|svm' /proc/cpuinfo; then accel=kvm; else accel=tcg; fi
fi
case "$accel" in
  kvm) accel_args=(-accel kvm -cpu host) ;;
  tcg) accel_args=(-accel "tcg,thread=multi" -cpu max) ;;
  *) echo "FAILED: PLC_VM_ACCEL must be kvm or tcg"; exit 1 ;;
esac
echo "vcan-vm: qemu $accel, 2 CPUs, 1 GiB, timeout ${timeout_s} s"
t0=$(date +%s.%N)
set +e
timeout --kill-after=10 "$timeout_s" qemu-system-x86_64 "${accel_args[@]}" -m 1G -smp 2 \
  -kernel "$vmlinuz" -initrd "$work/initramfs.cpio" -nographic -no-reboot -nodefaults -serial stdio \
  -append "console=ttyS0 panic=-1 quiet loglevel=1 mitigations=off" </dev/null >"$work/console.log" 2>&1
rc=$?
set -e
t1=$(date +%s.%N)
wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }')
echo "vcan-vm: qemu exit $rc after $wall s (console: $work/console.log)"
if [ $rc -eq 124 ] || [ $rc -eq 137 ]; then
  echo "FAILED: the VM did not power off within $timeout_s s"
  tail -n 40 "$work/console.log"
  exit 1
fi
python3 "$here/check_vcan_vm.py" "$work/console.log" "$work" --wall "$wall" --accel "$accel"
