#!/usr/bin/env python3
"""Issue 27, in a real browser: headless Chromium driven through
chromedriver's W3C WebDriver protocol (Python's standard library only, on
loopback) against plcrun + plchmi + a separate DeviceNet simulator process
(webhmi_cell.py). The page loads behind its login, values move with the
cell, a write of a writable variable changes the cell, a refused write shows
the reason and changes nothing, a force shows as forced, the trend draws,
and the devices view shows a device lost and back when its simulator is
stopped and started again. A screenshot of each view goes to SHOTS_DIR.

Exit 77 (ctest: skipped) only when chromium or chromedriver is missing.
  test_web_browser.py BIN_DIR SOURCE_DIR SHOTS_DIR"""

import base64
import json
import os
import shutil
import subprocess
import sys
import tempfile
import urllib.request

from webhmi_cell import PASSWORD, Cell, free_port, wait_for

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
CHROMEDRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"
ELEMENT = "element-6066-11e4-a52e-4f735466cecf"


class WebDriver:
    """The few W3C WebDriver commands the test needs."""

    def __init__(self, port, profile):
        self.base = "http://127.0.0.1:%d" % port
        caps = {"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": {"binary": CHROMIUM, "args": [
                "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                "--no-first-run", "--disable-background-networking",
                "--disable-component-update", "--disable-sync",
                "--disable-dev-shm-usage", "--window-size=1280,900",
                "--user-data-dir=" + profile]}}}}
        self.session = self.call("POST", "/session", caps)["sessionId"]

    def call(self, method, path, body=None):
        data = json.dumps(body).encode() if body is not None else None
        if method == "POST" and data is None:
            data = b"{}"
        req = urllib.request.Request(self.base + path, data=data, method=method,
                                     headers={"Content-Type": "application/json"})
        try:
            with urllib.request.urlopen(req, timeout=60) as r:
                return json.loads(r.read())["value"]
        except urllib.error.HTTPError as e:
            raise AssertionError("webdriver %s %s: %s" % (method, path, e.read()[:500]))

    def s(self, path):
        return "/session/" + self.session + path

    def get(self, url):
        self.call("POST", self.s("/url"), {"url": url})

    def find(self, css):
        return self.call("POST", self.s("/element"), {"using": "css selector", "value": css})[ELEMENT]

    def click(self, css):
        self.call("POST", self.s("/element/%s/click" % self.find(css)))

    def type(self, css, text, clear=True):
        e = self.find(css)
        if clear:
            self.call("POST", self.s("/element/%s/clear" % e))
        self.call("POST", self.s("/element/%s/value" % e), {"text": text})

    def js(self, script, *args):
        return self.call("POST", self.s("/execute/sync"), {"script": script, "args": list(args)})

    def text(self, css):
        return self.js("const e = document.querySelector(arguments[0]);"
                       "return e ? e.textContent : null;", css)

    def screenshot(self, path):
        with open(path, "wb") as f:
            f.write(base64.b64decode(self.call("GET", self.s("/screenshot"))))

    def quit(self):
        try:
            self.call("DELETE", self.s(""))
        except Exception:  # the browser is going anyway
            pass


def value_of(d, path):
    return d.js("const S = window.plcHmi; const i = S.index.get(arguments[0]);"
                "return i === undefined ? null : S.text[i];", path)


