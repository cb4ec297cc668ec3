"""docs/plugins.md "Adding a fluid model" and the README stay true to the source.

* Every code block of the tutorial preceded by ``<!-- excerpt: PATH -->`` appears verbatim in
  ``PATH`` (relative to the repository root); a line ``# (...)`` in a block marks an elision,
  and each piece between elisions must appear on its own.
* The plugin imports from porenet exactly what its README lists, and nothing private
  (no name or module component starting with ``_``, nothing from ``porenet.kinds``).

The checks are :mod:`porenet.testing.tutorial`'s, shared with the other tutorials' plugins.
"""

from porenet.testing.tutorial import tutorial_test

test_tutorial = tutorial_test(
    __file__, "## Adding a fluid model", ["config.py", "model.py", "plugin.py"], "gravity.toml"
)
