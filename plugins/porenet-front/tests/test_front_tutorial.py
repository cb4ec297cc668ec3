"""docs/plugins.md "Adding an observer" and the README stay true to the source
(:func:`porenet.testing.tutorial.plugin_checks`, as for every tutorial's plugin)."""

from porenet.testing.tutorial import tutorial_test

test_tutorial = tutorial_test(
    __file__,
    "## Adding an observer",
    ["config.py", "front.py", "observer.py", "plugin.py"],
    "front.toml",
)
