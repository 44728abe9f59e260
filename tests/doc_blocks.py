"""Run the code of a Markdown page as a reader would: every Python block and every shell command,
in order, in one folder, comparing what the page quotes as output.

What runs
---------
* A fenced block whose info string starts with ``python``: executed; all Python blocks of a page
  share one namespace, in order, like the cells of a notebook. A block written as a doctest
  (``>>>`` prompts) is run as one: each quoted output is compared.
* Shell commands: in fenced blocks marked ``sh``, ``bash``, ``shell`` or ``console``, and in
  indented (four-space) code blocks, every line that starts with ``acroplan`` or ``python`` (after
  an optional ``$`` prompt). Lines ending in ``\\`` continue. In a chained line (``a && b``) the
  parts that set up a new environment (``python3 -m venv``, ``. .venv/bin/activate``, ``pip
  install``) are the reader's installation, which the test suite's own environment stands for, and
  the rest runs. In a ``console`` block, the lines after a ``$`` command up to the next one are its
  quoted output, compared.
* Other fenced blocks (``toml``, ``text``, ...) are shown, not run, unless a mark below says so.
* How a command runs: a plain ``acroplan ARGS`` (no shell syntax: pipes, redirections, variables,
  globs, chains) runs in the test's own process through the console script's entry point
  (``acroplan.io.cli.app.run``, with ``sys.argv`` set, stdout and stderr captured apart, exit code
  from its ``SystemExit``), which is what the ``acroplan`` script calls; the page's commands then
  share one process, as its Python blocks do, and the imports and compiled integrators are paid
  once a page, not once a command. Every other command runs in ``bash``. That the installed script
  itself starts and exits as it should is tests/test_cli_startup.py's business.

Marks (HTML comments, invisible on the rendered page), each on its own line before the block
it is about:

``<!-- docs-test: skip REASON -->``
    The next block is not run: a sketch with placeholders, or a command that must not run inside
    the tests (the test command itself). The reason is required and shown in the test's report.
``<!-- docs-test: file NAME -->``
    The next block is written to the file NAME in the page's folder (a problem file that later
    commands read).
``<!-- docs-test: output -->``
    The next block is the output of the block before it (the last command or Python block),
    compared.
``<!-- docs-test: exit N -->``
    The commands of the next block exit with code N (default 0).
``<!-- docs-test: rtol=X -->``
    Numbers quoted in the next block's output may differ by X relative (default: a quoted number
    matches when it agrees to the digits it shows, half a unit of its last digit).
``<!-- docs-test: extras NAME, NAME -->``
    (anywhere in the page) The extras of acroplan the page needs; the page is skipped, naming the
    ``pip install`` that is missing, when one is not installed.

Output comparison: line by line after stripping; ``...`` matches any text (within a line, or a
whole line for any number of lines); numbers at the tolerance above; everything else exactly.
"""

from __future__ import annotations

import dataclasses
import doctest
import importlib.metadata
import os
import re
import subprocess
import sys
import textwrap

MARK = re.compile(r"^\s*<!--\s*docs-test:\s*(?P<kind>skip|file|output|exit|rtol=|extras)\s*(?P<arg>.*?)\s*-->\s*$")
FENCE = re.compile(r"^(?P<indent>\s*)(?P<fence>`{3,}|~{3,})\s*(?P<info>[^`\s]*)")
NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
SHELL = {"sh", "bash", "shell", "console"}
SETUP = re.compile(r"^(python3? -m venv\b|\.\s|source\s|pip3? install\b)")


class DocFailure(AssertionError):
    """A block of a page did not do what the page says."""


@dataclasses.dataclass
class Block:
    page: str
    line: int            # 1-based line of the block's first line
    kind: str            # "python", "shell", "other"
    info: str
    text: str
    skip: str | None = None
    file: str | None = None
    output: bool = False
    exit: int = 0
    rtol: float | None = None

    @property
    def where(self) -> str:
        return f"{self.page}:{self.line}"


def parse(text: str, page: str = "<page>") -> tuple[list[Block], list[str]]:
    """The page's blocks, in order, with their marks; and the extras it names."""
    lines = text.splitlines()
    blocks, extras, pending = [], [], {}
    i, prev_blank = 0, True
    while i < len(lines):
        line = lines[i]
        m = MARK.match(line)
        if m:
            kind, arg = m["kind"], m["arg"]
            if kind == "extras":
                extras += [e.strip() for e in arg.split(",") if e.strip()]
            elif kind == "skip":
                if not arg:
                    raise DocFailure(f"{page}:{i + 1}: a skip mark needs its reason")
                pending["skip"] = arg
            elif kind == "file":
                pending["file"] = arg
            elif kind == "output":
                pending["output"] = True
            elif kind == "exit":
                pending["exit"] = int(arg)
            else:
                pending["rtol"] = float(arg)
            i += 1
            continue
        f = FENCE.match(line)
        if f:
            indent, fence, info = len(f["indent"]), f["fence"], f["info"].lower()
            body, j = [], i + 1
            while j < len(lines) and not lines[j].strip().startswith(fence):
                body.append(lines[j][indent:] if lines[j][:indent].strip() == "" else lines[j].lstrip())
                j += 1
            kind = "python" if info.startswith("python") or info == "pycon" else (
                "shell" if info in SHELL else "other")
            blocks.append(Block(page, i + 2, kind, info, "\n".join(body), **pending))
            pending, i, prev_blank = {}, j + 1, False
            continue
        if line.startswith("    ") and prev_blank and line.strip():
            body, j = [], i
            while j < len(lines) and (lines[j].startswith("    ") or not lines[j].strip()):
                body.append(lines[j][4:])
                j += 1
            while body and not body[-1].strip():
                body.pop()
            blocks.append(Block(page, i + 1, "shell", "indented", "\n".join(body), **pending))
            pending, i, prev_blank = {}, j, not lines[j - 1].strip()  # its trailing blank lines
            continue
        prev_blank = not line.strip()
        i += 1
    return blocks, extras


