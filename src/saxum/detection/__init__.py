"""Contact detection: a broad phase on bounding boxes and a narrow phase between polygons (2D)
or convex polyhedra (3D)."""

from .detector import DetectionSettings, Detector, PolyhedronDetector, detector_for

__all__ = ["DetectionSettings", "Detector", "PolyhedronDetector", "detector_for"]
