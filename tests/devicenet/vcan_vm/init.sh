#!/bin/busybox sh
# /init of the SocketCAN test VM (run_vcan_vm.sh builds the initramfs around
# it and reads what it prints on the console). A Debian kernel with its CAN
# modules, a virtual CAN interface vcan0, and on it:
#   plcrun    the filling cell with the conveyor (VF66B, MAC 7) and the scale
#             (PR5510, MAC 5) on the DeviceNet scanner, bus socketcan:vcan0
#   dnslave   both slaves, bus socketcan:vcan0
#   candump   (can-utils, an independent CAN implementation) logging every
#             frame, error frames included
#   cansend   injecting frames the scanner and the slaves must cope with
# Real time throughout (three processes cannot share a virtual clock). Every
# wait is for an event (a line a process printed), bounded; the fixed
# pauses are the scenario's own (let the cell run, hold bus-off a while).
# The host's timeout (run_vcan_vm.sh) bounds the whole run.
# Ends with the results between "=== vcan-vm: BEGIN name ===" and
# "=== vcan-vm: END name ===" markers, then powers the VM off.
/bin/busybox --install -s /bin
export PATH=/vm/bin:/bin
# Every library the executables need is in /vm/lib (run_vcan_vm.sh).
export LD_LIBRARY_PATH=/vm/lib
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
mount -t tmpfs tmpfs /tmp
cd /tmp || exit 1
# The kernel's messages (a process killed, a module refused) stay out of
# the results, which are printed on the same console.
echo 1 >/proc/sys/kernel/printk

say() { echo "vcan-vm: $*"; }
t0=$(cut -d' ' -f1 /proc/uptime)
elapsed() { awk -v a="$t0" -v b="$(cut -d' ' -f1 /proc/uptime)" 'BEGIN { printf "%.1f", b - a }'; }
section() { # NAME FILE: a file between markers, as it is
  echo "=== vcan-vm: BEGIN $1 ==="
  cat "$2" 2>/dev/null
  echo "=== vcan-vm: END $1 ==="
}
packed() { # NAME FILE: gzip + base64 (the candump log is large for a serial line)
  echo "=== vcan-vm: BEGIN $1 (gzip base64) ==="
  gzip -c "$2" | base64
  echo "=== vcan-vm: END $1 ==="
}
finish() {
  say "scenario ${1:-done} after $(elapsed) s"
  [ -n "$plc_pid" ] && kill -0 "$plc_pid" 2>/dev/null && kill -TERM "$plc_pid"
  [ -n "$plc_pid" ] && { wait "$plc_pid"; say "exit plcrun $?"; }
  [ -n "$slave_pid" ] && kill -0 "$slave_pid" 2>/dev/null && kill -TERM "$slave_pid"
  [ -n "$slave_pid" ] && { wait "$slave_pid"; say "exit dnslave $?"; }
  sleep 0.2 # candump writes what it has read
  [ -n "$dump_pid" ] && kill -TERM "$dump_pid" && wait "$dump_pid"
  section plcrun-stdout plcrun.out
  section plcrun-stderr plcrun.err
  section dnslave dnslave.out
  section candump-stderr candump.err
  section events events.log
  # The trace: only the rows where a traced value changed.
  awk -F, 'NR == 1 { print; next } { k = $0; sub(/^[^,]*,[^,]*,/, "", k); if (k != last) print; last = k }' \
    trace.csv >trace-changes.csv 2>/dev/null
  packed trace-changes trace-changes.csv
  packed candump candump.log
  say "end at $(elapsed) s"
  poweroff -f
}
fail() {
  say "FAILED: $*"
  finish failed
}
# wait_count FILE PATTERN N SECONDS: until FILE has N lines with PATTERN.
wait_count() {
  i=0
  while :; do
    n=$(grep -c -- "$2" "$1" 2>/dev/null)
    [ "${n:-0}" -ge "$3" ] && return 0
    i=$((i + 1))
    [ $i -gt $(($4 * 10)) ] && return 1
    sleep 0.1
  done
}
event() { echo "$(elapsed) $*" >>events.log; }
inject() { # NAME FRAME: a frame onto vcan0 with can-utils' cansend
  event "inject $1 $2"
  cansend vcan0 "$2" || fail "cansend $2"
}

say "kernel $(uname -r), $(nproc) CPUs, /init at $(cut -d' ' -f1 /proc/uptime) s of uptime"
while read -r m; do
  insmod "/vm/modules/$m.ko" || fail "insmod $m"
done </vm/modules.list
# busybox's ip (its applets come before PATH) knows "link add ... type".
ip link add dev vcan0 type vcan || fail "ip link add vcan0 type vcan"
ip link set up vcan0 || fail "ip link set up vcan0"
say "vcan0 up: type $(cat /sys/class/net/vcan0/type) (ARPHRD_CAN 280), mtu $(cat /sys/class/net/vcan0/mtu) (CANFD_MTU 72)"

