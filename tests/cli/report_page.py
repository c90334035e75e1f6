#!/usr/bin/env python3
"""chainmail report: the page of a run (with and without frames), a sweep and a stability folder,
opened in headless Chromium from file:// with the network off (--part page; skipped, status 77,
without Chromium), the page of a quick bench with its scenes' 3D views (--part bench, skipped
likewise), and the bad folders it refuses with exit 2 and nothing written (--part bad-input)."""
import argparse
import base64
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cdp_pipe  # noqa: E402

SKIP = 77
CURTAIN = ["--set", "weave.rows=6", "--set", "weave.cols=6", "--set", "duration=0.2",
           "--reference", "none", "--cache", "none", "--quiet"]


def chainmail(exe, *args, check=True):
    proc = subprocess.run([exe, *args], capture_output=True, text=True, timeout=600)
    if check and proc.returncode != 0:
        raise AssertionError(f"chainmail {' '.join(args)}: exit {proc.returncode}: {proc.stderr}")
    return proc


def make_run(exe, scene, out, backends="plausible,massspring", frames=True):
    args = ["run", scene, "--backends", backends, "--out", out, "--report"] + CURTAIN
    chainmail(exe, *(args + (["--frames"] if frames else [])))
    for name in ("index.html", "report/data.js", "report/report.js"):
        assert os.path.isfile(os.path.join(out, name)), f"run --report wrote no {name}"
    return json.load(open(os.path.join(out, "summary.json")))


def snapshot(folder):
    listing = {}
    for root, _, files in os.walk(folder):
        for name in files:
            path = os.path.join(root, name)
            listing[os.path.relpath(path, folder)] = (os.path.getsize(path), os.path.getmtime(path))
    return listing


def refused(exe, folder, why):
    before = snapshot(folder) if os.path.isdir(folder) else None
    proc = chainmail(exe, "report", folder, check=False)
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2, f"{why}: exit {proc.returncode} ({proc.stderr})"
    assert len(lines) == 1, f"{why}: not one line: {proc.stderr!r}"
    after = snapshot(folder) if os.path.isdir(folder) else None
    assert before == after, f"{why}: the folder changed"
    print(f"refused ({why}): {lines[0]}")


def bad_input(exe, scene, tmp):
    base = os.path.join(tmp, "good")
    make_run(exe, scene, base)
    # report twice: the page is rewritten, listed in the manifest, and run may replace the folder
    chainmail(exe, "report", base)
    manifest = json.load(open(os.path.join(base, ".chainmail-manifest.json")))
    assert "index.html" in manifest["files"] and "report/data.js" in manifest["files"]
    assert "report/frames/plausible/00000.js" in manifest["files"]
    chainmail(exe, *(["run", scene, "--backends", "plausible", "--out", base] + CURTAIN))
    assert not os.path.exists(os.path.join(base, "index.html")), "the old page outlived its run"
    make_run(exe, scene, base)

    def variant(name, change):
        folder = os.path.join(tmp, name)
        shutil.copytree(base, folder)
        for old in ("index.html", "report"):  # a page written later must not be there
            path = os.path.join(folder, old)
            shutil.rmtree(path) if os.path.isdir(path) else os.remove(path)
        change(folder)
        refused(exe, folder, name)

    def write(path, text):
        with open(path, "w") as f:
            f.write(text)

    foreign = os.path.join(tmp, "foreign")
    os.makedirs(foreign)
    shutil.copy(os.path.join(base, "summary.json"), foreign)
    refused(exe, foreign, "a folder chainmail did not write")
    refused(exe, os.path.join(tmp, "absent"), "no such folder")
    variant("no_summary", lambda f: os.remove(os.path.join(f, "summary.json")))
    variant("corrupt_summary", lambda f: write(os.path.join(f, "summary.json"), '{"scene": {'))
    variant("summary_not_an_object", lambda f: write(os.path.join(f, "summary.json"), "[1, 2]"))
    frames = lambda f: os.path.join(f, "frames", "massspring")  # noqa: E731
    variant("frame_missing", lambda f: os.remove(os.path.join(frames(f), "00002.csv")))
    variant("frame_extra", lambda f: shutil.copy(os.path.join(frames(f), "00000.csv"),
                                                 os.path.join(frames(f), "00099.csv")))
    variant("frames_of_no_backend",
            lambda f: shutil.copytree(frames(f), os.path.join(f, "frames", "ghost")))
    variant("frame_short", lambda f: write(os.path.join(frames(f), "00001.csv"),
                                           "ring,i,j,x,y,z,qw,qx,qy,qz\n0,0,0,0,0,0,1,0,0,0\n"))
    sweep = os.path.join(tmp, "sweep")
    make_sweep(exe, scene, sweep)
    os.remove(os.path.join(sweep, "sweep.csv"))
    refused(exe, sweep, "a sweep folder without sweep.csv")
    print("bad input: every case refused with exit 2, one line, nothing written")


