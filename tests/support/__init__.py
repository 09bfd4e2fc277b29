"""Helpers of the tests (and benchmarks): cases, synthetic surfaces, reference solutions."""
