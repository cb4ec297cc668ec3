"""Scene configuration: schema, TOML loading and validation.

The names below load on first use, so that importing one module of this package (``config.
base``, which every model's config imports) does not import the others.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from porenet.config.base import ModelConfig
    from porenet.config.loading import load_scene
    from porenet.config.scene import InjectionConfig, SceneBase, StopConfig, scene_model

__all__ = ["InjectionConfig", "ModelConfig", "SceneBase", "StopConfig", "load_scene", "scene_model"]

_LAZY = {
    "ModelConfig": "porenet.config.base",
    "load_scene": "porenet.config.loading",
    "InjectionConfig": "porenet.config.scene",
    "SceneBase": "porenet.config.scene",
    "StopConfig": "porenet.config.scene",
    "scene_model": "porenet.config.scene",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'porenet.config' has no attribute {name!r}")