def make_sweep(exe, scene, out):
    chainmail(exe, "sweep", scene, "--backends", "plausible,massspring", "--out", out,
              "--vary", "backends.{backend}.dt=0.004,0.002", "--set", "weave.rows=6",
              "--set", "weave.cols=6", "--set", "duration=0.2", "--cache", "none")
    chainmail(exe, "report", out)


# the screenshot's pixels, decoded by the page's own browser: per rectangle, a coarse mask of the
# cells that are not the panel's background (so panels compare by what they draw, not by colour)
MASKS = """(async (png, rects) => {
  const img = new Image(); img.src = 'data:image/png;base64,' + png; await img.decode();
  const c = document.createElement('canvas'); c.width = img.width; c.height = img.height;
  const g = c.getContext('2d'); g.drawImage(img, 0, 0);
  return rects.map((r) => {
    const d = g.getImageData(r.x, r.y, r.w, r.h).data; const N = 48; const cells = new Array(N * N).fill(0);
    let drawn = 0;
    for (let y = 0; y < r.h; ++y) for (let x = 0; x < r.w; ++x) {
      const k = 4 * (y * r.w + x);
      if (Math.abs(d[k] - 238) + Math.abs(d[k + 1] - 241) + Math.abs(d[k + 2] - 245) > 40) {
        ++drawn; cells[Math.floor(y * N / r.h) * N + Math.floor(x * N / r.w)] = 1;
      }
    }
    return { drawn: drawn / (r.w * r.h), mask: cells.join('') };
  });
})"""
RECTS = """Array.from(document.querySelectorAll(SELECTOR)).map((v) => {
  const r = v.getBoundingClientRect();
  return { x: Math.round(r.left) + 2, y: Math.round(r.top) + 2, w: Math.round(r.width) - 4,
           h: Math.round(r.height) - 4 }; })"""


def masks(browser, selector=".viewport"):
    rects = browser.eval(RECTS.replace("SELECTOR", json.dumps(selector)))
    png = base64.b64encode(browser.screenshot()).decode()
    return browser.eval(f"{MASKS}({json.dumps(png)}, {json.dumps(rects)})", timeout=120)


def differ(a, b):
    return sum(x != y for x, y in zip(a["mask"], b["mask"])) / len(a["mask"])


def cells(browser, selector):
    return browser.eval(f"Array.from(document.querySelectorAll({json.dumps(selector)}))"
                        ".map((td) => td.dataset.v)")


def check_clean(browser, what):
    assert not browser.errors, f"{what}: console errors: {browser.errors}"
    remote = [u for u in browser.requests if not u.startswith(("file:", "data:", "about:"))]
    assert not remote, f"{what}: requests off the disk: {remote}"


def check_tables(browser, summary, anchor):
    for b, entry in summary["backends"].items():
        row = f"#metrics-{anchor} tr:has(td[data-v='{b}'])"
        header = browser.eval(f"Array.from(document.querySelectorAll('#metrics-{anchor} th'))"
                              ".map((th) => th.dataset.col)")
        values = cells(browser, row + " td")
        for name, value in entry["final"].items():
            shown = values[header.index(name)]
            assert value is None and shown == "" or float(shown) == value, (b, name, shown, value)
        timing = cells(browser, f"#timing-{anchor} tr:has(td[data-v='{b}']) td")
        assert float(timing[4]) == entry["ms_per_step"] and timing[9] == entry["hash"], timing
    print(f"tables of {anchor}: every number equals summary.json's")


