"""The report a new user builds: from the runtime dependencies only, opened in a real browser.

A fresh virtual environment gets the project without its test extra (README's first command),
builds the report of the draft sweep (tests/conftest.py) with it, and Debian's chromium, headless,
opens the report: every figure must decode to an image of non-zero size in the report's own
image view, and every table page must be shown in its HTML view with rows. `.ci/run` installs
chromium where it is missing; without it this test skips and says so.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DRAFT = ROOT / "tests" / "data" / "config_draft.yaml"
CHROMIUM = Path("/usr/bin/chromium")

pytestmark = pytest.mark.slow

#: Runs inside the report page once the app has rendered: drives the report's own views (the
#: same App.setView call its "eye" buttons make) for every result and records what rendered.
CHECK_JS = r"""
<script>
(async () => {
  const wait = ms => new Promise(r => setTimeout(r, ms));
  const out = {categories: [], images: [], pages: [], errors: []};
  try {
    await wait(1000);
    out.categories = Object.keys(categories);
    out.menu = document.body.innerText.slice(0, 4000);
    for (const [path, entry] of Object.entries(results)) {
      if (entry.mime_type === "image/png") {
        app.setView({content: "img", contentPath: entry.data_uri, resultPath: path});
        let img = null;
        for (let i = 0; i < 50; i++) {
          await wait(100);
          img = [...document.querySelectorAll("img")].find(x => x.getAttribute("src") === entry.data_uri);
          if (img && img.complete && img.naturalWidth > 0) break;
        }
        out.images.push({path, width: img ? img.naturalWidth : 0, height: img ? img.naturalHeight : 0});
      } else if (entry.mime_type === "text/html") {
        app.setView({content: "html", contentPath: entry.data_uri, resultPath: path});
        await wait(300);
        const frame = [...document.querySelectorAll("iframe")].find(x => x.getAttribute("src") === entry.data_uri);
        const text = await (await fetch(entry.data_uri)).text();
        const doc = new DOMParser().parseFromString(text, "text/html");
        out.pages.push({path, shown: !!frame, tables: doc.querySelectorAll("table").length,
                        rows: doc.querySelectorAll("tr").length});
      }
    }
  } catch (e) { out.errors.push(String(e)); }
  const pre = document.createElement("pre");
  pre.id = "render-check";
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
})();
</script>
"""


def chromium_dom(html: Path, budget_ms: int = 120_000) -> str:
    """The DOM of ``html`` after ``budget_ms`` of virtual time in headless chromium (as root:
    no sandbox, a fresh profile, no network services)."""
    profile = tempfile.mkdtemp(prefix="chromium-profile-")
    try:
        proc = subprocess.run(
            [str(CHROMIUM), "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
             "--no-first-run", "--disable-background-networking", "--disable-component-update",
             "--disable-sync", f"--user-data-dir={profile}", f"--virtual-time-budget={budget_ms}",
             "--dump-dom", html.as_uri()],
            capture_output=True, text=True, timeout=600)
    finally:
        shutil.rmtree(profile, ignore_errors=True)
    if proc.returncode != 0:
        raise AssertionError(f"chromium failed ({proc.returncode}): {proc.stderr[-2000:]}")
    return proc.stdout


@pytest.fixture(scope="module")
def runtime_python(tmp_path_factory):
    """A fresh venv with the project and its runtime dependencies only (no test extra)."""
    d = tmp_path_factory.mktemp("runtime-venv")
    venv.EnvBuilder(with_pip=True, clear=True).create(d)
    py = d / "bin" / "python"
    proc = subprocess.run([str(py), "-m", "pip", "install", "-q", "-e", str(ROOT)],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-3000:]
    # the point of the venv: nothing from the test extra (pytest pulls pygments in)
    probe = subprocess.run([str(py), "-c", "import importlib.util as u; "
                            "print(u.find_spec('pytest') is None, u.find_spec('hypothesis') is None)"],
                           capture_output=True, text=True)
    assert probe.stdout.split() == ["True", "True"], probe.stdout + probe.stderr
    return py


def test_report_from_runtime_dependencies_renders_in_a_browser(draft_run, runtime_python, tmp_path):
    if not CHROMIUM.exists():
        pytest.skip("/usr/bin/chromium is missing and could not be installed (.ci/run installs "
                    "it with apt-get where apt is available)")
    wd = tmp_path / "sweep"
    shutil.copytree(draft_run, wd, symlinks=True)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["PATH"] = f"{runtime_python.parent}{os.pathsep}{env.get('PATH', '')}"
    base = [str(runtime_python), "-m", "snakemake", "--snakefile", str(ROOT / "Snakefile"),
            "--directory", str(wd), "--configfile", str(DRAFT), "--cores", "2"]
    for extra in ([], ["--report", "report.html"]):  # the README's commands, in that venv
        proc = subprocess.run(base + extra, capture_output=True, text=True, cwd=wd, env=env)
        assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-5000:]
    report = wd / "report.html"
    assert report.stat().st_size > 100_000

    page = tmp_path / "report_checked.html"
    text = report.read_text(encoding="utf-8")
    cut = text.rindex("</body>")  # the last one: embedded pages hold their own
    page.write_text(text[:cut] + CHECK_JS + text[cut:], encoding="utf-8")
    dom = chromium_dom(page)
    m = re.search(r'<pre id="render-check">(.*?)</pre>', dom, re.S)
    assert m, dom[-3000:]
    import html

    out = json.loads(html.unescape(m.group(1)))
    assert not out["errors"], out["errors"]
    assert {"Figures", "Tables", "Diagnosability", "Study vs this model"} <= set(out["categories"])

    figures = sorted(p.name for p in (wd / "results" / "figures").glob("*.png"))
    maps = sorted(p.name for p in (wd / "results" / "figures_diagnosability").glob("*.png"))
    shown = {Path(i["path"]).name: i for i in out["images"]}
    for name in figures + maps:
        assert name in shown, f"{name} is not in the report"
        assert shown[name]["width"] > 300 and shown[name]["height"] > 200, shown[name]
    fig10 = shown["fig10_band_limits.png"]
    assert fig10["height"] <= 1000 and fig10["width"] <= 2000, fig10  # was 1146 x 4605 px
    pages = {Path(p["path"]).name: p for p in out["pages"]}
    for name in ("cases.html", "bands.html", "harmonics.html", "pivots.html", "paper.html",
                 "diagnosability.html", "false_alarms.html"):
        assert name in pages, f"{name} is not viewable in the report ({sorted(pages)})"
        assert pages[name]["shown"] and pages[name]["tables"] >= 1 and pages[name]["rows"] > 2, pages[name]
