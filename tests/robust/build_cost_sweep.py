#!/usr/bin/env python3
"""The build's estimated peak memory against the measured one (issue 22), on a sweep of scenes from
the shipped ones to the extremes the limits allow: each is rendered (one draft frame, one thread) by
`houle render --verbose`, whose estimates (before the build; once the rays are traced, before the
sea's grids) are read from its output and compared with the process's peak resident set (getrusage
of the child). Fails when the second is more than 25 % off, or when the CPU time estimated before
the build and the one measured are more than 3 times apart (with 2 s of slack for start-up and
small builds; a build that surprised by minutes is what this holds); prints the table (scene,
estimates, measured, ratio, estimated and measured CPU).

usage: build_cost_sweep.py HOULE SOURCE_DIR [--only NAME] [--large]

--large adds the scenes of 2 and 4 km (up to 4 GiB and a minute of CPU each, 2.5 minutes in all):
the test (ctest's build_cost_sweep) leaves them out, a release check before a change to the estimate
runs them.
"""
import atexit
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile

houle, src = sys.argv[1], sys.argv[2]
only = sys.argv[sys.argv.index("--only") + 1] if "--only" in sys.argv else None
large = "--large" in sys.argv
work = tempfile.mkdtemp()
atexit.register(shutil.rmtree, work, ignore_errors=True)


