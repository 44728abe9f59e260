"""How much code the planar and spatial families share verbatim (issue #21's measure).

    python benchmarks/family_duplicates.py [REV]      # REV: a git revision; default the working tree

Counts the lines of ``families/planar/*.py`` that stand again, in the same order, in runs of six or
more in one of ``families/spatial/*.py`` (lines stripped; blank lines, comments, imports and lone
brackets left out; difflib's matching blocks per pair of files).
"""

from __future__ import annotations

import difflib
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
RUN = 6


def _files(family: str, rev: str | None) -> dict[str, str]:
    folder = f"src/acroplan/families/{family}"
    if rev is None:
        return {str(p): p.read_text(encoding="utf-8") for p in sorted((ROOT / folder).glob("*.py"))}
    names = subprocess.run(["git", "-C", str(ROOT), "ls-tree", "-r", "--name-only", rev, folder],
                           capture_output=True, text=True, check=True).stdout.split()
    return {n: subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:{n}"], capture_output=True, text=True,
                              check=True).stdout for n in names if n.endswith(".py")}


def _lines(text: str) -> list[str]:
    out = []
    for line in text.splitlines():
        s = line.strip()
        if not s or s.startswith("#") or s.startswith(("import ", "from ")) or s in "()[]{}" or s in ("):", "],", "),"):
            continue
        out.append(s)
    return out


def shared_lines(rev: str | None = None) -> int:
    planar = {k: _lines(v) for k, v in _files("planar", rev).items()}
    spatial = {k: _lines(v) for k, v in _files("spatial", rev).items()}
    total = 0
    for a in planar.values():
        for b in spatial.values():
            blocks = difflib.SequenceMatcher(None, a, b, autojunk=False).get_matching_blocks()
            total += sum(m.size for m in blocks if m.size >= RUN)
    return total


if __name__ == "__main__":
    rev = sys.argv[1] if len(sys.argv) > 1 else None
    print(f"{rev or 'working tree'}: {shared_lines(rev)} lines of families/planar stand again in families/spatial "
          f"(runs of {RUN} or more)")
