"""Contact detection: a broad phase on bounding boxes and a narrow phase between polygons."""

from .detector import DetectionSettings, Detector

__all__ = ["DetectionSettings", "Detector"]
