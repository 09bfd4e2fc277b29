"""Unit conversions used by both scales (lengths mm, forces N, moduli MPa).

Membrane forces per width are N/mm internally; the textile literature and our reference data
report them in gram-force per centimetre (1 gf = 9.80665e-3 N). Pressures are N/mm^2 (MPa)
internally; compression garments are specified in mmHg (and kPa).
"""

__all__ = [
    "GF_PER_CM_PER_N_PER_MM",
    "GRAM_FORCE",
    "KPA",
    "MMHG",
    "n_mm_per_mm_to_gf_cm_per_cm",
    "n_per_mm_to_gf_per_cm",
]

GRAM_FORCE = 9.80665e-3
"""One gram-force in newtons."""

GF_PER_CM_PER_N_PER_MM = 10.0 / GRAM_FORCE
"""Multiply a force per width in N/mm by this to get gf/cm (about 1019.7)."""


MMHG = 133.322387415e-6
"""One millimetre of mercury in N/mm^2 (133.322 Pa; 30 mmHg = 4.0e-3 N/mm^2 = 4.0 kPa)."""

KPA = 1.0e-3
"""One kilopascal in N/mm^2."""


def n_per_mm_to_gf_per_cm(force_per_width):
    """Convert a force per width from N/mm to gf/cm (scalar or numpy array)."""
    return force_per_width * GF_PER_CM_PER_N_PER_MM


def n_mm_per_mm_to_gf_cm_per_cm(moment_per_width):
    """Convert a moment per width from N mm / mm to gf cm / cm (1 N mm / mm = 1 N = 102 gf;
    scalar or numpy array)."""
    return moment_per_width / GRAM_FORCE