def commands(block: Block) -> list[tuple[str, list[str]]]:
    """The commands of a shell block and, for a console block, each one's quoted output."""
    out, current = [], None
    joined, buf = [], ""
    for raw in block.text.splitlines():
        if buf:
            buf += " " + raw.strip()
        else:
            buf = raw
        if buf.rstrip().endswith("\\"):
            buf = buf.rstrip()[:-1]
            continue
        joined.append(buf)
        buf = ""
    if buf:
        joined.append(buf)
    console = block.info == "console"
    for line in joined:
        s = line.strip()
        prompt = s.startswith("$ ")
        if prompt:
            s = s[2:].strip()
        if (prompt or not console) and re.match(r"^(acroplan|python)\b", s.split("&&")[-1].strip()):
            parts = [p.strip() for p in s.split("&&")]
            run = [p for p in parts if not SETUP.match(p)]
            current = (" && ".join(run), [])
            out.append(current)
        elif console and current is not None and not prompt:
            current[1].append(line)
        elif prompt:
            current = None
    return out


def installed_extras(extras: list[str]) -> list[str]:
    """The extras among ``extras`` whose requirements are not installed."""
    missing = []
    reqs = importlib.metadata.requires("acroplan") or []
    for extra in extras:
        for r in reqs:
            if f'extra == "{extra}"' not in r:
                continue
            name = re.match(r"[A-Za-z0-9_.-]+", r)[0]
            try:
                importlib.metadata.version(name)
            except importlib.metadata.PackageNotFoundError:
                missing.append(extra)
                break
    return missing


# ------------------------------------------------------------------ comparing quoted output
def _number_ok(got: str, want: str, rtol: float | None) -> bool:
    g, w = float(got), float(want)
    if rtol is not None:
        return abs(g - w) <= rtol * max(abs(w), 1e-300)
    mant = want.lower().split("e")[0]
    exp = int(want.lower().split("e")[1]) if "e" in want.lower() else 0
    decimals = len(mant.split(".")[1]) if "." in mant else 0
    return abs(g - w) <= 0.5 * 10.0 ** (exp - decimals) * (1 + 1e-9)


def _line_ok(got: str, want: str, rtol: float | None) -> bool:
    got, want = " ".join(got.split()), " ".join(want.split())
    pattern, nums, pos = "", [], 0
    for m in re.finditer(r"\.\.\.|" + NUMBER.pattern, want):
        pattern += re.escape(want[pos:m.start()])
        if m[0] == "...":
            pattern += ".*?"
        else:
            pattern += "(" + NUMBER.pattern + ")"
            nums.append(m[0])
        pos = m.end()
    pattern += re.escape(want[pos:])
    m = re.fullmatch(pattern, got)
    return bool(m) and all(_number_ok(g, w, rtol) for g, w in zip(m.groups(), nums))


def same_output(got: str, want: str, rtol: float | None = None) -> bool:
    """Whether the text ``got`` is the quoted output ``want`` (see the module docstring)."""
    g = [ln for ln in got.splitlines() if ln.strip()]
    w = [ln for ln in want.splitlines() if ln.strip()]

    def match(i, j):
        if j == len(w):
            return i == len(g)
        if w[j].strip() == "...":
            return any(match(k, j + 1) for k in range(i, len(g) + 1))
        return i < len(g) and _line_ok(g[i], w[j], rtol) and match(i + 1, j + 1)

    return match(0, 0)


class _Checker(doctest.OutputChecker):
    def __init__(self, rtol):
        super().__init__()
        self.rtol = rtol

    def check_output(self, want, got, optionflags):
        return same_output(got, want, self.rtol) or super().check_output(want, got, optionflags)


# ------------------------------------------------------------------ running a page
@dataclasses.dataclass
class Run:
    block: Block
    ran: bool
    why: str = ""


