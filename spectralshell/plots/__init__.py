"""Stage 6a: figures (matplotlib only here, imported lazily by the callers)."""