candump -L -D vcan0,0:0,#FFFFFFFF >candump.log 2>candump.err &
dump_pid=$!
# Both are stopped with SIGTERM when the scenario is done; --for only
# bounds them. (A fixed run length cannot fit: on a loaded host the
# emulated VM took 35 s for the scenario in one run and 120 s in another.)
dnslave /vm/cell/dnslave.yaml --for 900s >dnslave.out 2>&1 &
slave_pid=$!
plcrun /vm/cell/cell.yaml --realtime --for 900s -q \
  --trace trace.csv --trace-vars Cell.containers,Cell.step,Cell.conveyor.Valid,Cell.scale.Online,Cell.conveyor.Faulted,Cell.guard.QBAD,Cell.dose.Error,Cell.last_error \
  --print-vars Cell.containers >plcrun.out 2>plcrun.err &
plc_pid=$!
event "started plcrun and dnslave"

C="conveyor (MAC 7)"
S="scale (MAC 5)"
wait_count plcrun.err "$C: online" 1 60 || fail "the conveyor never came on line"
wait_count plcrun.err "$S: online" 1 60 || fail "the scale never came on line"
event "both on line"
sleep 3 # the cell fills

# Frames the scanner and the slaves must drop without a word to the cell.
inject unknown-node 3C9#01.02                   # Group 1 poll response of MAC 9 (not scanned)
inject group3 6C9#01                            # Group 3 (the Predefined Set has none)
inject invalid-id 7F5#00                        # 0x7F0..0x7FF: invalid identifiers
inject extended 0000042D#01.02                  # 29-bit identifier that ends like the scale's poll
inject remote 42D#R                             # remote request on the scale's poll identifier
inject canfd 42D##0.01.02.03.04.05.06.07.08.09.0A.0B.0C # CAN FD: never reaches a classic CAN_RAW socket
inject bad-fragment 42B#80.41.01                # a middle fragment with no first, scale's explicit response
inject short-poll-response 3C7#01               # the conveyor's poll response, 1 byte of 4
inject short-dup-mac 407#00.01                  # the master's duplicate MAC message, 2 bytes of 7
# Explicit messages to the scale from a second master (MAC 10).
inject explicit-not-from-master 42C#0A.0E.01.01.07   # Get Identity attr 7 on its explicit connection
inject allocate-other-master 42E#0A.4B.03.01.03.0A   # Allocate explicit + poll for MAC 10
# Duplicate MAC ID check messages from another node (vendor 0x1234, serial 0x11223344).
inject dup-mac-request-master 407#00.34.12.44.33.22.11
inject dup-mac-response-master 407#80.34.12.44.33.22.11
inject dup-mac-request-scale 42F#00.34.12.44.33.22.11
sleep 1
event "frames injected"

# Controller states, as a CAN driver reports them in error frames
# (linux/can/error.h); vcan has no controller, cansend plays its part.
inject error-passive 20000004#00.20.00.00.00.00.00.00 # CAN_ERR_CRTL, CAN_ERR_CRTL_TX_PASSIVE
wait_count plcrun.err "devicenet: bus error-passive" 1 10 || fail "no error-passive"
inject error-active 20000004#00.40.00.00.00.00.00.00 # CAN_ERR_CRTL, CAN_ERR_CRTL_ACTIVE
wait_count plcrun.err "devicenet: bus error-active" 1 10 || fail "no error-active after error-passive"
# Bus-off: on a real bus no frame passes while the controller is off, and
# the backend takes the first frame after it as "restarted". On vcan the
# slaves would go on answering, so they are silenced first (SIGUSR1), the
# scanner loses them, and then bus-off must keep the scanner off the bus.
kill -USR1 "$slave_pid"
event "slaves silent"
wait_count plcrun.err "$C: lost" 1 10 || fail "the conveyor was not lost"
wait_count plcrun.err "$S: lost" 1 10 || fail "the scale was not lost"
inject bus-off 20000040#00.00.00.00.00.00.00.00 # CAN_ERR_BUSOFF
wait_count plcrun.err "devicenet: bus bus-off" 1 10 || fail "no bus-off"
sleep 3 # the scanner's retries (every 1 s) must not go out
inject restarted 20000100#00.00.00.00.00.00.00.00 # CAN_ERR_RESTARTED
wait_count plcrun.err "devicenet: bus error-active" 2 10 || fail "no error-active after restart"
kill -USR1 "$slave_pid"
event "slaves back"
wait_count plcrun.err "$C: online" 2 30 || fail "the conveyor did not come back after bus-off"
wait_count plcrun.err "$S: online" 2 30 || fail "the scale did not come back after bus-off"
event "both on line after bus-off"
sleep 2

# The interface goes down (writes fail with ENETDOWN) and up again.
ip link set vcan0 down
event "vcan0 down"
wait_count plcrun.err "$C: lost" 2 10 || fail "the conveyor was not lost with vcan0 down"
wait_count plcrun.err "$S: lost" 2 10 || fail "the scale was not lost with vcan0 down"
ip link set vcan0 up
event "vcan0 up"
wait_count plcrun.err "$C: online" 3 30 || fail "the conveyor did not come back after vcan0 up"
wait_count plcrun.err "$S: online" 3 30 || fail "the scale did not come back after vcan0 up"
event "both on line after vcan0 up"

sleep 8 # the cell resets the drive and fills on
# SIGTERM: plcrun stops at a scan boundary with its outputs safe, prints
# its summary and exits 0, as dnslave does.
kill -TERM "$plc_pid"
wait "$plc_pid"
say "exit plcrun $?"
plc_pid=
event "plcrun stopped"
kill -TERM "$slave_pid"
wait "$slave_pid"
say "exit dnslave $?"
slave_pid=
finish
