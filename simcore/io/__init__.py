"""Dataset writers (HDF5) and exports (PNG previews)."""
