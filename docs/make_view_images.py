"""The screenshots of the 3-D view in docs/view.md: the falling cat and a twisting dive (the 3-D
human, Yeadon's solids), each page loaded in a headless Chromium (tests/browser.py), the slider
moved to a time of the motion, and the page saved as a PNG.

    python docs/make_view_images.py docs/images     # about 30 s; needs chromium and acroplan[view,human]
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import browser  # noqa: E402  (tests/browser.py)

import acroplan  # noqa: E402
from acroplan.families.human.twist import asymmetric_arm_twist  # noqa: E402

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


def main(folder: str) -> None:
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        cat = acroplan.examples.load("falling-cat").solve()
        shoot(cat.view(Path(tmp) / "cat.html", frames=60), folder / "view-falling-cat.png", 0.45)
        dive = asymmetric_arm_twist(acroplan.simulate)
        s, _, w = dive.final
        title = (f"a twisting dive: Yeadon's male1 lowers the right arm, {abs(s):.2f} somersaults backwards, "
                 f"{abs(w):.2f} twists")
        shoot(dive.result.view(Path(tmp) / "twist.html", frames=60, title=title), folder / "view-twisting-dive.png",
              0.6)
    print(f"wrote {folder}/view-falling-cat.png and {folder}/view-twisting-dive.png")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "docs" / "images"))
