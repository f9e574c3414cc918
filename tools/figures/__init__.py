"""figures (see the package above)."""
