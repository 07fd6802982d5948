"""tofradar core: scene model, rendering, sensor models and DSP, with no GUI dependency."""

__version__ = "0.1.0"
