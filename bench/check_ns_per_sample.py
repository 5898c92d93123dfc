#!/usr/bin/env python3
"""Checks that houle_bench_kernels' ns_per_sample counter is nanoseconds per sample, i.e. 1e9 divided by
its items_per_second. Usage: check_ns_per_sample.py <houle_bench_kernels binary>"""
import json
import subprocess
import sys

out = subprocess.run([sys.argv[1], "--benchmark_min_time=0.001", "--benchmark_format=json",
                      "--benchmark_filter=camera_row_rays|gerstner_eval|capillary|sky_lookup|water_mix|sea_light|under_light|floor_hits"], check=True, capture_output=True, text=True)
runs = json.loads(out.stdout)["benchmarks"]
bad = [r["name"] for r in runs if abs(r["ns_per_sample"] * r["items_per_second"] / 1e9 - 1.0) > 1e-3]
if not runs or bad:
    sys.exit(f"ns_per_sample is not 1e9 / items_per_second in: {bad or 'no benchmarks ran'}")
print(f"ns_per_sample: {len(runs)} benchmarks, e.g. {runs[0]['name']}: {runs[0]['ns_per_sample']:.3g} ns")
