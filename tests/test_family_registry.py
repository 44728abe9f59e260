"""The family registry's answers are kept until a family is registered (every plan asks for its
system's family, and the registry was sorted along the class's MRO each time): a family
registered later is found at once, in its priority's place."""

from __future__ import annotations

import pytest

import acroplan
from acroplan.core import family as fam


class _Body:
    """A user's own system class (no family owns it)."""


class _Child(_Body):
    pass


@pytest.fixture
def registered():
    made = []
    yield made
    with fam._LOCK:
        for f in made:
            fam._FAMILIES.pop(f.name, None)
        fam._forget()


def test_a_family_registered_later_is_found_and_sorted_in(registered):
    assert fam.family_of(_Child) is None and fam.family_of(_Child()) is None  # asked: remembered as none
    before = fam.families()
    assert fam.families() is before  # the same order, kept
    new = fam.Family(name="test-registry-family", system_types=(_Body,), priority=10**6)
    registered.append(new)
    fam.register_family(new)
    assert fam.family_of(_Child) is new and fam.family_of(_Body()) is new  # along the MRO
    assert fam.families()[0] is new and [f.name for f in fam.families()[1:]] == [f.name for f in before]
    # the bundled families' answers are unchanged
    assert fam.family_of(acroplan.Acrobot).name == "acrobot"
