"""The cell the web HMI tests run: the filling cell's DeviceNet variant
(programs/filling_cell/cell_vf66b_devicenet.yaml) in real time, its two
slaves in a separate simulator process (dnslave), and plchmi serving the
web HMI on loopback. Ports are chosen free; every wait is bounded."""

import http.client
import json
import os
import re
import signal
import socket
import subprocess
import tempfile
import time

PASSWORD = "web-hmi-test"


def free_port(kind=socket.SOCK_STREAM):
    s = socket.socket(socket.AF_INET, kind)
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def wait_for(what, probe, timeout=30.0, interval=0.1):
    """Polls `probe` until it returns something true, at most `timeout` s."""
    deadline = time.monotonic() + timeout
    while True:
        got = probe()
        if got:
            return got
        if time.monotonic() > deadline:
            raise AssertionError("timed out waiting for " + what)
        time.sleep(interval)


class Cell:
    def __init__(self, bindir, srcdir, read_only=False, extra_web=""):
        self.bindir, self.srcdir = bindir, srcdir
        self.dir = tempfile.mkdtemp(prefix="webhmi-")
        self.port = free_port()
        self.bus = free_port(socket.SOCK_DGRAM)
        self.read_only = read_only
        self.extra_web = extra_web
        self.plcrun = self.slaves = None
        self.log = open(os.path.join(self.dir, "plcrun.log"), "w+")

    def write_configs(self):
        prog = os.path.join(self.srcdir, "programs", "filling_cell")
        with open(os.path.join(prog, "cell_vf66b_devicenet.yaml")) as f:
            cell = f.read()
        with open(os.path.join(prog, "dnslave_vf66b.yaml")) as f:
            slaves = f.read()
        bus = "udp:127.0.0.1:%d" % self.bus
        cell = cell.replace("udp:127.0.0.1:47800", bus)
        slaves = slaves.replace("udp:127.0.0.1:47800", bus)
        hashed = subprocess.run([os.path.join(self.bindir, "plchmi"), "--hash-password"],
                                input=PASSWORD + "\n", capture_output=True, text=True,
                                check=True).stdout.strip()
        cell += """
hmi:
  url: "memq://"
  rate: 10
  publish: ["Cell.*"]
  writable: ["Cell.target_kg"]
  forceable: ["Cell.run"]
  stop_commands: true
  web:
    address: 127.0.0.1
    port: %d
    read_only: %s
    login: "%s"
%s""" % (self.port, "true" if self.read_only else "false", hashed, self.extra_web)
        self.cell_yaml = os.path.join(self.dir, "cell.yaml")
        self.slaves_yaml = os.path.join(self.dir, "dnslave.yaml")
        with open(self.cell_yaml, "w") as f:
            f.write(cell)
        with open(self.slaves_yaml, "w") as f:
            f.write(slaves)

    def start_slaves(self):
        self.slaves = subprocess.Popen([os.path.join(self.bindir, "dnslave"), self.slaves_yaml],
                                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    def stop_slaves(self):
        if self.slaves:
            self.slaves.send_signal(signal.SIGTERM)
            try:
                self.slaves.wait(10)
            except subprocess.TimeoutExpired:
                self.slaves.kill()
                self.slaves.wait()
            self.slaves = None

    def start(self):
        self.write_configs()
        self.start_slaves()
        self.plcrun = subprocess.Popen(
            [os.path.join(self.bindir, "plcrun"), self.cell_yaml, "--for", "10m"],
            stdout=self.log, stderr=subprocess.STDOUT)
        wait_for("the web HMI to listen", self.listening)
        return self

    def listening(self):
        if self.plcrun.poll() is not None:
            self.log.seek(0)
            raise AssertionError("plcrun ended: " + self.log.read())
        try:
            socket.create_connection(("127.0.0.1", self.port), 0.5).close()
            return True
        except OSError:
            return False

    def stop(self):
        if self.plcrun and self.plcrun.poll() is None:
            self.plcrun.send_signal(signal.SIGINT)
            try:
                self.plcrun.wait(20)
            except subprocess.TimeoutExpired:
                self.plcrun.kill()
                self.plcrun.wait()
        self.stop_slaves()

    def output(self):
        self.log.flush()
        self.log.seek(0)
        return self.log.read()

    @property
    def origin(self):
        return "http://127.0.0.1:%d" % self.port

    # -- plain HTTP, as a script (not a browser) would

    def request(self, method, path, body=None, headers=None):
        c = http.client.HTTPConnection("127.0.0.1", self.port, timeout=10)
        h = {"Host": "127.0.0.1:%d" % self.port}
        h.update(headers or {})
        c.request(method, path, body=body, headers=h)
        r = c.getresponse()
        data = r.read()
        c.close()
        return r.status, dict(r.getheaders()), data

    def login(self, password=PASSWORD):
        """(cookie header value, csrf token)"""
        status, headers, data = self.request("POST", "/api/login", password,
                                             {"Origin": self.origin})
        if status != 200:
            return None, None
        cookie = re.match(r"([^;]+)", headers["Set-Cookie"]).group(1)
        return cookie, json.loads(data)["csrf"]

    def command(self, cookie, csrf, text, origin=True):
        h = {"Cookie": cookie, "X-CSRF-Token": csrf}
        if origin:
            h["Origin"] = self.origin
        status, _, data = self.request("POST", "/api/command", text, h)
        return status, json.loads(data) if data else {}

    def read(self, cookie, csrf, path):
        status, r = self.command(cookie, csrf, "read\n" + path)
        assert status == 200 and r["ok"], r
        return r["values"][0]
