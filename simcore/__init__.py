"""tofradar core: scene model, rendering, sensor models and DSP, with no GUI dependency."""

#: The package version; the one source, read by the build (pyproject ``dynamic``).
__version__ = "0.2.0.dev0"
