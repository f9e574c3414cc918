"""release (see the package above)."""
