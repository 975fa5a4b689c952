#!/usr/bin/env python3
"""Checks what the SocketCAN test VM (init.sh) printed on its console.

    check_vcan_vm.py CONSOLE_LOG WORK_DIR [--wall SECONDS] [--accel kvm|tcg]

Writes the sections (plcrun's summary and log, dnslave's, the candump log,
the trace) into WORK_DIR, prints one line per check and a closing
"N passed, M failed" line; exit 0 when every check passed.

DeviceNet identifiers (toyo-vf66-devicenet.md §1.4, table of message
groups): Group 1 = (message id << 6) | MAC, Group 2 = 0x400 | (MAC << 3) |
message id. The cell's master is MAC 0, the scale MAC 5, the conveyor MAC 7.
"""

import argparse
import base64
import gzip
import os
import re
import sys

MASTER, SCALE, CONVEYOR = 0, 5, 7
MASTER_VENDOR, MASTER_SERIAL = 0xFFFF, 0x50C0FFEE  # ScannerConfig defaults
SCALE_VENDOR, SCALE_SERIAL = 560, 5510  # profile pr1721_34, dnslave_vf66b.yaml serial
CAN_ERR_FLAG = 0x20000000


def g1(msg, mac):
    return (msg << 6) | mac


def g2(mac, msg):
    return 0x400 | (mac << 3) | msg


def le(value, n):
    return [(value >> (8 * i)) & 0xFF for i in range(n)]


def sections(console):
    """{name: text} of every BEGIN/END block; packed ones decoded."""
    out = {}
    lines = console.replace("\r", "").split("\n")
    i = 0
    begin = re.compile(r"^=== vcan-vm: BEGIN (\S+)( \(gzip base64\))? ===$")
    while i < len(lines):
        m = begin.match(lines[i])
        i += 1
        if not m:
            continue
        name, packed, body = m.group(1), m.group(2), []
        while i < len(lines) and lines[i] != f"=== vcan-vm: END {name} ===":
            body.append(lines[i])
            i += 1
        i += 1
        text = "\n".join(body)
        if packed:
            raw = base64.b64decode("".join(body)) if body else b""
            text = gzip.decompress(raw).decode() if raw else ""
        out[name] = text
    return out


class Frame:
    """One line of `candump -L`: (time) vcan0 ID#DATA | ID#R | ID##FLAGSDATA."""

    LINE = re.compile(r"^\((\d+\.\d+)\) (\S+) ([0-9A-Fa-f]+)(##?)(R?)([0-9A-Fa-f]*)$")

    def __init__(self, line):
        m = self.LINE.match(line.strip())
        if not m:
            raise ValueError(line)
        self.t = float(m.group(1))
        self.text = f"{m.group(3)}{m.group(4)}{m.group(5)}{m.group(6)}".upper()
        ident = m.group(3)
        self.raw_id = int(ident, 16)
        self.extended = len(ident) == 8 and not self.raw_id & CAN_ERR_FLAG
        self.error = len(ident) == 8 and bool(self.raw_id & CAN_ERR_FLAG)
        self.fd = m.group(4) == "##"
        self.remote = m.group(5) == "R"
        payload = m.group(6)
        if self.fd:
            payload = payload[1:]  # the flags nibble
        self.data = list(bytes.fromhex(payload))
        self.id = self.raw_id & (0x1FFFFFFF if len(ident) == 8 else 0x7FF)

    def classic(self, ident):
        return not (self.extended or self.error or self.fd or self.remote) and self.id == ident


def normalise(frame_text):
    """A frame in cansend's notation (dots, any case) or candump's, compared
    without the CAN FD flags nibble: the kernel adds CANFD_FDF (0x04) to
    what cansend wrote."""
    f = frame_text.replace(".", "").upper()
    if "##" in f:
        ident, rest = f.split("##")
        return f"{ident}##{rest[1:]}"
    return f


class Checks:
    def __init__(self):
        self.passed = self.failed = 0

    def check(self, ok, what, detail=""):
        print(f"{'ok  ' if ok else 'FAIL'} {what}" + (f" ({detail})" if detail else ""))
        if ok:
            self.passed += 1
        else:
            self.failed += 1
        return ok


