#!/usr/bin/env python3
"""The guide in a real browser: serves the built rustdoc pages on 127.0.0.1,
walks every link of the guide's pages, opens the guide's first page and one
chapter in headless Chromium, and fails on a broken internal link or a line
the pages write to the browser's console.

Usage: scripts/guide-browser.py [DOC_DIR]   (default target/doc, after
`cargo doc`). Screenshots go to target/guide-*.png. Needs `chromium`.
"""
import html.parser
import http.server
import pathlib
import re
import shutil
import subprocess
import sys
import threading
import urllib.parse

ROOT = pathlib.Path(__file__).resolve().parent.parent
DOC = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "target" / "doc"
GUIDE = DOC / "geopid" / "guide"
PAGES = ["geopid/guide/index.html", "geopid/guide/first_flight/index.html"]
# Headless Chromium logs every console message at one level, so errors are
# told from notes by text. These are Chromium's notes on rustdoc's own font
# preloads (a hint the page gives, not a failure): the fonts load either way.
BENIGN = [
    re.compile(r'"A preload for .\S+\.woff2. is found, but is not used because the request credentials mode does not match'),
    re.compile(r'"The resource \S+\.woff2 was preloaded using link preload but not used within a few seconds'),
]
FAILED_REQUESTS = []


class Links(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.hrefs, self.ids, self.refresh = [], set(), None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        # rustdoc's redirect pages (an item of a private module, re-exported)
        # forward the fragment to the item's page.
        if tag == "meta" and a.get("http-equiv") == "refresh" and "URL=" in a.get("content", ""):
            self.refresh = a["content"].split("URL=", 1)[1]
        for k in ("href", "src"):
            if a.get(k) and tag in ("a", "img", "script", "link"):
                self.hrefs.append(a[k])


def parse(path):
    p = Links()
    p.feed(path.read_text(errors="replace"))
    return p


def link_walk():
    """Broken links of the guide's pages: files that do not exist, anchors
    that no element of the target page carries."""
    broken, checked, cache = [], 0, {}
    pages = sorted(GUIDE.rglob("*.html"))
    if not pages:
        sys.exit(f"guide-browser: no pages under {GUIDE}: run cargo doc first")
    for page in pages:
        for href in parse(page).hrefs:
            url = urllib.parse.urlparse(href)
            if url.scheme or href.startswith("//") or href.startswith("javascript:"):
                continue
            target = page if not url.path else (page.parent / urllib.parse.unquote(url.path)).resolve()
            if target.is_dir():
                target = target / "index.html"
            checked += 1
            where = f"{page.relative_to(DOC)}: {href}"
            if not target.exists():
                broken.append(f"{where} (no file {target})")
                continue
            if url.fragment and target.suffix == ".html":
                for _ in range(4):
                    if target not in cache:
                        cache[target] = parse(target)
                    if cache[target].refresh is None:
                        break
                    target = (target.parent / cache[target].refresh).resolve()
                    if not target.exists():
                        break
                if not target.exists():
                    broken.append(f"{where} (redirect to a missing {target})")
                    continue
                ids = cache.setdefault(target, parse(target)).ids
                # rustdoc's line anchors in source pages are made by script.
                if url.fragment not in ids and not re.fullmatch(r"\d+(-\d+)?", url.fragment):
                    broken.append(f"{where} (no id `{url.fragment}`)")
    return pages, checked, broken


def serve():
    handler = lambda *a, **k: http.server.SimpleHTTPRequestHandler(*a, directory=str(DOC), **k)

    class Quiet(http.server.ThreadingHTTPServer):
        pass

    http.server.SimpleHTTPRequestHandler.log_message = lambda *a: None

    def log_request(self, code="-", size="-"):
        if str(code).isdigit() and int(code) >= 400:
            FAILED_REQUESTS.append(f"{self.path}: HTTP {code}")

    http.server.SimpleHTTPRequestHandler.log_request = log_request
    srv = Quiet(("127.0.0.1", 0), handler)
    threading.Thread(target=srv.serve_forever, daemon=True).start()
    return srv


def browse(port):
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if not exe:
        sys.exit("guide-browser: chromium is not installed")
    problems = []
    for n, page in enumerate(PAGES):
        shot = ROOT / "target" / f"guide-{n}.png"
        url = f"http://127.0.0.1:{port}/{page}"
        p = subprocess.run(
            [exe, "--headless", "--no-sandbox", "--disable-gpu", "--enable-logging=stderr",
             "--v=0", "--hide-scrollbars", "--window-size=1280,1600",
             "--virtual-time-budget=5000", f"--screenshot={shot}", url],
            capture_output=True, text=True, timeout=120,
        )
        console = [l for l in p.stderr.splitlines() if ":CONSOLE" in l]
        errors = [l for l in console if not any(b.search(l) for b in BENIGN)]
        print(
            f"  {url}: exit {p.returncode}, {len(console)} console line(s), "
            f"{len(console) - len(errors)} of them rustdoc's font-preload notes; "
            f"screenshot {shot.relative_to(ROOT)}"
        )
        problems += [f"{page}: console: {l}" for l in errors]
        if p.returncode != 0 or not shot.exists():
            problems.append(f"{page}: chromium exited {p.returncode}: {p.stderr.strip()[-400:]}")
    return problems


def main():
    pages, checked, broken = link_walk()
    for b in broken:
        print(f"  broken link {b}")
    srv = serve()
    try:
        problems = browse(srv.server_address[1])
    finally:
        srv.shutdown()
    problems += [f"request failed: {r}" for r in FAILED_REQUESTS]
    for p in problems:
        print(f"  {p}")
    print(
        f"guide in the browser: {len(pages)} pages, {checked} links walked, {len(broken)} broken; "
        f"{len(PAGES)} pages opened, {len(problems)} console or browser problem(s)"
    )
    sys.exit(1 if broken or problems else 0)


if __name__ == "__main__":
    main()
