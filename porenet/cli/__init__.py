"""The ``porenet`` command: :mod:`~porenet.cli.main` (the subcommands),
:mod:`~porenet.cli.parser` (the argument parser), :mod:`~porenet.cli.checks` (checks of the
arguments before anything heavy is imported) and :mod:`~porenet.cli.interrupts` (Ctrl-C)."""
