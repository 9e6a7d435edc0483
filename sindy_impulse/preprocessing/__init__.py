"""Preparing raw hammer-test records for per-mode identification."""
