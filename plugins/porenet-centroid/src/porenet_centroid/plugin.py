"""porenet hook implementations of porenet-centroid (entry point ``centroid``)."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet_centroid.config import CentroidClassifierConfig


@hookimpl
def porenet_register_classifiers(register: Register) -> None:
    """Register ``centroid.nearest``; its implementation is imported only when selected."""
    register(CentroidClassifierConfig, "porenet_centroid.classifier:CentroidClassifier")
