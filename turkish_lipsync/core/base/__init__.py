"""The base stage under every other: the data model, the error family, data tables and option choices."""
