"""docs/plugins.md "Adding a coupler" and the README stay true to the source, with the checks
every tutorial's plugin runs (:mod:`porenet.testing.tutorial`)."""

from porenet.testing.tutorial import tutorial_test

test_tutorial = tutorial_test(
    __file__, "## Adding a coupler", ["config.py", "model.py", "plugin.py"], "oneway.toml"
)
