#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets into corpus/<target>/.

Seeds are real inputs: the example cell configs, conditions and debugger
commands on the filling cell, recordings made by plcrun, and the bytes the
filling cell's devices and blocks exchanged in a traced virtual-time run
(plcrun --trace of the %I/%Q bytes of each device), laid out the way each
target reads its input. Rerun after a wire or file format changes:

    tests/fuzz/make_seeds.py build/bin/plcrun

Files named crash-* (reproducers of fixed crashes) are left alone, except
hmi_commands' two, which are written again in the current command_t encoding.
`make_seeds.py PLCRUN --recordings DIR` writes only the two recordings, into
DIR (scripts/fuzz does, so the recording target always starts from the
current file format).
"""
import csv
import hashlib
import hmac
import os
import pathlib
import shutil
import struct
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
CORPUS = pathlib.Path(__file__).resolve().parent / "corpus"
CELL = ROOT / "programs/filling_cell/cell.yaml"


def put(target, name, data):
    d = CORPUS / target
    d.mkdir(parents=True, exist_ok=True)
    (d / name).write_bytes(data.encode() if isinstance(data, str) else bytes(data))


def clear(target):
    d = CORPUS / target
    if d.exists():
        for f in d.iterdir():
            if not f.name.startswith("crash-"):
                f.unlink()


def trace_bytes(plcrun, tmp, scans):
    """Per scan, the bytes of each device's input and output area."""
    areas = {"e1_in": ("I", 0, 24), "e1_out": ("Q", 0, 24), "w_in": ("I", 32, 8),
             "w_out": ("Q", 32, 8), "fs_in": ("I", 48, 8), "fs_out": ("Q", 48, 8)}
    cols = [f"%{a}D{o + 4 * k}" for a, o, n in areas.values() for k in range(n // 4)]
    out = tmp / "bytes.csv"
    subprocess.run([plcrun, str(CELL), "--virtual", "--cycles", str(scans), "--trace", str(out),
                    "--trace-vars", ",".join(cols), "-q"], check=True, capture_output=True)
    rows = []
    with open(out) as f:
        for r in csv.DictReader(f):
            scan = {}
            for name, (a, o, n) in areas.items():
                b = b""
                for k in range(n // 4):
                    b += int(r[f"%{a}D{o + 4 * k}"].replace("16#", ""), 16).to_bytes(4, "big")
                scan[name] = b
            rows.append(scan)
    return rows


def changes(rows, key, every=1, new=b"\x01", keep=b"\x00"):
    """The frames of one area, each behind a control byte: `new` and the
    bytes when they changed, else `keep` (the target keeps the last ones)."""
    out, last = b"", None
    for r in rows[::every]:
        if r[key] != last:
            out += new + r[key]
            last = r[key]
        else:
            out += keep
    return out


def device_frames(rows, key, every=1):
    """FuzzDevice control bytes: answering (bit 1), new inputs (bit 0)."""
    return changes(rows, key, every, new=b"\x03", keep=b"\x02")


def lcm_fingerprint(members):
    """An LCM struct's fingerprint as lcm-gen computes it (lcmgen.c,
    lcm_struct_hash, then rotated left by one as the generated code does).
    members: (name, type, [dimension sizes]) of primitive types only."""
    mask = (1 << 64) - 1

    def signed(v):
        v &= mask
        return v - (1 << 64) if v >> 63 else v

    def update(v, c):
        return signed(((v << 8) ^ (v >> 55)) + c)

    def update_string(v, text):
        v = update(v, len(text))
        for ch in text.encode():
            v = update(v, ch)
        return v

    v = 0x12345678
    for name, typ, dims in members:
        v = update_string(v, name)
        v = update_string(v, typ)
        v = update(v, len(dims))
        for d in dims:
            v = update(v, 0 if d.isdigit() else 1)  # LCM_CONST, LCM_VAR
            v = update_string(v, d)
    h = v & mask
    return ((h << 1) + (h >> 63)) & mask


# hmi-bridge/lcm/command_t.lcm
COMMAND_T = lcm_fingerprint([
    ("request_id", "int64_t", []), ("client", "string", []), ("verb", "string", []),
    ("n_args", "int32_t", []), ("args", "string", ["n_args"]), ("epoch", "byte", ["16"]),
    ("counter", "int64_t", []), ("tag", "byte", ["32"])])
FUZZ_KEY = bytes([0x5a] * 32)  # fuzz_hmi_commands.cpp's key file


def lcm_string(text):
    b = text.encode() + b"\0"
    return struct.pack(">i", len(b)) + b


def command(verb, args, request_id=1, counter=1, epoch=bytes(16), tag=bytes(32), n_args=None):
    return (struct.pack(">Qq", COMMAND_T, request_id) + lcm_string("seed") + lcm_string(verb) +
            struct.pack(">i", len(args) if n_args is None else n_args) +
            b"".join(lcm_string(a) for a in args) + epoch + struct.pack(">q", counter) + tag)


def signed_command(verb, args, cell, epoch, prefix="PLC", channel="PLC_CMD"):
    """Signed as plc::hmi::sign does (hmi-bridge/src/command_auth.cpp)."""
    body = command(verb, args, epoch=epoch)
    lp = lambda b: struct.pack(">I", len(b)) + b  # noqa: E731
    msg = (b"softplc-hmi\0" + bytes([2, 1]) + lp(prefix.encode()) + lp(cell.encode()) +
           lp(channel.encode()) + epoch + lp(body))
    return body[:-32] + hmac.new(FUZZ_KEY, msg, hashlib.sha256).digest()


def hmi_commands():
    """One command_t after a byte choosing the bridge (0 open, 1 keyed)."""
    clear("hmi_commands")
    put("hmi_commands", "junk", b"\x00junk")
    for name, verb, args in [("describe", "describe", []),
                             ("read", "read", ["Cell.target_kg", "Cell.run", "%QW0"]),
                             ("write", "write", ["Cell.target_kg", "2.5"]),
                             ("write_refused", "write", ["Cell.run", "TRUE"]),
                             ("force", "force", ["Cell.run", "TRUE"]),
                             ("unforce_all", "unforce", ["all", "restore"]),
                             ("step_refused", "step", ["3"])]:
        put("hmi_commands", name + "_open", b"\x00" + command(verb, args))
    put("hmi_commands", "write_keyed_untagged",
        b"\x01" + command("write", ["Cell.target_kg", "2.5"]))
    put("hmi_commands", "describe_keyed", b"\x01" + command("describe", []))
    # A right tag for an epoch the bridge never has: refused as stale.
    put("hmi_commands", "write_keyed_stale_epoch",
        b"\x01" + signed_command("write", ["Cell.target_kg", "2.5"], "filling", bytes(16)))
    # Argument counts that lcm-gen's decoder would resize its vector to.
    put("hmi_commands", "crash-negative-n_args",
        b"\x00" + command("read", ["Cell.run"], n_args=-1))
    put("hmi_commands", "crash-huge-n_args",
        b"\x00" + command("read", ["Cell.run"], n_args=0x7FFFFFFF))


def lcm_udpm_seeds():
    """LCM udpm datagrams (liblcm 1.3.1's format, big-endian) for the
    lcm_udpm target, written here field by field: part 0 reads records
    [sender][time step][length u16 LE][datagram], part 1 a message to
    encode and the order of its fragments."""
    clear("lcm_udpm")

    def lc02(seq, channel, payload):
        return struct.pack(">II", 0x4C433032, seq) + channel + b"\0" + payload

    def lc03(seq, size, offset, no, n, channel, piece):
        head = struct.pack(">IIIIHH", 0x4C433033, seq, size, offset, no, n)
        return head + (channel + b"\0" if no == 0 else b"") + piece

    def records(*datagrams):
        return b"\x00" + b"".join(bytes([sender, step]) + struct.pack("<H", len(d)) + d
                                  for sender, step, d in datagrams)

    body = bytes(range(256)) + bytes(range(44))  # 300 bytes
    put("lcm_udpm", "short_valid.bin", records((1, 0, lc02(0, b"PLC_CMD", body[:120]))))
    put("lcm_udpm", "fragments_valid.bin", records(
        (1, 1, lc03(5, 300, 0, 0, 3, b"PLC_DESC", body[:100])),
        (2, 1, lc02(9, b"PLC_VALUES", body[:40])),
        (1, 1, lc03(5, 300, 200, 2, 3, b"", body[200:])),
        (1, 1, lc03(5, 300, 100, 1, 3, b"", body[100:200]))))
    # Issue 22: fragment 0 of a 64-byte message, 32 bytes at offset
    # 0xFFFFFFF0 (60 bytes on PLC_CMD), then a valid message.
    put("lcm_udpm", "wrapping_offset.bin", records(
        (1, 0, lc03(1, 64, 0xFFFFFFF0, 0, 2, b"PLC_CMD", b"A" * 32)),
        (1, 1, lc02(2, b"PLC_CMD", body[:16]))))
    put("lcm_udpm", "hostile_mix.bin", records(
        (3, 0, struct.pack(">III", 0x4C433033, 9, 64)),
        (3, 0, lc03(4, 0xFFFFFFFF, 0, 0, 2, b"PLC_CMD", b"x" * 32)),
        (3, 0, lc03(5, 64, 0, 0, 0, b"PLC_CMD", b"x" * 32)),
        (3, 0, lc03(6, 64, 0, 7, 2, b"PLC_CMD", b"x" * 32)),
        (3, 0, lc02(7, b"X" * 80, b"\x01")),
        (4, 0, lc03(8, 100, 0, 0, 3, b"PLC_CMD", b"a" * 50)),
        (4, 0, lc03(8, 100, 40, 1, 3, b"", b"b" * 30)),
        (4, 0, lc03(8, 100, 80, 2, 3, b"", b"c" * 20)),
        (5, 0, b"GET / HTTP/1.0\r\n")))
    # Part 1: channel (length, letters), size/4 (u16 LE: 200,000 bytes, four
    # fragments), generator seed, seqno, then shuffle and per-fragment bytes.
    put("lcm_udpm", "round_trip.bin",
        b"\x01" + bytes([10]) + bytes([15, 11, 2, 4, 21, 0, 11, 20, 4, 18]) +
        struct.pack("<HII", 50000, 0x12345678, 42) + bytes([1, 0]) +
        bytes([1, 8]) + lc02(1, b"PLC_CMD", b"") + bytes([2, 0, 0, 0xFF, 0, 0]))


def profibus_seeds():
    """PROFIBUS: telegrams from outside (profirust's real-hardware FDL status
    exchange, pyprofibus's start-up against dpslavesim, tests/profibus) as a
    stream, the same bytes as a rogue station's, and GSD files."""
    clear("profibus_fdl")
    clear("profibus_gsd")
    h = bytes.fromhex
    session = [h("10 22 02 49 6D 16"), h("10 02 22 00 24 16"),
               h("68 05 05 68 85 82 6D 3C 3E EE 16"),
               h("A2 82 85 08 3E 3C 02 05 00 FF 56 10 F5 16"),
               h("68 0C 0C 68 85 82 5D 3D 3E 88 32 01 00 56 10 01 01 16"), h("E5"),
               h("68 06 06 68 85 82 7D 3E 3E B7 B7 16"),
               h("A2 05 02 7D 00 00 00 00 12 00 00 80 16 16"),
               h("A2 02 05 08 00 00 00 00 00 40 02 70 C1 16"), h("DC 02 02"),
               h("68 07 07 68 FF 82 46 3A 3E 08 01 48 16")]
    put("profibus_fdl", "stream.bin", b"\x00" + b"".join(bytes([len(t) - 1]) + t for t in session))
    put("profibus_fdl", "garbage.bin", b"\x00" + bytes([40]) + bytes(range(0x60, 0x89)))
    put("profibus_fdl", "stations.bin",
        b"\x01" + b"\x00" * 40 + b"".join(b"\x01" + bytes([len(t) - 1]) + t for t in session) +
        b"\x02\x08\x01" + b"\x00" * 20 + b"\x02\x04\x01" + b"\x00" * 20)
    put("profibus_gsd", "GWT_5610.gsd", (ROOT / "iec-io/profibus/gsd/GWT_5610.gsd").read_bytes())
    put("profibus_gsd", "GWT_5610_seed.gsd",
        (ROOT / "tests/profibus/data/GWT_5610_seed.gsd").read_bytes())
    put("profibus_gsd", "user_prm.gsd", (
        "#Profibus_DP\nIdent_Number = 0x00C1\nUser_Prm_Data_Len = 3\n"
        "Ext_User_Prm_Data_Const(0) = 0x80, \\\n  0x00\nExt_User_Prm_Data_Ref(1) = 2\n"
        "PrmText = 7\nText(0) = \"off\"\nText(1) = \"on\"\nEndPrmText\n"
        "ExtUserPrmData = 2 \"Filter\"\nUnsigned16 0x1234 0-0xFFFF\nPrm_Text_Ref = 7\n"
        "EndExtUserPrmData\nExtUserPrmData = 3 \"Range\"\nBitArea(4-6) 2 1,2,4\n"
        "EndExtUserPrmData\nModule = \"2 AI\" 0x40,0x41, \\\n  0x00\n  17\n"
        "Ext_Module_Prm_Data_Len = 1\nExt_User_Prm_Data_Ref(0) = 3\nEndModule\n").encode())


def web_request_seeds():
    """fuzz_web_request: requests as the web HMI's page sends them (0), command
    bodies (1), passwords against the target's key (2)."""
    clear("web_request")
    key = bytes((i * 37) % 256 for i in range(32)).hex()
    cookie = "plc_session=" + "ab" * 32
    for i, body in enumerate(["write\nCell.target_kg\n0.625", "force\nCell.run\nTRUE\n",
                              "read\nCell.run\r\nCell.step", "ack\nall", "pause"]):
        req = ("POST /api/command HTTP/1.1\r\nHost: 127.0.0.1:8080\r\n"
               "Origin: http://127.0.0.1:8080\r\nCookie: a=1; %s\r\nX-CSRF-Token: %s\r\n"
               "Content-Type: text/plain\r\nContent-Length: %d\r\n\r\n%s"
               % (cookie, "cd" * 32, len(body), body))
        put("web_request", f"request{i}.bin", b"\x00" + req.encode())
        put("web_request", f"body{i}.bin", b"\x01" + body.encode())
    put("web_request", "upgrade.bin", b"\x00" + (
        "GET /api/ws HTTP/1.1\r\nHost: localhost:8080\r\nConnection: Upgrade\r\n"
        "Upgrade: websocket\r\nSec-WebSocket-Version: 13\r\n"
        "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nCookie: %s\r\n\r\n" % cookie).encode())
    put("web_request", "chunked.bin", b"\x00" + (
        "POST /api/login HTTP/1.1\r\nHost: 127.0.0.1:8080\r\nTransfer-Encoding: chunked\r\n"
        "\r\n5\r\nhello\r\n0\r\n\r\n").encode())
    put("web_request", "key.bin", b"\x02" + key.encode())
    put("web_request", "key_upper.bin", b"\x02" + key.upper().encode() + b"\n")
    put("web_request", "password.bin", b"\x02hunter2")


def recordings(plcrun, out, tmp):
    """A recording from scan 0 and one started mid-session (with a snapshot)."""
    out.mkdir(parents=True, exist_ok=True)
    subprocess.run([plcrun, str(CELL), "--virtual", "--cycles", "12", "--record",
                    str(out / "from_scan_0.rec"), "-q"], check=True, capture_output=True)
    cmds = tmp / "cmds.txt"
    cmds.write_text(f"step 300\nrecord {out / 'mid_session.rec'}\nstep 10\nrecord stop\nquit\n")
    subprocess.run([plcrun, str(CELL), "--virtual", "--commands", str(cmds)], check=True,
                   capture_output=True)


def main():
    plcrun = sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "build/bin/plcrun")
    tmp = pathlib.Path(tempfile.mkdtemp())
    if len(sys.argv) > 3 and sys.argv[2] == "--recordings":
        try:
            recordings(plcrun, pathlib.Path(sys.argv[3]).resolve(), tmp)
        finally:
            shutil.rmtree(tmp)
        return
    try:
        for t in ["config", "condition", "debugger", "recording", "drive_telegrams", "drive_params",
                  "safety_pdu", "safety_fparams", "weighing_windows"]:
            clear(t)

        for cell in sorted((ROOT / "programs").glob("*/cell.yaml")):
            put("config", cell.parent.name + ".yaml", cell.read_text())

        for i, c in enumerate([
                "Cell.dose.State = 3 AND Cell.dose.ActualNet > 19.5",
                "NOT Cell.guard.QBAD OR (Cell.conveyor.ActPosition >= 16#5000 AND Cell.dose.SettleTime > T#1s)",
                "%IX0.3 AND %QW0 <> 0 XOR Cell.run",
                "(Cell.containers MOD 7 + 2 * -Cell.dose.BatchCount) / 3 <= Cell.target_kg - 1.5e1",
                "Cell.conveyor.ZSW1 & 2#0000_0100 = 8#4",
                "Cell.pitch < 0.5 OR Cell.dose.MaxFillTime = T#1m30s500ms"]):
            put("condition", f"cond{i}.txt", c)

        for i, script in enumerate([
                "break Cell.dose.State = 3\ncontinue\nprint Cell.dose.ActualNet Cell.dose.PreactActual\n"
                "watch Cell.containers %QW0\nstep 10\ngoto 5\nbreaks\ndelete all\nstatus\n",
                "force Cell.guard.FMOD.PASS_ON TRUE\nstep task main 50\nforces\nunforce all restore\n"
                "write Cell.target_kg 12.5\nwrite %QB2 16#FF\nstep\nprint %IW0 Cell.target_kg\nstats\n",
                "trace add Cell.dose.ActualNet Cell.containers\ntrace trigger Cell.dose.State = 2\n"
                "trace pre 10\ntrace start out.csv\ncontinue for 500ms\ntrace stop\n"
                "record out.rec\nstep 20\nrecord stop\nrun until Cell.containers > 0\n",
                "break before Cell if Cell.run\ncontinue\nprint Cell.run\nstep\ncontinue\n"
                "delete 1\nbreak Cell.dose.BatchCount >= 1 hits 2\ncontinue\nhelp\nquit\n"]):
            put("debugger", f"commands{i}.txt", script)

        recordings(plcrun, CORPUS / "recording", tmp)
        hmi_commands()
        lcm_udpm_seeds()
        profibus_seeds()
        web_request_seeds()

        rows = trace_bytes(plcrun, tmp, 1500)
        # drive: selector = part * 3 + telegram (2 = telegram 111)
        t111 = rows[200]["e1_out"] + rows[200]["e1_in"]
        put("drive_telegrams", "decoders.bin", b"\x02" + b"\x00" * 28 + b"\x00" * 30 + t111)
        put("drive_telegrams", "e1_model_111.bin", b"\x05" + changes(rows[:600], "e1_out"))
        sina = b"\x01\x01" + struct.pack("<hiihhh", 1, 100000, 3000, 100, 100, 100)
        put("drive_telegrams", "sinapos_111.bin",
            b"\x08" + sina + b"".join(b"\x00" + f for f in
                                      [device_frames([r], "e1_in") for r in rows[:300]]))
        read317 = bytes([1, 1, 0, 1, 0x10, 0, 0x23, 0x17, 0, 0])
        write317 = bytes([2, 2, 0, 1, 0x10, 0, 0x23, 0x17, 0, 0, 0x06, 1, 0x0B, 0xB8])
        resp_read = bytes([1, 1, 0, 1, 0x06, 1, 0x0B, 0xB8])
        resp_err = bytes([2, 0x82, 0, 1, 0x44, 1, 0, 0x14])
        for name, b in [("req_read", read317), ("req_write", write317), ("resp_read", resp_read),
                        ("resp_error", resp_err), ("resp_write", bytes([2, 2, 0, 1]))]:
            put("drive_params", f"decode_{name}.bin", b"\x00" + b)
        put("drive_params", "server.bin",
            b"\x01" + b"\x00" + bytes([len(read317)]) + read317 + b"\x01\xf0" + b"\x02" +
            b"\x00" + bytes([len(write317)]) + write317 + b"\x01\xf0")
        para = b"\x03" + struct.pack("<HHBBB", 0x2317, 0, 0, 0x06, 200) + b"\x00" * 32
        put("drive_params", "sina_para_read.bin",
            b"\x02" + para + b"\x00" + device_frames(rows[:1], "e1_in") + b"\x01" +
            b"\x00" + bytes([0, len(resp_read)]) + resp_read + b"\x02" + b"\x00\x02" * 5)

        put("safety_pdu", "crc2.bin", b"\x00\x03" + bytes([1, 2, 3, 4, 0x22]) +
            struct.pack("<IHH", 7, 0x1234, 9) + b"\x08" + rows[300]["fs_in"] + b"\x04")
        put("safety_pdu", "f_host.bin",
            b"\x01\x64" + b"".join(b"\x02" + (b"\x00" if i == 1 else b"") +
                                   device_frames([r], "fs_in") for i, r in enumerate(rows[:400])))
        put("safety_pdu", "f_device.bin",
            b"\x02\x64\x00" + b"".join(b"\x01" + r["fs_out"] for r in rows[:200:4]) +
            b"".join(bytes([2 | (k % 3) << 2, 1, 0, 0, 0, 0x02]) for k in range(60)))

        fpar = bytes([0x08, 0x40, 0, 10, 0, 1, 0, 100, 0x12, 0x34, 0xAB, 0xCD, 0, 0])
        put("safety_fparams", "device.bin",
            b"\x01\x00\x00\x03" + b"\x01" + fpar + b"\x00" + fpar + b"\x03\x10" +
            b"\x02" + bytes([len(fpar)]) + fpar + b"\x05\x0d" + rows[300]["fs_out"] + b"\x04\x03\x10")

        put("weighing_windows", "codec.bin",
            b"\x00" + b"".join(r["w_in"] + b"\x00\x00" for r in rows[:1500:60]))
        put("weighing_windows", "pr5510_model.bin",
            b"\x01\x00" + b"".join(b"\xfd" + r["w_out"] for r in rows[:1500:16]) + b"\x00\x01\x03")
        put("weighing_windows", "blocks.bin",
            b"\x02\x04" + b"".join(b"\x08" + device_frames([r], "w_in") for r in rows[:1500:3]))
    finally:
        shutil.rmtree(tmp)
    total = sum(f.stat().st_size for f in CORPUS.rglob("*") if f.is_file())
    print(f"seeds written to {CORPUS} ({total} bytes)")


if __name__ == "__main__":
    main()
