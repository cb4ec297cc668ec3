"""Make the plugin importable from its source tree, so its tests run without installing it,
and give them ``reg``: porenet's kinds and this plugin's, and no installed plugin."""

from porenet.testing.contract import registry_fixture

reg = registry_fixture(__file__, {"oneway": "porenet_oneway.plugin"})
