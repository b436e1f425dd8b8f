"""Stage 3, discretisation: Fourier/Floquet conventions and Hill matrices (truncated systems)."""
