#!/usr/bin/env python3
"""houle's frame time against the bare open-sea marcher (the "yardstick"), measured interleaved.

A shared machine's speed drifts from minute to minute, so a frame time alone says little; a ratio to
a program measured in the same minutes says more (docs/design.md 10). Each round, per size, runs:
the bare marcher, `houle bench` on the built-in coast, `houle bench` on the fly-along scene, and the
bare marcher again. The ratio is houle's median to the mean of the two bare-marcher medians around
it; the fly-along is compared with the fixed shot of its own round. The summary gives each figure's
range over the rounds, how many rounds meet the real-time targets (ratio at most 1.5, fly-along at
most 1.2x the fixed shot, p99 at most 1.25x the median), and the ratios of the least times.

Usage: bench/yardstick_ratio.py --yardstick DIR [--houle BIN] [--rounds N] [--sizes 640x360,...]
DIR holds the bare marcher's ocean_v3 / ocean_v4, built with `make -C DIR` (it is not part of houle).
"""
import argparse
import os
import re
import statistics
import subprocess
import sys

# houle bench's frame counts as the real-time issue measures them; the bare marcher's as its README.
HOULE_FRAMES = {"640x360": 40, "1280x720": 20}
YARD_FRAMES = {"640x360": 100, "1280x720": 40}


def fail(message):
    sys.exit(f"yardstick_ratio: {message}")


def yardstick_command(directory, size):
    """The bare marcher's binary and mode for this CPU: AVX-512 if it has it, else AVX2."""
    flags = open("/proc/cpuinfo").read()
    avx512 = re.search(r"\bavx512f\b", flags) is not None
    w, h = size.split("x")
    if avx512:
        binary, mode = "ocean_v4", "tile16b_opt_hw" if int(w) <= 640 else "tile16b82_opt_hw"
    else:
        binary, mode = "ocean_v3", "tile8b_opt_hw"
    path = os.path.join(directory, binary)
    if not os.access(path, os.X_OK):
        fail(f"{path}: no such program; build it with `make -C {directory}`")
    return [path, "-w", w, "-h", h, "-f", str(YARD_FRAMES.get(size, 40)), "-m", mode]


def run(command, env=None):
    done = subprocess.run(command, capture_output=True, text=True, env=env)
    if done.returncode != 0:
        fail(f"`{' '.join(command)}` failed ({done.returncode}):\n{done.stderr.strip()}")
    return done.stdout + done.stderr


def yardstick(command):
    """(median, p99) in ms from the bare marcher's table: the columns named med_ms and p99_ms."""
    out = run(command, dict(os.environ, OMP_NUM_THREADS="2"))
    lines = out.splitlines()
    for k, line in enumerate(lines[:-1]):
        names = line.split()
        if "med_ms" in names and "p99_ms" in names:
            values = lines[k + 1].split()  # the last column, diff, may be empty
            if len(values) > max(names.index("med_ms"), names.index("p99_ms")):
                return float(values[names.index("med_ms")]), float(values[names.index("p99_ms")])
    fail(f"`{' '.join(command)}` printed no med_ms / p99_ms row:\n{out.strip()}")


def houle(binary, scene, size):
    """(median, p99, {stage: median}) in ms from `houle bench`'s table."""
    command = [binary, "bench"] + ([scene] if scene else []) + [
        "--frames", str(HOULE_FRAMES.get(size, 20)), "--size", size, "--threads", "2"]
    out = run(command)
    stages = {}
    for line in out.splitlines():
        m = re.match(r"(frame|surface|march|intersect|shade)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)", line)
        if m:
            stages[m.group(1)] = (float(m.group(2)), float(m.group(4)))
    if "frame" not in stages:
        fail(f"`{' '.join(command)}` printed no frame row:\n{out.strip()}")
    return stages["frame"][0], stages["frame"][1], {k: v[0] for k, v in stages.items() if k != "frame"}


def span(values, digits=2):
    return f"{min(values):.{digits}f}-{max(values):.{digits}f}" if values else "-"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--yardstick", required=True, help="the directory of the built bare marcher")
    parser.add_argument("--houle", default="build/release/frontends/houle", help="houle's binary (default: %(default)s)")
    parser.add_argument("--fly", default="scenes/coast_flyby.toml", help="the moving camera's scene (default: %(default)s)")
    parser.add_argument("--rounds", type=int, default=6, help="rounds (default: %(default)s)")
    parser.add_argument("--sizes", default="640x360,1280x720", help="comma-separated WxH (default: %(default)s)")
    args = parser.parse_args()
    if args.rounds < 1:
        fail("--rounds: at least 1")
    sizes = args.sizes.split(",")
    for size in sizes:
        if not re.fullmatch(r"[1-9]\d*x[1-9]\d*", size):
            fail(f"--sizes: '{size}' is not WxH")
    for path in (args.houle, args.fly):
        if not os.path.exists(path):
            fail(f"{path}: no such file")

    rows = {size: [] for size in sizes}
    for r in range(1, args.rounds + 1):
        for size in sizes:
            yard_command = yardstick_command(args.yardstick, size)
            y1 = yardstick(yard_command)
            fixed = houle(args.houle, None, size)
            fly = houle(args.houle, args.fly, size)
            y2 = yardstick(yard_command)
            yard = (y1[0] + y2[0]) / 2
            row = {"yard": yard, "yard_p99": max(y1[1] / y1[0], y2[1] / y2[0]), "fixed": fixed[0],
                   "fixed_p99": fixed[1] / fixed[0], "fly": fly[0], "ratio": fixed[0] / yard,
                   "fly_ratio": fly[0] / yard, "fly_fixed": fly[0] / fixed[0]}
            rows[size].append(row)
            stages = " ".join(f"{k} {v:.2f}" for k, v in fixed[2].items())
            print(f"round {r} {size}: bare marcher {y1[0]:.2f}/{y2[0]:.2f} ms, houle {fixed[0]:.2f} ms "
                  f"(p99 {row['fixed_p99']:.2f}x; {stages}), fly-along {fly[0]:.2f} ms | ratio {row['ratio']:.2f}, "
                  f"fly-along/fixed {row['fly_fixed']:.2f}", flush=True)

    print(f"\n{args.rounds} rounds; ranges over the rounds, and the rounds that meet each target:")
    for size, rs in rows.items():
        col = lambda key: [x[key] for x in rs]
        meets = lambda key, bound: sum(x[key] <= bound for x in rs)
        print(f"{size}: bare marcher {span(col('yard'))} ms (p99 {span(col('yard_p99'))}x the median), "
              f"houle {span(col('fixed'))} ms, fly-along {span(col('fly'))} ms")
        print(f"  ratio to the bare marcher {span(col('ratio'))} (median {statistics.median(col('ratio')):.2f}; "
              f"<= 1.5 in {meets('ratio', 1.5)}/{len(rs)}), the fly-along's {span(col('fly_ratio'))}")
        # The least of each over the rounds: the nearest to what a quiet machine would give.
        print(f"  the least of each: houle {min(col('fixed')) / min(col('yard')):.2f}x the bare marcher, "
              f"the fly-along {min(col('fly')) / min(col('fixed')):.2f}x the fixed shot")
        print(f"  fly-along / fixed {span(col('fly_fixed'))} (median {statistics.median(col('fly_fixed')):.2f}; "
              f"<= 1.2 in {meets('fly_fixed', 1.2)}/{len(rs)})")
        print(f"  houle's p99 / median {span(col('fixed_p99'))} (<= 1.25 in {meets('fixed_p99', 1.25)}/{len(rs)})")


if __name__ == "__main__":
    main()
