"""The tracker's benchmark (issue 38): ``python -m benchmarks.tracking.track_study``."""