def main():
    bindir, srcdir, shots = sys.argv[1], sys.argv[2], sys.argv[3]
    if not (os.path.exists(CHROMIUM) and os.path.exists(CHROMEDRIVER)):
        print("SKIP: chromium or chromedriver missing (scripts/setup installs chromium "
              "chromium-driver)")
        return 77
    os.makedirs(shots, exist_ok=True)
    cell = Cell(bindir, srcdir).start()
    drv_port = free_port()
    profile = tempfile.mkdtemp(prefix="webhmi-chromium-")
    driver = subprocess.Popen([CHROMEDRIVER, "--port=%d" % drv_port],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    d = None
    try:
        wait_for("chromedriver", lambda: _up(drv_port))
        d = WebDriver(drv_port, profile)
        d.get(cell.origin + "/")

        # Login: the page shows nothing before it.
        wait_for("the login form", lambda: d.js("return !document.querySelector('#login').hidden"))
        assert d.js("return document.querySelector('#views').hidden"), "data shown before login"
        d.type("#password", "wrong")
        d.click("#login-btn")
        wait_for("the refusal", lambda: d.text("#login-error") == "wrong password")
        d.type("#password", PASSWORD)
        d.click("#login-btn")

        # The cell view: tasks with live scan statistics.
        wait_for("the tasks", lambda: d.js(
            "return document.querySelectorAll('#tasks tbody tr').length > 0"))
        scans0 = int(d.text("#tasks tbody tr .scans"))
        wait_for("scans to move", lambda: int(d.text("#tasks tbody tr .scans")) > scans0, 10)
        print("cell view: scans %d -> %s" % (scans0, d.text("#tasks tbody tr .scans")))
        d.screenshot(os.path.join(shots, "web_cell.png"))

        # Values move with the cell: some published value changes.
        before = d.js("return window.plcHmi.text.slice()")
        moved = wait_for("a value to change", lambda: d.js(
            "const b = arguments[0]; return window.plcHmi.text.filter((t, i) => b[i] !== '' "
            "&& t !== b[i]).length", before), 15)
        print("values moved: %d variables changed" % moved)

        # The variable browser: search, tree, write a writable variable.
        d.click("#tab-vars")
        d.type("#search", "Cell.")
        wait_for("the tree", lambda: d.js(
            "return !!document.querySelector('tr[data-path=\"Cell.target_kg\"]')"))
        d.screenshot(os.path.join(shots, "web_variables.png"))
        d.click('tr[data-path="Cell.target_kg"] a')
        wait_for("the dialog", lambda: d.js("return document.querySelector('#dialog').open"))
        d.type("#dlg-value", "0.625")
        d.click("#dlg-write")
        wait_for("the write's answer", lambda: (d.text("#dlg-result") or "").startswith("write done"))
        wait_for("the cell to hold 0.625", lambda: value_of(d, "Cell.target_kg") == "0.625", 10)
        print("write: Cell.target_kg = %s" % value_of(d, "Cell.target_kg"))
        d.click("#dlg-close")

        # A refused write: the reason shown, the cell unchanged.
        pitch_path = "Cell.belt_speed"
        old = value_of(d, pitch_path)
        d.click('tr[data-path="%s"] a' % pitch_path)
        wait_for("the dialog", lambda: d.js("return document.querySelector('#dialog').open"))
        assert "Not writable" in d.text("#dlg-rules"), d.text("#dlg-rules")
        d.type("#dlg-value", "123.0")
        d.click("#dlg-write")
        wait_for("the refusal", lambda: (d.text("#dlg-result") or "").startswith("Refused"))
        reason = d.text("#dlg-result")
        assert "writable patterns do not match" in reason, reason
        d.screenshot(os.path.join(shots, "web_write_refused.png"))
        status, r = _read_as_script(cell, pitch_path)
        assert r["text"] != "123.0" and r["text"] != "123", r
        print("refused write: '%s'; %s stays %s (was %s)" % (reason, pitch_path, r["text"], old))
        d.click("#dlg-close")

        # A force shows as forced.
        d.click('tr[data-path="Cell.run"] a')
        wait_for("the dialog", lambda: d.js("return document.querySelector('#dialog').open"))
        d.type("#dlg-value", "TRUE")
        d.click("#dlg-force")
        wait_for("FORCED in the dialog", lambda: d.text("#dlg-forced") == "FORCED")
        d.screenshot(os.path.join(shots, "web_force.png"))
        d.click("#dlg-close")
        wait_for("F in the variable's row", lambda: d.text(
            'tr[data-path="Cell.run"] .forced') == "F")
        status, r = _read_as_script(cell, "Cell.run")
        assert r["forced"] and r["text"] == "TRUE", r
        print("force: Cell.run forced to %s" % r["text"])

        # The trend draws: a REAL, an INT and a BOOL.
        for p in ("Cell.belt_speed", "Cell.step", "Cell.run", "Cell.target_kg"):
            d.click('tr[data-path="%s"] input[type=checkbox]' % p)
        d.click("#tab-trends")
        d.click('[data-window="10"]')
        wait_for("the trend to draw", lambda: d.js("return window.plcHmi.drawn") > 40, 20)
        painted = d.js("const c = document.querySelector('#trend-canvas');"
                       "const px = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;"
                       "let n = 0; for (let i = 0; i < px.length; i += 4)"
                       " if (px[i] < 100 && px[i + 2] > 150) n++; return n;")
        assert painted > 100, painted
        print("trend: %d points drawn, %d blue pixels" % (d.js("return window.plcHmi.drawn"), painted))
        d.screenshot(os.path.join(shots, "web_trends.png"))

        # Devices: lost when their simulator stops, back when it starts again.
        d.click("#tab-devices")
        wait_for("the devices online", lambda: d.text('tr[data-device="scale"] .state') == "online",
                 30)
        d.screenshot(os.path.join(shots, "web_devices.png"))
        cell.stop_slaves()
        wait_for("the scale lost", lambda: d.text('tr[data-device="scale"] .state') != "online", 30)
        wait_for("the lost event", lambda: d.js(
            "return !!document.querySelector('#device-history tr.hist-lost')"), 30)
        print("devices: scale %s with its simulator stopped" % d.text('tr[data-device="scale"] .state'))
        d.screenshot(os.path.join(shots, "web_devices_lost.png"))
        cell.start_slaves()
        wait_for("the scale back", lambda: d.text('tr[data-device="scale"] .state') == "online", 60)
        wait_for("the back event", lambda: d.js(
            "return !!document.querySelector('#device-history tr.hist-back')"), 30)
        print("devices: history %s" % d.js(
            "return [...document.querySelectorAll('#device-history tbody tr')]"
            ".map(r => r.textContent).join(' | ')"))
        d.screenshot(os.path.join(shots, "web_devices_back.png"))

        # Alarms: the events, acknowledged.
        d.click("#tab-alarms")
        wait_for("alarm events", lambda: d.js(
            "return document.querySelectorAll('#alarm-events tbody tr').length") >= 2)
        d.click("#ack-all")
        wait_for("acknowledged", lambda: d.js(
            "return document.querySelectorAll('#alarm-events tbody tr:not(.acked)').length") == 0)
        d.screenshot(os.path.join(shots, "web_alarms.png"))

        # The stale-data banner when the cell stops.
        cell.stop()
        wait_for("the stale banner", lambda: d.js(
            "return !document.querySelector('#stale').hidden"), 20)
        print("stale banner: %s" % d.text("#stale"))
        d.screenshot(os.path.join(shots, "web_stale.png"))
        print("PASS")
        return 0
    except BaseException:
        print(cell.output())
        raise
    finally:
        if d:
            d.quit()
        driver.terminate()
        driver.wait(10)
        cell.stop()
        shutil.rmtree(profile, ignore_errors=True)


def _up(port):
    try:
        urllib.request.urlopen("http://127.0.0.1:%d/status" % port, timeout=2).read()
        return True
    except OSError:
        return False


def _read_as_script(cell, path):
    cookie, csrf = cell.login()
    status, r = cell.command(cookie, csrf, "read\n" + path)
    return status, r["values"][0]


if __name__ == "__main__":
    sys.exit(main())
