"""Regenerate docs/configuration.md from the registered config schemas."""

from __future__ import annotations

import os
from pathlib import Path

from porenet.config.reference import config_reference
from porenet.hooks import build_registry

if __name__ == "__main__":
    os.environ["PORENET_PLUGINS"] = ""  # built-in kinds only; plugins document their own
    target = Path(__file__).resolve().parents[2] / "docs" / "configuration.md"
    target.write_text(config_reference(build_registry(strict=True)))
    print(f"wrote {target}")