def run_page(browser, folder, summary):
    seconds = browser.open("file://" + os.path.abspath(folder) + "/index.html")
    browser.wait_for("document.body.dataset.ready === 'true' && "
                     "document.querySelector('.stage') && document.querySelector('.stage').dataset.frame === '0'")
    print(f"run page: loaded in {seconds:.2f} s")
    check_tables(browser, summary, "scene")
    assert browser.eval("!!document.querySelector('#time-scene circle')"), "no metric-over-time plot"
    loaded = [u for u in browser.requests if "/report/frames/" in u]
    assert loaded and all(n.endswith("/00000.js") for n in loaded), f"frames not lazy: {loaded}"
    browser.eval("document.getElementById('view3d').scrollIntoView()")
    first = masks(browser)
    assert len(first) == len(summary["backends"]), "not one panel per backend"
    for panel in first:
        assert panel["drawn"] > 0.01, f"a blank 3D panel: {panel['drawn']}"
    assert differ(first[0], first[1]) < 0.05, "the same start drawn differently"
    last = summary["backends"]["plausible"]["samples"] - 1
    browser.eval(f"(() => {{ const s = document.getElementById('frame-slider'); s.value = {last};"
                 " s.dispatchEvent(new Event('input')); })()")
    browser.wait_for(f"document.querySelector('.stage').dataset.frame === '{last}'")
    end = masks(browser)
    assert all(p["drawn"] > 0.01 for p in end), "a blank panel at the end"
    # a backend may hardly move in 0.2 s; the slider must change what some panel draws
    moved = [differ(a, b) for a, b in zip(first, end)]
    assert max(moved) > 0.02, f"the slider did not change the drawn frame: {moved}"
    assert browser.eval(f"Array.from(document.querySelectorAll('.panel')).every((p) => "
                        f"p.dataset.frame === '{last}')"), "a panel did not move to the new frame"
    assert differ(end[0], end[1]) > 0.02, "the backends end alike in the panels"
    rows = list(csv.DictReader(open(os.path.join(folder, "metrics.csv"))))
    for b in summary["backends"]:
        shown = browser.eval(f"document.querySelector(\".panel[data-backend='{b}'] "
                             "td[data-metric='max_stretch']\").dataset.v")
        assert shown == [r for r in rows if r["backend"] == b][last]["max_stretch"], (b, shown)
    check_clean(browser, "run page")
    print(f"3D: {len(first)} panels drawn, moved by the slider {[round(m, 3) for m in moved]}, ({', '.join(format(p['drawn'], '.0%') for p in end)}"
          f" of each covered), frame 0 alike, frame {last} differs between backends")


def other_pages(browser, tmp, no_frames_summary):
    browser.open("file://" + os.path.join(tmp, "plain", "index.html"))
    browser.wait_for("document.body.dataset.ready === 'true'")
    assert browser.eval("!!document.getElementById('no-frames') && !document.querySelector('canvas')")
    check_tables(browser, no_frames_summary, "scene")
    check_clean(browser, "page without frames")
    browser.open("file://" + os.path.join(tmp, "sweep", "index.html"))
    browser.wait_for("document.body.dataset.ready === 'true'")
    points = list(csv.DictReader(open(os.path.join(tmp, "sweep", "sweep.csv"))))
    # a log-log plot: a point without an error, or of zero error, has no place on it
    def plotted(p):
        try:
            return float(p["wall_per_sim_s"]) > 0 and float(p["error_m"]) > 0
        except ValueError:
            return False
    drawn = browser.eval("document.querySelectorAll('#sweep-plot-sweep circle').length")
    # (none without a reference run: a build without Bullet has no drape error to plot)
    assert drawn == sum(1 for p in points if plotted(p)), drawn
    front = browser.eval("Array.from(document.querySelectorAll('#pareto-sweep tbody tr'))"
                         ".map((tr) => Array.from(tr.cells).map((td) => td.dataset.v))")
    assert bool(front) == (drawn > 0), front  # a front wherever there are points to rank
    assert all(any(p["backend"] == b and float(p["wall_per_sim_s"]) == float(t) and
                   float(p["error_m"]) == float(e) for p in points) for b, t, e in front)
    check_clean(browser, "sweep page")
    browser.open("file://" + os.path.join(tmp, "stability", "index.html"))
    browser.wait_for("document.body.dataset.ready === 'true'")
    rows = list(csv.DictReader(open(os.path.join(tmp, "stability", "stability.csv"))))
    verdicts = cells(browser, "#stability-stability td[data-col='verdict']")
    assert verdicts == [r["verdict"] for r in rows], verdicts
    check_clean(browser, "stability page")
    print(f"pages without frames, of a sweep ({len(points)} points, {len(front)} on the front) and "
          f"of stability ({len(rows)} verdicts): drawn, numbers as in their files, no errors")


def page(exe, scene, tmp):
    binary = cdp_pipe.find_chromium()
    if not binary:
        print("SKIP: no chromium (apt-get install chromium) to open the report page")
        return SKIP
    summary = make_run(exe, scene, os.path.join(tmp, "run"))
    plain = make_run(exe, scene, os.path.join(tmp, "plain"), frames=False)
    make_sweep(exe, scene, os.path.join(tmp, "sweep"))
    chainmail(exe, "stability", "--quick", "--backends", "plausible,massspring", "--out",
              os.path.join(tmp, "stability"))
    chainmail(exe, "report", os.path.join(tmp, "stability"))
    browser = cdp_pipe.Browser(binary)
    try:
        run_page(browser, os.path.join(tmp, "run"), summary)
        other_pages(browser, tmp, plain)
    finally:
        browser.close()
    return 0


