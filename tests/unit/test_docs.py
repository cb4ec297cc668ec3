"""docs/ stays true to the code."""

from __future__ import annotations

from pathlib import Path

from porenet.config.reference import config_reference
from porenet.hooks import build_registry

ROOT = Path(__file__).resolve().parents[2]


def test_configuration_reference_is_current(monkeypatch):
    monkeypatch.setenv("PORENET_PLUGINS", "")
    expected = config_reference(build_registry(strict=True))
    actual = (ROOT / "docs" / "configuration.md").read_text()
    assert actual == expected, "run: python examples/scripts/make_config_reference.py"
