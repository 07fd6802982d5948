"""FMCW radar: scatterers from the radar render, IF synthesis, receiver."""
