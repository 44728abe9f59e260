"""The docs stay true: the API reference is current and names every public object."""

import importlib.util
import pathlib

import acroplan

ROOT = pathlib.Path(__file__).parents[1]


def test_api_reference_is_current():
    spec = importlib.util.spec_from_file_location("make_api", ROOT / "docs" / "make_api.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert (ROOT / "docs" / "api.md").read_text(encoding="utf-8") == mod.render(), \
        "docs/api.md is stale: run python docs/make_api.py"


def test_every_public_name_is_documented():
    text = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    for name in acroplan.__all__:
        assert f"acroplan.{name}" in text or f".{name}(" in text or f".{name}`" in text, name


def test_public_callables_have_docstrings():
    for name in acroplan.__all__:
        obj = getattr(acroplan, name)
        assert obj.__doc__ and len(obj.__doc__.strip()) > 20, name
