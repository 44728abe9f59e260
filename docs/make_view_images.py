"""The screenshots of the 3-D view in docs/view.md: the falling cat (planned) and the twisting dive
(the 3-D human as Yeadon's solids: docs/view.md's twisting-dive.toml, simulated and viewed by the
command line), each page loaded in a headless Chromium (tests/browser.py), the slider moved to a
time of the motion, and the page saved as a PNG.

    python docs/make_view_images.py docs/images     # about a minute; needs chromium, acroplan[view,human,bodies]
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import browser  # noqa: E402  (tests/browser.py)

import acroplan  # noqa: E402
from acroplan.io.cli import main as cli  # noqa: E402
from acroplan.io.cli.view import write_view  # noqa: E402

READY = "document.querySelector('.js-plotly-plot') && document.querySelector('.js-plotly-plot')._fullLayout"
REDRAWN = "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(() => setTimeout(r, 300))))"


def shoot(page: Path, out: Path, at: float) -> None:
    """Load ``page``, move the slider to the fraction ``at`` of the motion, save the screenshot."""
    with browser.Browser(width=1200, height=680) as b:
        b.open(browser.file_url(page))
        b.wait_js(READY)
        b.js(REDRAWN, await_promise=True)
        rail = b.js("(() => { const r = document.querySelector('.slider-rail-rect').getBoundingClientRect();"
                    " return [r.left, r.top, r.width, r.height]; })()")
        b.click(rail[0] + at * rail[2], rail[1] + rail[3] / 2)
        b.js(REDRAWN, await_promise=True)
        if b.errors:
            raise RuntimeError(f"{page.name}: console errors {b.errors}")
        tmp = out.with_name(f".{out.name}.tmp")
        b.screenshot().save(tmp, format="png", optimize=True)
        tmp.replace(out)


def problem_file(page: Path, name: str) -> str:
    """The block of ``page`` marked ``<!-- docs-test: file NAME -->`` (docs/view.md's problem file)."""
    lines = page.read_text(encoding="utf-8").splitlines()
    start = lines.index(f"<!-- docs-test: file {name} -->") + 2  # (after the mark and the fence)
    end = next(i for i in range(start, len(lines)) if lines[i].startswith("```"))
    return "\n".join(lines[start:end]) + "\n"


def main(folder: str) -> None:
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        cat = acroplan.examples.load("falling-cat").solve()
        shoot(cat.view(tmp / "cat.html", frames=60, title="the falling cat turns over at L = 0 (Kane and Scher)"),
              folder / "view-falling-cat.png", 0.45)
        (tmp / "twisting-dive.toml").write_text(problem_file(ROOT / "docs" / "view.md", "twisting-dive.toml"))
        try:  # (the command exits with its code, as on the command line)
            cli(["simulate", str(tmp / "twisting-dive.toml"), "--out", str(tmp / "twisting-dive"), "-q"],
                standalone_mode=False)
        except SystemExit as e:
            if e.code:
                raise
        shoot(write_view(tmp / "twisting-dive", frames=60), folder / "view-twisting-dive.png", 0.55)
    print(f"wrote {folder}/view-falling-cat.png and {folder}/view-twisting-dive.png")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "docs" / "images"))