# the quick bench's sheets are 4 x 4 rings, three backends: every panel of a view on one screen
BENCH_BACKENDS = "plausible,massspring,torus_xpbd"


def bench_view(browser, folder, scene, view):
    """one scene's 3D view of the bench page: started when scrolled to, a drawn panel per backend
    that kept frames, the slider moving every panel to another frame"""
    summary = json.load(open(os.path.join(folder, scene, "summary.json")))
    stage = f"document.querySelector('#{view} .stage')"
    browser.eval(f"document.getElementById('{view}').scrollIntoView()")
    browser.wait_for(f"{stage} && {stage}.dataset.frame === '0'")
    first = masks(browser, f"#{view} .viewport")
    assert len(first) == len(summary["backends"]), f"{scene}: not one panel per backend"
    assert all(p["drawn"] > 0.01 for p in first), f"{scene}: a blank 3D panel: {first}"
    last = summary["backends"]["plausible"]["samples"] - 1
    assert last > 0, f"{scene}: one sample, no slider to move"
    browser.eval(f"(() => {{ const s = document.getElementById('frame-slider-{view[7:]}');"
                 f" s.value = {last}; s.dispatchEvent(new Event('input')); }})()")
    browser.wait_for(f"{stage}.dataset.frame === '{last}'")
    assert browser.eval(f"Array.from(document.querySelectorAll('#{view} .panel')).every((p) => "
                        f"p.dataset.frame === '{last}')"), f"{scene}: a panel stayed behind"
    end = masks(browser, f"#{view} .viewport")
    assert all(p["drawn"] > 0.01 for p in end), f"{scene}: a blank panel at the end"
    moved = [differ(a, b) for a, b in zip(first, end)]
    assert max(moved) > 0.02, f"{scene}: the slider did not change the drawn frame: {moved}"
    rows = list(csv.DictReader(open(os.path.join(folder, scene, "metrics.csv"))))
    for b in summary["backends"]:
        shown = browser.eval(f"document.querySelector(\"#{view} .panel[data-backend='{b}'] "
                             "td[data-metric='max_stretch']\").dataset.v")
        assert shown == [r for r in rows if r["backend"] == b][last]["max_stretch"], (b, shown)
    print(f"bench 3D view of {scene}: {len(first)} panels drawn "
          f"({', '.join(format(p['drawn'], '.0%') for p in first)} covered), frame {last} "
          f"changed {[round(m, 3) for m in moved]} of each panel's cells")


def bench(exe, tmp):
    binary = cdp_pipe.find_chromium()
    if not binary:
        print("SKIP: no chromium (apt-get install chromium) to open the report page")
        return SKIP
    folder = os.path.join(tmp, "bench")
    chainmail(exe, "bench", "--quick", "--no-scaling", "--no-render", "--backends",
              BENCH_BACKENDS, "--out", folder)
    kept = sorted(s for s in os.listdir(folder) if os.path.isdir(os.path.join(folder, s, "frames"))
                  and os.path.isfile(os.path.join(folder, s, "summary.json")))
    assert kept, "the bench kept no frames"
    for scene in kept:
        for b in BENCH_BACKENDS.split(","):
            assert os.path.isfile(os.path.join(folder, "report", "frames", scene, b, "00000.js"))
    browser = cdp_pipe.Browser(binary)
    try:
        seconds = browser.open("file://" + folder + "/index.html")
        browser.wait_for("document.body.dataset.ready === 'true'")
        lazy = [u for u in browser.requests if "/report/frames/" in u or "three.min.js" in u]
        assert not lazy, f"the bench page loaded 3D files before they were scrolled to: {lazy}"
        views = browser.eval("Object.fromEntries(Array.from(document.querySelectorAll("
                             "'div.view3d[id^=view3d-]')).map((v) => [v.closest('section')"
                             ".querySelector('h2').textContent.split(' ')[1], v.id]))")
        assert sorted(views) == kept, f"3D views {views}, frames kept by {kept}"
        for scene in kept:
            bench_view(browser, folder, scene, views[scene])
        check_clean(browser, "bench page")
    finally:
        browser.close()
    print(f"bench page: loaded in {seconds:.2f} s, no 3D file before its view was scrolled to")
    return 0


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--chainmail", required=True)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--part", choices=("page", "bench", "bad-input"), required=True)
    args = parser.parse_args()
    tmp = tempfile.mkdtemp(prefix="cm-report-")
    try:
        if args.part == "bad-input":
            bad_input(args.chainmail, args.scene, tmp)
            return 0
        if args.part == "bench":
            return bench(args.chainmail, tmp)
        return page(args.chainmail, args.scene, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
