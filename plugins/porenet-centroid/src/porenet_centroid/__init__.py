"""porenet-centroid: a nearest-centroid pattern classifier, shipped as a separate package."""

__version__ = "0.1.0"
