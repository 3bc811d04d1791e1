"""Work–precision benchmarks: run time against error for every scene and method (issue 7).

`python -m benchmarks.run_all` refreshes RESULTS.md and its plots; `mechfmu bench SCENE`
runs one scene. Each module has one job: references (the independent answers),
baselines (hand-written numpy right-hand sides under scipy), runners (our FMUs, masters
and CasADi), scenes (what each scene runs), suite (sweeps, tables, plots), overhead
(ctypes cost, build times, memory).
"""
