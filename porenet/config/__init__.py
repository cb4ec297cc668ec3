"""Scene configuration: schema, TOML loading and validation."""

from porenet.config.base import ModelConfig
from porenet.config.loading import load_scene
from porenet.config.scene import InjectionConfig, SceneBase, StopConfig, scene_model

__all__ = ["InjectionConfig", "ModelConfig", "SceneBase", "StopConfig", "load_scene", "scene_model"]
