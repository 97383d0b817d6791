#!/usr/bin/python3
"""The frames a second that reach the viewer's page in a headless Chromium, live, in realtime at 10 ticks/s
(viewer/README.md "Rates", BENCHMARKS.md "The viewer"). Not a test: it prints figures.

    bench/viewer/page_rate.py [--robots 9,256] [--seconds 20] [--domain D] [--build BUILD]

For each N: `scripts/swarm run --mode realtime --view` (N <= 9: scenarios/paper.yaml, the paper's 9 robots;
more: bench/scale/realtime.yaml's random walkers, --robots N), a Chromium page on it, and over --seconds of the
run's middle: the frames that reached the page a second (arrival times the page logs, window.sfViewer.rates.log),
the distinct ticks a second they show, the ticks of the window no frame showed (a frame the world did not offer, or
one a newer replaced while the page drew), the longest gap between two frames, the page's draw time a frame and the lag
(the frame's age since the world wrote it, ms) as the status bar shows it."""

import argparse
import os
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tests", "viewer"))
sys.path.insert(0, os.path.join(ROOT, "tests", "scripts"))
import cdp  # noqa: E402  (the tests' DevTools client)
import helpers  # noqa: E402  (free_port, test_domain)
from viewer_helpers import wait_http  # noqa: E402


def measure(n, seconds, domain, build):
    tmp = tempfile.mkdtemp(prefix="sf-bench-view-")
    port = helpers.free_port()
    scenario = ["--scenario", os.path.join(ROOT, "scenarios", "paper.yaml")] if n <= 9 else \
        ["--scenario", os.path.join(ROOT, "bench", "scale", "realtime.yaml"), "--robots", str(n)]
    ticks = int((seconds + 60) * 10)
    env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=build)
    run = subprocess.Popen([os.path.join(ROOT, "scripts", "swarm"), "run", *scenario, "--mode", "realtime",
                            "--max-ticks", str(ticks), "--domain", str(domain), "--out", os.path.join(tmp, "run"),
                            "--no-pictures", "--view", str(port)],
                           stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                           start_new_session=True)
    b = None
    try:
        url = f"http://127.0.0.1:{port}/"
        wait_http(url, 120)
        b = cdp.Browser()
        b.navigate(url)
        b.wait_for(f"window.sfViewer && sfViewer.frame && sfViewer.frame.robots.length === {n}", timeout=180,
                   what=f"a frame of {n} robots")
        time.sleep(3.0)  # the page's first frames and the run's start-up out of the window
        b.eval("sfViewer.rates.log = []; sfViewer.drawTimes = []")
        b.eval("sfViewer._lags = []; sfViewer._lagTimer = setInterval(() => { if (sfViewer.rates.lagMs !== null)"
               " sfViewer._lags.push(sfViewer.rates.lagMs); sfViewer.drawTimes.push(sfViewer.drawn.drawMs); }, 100)")
        time.sleep(seconds)
        log = b.eval("sfViewer.rates.log")
        lags = b.eval("sfViewer._lags")
        draws = b.eval("sfViewer.drawTimes")
        ended = b.eval("!!(sfViewer.end || sfViewer.frame.finished)")
        # The page's own cost of a frame: draw() ten times back to back (all layers, then without trails), and
        # JSON.parse of the frame as the WebSocket brings it, the median of each.
        loop = b.eval("""(() => { const med = (a) => a.sort((x, y) => x - y)[a.length >> 1];
            const time = (fn) => { const t = []; for (let i = 0; i < 10; i++) { const t0 = performance.now(); fn();
                                   t.push(performance.now() - t0); } return med(t); };
            const all = time(() => sfViewer.draw()); sfViewer.layers.trails = false;
            const noTrails = time(() => sfViewer.draw()); sfViewer.layers.trails = true;
            const text = JSON.stringify(sfViewer.frame);
            return {all: all, noTrails: noTrails, parse: time(() => JSON.parse(text)), bytes: text.length}; })()""")
    finally:
        if b:
            b.close()
        if run.poll() is None:
            os.killpg(run.pid, signal.SIGTERM)
            try:
                run.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(run.pid, signal.SIGKILL)
                run.wait(timeout=10)
        shutil.rmtree(tmp, ignore_errors=True)
    if ended or len(log) < 2:
        raise SystemExit(f"N={n}: the run ended inside the window (or no frames): raise --max-ticks")
    span = (log[-1][0] - log[0][0]) / 1000
    gaps = [(b_[0] - a[0]) for a, b_ in zip(log, log[1:])]
    return {"robots": n, "seconds": round(span, 1), "frames_per_s": round((len(log) - 1) / span, 2),
            "ticks_per_s": round((log[-1][1] - log[0][1]) / span, 2),
            "distinct_ticks_shown": len({t for _, t in log}),
            "ticks_not_shown": log[-1][1] - log[0][1] + 1 - len({t for _, t in log}),
            "ticks_spanned": log[-1][1] - log[0][1] + 1,
            "max_gap_ms": round(max(gaps)), "p95_gap_ms": round(sorted(gaps)[int(0.95 * (len(gaps) - 1))]),
            "lag_ms_median": round(statistics.median(lags)) if lags else None,
            "draw_ms_median": round(statistics.median(draws), 2) if draws else None,
            "draw_loop_ms": round(loop["all"], 2), "draw_loop_no_trails_ms": round(loop["noTrails"], 2),
            "parse_ms": round(loop["parse"], 2), "frame_kb": round(loop["bytes"] / 1024)}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--robots", default="9,256", help="comma-separated robot counts (default 9,256)")
    p.add_argument("--seconds", type=float, default=20.0, help="the measuring window a run (default 20)")
    p.add_argument("--domain", type=int, default=None, help="DDS domain (default: the bench/ test domain, 27)")
    p.add_argument("--build", default=os.environ.get("BUILD_DIR") or os.path.join(ROOT, "build"))
    a = p.parse_args()
    domain = a.domain if a.domain is not None else helpers.test_domain(27)
    print("robots  frames/s  ticks/s  not shown  max gap ms  p95 gap ms  lag ms (median)  draw ms (median)  window s"
          "  | draw() alone ms, without trails, JSON.parse ms, frame KB")
    for n in [int(x) for x in a.robots.split(",")]:
        r = measure(n, a.seconds, domain, a.build)
        not_shown = f"{r['ticks_not_shown']}/{r['ticks_spanned']}"
        print(f"{r['robots']:>6}  {r['frames_per_s']:>8}  {r['ticks_per_s']:>7}  {not_shown:>9}  "
              f"{r['max_gap_ms']:>10}  {r['p95_gap_ms']:>10}  {str(r['lag_ms_median']):>15}  "
              f"{str(r['draw_ms_median']):>16}  {r['seconds']:>8}"
              f"  | {r['draw_loop_ms']}, {r['draw_loop_no_trails_ms']}, {r['parse_ms']}, {r['frame_kb']}", flush=True)


if __name__ == "__main__":
    main()
