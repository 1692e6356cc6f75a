"""Verification and orchestration: the cross-check, the wall-clock budget, bench, sweeps and maps,
random draws, expected answers and baselines."""
