"""Webots' ``controller.camera`` module, as Webots ships it (one per class)."""

from ego.controller import Camera, CameraRecognitionObject

__all__ = ['Camera', 'CameraRecognitionObject']
