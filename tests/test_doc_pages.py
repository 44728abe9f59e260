"""Every page runs as written: each Python block and each shell command of README.md and docs/*.md,
in order, in a fresh folder, with quoted outputs compared (tests/doc_blocks.py says how a page marks
what is a sketch, a file to write, an output, an exit code or a tolerance)."""

import pathlib

import pytest

import doc_blocks as db

ROOT = pathlib.Path(__file__).parents[1]
PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))


@pytest.mark.parametrize("page", PAGES, ids=[p.relative_to(ROOT).as_posix() for p in PAGES])
def test_page_runs_as_written(page, tmp_path):
    text = page.read_text(encoding="utf-8")
    _, extras = db.parse(text, page.name)
    missing = db.installed_extras(extras)
    if missing:
        pytest.skip(f"{page.name} needs pip install '.[{','.join(missing)}]'")
    db.run_page(text, tmp_path, page.relative_to(ROOT).as_posix())


# ------------------------------------------------------------------ the test of the test
PAGE = '''# A page

<!-- docs-test: extras test -->

```python
x = 2 + 2
```

```python
>>> x * 10
40
>>> 1 / 3
0.333
```

<!-- docs-test: file hello.toml -->
```toml
a = 1
```

    python -c "print(open('hello.toml').read().strip())"

<!-- docs-test: output -->
```text
a = 1
```

```console
$ python -c "print('took 0.71 s, 3 points'); print('done')"
took ... s, 3 points
done
```

    acroplan examples          # the bundled problems (in this process)

<!-- docs-test: skip a sketch with placeholders -->
    acroplan plan PROBLEM.toml --out DIR

<!-- docs-test: exit 3 -->
```sh
python -c "import sys; sys.exit(3)"
```
'''


def test_a_page_that_is_true_runs(tmp_path):
    runs = db.run_page(PAGE, tmp_path)
    ran = [r.block.line for r in runs if r.ran]
    assert len(ran) == 8 and not any(r.ran for r in runs if r.block.skip)
    assert [r.why for r in runs if not r.ran] == ["a sketch with placeholders"]


@pytest.mark.parametrize("broken, why", [
    ("x = 2 + 2", "x = 1 / 0"),                                   # a Python block raises
    ("40\n", "41\n"),                                             # a doctest's output is wrong
    ("0.333", "0.334"),                                           # a number beyond its quoted digits
    ("a = 1\n```\n\n```console", "a = 2\n```\n\n```console"),     # a quoted output is wrong
    ("took ... s, 3 points", "took ... s, 4 points"),             # a console output is wrong
    ('sys.exit(3)', 'sys.exit(1)'),                               # a command exits with the wrong code
    ("print('done')", "import acroplan.no_such_module"),          # a command fails
    ("acroplan examples ", "acroplan no-such-command "),          # an acroplan command fails (in process)
])
def test_a_broken_block_fails_the_page(tmp_path, broken, why):
    assert broken in PAGE
    with pytest.raises(db.DocFailure):
        db.run_page(PAGE.replace(broken, why, 1), tmp_path)


def test_setup_parts_of_a_command_are_the_suites_own_environment():
    b = db.Block("p", 1, "shell", "indented",
                 'python3 -m venv .venv && . .venv/bin/activate && pip install ".[human]" && acroplan examples')
    assert db.commands(b) == [("acroplan examples", [])]


@pytest.mark.parametrize("cmd, args", [
    ("acroplan plan a.toml --out 'my out'   # a comment", ["plan", "a.toml", "--out", "my out"]),
    ("acroplan map s.zarr --title \"P0 (kg m^2/s)\"", ["map", "s.zarr", "--title", "P0 (kg m^2/s)"]),
    ("acroplan examples | head -3", None),                     # a pipe: bash
    ("acroplan plan a.toml > log.txt", None),                  # a redirection: bash
    ("acroplan plan $FILE", None),                             # a variable: bash
    ("acroplan init a && acroplan plan a.toml", None),         # a chain: bash
    ("python -c 'print(1)'", None),                            # not acroplan: bash
])
def test_plain_acroplan_commands_run_in_process_and_the_rest_in_bash(cmd, args):
    assert db.in_process(cmd) == args


def test_an_in_process_command_gives_its_exit_code_and_both_streams(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out = db.run_command("acroplan plan no-such-file.toml --out o", dict(), 60)
    assert code == 2 and "no-such-file.toml" in out
    code, out = db.run_command("acroplan init my-dive", dict(), 60)
    assert code == 0 and "wrote my-dive.toml" in out and (tmp_path / "my-dive.toml").is_file()


def test_a_skip_needs_its_reason():
    with pytest.raises(db.DocFailure, match="needs its reason"):
        db.parse("<!-- docs-test: skip -->\n    acroplan x\n")


@pytest.mark.parametrize("got, want, ok", [
    ("81.8", "81.8", True), ("81.84", "81.8", True), ("81.86", "81.8", False),
    ("1.23e-14", "1.2e-14", True), ("3.0e-14", "1.2e-14", False),
    ("status: success", "status: success", True), ("status: infeasible", "status: success", False),
    ("a\nb\nc", "a\n...\nc", True), ("wrote x.png", "wrote ...", True),
])
def test_quoted_numbers_agree_to_the_digits_they_show(got, want, ok):
    assert db.same_output(got, want) is ok
