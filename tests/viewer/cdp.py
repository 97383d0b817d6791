"""A headless Chromium driven over the Chrome DevTools Protocol (its --remote-debugging-port WebSocket), with
Debian's python3-websockets: load a page, evaluate JavaScript, click, take a screenshot. Every wait has a deadline;
close() kills the browser by pid and removes its profile folder."""

import asyncio
import base64
import io
import itertools
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
import urllib.request

import websockets

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"


def _read(path):
    try:
        with open(path) as f:
            return f.read().strip()
    except OSError:
        return ""


class Browser:
    def __init__(self, width=1400, height=900):
        self.profile = tempfile.mkdtemp(prefix="sf-chromium-")
        self.proc = subprocess.Popen(
            [CHROMIUM, "--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run", "--mute-audio",
             "--remote-debugging-port=0", "--remote-debugging-address=127.0.0.1", f"--user-data-dir={self.profile}",
             f"--window-size={width},{height}", "--force-device-scale-factor=1", "--hide-scrollbars",
             "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
        try:
            self._attach()
        except BaseException:  # the browser started: never leave it running
            self.close()
            raise

    def _attach(self):
        port_file = os.path.join(self.profile, "DevToolsActivePort")
        deadline = time.monotonic() + 60
        while not _read(port_file):
            if time.monotonic() > deadline or self.proc.poll() is not None:
                raise RuntimeError(f"chromium did not open its debugging port (exit {self.proc.poll()})")
            time.sleep(0.1)
        port = int(_read(port_file).split()[0])
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10) as r:
            targets = json.load(r)
        page = next(t for t in targets if t.get("type") == "page")
        self.ws_url = page["webSocketDebuggerUrl"]
        self.loop = asyncio.new_event_loop()
        asyncio.set_event_loop(self.loop)
        self.ws = self.loop.run_until_complete(self._connect())
        self.ids = itertools.count(1)

    async def _connect(self):
        return await websockets.connect(self.ws_url, max_size=64 << 20)

    def call(self, method, timeout=30, **params):
        return self.loop.run_until_complete(self._call(method, params, timeout))

    async def _call(self, method, params, timeout):
        i = next(self.ids)
        await self.ws.send(json.dumps({"id": i, "method": method, "params": params}))
        deadline = time.monotonic() + timeout
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError(f"{method}: no answer within {timeout} s")
            m = json.loads(await asyncio.wait_for(self.ws.recv(), left))
            if m.get("id") == i:
                if "error" in m:
                    raise RuntimeError(f"{method}: {m['error']}")
                return m.get("result", {})

    def navigate(self, url):
        self.call("Page.enable")
        self.call("Page.navigate", url=url)

    def eval(self, expression):
        r = self.call("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in r:
            raise RuntimeError(f"{expression}: {r['exceptionDetails']}")
        return r["result"].get("value")

    def wait_for(self, expression, timeout=60, what=None):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            v = self.eval(expression)
            if v:
                return v
            time.sleep(0.1)
        raise TimeoutError(f"{what or expression}: not true within {timeout} s")

    def click(self, x, y):
        for kind in ("mousePressed", "mouseReleased"):
            self.call("Input.dispatchMouseEvent", type=kind, x=x, y=y, button="left", clickCount=1)

    def click_element(self, element_id):
        x, y = self.eval(f"(() => {{ const r = document.getElementById('{element_id}').getBoundingClientRect();"
                         f" return [r.x + r.width / 2, r.y + r.height / 2]; }})()")
        self.click(x, y)

    def key(self, key):
        """A key pressed and released on the page, as a user's (`key`: " ", "ArrowRight", "+", "-")."""
        codes = {" ": ("Space", 32, " "), "ArrowRight": ("ArrowRight", 39, ""), "+": ("Equal", 187, "+"),
                 "-": ("Minus", 189, "-")}
        code, vk, text = codes[key]
        self.call("Input.dispatchKeyEvent", type="keyDown", key=key, code=code, windowsVirtualKeyCode=vk, text=text)
        self.call("Input.dispatchKeyEvent", type="keyUp", key=key, code=code, windowsVirtualKeyCode=vk)

    def screenshot(self):
        """The page as an RGB(A) array (rows, columns, channels), values 0..1."""
        from matplotlib import image  # Debian's python3-matplotlib (scripts/setup)
        png = base64.b64decode(self.call("Page.captureScreenshot", format="png")["data"])
        return image.imread(io.BytesIO(png), format="png"), png

    def close(self):
        try:
            if getattr(self, "ws", None) is not None and getattr(self, "loop", None) is not None:
                self.loop.run_until_complete(self.ws.close())
        except Exception:  # the browser may be gone already
            pass
        try:
            os.killpg(self.proc.pid, signal.SIGKILL)  # the browser and its helper processes (its own session)
        except ProcessLookupError:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            pass
        if getattr(self, "loop", None) is not None:
            asyncio.set_event_loop(None)
            self.loop.close()
            self.loop = None
        shutil.rmtree(self.profile, ignore_errors=True)
