"""The ``acroplan`` command line.

Exit codes: 0 success, 2 invalid input, 3 infeasible (with proof), 4 not converged. Errors are one
line naming the field and the fix (``--debug`` shows the traceback); colours only on a terminal;
progress bars only on a terminal; ``--json`` prints a machine-readable summary on stdout.

One module per command (:mod:`~.plan`, :mod:`~.simulate`, :mod:`~.reach`, :mod:`~.momentum`,
:mod:`~.nilpotent`, :mod:`~.animate`, :mod:`~.examples` with ``init``; the sweep commands live with
their store), what they share in :mod:`~.common`, the group in :mod:`~.app`: a lazy group that
imports a command's module only when the command runs or its help is asked. The modules import
acroplan's numerics inside the commands, so that ``--help`` starts at once.

Output folders are checked and reserved (:class:`~acroplan.io.output.OutputFolder`: lock, repair
of what a killed run left) before any planning, and written atomically. No JSON written or printed
holds a non-finite number: such a value is written as ``null`` and named in the document's
``warnings`` list.
"""

from .app import COMMANDS, LazyGroup, main, run
from .common import json_text

__all__ = ["main", "run", "json_text", "COMMANDS", "LazyGroup"]
