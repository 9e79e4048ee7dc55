#!/usr/bin/python3
"""`memloop view` in headless Chromium, driven as a user would through the DevTools protocol:
open the address memloop view printed (with its token), see the graph by position, open a loop
closure, reject it, reload
and see it rejected, then check that `memloop export` no longer lists it; a request without the
token is refused. Exits 77 (skipped) without chromium or python3-websocket (make test installs
both). MEMLOOP_VIEWER_SCREENSHOT=FILE saves the loop closures page (docs/viewer.png)."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

CLI = os.environ.get("MEMLOOP_CLI", "memloop")


def skip(why):
    print("SKIPPED:", why)
    sys.exit(77)


try:
    import websocket  # python3-websocket
except ImportError:
    skip("python3-websocket is not installed (make test installs it)")
if shutil.which("chromium") is None:
    skip("chromium is not installed (make test installs it)")


def wait_for(what, check, seconds=60):
    deadline = time.time() + seconds
    while time.time() < deadline:
        value = check()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError("timed out waiting for " + what)


class Browser:
    """One headless Chromium page, evaluated through the DevTools protocol."""

    def __init__(self, folder):
        profile = os.path.join(folder, "chromium")
        self.process = subprocess.Popen(
            ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
             "--remote-debugging-port=0", "--user-data-dir=" + profile,
             "--window-size=1200,900", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        port_file = os.path.join(profile, "DevToolsActivePort")
        wait_for("Chromium's DevTools port", lambda: os.path.exists(port_file)
                 and open(port_file).read().count("\n") >= 1)
        port = open(port_file).read().split("\n")[0]
        targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list"))
        page = next(t for t in targets if t["type"] == "page")
        self.socket = websocket.create_connection(page["webSocketDebuggerUrl"], timeout=60)
        self.next_id = 0

    def call(self, method, **params):
        self.next_id += 1
        self.socket.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        while True:
            message = json.loads(self.socket.recv())
            if message.get("id") == self.next_id:
                if "error" in message:
                    raise AssertionError(f"{method}: {message['error']}")
                return message.get("result", {})

    def eval(self, expression):
        result = self.call("Runtime.evaluate", expression=expression, returnByValue=True,
                           awaitPromise=True)
        if "exceptionDetails" in result:
            raise AssertionError(f"{expression}: {result['exceptionDetails']}")
        return result["result"].get("value")

    def close(self):
        self.socket.close()
        self.process.kill()
        self.process.wait()


def main():
    folder = tempfile.mkdtemp(prefix="memloop_viewer_")
    view = None
    browser = None
    try:
        # The generated walk as a TUM folder (time stamps, a true trajectory): its first lap and
        # the revisit, 130 images (rgb.txt's 3 comment lines, then a line an image).
        route = os.path.join(folder, "walk")
        subprocess.run([CLI, "generate", route, "--layout", "tum"], check=True,
                       stdout=subprocess.DEVNULL)
        rgb = os.path.join(route, "rgb.txt")
        with open(rgb) as listing:
            lines = listing.readlines()[:133]
        with open(rgb, "w") as listing:
            listing.writelines(lines)
        map_path = os.path.join(folder, "map.db")
        subprocess.run([CLI, "run", route, "--db", map_path, "--set", "memory.time_limit_ms=0"],
                       check=True, stdout=subprocess.DEVNULL)

        view = subprocess.Popen([CLI, "view", map_path, "--images", route, "--poses",
                                 os.path.join(route, "groundtruth.txt")],
                                stdout=subprocess.PIPE, text=True)
        address = view.stdout.readline().split()[2]  # "memloop view: http://... serves MAP"
        with_token = view.stdout.readline().split()[-1]  # "  to edit ... open URL#token=T"
        assert address.startswith("http://127.0.0.1:"), address
        assert "#token=" in with_token, with_token

        # Without the token, the server refuses to write (as it would for another page).
        request = urllib.request.Request(
            address + "api/edits", method="POST", headers={"Content-Type": "application/json"},
            data=json.dumps({"action": "reject", "query_image": 1, "match_image": 0}).encode())
        try:
            urllib.request.urlopen(request)
            raise AssertionError("an edit without the token was accepted")
        except urllib.error.HTTPError as refused:
            assert refused.code == 403, refused.code

        browser = Browser(folder)
        browser.call("Page.enable")
        browser.call("Page.navigate", url=with_token)
        wait_for("the token to be taken", lambda: "editing allowed" in (browser.eval(
            "(document.getElementById('editing') || {}).textContent") or ""))
        browser.eval("location.hash = '#/loops'")
        wait_for("the loop closures", lambda: browser.eval(
            "document.querySelectorAll('tr.loop').length") > 0)
        # Each row shows the pair's file names and thumbnails.
        first_row = browser.eval("document.querySelector('tr.loop').textContent")
        assert "rgb/" in first_row and ".png" in first_row, first_row
        wait_for("the thumbnails", lambda: browser.eval(
            "[...document.querySelectorAll('tr.loop img')].slice(0, 4)"
            ".every(i => i.complete && i.naturalWidth === 160)"))
        if os.environ.get("MEMLOOP_VIEWER_SCREENSHOT"):
            import base64
            shot = browser.call("Page.captureScreenshot", format="png")
            with open(os.environ["MEMLOOP_VIEWER_SCREENSHOT"], "wb") as out:
                out.write(base64.b64decode(shot["data"]))

        # The graph by position: the trajectory and its loop closures drawn.
        browser.eval("location.hash = '#/graph'")
        wait_for("the graph", lambda: browser.eval(
            "(() => { const c = document.getElementById('graph'); if (!c) return false;"
            " const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;"
            " let green = 0; for (let i = 0; i < d.length; i += 4)"
            " if (d[i + 1] > 90 && d[i] < 60 && d[i + 3] > 0) green++; return green > 20; })()"))
        browser.eval("location.hash = '#/loops'")
        wait_for("the loop closures again", lambda: browser.eval(
            "document.querySelectorAll('tr.loop').length") > 0)

        # Open the first loop closure, see its two images, reject it.
        browser.eval("document.querySelector('tr.loop a').click()")
        wait_for("the loop closure's page", lambda: browser.eval(
            "((document.getElementById('page') || {}).dataset || {}).view") == "loop")
        wait_for("its images", lambda: browser.eval(
            "[...document.querySelectorAll('.pair img')]"
            ".filter(i => i.complete && i.naturalWidth > 0).length") == 2)
        pair = browser.eval("document.querySelector('[data-reject]').dataset.reject")
        query, match = (int(v) for v in pair.split(","))
        browser.eval("document.querySelector('[data-reject]').click()")
        wait_for("the edit to be kept", lambda: "kept in the map" in (browser.eval(
            "(document.getElementById('banner') || {}).textContent") or ""))

        # Reloaded, the page shows it rejected (the map holds the edit, not the page).
        browser.call("Page.reload")
        wait_for("the reloaded page", lambda: browser.eval(
            "((document.getElementById('page') || {}).dataset || {}).view") == "loop")
        state = wait_for("the state", lambda: browser.eval(
            "document.querySelector('h1 span') && document.querySelector('h1 span').textContent"))
        assert state == "rejected", state

        # export no longer lists it; inspect says why.
        exported_file = os.path.join(folder, "loops.json")
        subprocess.run([CLI, "export", map_path, "--format", "json", "--out", exported_file],
                       check=True, stdout=subprocess.DEVNULL)
        with open(exported_file) as exported:
            pairs = {(loop["query"]["image"], loop["match"]["image"])
                     for loop in json.load(exported)["loop_closures"]}
        assert (query, match) not in pairs, pairs
        assert len(pairs) > 0, pairs
        inspect = subprocess.run([CLI, "inspect", map_path], check=True, capture_output=True,
                                 text=True).stdout
        assert "1 detected ones rejected" in inspect, inspect
        print(f"rejected loop closure {query} -> {match} in the browser; export lists "
              f"{len(pairs)} without it")
    finally:
        if browser:
            browser.close()
        if view:
            view.terminate()
            view.wait(timeout=30)
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
