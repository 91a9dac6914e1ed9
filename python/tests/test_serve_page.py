"""The page of `nsf serve` in a headless Chromium (docs/SERVE.md): it draws the particles, the
ground (the scene's plane collider) and moves between the first and the sixth frame of a run. Skipped without Chromium (Debian's
`chromium`, installed by scripts/install-deps.sh)."""

import base64
import json
import os
import re
import shutil
import struct
import subprocess
import time
import zlib

import pytest

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
GROUND = (115, 128, 140)  # the page's ground colour, (0.45, 0.5, 0.55)


def png_pixels(data):
    """(width, height, rows of RGB tuples) of an 8-bit, non-interlaced RGB or RGBA PNG."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    at, idat = 8, b""
    while at < len(data):
        n, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + n]
        if kind == b"IHDR":
            w, h, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and color in (2, 6) and interlace == 0, (depth, color, interlace)
            bpp = 3 if color == 2 else 4
        elif kind == b"IDAT":
            idat += body
        at += 12 + n
    raw, stride, rows, prev = zlib.decompress(idat), w * bpp, [], bytearray(w * bpp)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([tuple(line[x * bpp:x * bpp + 3]) for x in range(w)])
        prev = line
    return w, h, rows


class Browser:
    """A headless Chromium driven over the DevTools protocol on a pipe (fds 3 and 4): real time,
    so that the page's WebSocket stream runs as it does for a visitor."""

    def __init__(self):
        to_chrome, self._w = os.pipe()
        self._r, from_chrome = os.pipe()

        def fds():  # via fresh copies: dup2 onto the same number would keep close-on-exec
            a, b = os.dup(to_chrome), os.dup(from_chrome)
            os.dup2(a, 3)
            os.dup2(b, 4)

        self.proc = subprocess.Popen(
            [CHROMIUM, "--headless", "--no-sandbox", "--use-angle=swiftshader",
             "--enable-unsafe-swiftshader", "--window-size=480,360", "--remote-debugging-pipe",
             "about:blank"], preexec_fn=fds, close_fds=False, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL)
        os.close(to_chrome)
        os.close(from_chrome)
        self._id, self._buf = 0, b""
        target = self.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = self.call("Target.attachToTarget", {"targetId": target, "flatten": True})[
            "sessionId"]

    def call(self, method, params=None, session=None):
        self._id += 1
        msg = {"id": self._id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self._w, json.dumps(msg).encode() + b"\0")
        while True:
            while b"\0" not in self._buf:
                chunk = os.read(self._r, 1 << 16)
                assert chunk, "Chromium closed its pipe"
                self._buf += chunk
            line, self._buf = self._buf.split(b"\0", 1)
            reply = json.loads(line)
            if reply.get("id") == self._id:
                assert "error" not in reply, reply
                return reply["result"]

    def evaluate(self, expression):
        return self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True},
                         self.session)["result"].get("value")

    def wait_for(self, expression, timeout=60):
        """Polls the page until `expression` is true; fails naming it and the page's status."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if self.evaluate(expression):
                return
            time.sleep(0.05)
        status = self.evaluate("document.getElementById('status').textContent")
        raise AssertionError(f"the page never had {expression} in {timeout} s: {status}")

    def picture(self):
        """The canvas as the page last drew it (?dump keeps its drawing buffer)."""
        url = self.evaluate("document.getElementById('view').toDataURL('image/png')")
        return png_pixels(base64.b64decode(url.split(",", 1)[1]))

    def close(self):
        try:
            self.call("Browser.close")
        except (AssertionError, OSError):
            pass
        self.proc.wait(timeout=30)
        os.close(self._w)
        os.close(self._r)


@pytest.mark.skipif(CHROMIUM is None, reason="no Chromium (apt install chromium)")
def test_the_page_draws_the_ground_and_moves(nsf_cli, tiny_model, tiny_scene):
    # Five frames a second, held at the end: at real time the tiny scene's 12 frames loop every
    # 0.18 s, and two pictures polled for could land a loop apart, alike.
    server = subprocess.Popen([nsf_cli, "serve", tiny_model, tiny_scene, "--mu", "1.0", "-p", "0",
                               "-q", "--threads", "1", "--fps", "5", "--at-end", "hold"],
                              stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True)
    try:
        first = server.stdout.readline()
        m = re.search(r"(http://[^ ]+/) ", first)
        assert m, "nsf serve printed no address: " + first
        browser = Browser()
        try:
            browser.call("Page.navigate", {"url": m.group(1) + "?dump=0"}, browser.session)
            browser.wait_for("typeof frameInfo !== 'undefined' && frameInfo !== null")
            # The scene started again, so that the two pictures are of one run: its first frame
            # and its sixth or a later one. The reset is sent again until the page shows the
            # start: once, it was never seen (the page stayed on the held last frame).
            dt = browser.evaluate("model.header.frame_time")
            for attempt in range(5):
                browser.evaluate("ws.send(JSON.stringify({type: 'reset'}))")
                try:
                    browser.wait_for(f"frameInfo.time <= {1.01 * dt}", timeout=12)
                    break
                except AssertionError:
                    if attempt == 4:
                        raise
            start = browser.evaluate("frameInfo.frame")
            browser.wait_for(f"drawnFrame >= {start}")  # the canvas shows that frame or the next
            _, _, early = browser.picture()
            browser.wait_for(f"drawnFrame >= {start + 5}")
            w, h, late = browser.picture()
        finally:
            browser.close()
    except AssertionError as e:  # what the server said, for a failure that is hard to repeat
        server.terminate()
        said, _ = server.communicate(timeout=30)
        raise AssertionError(f"{e}\nnsf serve said:\n{said[-3000:]}") from e
    finally:
        server.terminate()
        server.wait(timeout=30)
    pixels = [p for row in late for p in row]
    ground = sum(all(abs(p[k] - GROUND[k]) <= 12 for k in range(3)) for p in pixels)
    assert ground > 0.02 * w * h, f"the ground covers {ground} of {w * h} pixels"
    # The particles: blue (low) to gold (high), far from the background and the ground.
    bodies = sum(p[2] > 150 and p[2] > p[0] + 60 or p[0] > 180 and p[1] > 150 and p[2] < 120
                 for p in pixels)
    assert bodies > 0.002 * w * h, f"the particles cover {bodies} of {w * h} pixels"
    changed = sum(a != b for ra, rb in zip(early, late) for a, b in zip(ra, rb))
    assert changed > 0.001 * w * h, f"the first and sixth frames differ in {changed} pixels"
