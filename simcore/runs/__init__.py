"""Runs: a project's frames into a dataset (one scene, a folder of scenes, or a sweep)."""
