"""Special functions for spectralshell (modified spherical Bessel ratios for complex argument)."""

from .spherical import M_MAX, logderiv_i, logderiv_k, ratio_i, ratio_k

__all__ = ["M_MAX", "ratio_i", "ratio_k", "logderiv_i", "logderiv_k"]
