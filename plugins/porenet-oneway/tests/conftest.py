"""Make the plugin and porenet-linear, which it builds on, importable from their source trees,
so its tests run without installing either, and give them ``reg``: porenet's kinds and both
plugins', and no installed plugin."""

import sys
from pathlib import Path

from porenet.testing.contract import registry_fixture

LINEAR_SRC = str(Path(__file__).resolve().parents[2] / "porenet-linear" / "src")
if LINEAR_SRC not in sys.path:
    sys.path.insert(0, LINEAR_SRC)

PLUGINS = {"linear": "porenet_linear.plugin", "oneway": "porenet_oneway.plugin"}
reg = registry_fixture(__file__, PLUGINS)
