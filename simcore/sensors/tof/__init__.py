"""AMCW Time-of-Flight camera."""
