"""``python -m acroplan``: the command line (:mod:`acroplan.io.cli`)."""

from acroplan.io.cli import run

run()
