"""Pages as a reader sees them: Debian's Chromium, headless, opens a page the
project wrote and says what it rendered.

The page is copied beside itself with a short script that, once the page
has loaded, writes what the browser made of it into the page (each image
decoded or not and its size, each table's rows and columns, the headings,
the page's width against the window's, anything the page would fetch from
elsewhere), and ``chromium --dump-dom`` prints it. Chromium is installed
when missing (Debian's ``chromium``, as root, as ``tests/cluster/start_slurm.sh``
installs Slurm); a test that needs it is skipped, saying why, only where it
cannot be installed (not root, no apt-get, no package source).
"""

from __future__ import annotations

import html
import json
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

#: The window the pages are opened in: a laptop's.
WINDOW = (1280, 900)
#: Chromium's flags for a closed network and no profile of its own (no background connections, no sandbox as root).
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync")
PROBE = """<script>
window.addEventListener("load", () => {
  const outside = [...document.querySelectorAll("[src], link[href]")]
    .map(e => e.getAttribute("src") || e.getAttribute("href"))
    .filter(u => !u.startsWith("data:") && !u.startsWith("#"));
  const seen = {
    images: [...document.images].map(i => ({alt: i.alt, decoded: i.complete && i.naturalWidth > 0,
      natural: [i.naturalWidth, i.naturalHeight], shown: [i.clientWidth, i.clientHeight]})),
    tables: [...document.querySelectorAll("table")].map(t => ({rows: t.rows.length,
      columns: t.rows.length ? t.rows[0].cells.length : 0, width: t.scrollWidth,
      header: t.rows.length ? [...t.rows[0].cells].map(c => c.textContent.trim()) : []})),
    headings: [...document.querySelectorAll("h1, h2")].map(h => h.textContent.trim()),
    width: document.documentElement.scrollWidth, window: window.innerWidth, outside: outside};
  const out = document.createElement("pre");
  out.id = "browser-seen";
  out.textContent = JSON.stringify(seen);
  document.body.appendChild(out);
});
</script>"""


def chromium() -> str:
    """The path of Debian's Chromium, installed first when missing (root
    only); the calling test is skipped, saying why, where it cannot be."""
    found = shutil.which("chromium")
    if found:
        return found
    if os.geteuid() != 0:
        pytest.skip("Chromium cannot be installed here: not root")
    if not shutil.which("apt-get"):
        pytest.skip("Chromium cannot be installed here: no apt-get")
    env = {**os.environ, "DEBIAN_FRONTEND": "noninteractive"}
    for step in (["apt-get", "install", "-y", "-q", "chromium"], ["apt-get", "update", "-q"],
                 ["apt-get", "install", "-y", "-q", "chromium"]):
        run = subprocess.run(step, capture_output=True, text=True, env=env, timeout=900)
        if run.returncode == 0 and shutil.which("chromium"):
            return shutil.which("chromium")
    pytest.skip(f"Chromium cannot be installed here: apt-get install chromium failed ({run.stderr.strip()[-200:]})")


def rendered(page: Path) -> dict:
    """What Chromium rendered of ``page`` in a :data:`WINDOW` window, once
    loaded: ``images`` (``alt``, ``decoded``, ``natural`` and ``shown`` sizes
    in pixels), ``tables`` (``rows``, ``columns`` of the first row,
    ``width``, ``header``), ``headings`` (h1 and h2), ``width`` (the page's)
    and ``window`` (the window's), ``outside`` (what the page would fetch
    from elsewhere: anything not inline)."""
    page = Path(page)
    text = page.read_text(encoding="utf-8")
    assert text.count("</body>") == 1, f"{page} has no single </body>"
    probe = page.with_name(f".browser-{page.name}")  # beside the page: its relative links resolve as the page's
    probe.write_text(text.replace("</body>", PROBE + "</body>"), encoding="utf-8")
    try:
        with tempfile.TemporaryDirectory() as profile:
            run = subprocess.run([chromium(), *FLAGS, f"--user-data-dir={profile}",
                                  f"--window-size={WINDOW[0]},{WINDOW[1]}", "--virtual-time-budget=10000",
                                  "--dump-dom", probe.resolve().as_uri()], capture_output=True, text=True, timeout=120)
    finally:
        probe.unlink()
    seen = re.search(r'<pre id="browser-seen">(.*?)</pre>', run.stdout, re.S)
    assert seen, f"Chromium did not render {page} (exit {run.returncode}): {run.stderr.strip()[-500:]}"
    return json.loads(html.unescape(seen.group(1)))


def assert_readable(seen: dict, images: int) -> None:
    """The page as a reader needs it: ``images`` images, each decoded and
    shown at a size (a broken or empty picture shows neither), nothing
    fetched from elsewhere (the page is self-contained), and no sideways
    scrolling in a laptop's window."""
    assert len(seen["images"]) == images, [i["alt"] for i in seen["images"]]
    for image in seen["images"]:
        assert image["decoded"] and min(image["natural"]) > 0 and min(image["shown"]) > 0, image
        assert image["shown"][0] <= seen["window"], image
    assert not seen["outside"], seen["outside"]
    assert seen["width"] <= seen["window"], f"the page is {seen['width']} px wide in a {seen['window']} px window"