def run_page(text: str, workdir, page: str = "<page>", *, timeout: float = 600.0) -> list[Run]:
    """Run every block of a page in ``workdir``; raise :class:`DocFailure` at the first that fails."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    blocks, _ = parse(text, page)
    namespace: dict = {"__name__": "__docs__"}
    env = dict(os.environ, MPLBACKEND="Agg",
               PATH=os.path.dirname(sys.executable) + os.pathsep + os.environ.get("PATH", ""))
    last_output: str | None = None
    report = []
    cwd = os.getcwd()
    os.chdir(workdir)
    try:
        for b in blocks:
            if b.skip:
                report.append(Run(b, False, b.skip))
                continue
            if b.file:
                with open(b.file, "w", encoding="utf-8") as fh:
                    fh.write(b.text + "\n")
                report.append(Run(b, True, f"wrote {b.file}"))
                continue
            if b.output:
                if last_output is None:
                    raise DocFailure(f"{b.where}: an output block with no block before it")
                if not same_output(last_output, b.text, b.rtol):
                    raise DocFailure(f"{b.where}: the page quotes\n{b.text}\nbut the block before printed\n{last_output}")
                report.append(Run(b, True, "output compared"))
                continue
            if b.kind == "python":
                last_output = _run_python(b, namespace)
                plt.close("all")
                report.append(Run(b, True))
            elif b.kind == "shell":
                cmds = commands(b)
                for cmd, quoted in cmds:
                    code, last_output = run_command(cmd, env, timeout)
                    if code != b.exit:
                        raise DocFailure(f"{b.where}: `{cmd}` exited {code} (the page expects "
                                         f"{b.exit}):\n{last_output[-3000:]}")
                    if quoted and not same_output(last_output, "\n".join(quoted), b.rtol):
                        raise DocFailure(f"{b.where}: `{cmd}`: the page quotes\n" + "\n".join(quoted)
                                         + f"\nbut it printed\n{last_output}")
                report.append(Run(b, bool(cmds), "" if cmds else "no command"))
            else:
                report.append(Run(b, False, f"a {b.info or 'plain'} block: shown, not run"))
    finally:
        os.chdir(cwd)
    return report


_SHELL_SYNTAX = re.compile(r"[|&;<>$`*?(){}\[\]~!\\]")


def in_process(cmd: str) -> list[str] | None:
    """The arguments of a plain ``acroplan ARGS`` command (run in this process), else ``None``."""
    import shlex

    try:
        words = shlex.split(cmd, comments=True)
    except ValueError:
        return None
    if not words or words[0] != "acroplan":
        return None
    # shell syntax outside quotes: leave it to bash
    bare = re.sub(r"'[^']*'|\"[^\"]*\"", "", cmd).split("#")[0]
    if _SHELL_SYNTAX.search(bare) or "=" in words[0]:
        return None
    return words[1:]


def run_command(cmd: str, env: dict, timeout: float) -> tuple[int, str]:
    """Run one command of a page: (exit code, stdout then stderr)."""
    args = in_process(cmd)
    if args is None:
        proc = subprocess.run(["bash", "-c", cmd], env=env, capture_output=True, text=True, timeout=timeout)
        return proc.returncode, proc.stdout + proc.stderr
    import contextlib
    import io
    import warnings

    from acroplan.io.cli.app import run

    out, err = io.StringIO(), io.StringIO()
    argv = sys.argv
    sys.argv = ["acroplan", *args]
    try:
        # a fresh registry of shown warnings, as in a new process
        with warnings.catch_warnings(), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            warnings.resetwarnings()  # then Python's own start-up filters
            warnings.filterwarnings("default", category=DeprecationWarning, module="__main__")
            for quiet in (DeprecationWarning, PendingDeprecationWarning, ImportWarning, ResourceWarning):
                warnings.simplefilter("ignore", quiet, append=True)
            try:
                run()
                code = 0
            except SystemExit as e:
                code = e.code if isinstance(e.code, int) else (0 if e.code is None else 1)
    finally:
        sys.argv = argv
        import matplotlib.pyplot as plt

        plt.close("all")
    return code, out.getvalue() + err.getvalue()


def _run_python(b: Block, namespace: dict) -> str:
    import contextlib
    import io

    if ">>>" in b.text:
        test = doctest.DocTestParser().get_doctest(b.text, namespace, b.page, b.page, b.line - 1)
        out = io.StringIO()
        runner = doctest.DocTestRunner(checker=_Checker(b.rtol), optionflags=doctest.ELLIPSIS
                                       | doctest.NORMALIZE_WHITESPACE)
        runner.run(test, out=out.write, clear_globs=False)
        if runner.failures:
            raise DocFailure(f"{b.where}: doctest failed\n{out.getvalue()}")
        namespace.update(test.globs)
        return ""
    buf = io.StringIO()
    try:
        code = compile(textwrap.dedent(b.text), f"{b.where}", "exec")
        with contextlib.redirect_stdout(buf):
            exec(code, namespace)
    except Exception as e:  # noqa: BLE001 - reported with the page's line
        raise DocFailure(f"{b.where}: {type(e).__name__}: {e}") from e
    return buf.getvalue()
