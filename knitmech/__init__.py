"""The whole pipeline: scenes, fidelity levels, staged and cached runs, result folders.

Ties the two scales together: `rve_rod` (yarn level, up to the response-surface file) and
`fabric_dolfinx` (fabric level, from that file).
"""