def scene(name, text):
    path = os.path.join(work, name + ".toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def features(n, side, seed):
    r = random.Random(seed)
    out = []
    for _ in range(n):
        out.append("[[floor.shoals]]\ncenter = [%g, %g]\nsemi_axis_a = %g\nsemi_axis_b = %g\nheight = %g\n"
                   % (r.uniform(0, side), r.uniform(0, side * 0.8), r.uniform(2, 20), r.uniform(2, 20), r.uniform(-2, 2)))
        out.append("[[floor.bars]]\npoint = [%g, %g]\nalong_deg = %g\nhalf_width = %g\nheight = %g\n"
                   % (r.uniform(0, side), r.uniform(0, side * 0.8), r.uniform(-30, 30), r.uniform(1, 5), r.uniform(-0.5, 0.5)))
        out.append("[[floor.channels]]\nfrom = [%g, %g]\nto = [%g, %g]\nhalf_width = %g\ndepth = %g\n"
                   % (r.uniform(0, side), r.uniform(0, side * 0.8), r.uniform(0, side), r.uniform(0, side * 0.8),
                      r.uniform(1, 5), r.uniform(-1, 1)))
    return "\n".join(out)


def beach(side, extra="", trains=1, dwt=""):
    t = "".join("[[trains]]\nperiod = %g\namplitude = 0.3\ndirection_deg = %g\n" % (4 + i % 5, 70 + 3 * i) for i in range(trains))
    return ("[domain]\nx_max = %g\ny_max = %g\n[floor.base]\nkind = \"planar_beach\"\ndepth = 15.0\nslope = 0.02\n"
            "shoreline = [0.0, %g]\n%s\n%s\n[camera]\nposition = [%g, -20.0, 12.0]\nlook_at = [%g, %g, 0.0]\n[dwt]\n%s\n"
            % (side, side, 0.95 * side, t, extra, side / 2, side / 2, side / 2, dwt))


def height_map(n, side):
    path = os.path.join(work, "map%d.pgm" % n)
    with open(path, "w") as f:
        f.write("P2\n%d %d\n255\n" % (n, n))
        for j in range(n):
            f.write(" ".join(str(min(255, j * 255 // n + (i * 7 % 13))) for i in range(n)) + "\n")
    return ("[floor.height_map]\nfile = \"map%d.pgm\"\ncell = %g\ndepth_at_black = 20.0\ndepth_at_white = -2.0\n"
            "[[trains]]\nperiod = 6.0\n[camera]\nposition = [%g, -20.0, 12.0]\nlook_at = [%g, %g, 0.0]\n"
            "[domain]\nx_max = %g\ny_max = %g\n" % (n, side / (n - 1), side / 2, side / 2, side / 2, side, side))


jetties = "".join("[[walls]]\npoints = [[%g, 380.0], [%g, 300.0]]\nthickness = 1.0\n" % (10 + 12 * i, 10 + 12 * i) for i in range(32))
sweep = [
    ("coast", os.path.join(src, "scenes/coast.toml")),
    ("fig4", os.path.join(src, "scenes/paper_fig4.toml")),
    ("plate3", os.path.join(src, "scenes/paper_plate3.toml")),
    ("floor-1024-each", scene("floor", beach(200, features(1024, 200, 1), dwt="on_cap = \"warn\""))),
    ("height-map-2048", scene("map", height_map(2048, 2000))),
    ("16-trains", scene("trains16", beach(400, trains=16))),
    ("32-jetties", scene("jetties", beach(400, jetties, trains=2))),
]
if large:
    sweep += [
        ("floor-1024-each-2km", scene("floor2k", beach(2000, features(1024, 2000, 2), dwt="on_cap = \"warn\""))),
        ("4km-fine-rays", scene("fine", beach(4000, dwt="step = 0.05\ninsertion_distance = 0.05\nmax_rays = 1048576\n"
                                                       "max_samples = 8388608\non_cap = \"warn\""))),
        ("4km-3-trains", scene("big3", beach(4000, trains=3, dwt="on_cap = \"warn\""))),
    ]

measure = """import resource, subprocess, sys
code = subprocess.run(sys.argv[1:]).returncode
u = resource.getrusage(resource.RUSAGE_CHILDREN)
print("child exit %d maxrss %d cpu %.3f" % (code, u.ru_maxrss, u.ru_utime + u.ru_stime))"""
failures = 0
print("| scene | estimated MiB | once traced | measured MiB | ratio | estimated CPU s | measured CPU s |")
print("|---|---|---|---|---|---|---|")
for name, path in sweep:
    if only and name != only:
        continue
    # The peak of one child, measured by a Python of its own (ru_maxrss of the children is the largest so far).
    p = subprocess.run([sys.executable, "-c", measure, houle, "render", path, "--verbose", "--quiet", "--frames", "0:0",
                        "--size", "64x36", "--quality", "draft", "--threads", "1", "--raw", os.devnull],
                       capture_output=True, text=True)
    m = re.search(r"estimated build: (\d+) MiB at the peak \(.*\), ([0-9.]+) s of CPU", p.stderr)
    usage = re.search(r"^child exit (-?\d+) maxrss (\d+) cpu ([0-9.]+)$", p.stdout, re.M)
    if not m or not usage or usage.group(1) != "0":
        failures += 1
        print("| %s | FAILED: %s %s |" % (name, p.stdout.strip(), p.stderr.strip().replace("\n", " / ")))
        continue
    traced = re.search(r"estimated once traced: (\d+) MiB at the peak", p.stderr)
    measured = int(usage.group(2)) / 1024.0
    cpu = float(usage.group(3))
    estimate = float(m.group(1))
    # The build is checked again once the rays are traced, before the sea's grids (most of its memory
    # and time): that estimate, with the rays as traced, is the one the build is held to. The first,
    # before any work, cannot foresee rays inserted without end over a rough floor (the caps bound them).
    held = float(traced.group(1))
    ratio = held / measured
    ok = 0.75 <= ratio <= 1.25
    cpu_estimate = float(m.group(2))
    cpu_ok = cpu <= 3.0 * cpu_estimate + 2.0 and cpu_estimate <= 3.0 * cpu + 2.0
    failures += not ok or not cpu_ok
    print("| %s | %.0f | %.0f | %.0f | %.2f%s | %s | %.1f%s |" % (name, estimate, float(traced.group(1)), measured, ratio,
                                                              "" if ok else " FAIL", m.group(2), cpu,
                                                              "" if cpu_ok else " FAIL"))
    if "--parts" in sys.argv:
        print(re.search(r"estimated build: .*", p.stderr).group(0))
    sys.stdout.flush()
sys.exit(1 if failures else 0)
