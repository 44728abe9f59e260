"""The I/O layer, on top of everything: problem files (:mod:`~.problem`), the bundled examples
(:mod:`~.examples`), atomic output folders (:mod:`~.output`) and the command line (:mod:`~.cli`)."""