def device_summary(stdout, name):
    """The numbers of plcrun's summary line for one device."""
    m = re.search(rf"^device {name}\s+\(\w+\): (devicenet .*)$", stdout, re.M)
    if not m:
        return None
    line = m.group(1)
    d = {"line": line}
    head = re.match(r"devicenet mac (\d+) (\S+);", line)
    d["state"] = head.group(2) if head else "?"
    for key, pat in [
        ("polls", r"polls (\d+)"),
        ("responses", r"responses (\d+)"),
        ("losses", r"losses (\d+)"),
        ("allocations", r"allocations (\d+)"),
        ("refused", r"\(refused (\d+)\)"),
        ("bad_frames", r"; polls .*? bad-frames (\d+)"),
        ("wrong_size", r"wrong-size (\d+)"),
    ]:
        mm = re.search(pat, line)
        d[key] = int(mm.group(1)) if mm else -1
    bus = re.search(
        r"; bus (\S+) tx (\d+) rx (\d+) rx-bad (\d+) tx-dropped (\d+) error-frames (\d+) "
        r"bus-bad-frames (\d+)",
        line,
    )
    if bus:
        d["bus_state"] = bus.group(1)
        for k, v in zip(
            ["tx", "rx", "rx_bad", "tx_dropped", "error_frames", "bus_bad_frames"], bus.groups()[1:]
        ):
            d[k] = int(v)
    return d


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("console")
    ap.add_argument("work")
    ap.add_argument("--wall", default="?")
    ap.add_argument("--accel", default="?")
    a = ap.parse_args()
    # The firmware's and the kernel's terminal resets (ESC c, ESC [2J, ...)
    # share the console's lines.
    console = re.sub(r"\x1b(\[[0-9;?]*[A-Za-z]|c)", "", open(a.console, errors="replace").read())
    s = sections(console)
    for name, text in s.items():
        with open(os.path.join(a.work, name.replace("/", "_") + ".txt"), "w") as f:
            f.write(text + ("\n" if text and not text.endswith("\n") else ""))
    c = Checks()
    clean = console.replace("\r", "")

    # The run itself.
    scenario = re.search(r"^vcan-vm: scenario (\S+) after ([\d.]+) s$", clean, re.M)
    for m in re.finditer(r"^vcan-vm: FAILED: (.*)$", clean, re.M):
        c.check(False, "the scenario in the VM", m.group(1))
    c.check(scenario is not None and scenario.group(1) == "done", "the scenario ran to its end",
            scenario.group(0) if scenario else "no 'scenario' line: see the console log")
    # A wrong exit names the code and the program's first words (127: the
    # loader found no library, say).
    for prog, section in [("plcrun", "plcrun-stderr"), ("dnslave", "dnslave")]:
        code = re.search(rf"^vcan-vm: exit {prog} (\S+)$", clean, re.M)
        first = next((l for l in s.get(section, "").splitlines() if l.strip()), "")
        ok = code is not None and code.group(1) == "0"
        c.check(ok, f"{prog} stopped on SIGTERM after the scenario, exit 0",
                "" if ok else f"exit {code.group(1) if code else '?'}: {first}")
    c.check("candump" in s and "plcrun-stdout" in s, "the results came back from the VM",
            ", ".join(sorted(s)))
    if "candump" not in s or "plcrun-stdout" not in s:
        print(f"{c.passed} passed, {c.failed} failed")
        return 1
    stdout, stderr, slaves = s["plcrun-stdout"], s.get("plcrun-stderr", ""), s.get("dnslave", "")
    boot = re.search(r"^vcan-vm: kernel .*$", clean, re.M)
    if boot:
        print(boot.group(0))
    vcan = re.search(r"^vcan-vm: vcan0 up: .*$", clean, re.M)
    c.check(vcan is not None, "vcan0 created and up (CAN modules loaded)",
            vcan.group(0) if vcan else "")

    # plcrun's log: each device on line three times (start, after bus-off,
    # after vcan0 up), lost twice (slaves silenced, vcan0 down), never by
    # an injected frame; the bus states the error frames announced, in order.
    for name, mac in [("conveyor", CONVEYOR), ("scale", SCALE)]:
        online = len(re.findall(rf"^devicenet: {name} \(MAC {mac}\): online$", stderr, re.M))
        lost = re.findall(rf"^devicenet: {name} \(MAC {mac}\): lost: (.*)$", stderr, re.M)
        c.check(online == 3, f"{name} on line 3 times (start, after bus-off, after vcan0 up)",
                f"{online}")
        c.check(len(lost) == 2 and all("connection timed out" in w for w in lost),
                f"{name} lost twice, by its connection timeout (silenced; vcan0 down)",
                "; ".join(lost) or "never")
    states = re.findall(r"^devicenet: bus (\S+)$", stderr, re.M)
    c.check(states == ["error-passive", "error-active", "bus-off", "error-active"],
            "bus states from the kernel-delivered error frames", " -> ".join(states) or "none")

    # plcrun's summary: the scanner's and the backend's counters.
    conv, scale = device_summary(stdout, "conveyor"), device_summary(stdout, "scale")
    c.check(conv is not None and scale is not None, "plcrun printed both devices' counters")
    if conv is None or scale is None:
        print(stdout)
        print(f"{c.passed} passed, {c.failed} failed")
        return 1
    stopped = re.search(r"^\s*STOPPED: (.*)$", stdout, re.M)
    c.check(stopped is None, "the scan ran until it was stopped (no watchdog stop)",
            stopped.group(1) if stopped else "")
    print("summary conveyor: " + conv["line"])
    print("summary scale:    " + scale["line"])
    for name, d in [("conveyor", conv), ("scale", scale)]:
        c.check(d["state"] == "online" and d["losses"] == 2 and d["allocations"] == 3,
                f"{name}: on line at the end, 2 losses, 3 allocations",
                f"{d['state']}, {d['losses']} losses, {d['allocations']} allocations")
        # How many polls fit depends on how fast the emulated VM runs the
        # scenario (448 in 31 s on an idle host, over 1,000 on a loaded one
        # that stretches it): at least 200, and most of them answered.
        c.check(d["responses"] > 200 and d["responses"] * 10 >= d["polls"] * 7,
                f"{name}: polled I/O over vcan0",
                f"{d['polls']} polls, {d['responses']} responses")
    c.check(conv["wrong_size"] == 1 and conv["bad_frames"] == 0,
            "conveyor: the 1-byte poll response counted as wrong size, dropped",
            f"wrong-size {conv['wrong_size']}, bad-frames {conv['bad_frames']}")
    c.check(scale["bad_frames"] == 1 and scale["wrong_size"] == 0,
            "scale: the orphan middle fragment counted as a bad frame; the refusal addressed "
            "to the second master not taken as ours",
            f"bad-frames {scale['bad_frames']}, wrong-size {scale['wrong_size']}")
    bus = conv  # one bus, the same counters on every device's line
    c.check(bus.get("bus_state") == "error-active", "bus error-active at the end",
            bus.get("bus_state", "?"))
    c.check(bus.get("rx_bad") == 0, "no short or CAN FD frame reached the CAN_RAW socket",
            f"rx-bad {bus.get('rx_bad')}")
    c.check(bus.get("error_frames") == 4, "4 error frames received (CAN_RAW_ERR_FILTER)",
            f"{bus.get('error_frames')}")
    c.check(bus.get("bus_bad_frames") == 2,
            "invalid identifier 0x7F5 and the short duplicate MAC message counted",
            f"bus-bad-frames {bus.get('bus_bad_frames')}")
    c.check(bus.get("tx_dropped", 0) > 0, "writes refused while vcan0 was down (ENETDOWN)",
            f"tx-dropped {bus.get('tx_dropped')}")
    containers = re.search(r"Cell\.containers\s*[:=]\s*(-?\d+)", stdout)
    c.check(containers is not None and int(containers.group(1)) >= 3, "the cell filled containers",
            containers.group(0) if containers else "no Cell.containers in the output")

    # dnslave: both slaves on line, allocated by master 0; the scale counted
    # the explicit request that did not come from its master.
    slave_lines = {m.group(1): m.group(2) for m in re.finditer(r"^dnslave: (\w+): (mac .*)$", slaves, re.M)}
    for name in ["conveyor", "scale"]:
        line = slave_lines.get(name, "")
        c.check(" online master 0 choice 0x03" in line, f"dnslave {name}: allocated by MAC 0", line)
    bad = re.search(r" bad (\d+)$", slave_lines.get("scale", ""))
    c.check(bad is not None and bad.group(1) == "1",
            "dnslave scale: the request from MAC 10 on its explicit connection counted, unanswered",
            slave_lines.get("scale", ""))

    # candump, the independent observer.
    frames = []
    bad_lines = []
    for line in s["candump"].splitlines():
        if line.strip():
            try:
                frames.append(Frame(line))
            except ValueError:
                bad_lines.append(line)
    c.check(not bad_lines and len(frames) > 1000, f"candump logged {len(frames)} frames",
            "; ".join(bad_lines[:3]))
    events = s.get("events", "")
    injected = re.findall(r"^[\d.]+ inject (\S+) (\S+)$", events, re.M)
    texts = [normalise(f.text) for f in frames]
    for name, frame in injected:
        n = texts.count(normalise(frame))
        c.check(n == 1, f"candump saw the injected {name} frame {normalise(frame)} once", f"{n}")

    def count(ident, length=None, data=None):
        return sum(
            1 for f in frames
            if f.classic(ident) and (length is None or len(f.data) == length)
            and (data is None or f.data == data)
        )

    expected_ids = {
        g2(MASTER, 7): "master duplicate MAC ID check",
        g2(CONVEYOR, 3): "conveyor explicit response",
        g2(CONVEYOR, 4): "conveyor explicit request",
        g2(CONVEYOR, 5): "conveyor poll",
        g2(CONVEYOR, 6): "conveyor unconnected request",
        g2(CONVEYOR, 7): "conveyor duplicate MAC ID check",
        g1(0xF, CONVEYOR): "conveyor poll response",
        g2(SCALE, 3): "scale explicit response",
        g2(SCALE, 4): "scale explicit request",
        g2(SCALE, 5): "scale poll",
        g2(SCALE, 6): "scale unconnected request",
        g2(SCALE, 7): "scale duplicate MAC ID check",
        g1(0xF, SCALE): "scale poll response",
    }
    print("candump frames by identifier:")
    for ident, what in sorted(expected_ids.items()):
        print(f"  0x{ident:03X} {what:32} {count(ident)}")
    injected_texts = {normalise(f) for _, f in injected}
    strangers = [f.text for f in frames if normalise(f.text) not in injected_texts and not (
        not (f.extended or f.error or f.fd or f.remote) and f.id in expected_ids)]
    c.check(not strangers, "every other frame carries a Predefined Set identifier of MAC 0, 5 or 7",
            " ".join(strangers[:5]))

    poll_c, resp_c = count(g2(CONVEYOR, 5), 4), count(g1(0xF, CONVEYOR), 4)
    poll_s, resp_s = count(g2(SCALE, 5), 8), count(g1(0xF, SCALE), 8)
    drops = bus.get("tx_dropped", 0)
    c.check(conv["polls"] - drops <= poll_c <= conv["polls"],
            "conveyor polls (0x43D, 4 bytes, assembly 21) on the wire as the scanner counts them",
            f"candump {poll_c}, scanner {conv['polls']}, tx-dropped {drops}")
    c.check(scale["polls"] - drops <= poll_s <= scale["polls"],
            "scale polls (0x42D, 8 bytes) on the wire as the scanner counts them",
            f"candump {poll_s}, scanner {scale['polls']}")
    # Responses to the last polls may still be on their way when plcrun
    # stops: up to 2, as the poll schedule catches up after a late tick (two
    # polls close together).
    c.check(conv["responses"] <= resp_c <= conv["responses"] + 2,
            "conveyor poll responses (0x3C7, 4 bytes, assembly 71) as the scanner took them",
            f"candump {resp_c}, scanner {conv['responses']}")
    c.check(scale["responses"] <= resp_s <= scale["responses"] + 2,
            "scale poll responses (0x3C5, 8 bytes) as the scanner took them",
            f"candump {resp_s}, scanner {scale['responses']}")
    dup_req = [0x00] + le(MASTER_VENDOR, 2) + le(MASTER_SERIAL, 4)
    dup_resp = [0x80] + le(MASTER_VENDOR, 2) + le(MASTER_SERIAL, 4)
    c.check(count(g2(MASTER, 7), 7, dup_req) == 2, "the master's duplicate MAC ID check: 2 requests")
    c.check(count(g2(MASTER, 7), 7, dup_resp) == 1,
            "the master answered the other node's duplicate MAC ID request (0x407, response bit)")
    scale_dup = [0x80] + le(SCALE_VENDOR, 2) + le(SCALE_SERIAL, 4)
    c.check(count(g2(SCALE, 7), 7, scale_dup) == 1,
            "the scale answered the duplicate MAC ID request for MAC 5 (vendor 560, serial 5510)")
    for name, mac in [("conveyor", CONVEYOR), ("scale", SCALE)]:
        own = sum(1 for f in frames if f.classic(g2(mac, 7)) and len(f.data) == 7
                  and f.data[0] == 0 and normalise(f.text) not in injected_texts)
        c.check(own == 2, f"{name}'s own duplicate MAC ID check: 2 requests", f"{own}")
        allocs = count(g2(mac, 6), 6, [MASTER, 0x4B, 0x03, 0x01, 0x03, MASTER])
        c.check(allocs >= 3, f"{name}: Allocate explicit + poll from MAC 0 (0x4B, class 3)", f"{allocs}")
    refusal = [f.data for f in frames if f.classic(g2(SCALE, 3)) and f.data[:1] == [10]]
    c.check(refusal == [[10, 0x94, 0x0C, 0x01]],
            "the scale refused the second master's Allocate, addressed to MAC 10 "
            "(0x94 object state conflict 0x0C/0x01)",
            " ".join(bytes(d).hex() for d in refusal) or "no answer to MAC 10")

    def at(name):
        for f in frames:
            if normalise(f.text) == normalise(dict(injected)[name]):
                return f.t
        return None

    off, on = at("bus-off"), at("restarted")
    if off is not None and on is not None:
        during = [f.text for f in frames if off < f.t < on]
        c.check(not during and on - off >= 1.5,
                "nothing sent between bus-off and the restart (scanner off the bus)",
                f"{on - off:.1f} s, frames: {' '.join(during[:5])}")
    else:
        c.check(False, "bus-off and restart frames in the candump log")

    # The trace (rows where a traced value changed). The frames were injected
    # from 3 s after both devices came on line until the slaves were
    # silenced, the first time the conveyor's Valid drops: 6 s on an idle
    # host, more on a loaded one that stretches the VM's scenario. The first
    # container is done about 3.3 s after the devices came on line, inside
    # that window, so at least 1 by then means the cell filled on while the
    # frames arrived. Valid's first rise is the start-up, not a return:
    # returns are counted after the first drop.
    # After the last recovery the cell resets the drive (fault 18) and
    # indexes again (step 2); the simulated PR5510 closes its feed valves
    # while its master is away, so the cell also fills on afterwards.
    rows = [r.split(",") for r in s.get("trace-changes", "").splitlines()]
    if len(rows) > 2:
        col = {n: i for i, n in enumerate(rows[0])}
        valid, cont, step = col["Cell.conveyor.Valid"], col["Cell.containers"], col["Cell.step"]
        drops, backs = [], []
        for prev, r in zip(rows[1:], rows[2:]):
            if prev[valid] == "TRUE" and r[valid] == "FALSE":
                drops.append(r)
            if drops and prev[valid] == "FALSE" and r[valid] == "TRUE":
                backs.append(r)
        c.check(len(drops) == 2 and len(backs) == 2,
                "trace: the conveyor's Valid dropped twice and came back twice",
                f"{len(drops)} drops, {len(backs)} returns")
        if drops:
            c.check(int(drops[0][cont]) >= 1, "trace: containers filled while the frames were injected",
                    f"{drops[0][cont]} containers when the slaves were silenced")
        if backs:
            after = [r for r in rows[1:] if int(r[0]) > int(backs[-1][0])]
            c.check(any(r[step] == "2" for r in after),
                    "trace: the cell indexes again after the last recovery (step 2)",
                    " ".join(r[step] for r in after[:8]))
    else:
        c.check(False, "the trace came back", f"{len(rows)} rows")

    print(f"vcan-vm: qemu {a.accel}, wall time {a.wall} s, "
          f"scenario {scenario.group(2) if scenario else '?'} s in the VM")
    print(f"{c.passed} passed, {c.failed} failed")
    return 0 if c.failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
