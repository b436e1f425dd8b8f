"""Stage 2, physics: per-Fourier-index blocks of each model, independent of any truncation."""
