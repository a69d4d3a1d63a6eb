"""Gait analysis: foot events (stance, lift, liftoff, strike, landing) from heel and toe
trajectories, then duty factor, phase, stride, slip, skating and the named gait — for
Gaitlab's own motion, BVH motion capture and CSV foot tracks. No OpenGL here."""

from .events import AnalysisError, FootEvents, Step, detect_events
from .metrics import GaitReport, analyze_tracks
from .tracks import FootTracks, tracks_from_motion

__all__ = ["AnalysisError", "FootEvents", "FootTracks", "GaitReport", "Step", "analyze_tracks", "detect_events",
           "tracks_from_motion"]
