#!/usr/bin/env python3
"""Runs every houle command of README.md as written, against the built houle, in an empty folder
(scenes/ linked in from the source tree), so the README shows only commands that work.

The commands are the lines of its ```sh and ```console blocks that start with `houle` (after the
console's `$ `; a trailing backslash joins the next line), run by bash with the build's houle first on
PATH; each must exit 0. The lines a console block shows under a command (all but those holding an
ellipsis, which stand for lines left out) must appear in its output, in order. Two changes keep the
run short and local, and are the only ones: a --frames range renders its first frame only (A:B becomes
A:A, a count N becomes 1), and farm's --submit becomes --dry-run (no Slurm here; the farm_slurm test
submits).
Usage: test_readme.py <houle binary> <source dir>"""
import os
import re
import subprocess
import sys
import tempfile

houle, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
text = open(os.path.join(src, "README.md")).read()

# (command, shown output lines) in README order.
commands = []
for lang, body in re.findall(r"^```(sh|console)\n(.*?)^```", text, re.S | re.M):
    lines = body.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        is_prompt = lang == "console" and line.startswith("$ ")
        command = line[2:] if is_prompt else line
        i += 1
        if not command.startswith("houle ") and command != "houle":
            continue
        while command.endswith("\\") and i < len(lines):
            command = command[:-1] + " " + lines[i].strip()
            i += 1
        shown = []
        while is_prompt and i < len(lines) and not lines[i].startswith("$ "):
            if "…" not in lines[i]:
                shown.append(lines[i])
            i += 1
        commands.append((command, shown))


def shorten(command):
    def first_frame(m):
        value = m.group(2)
        a = value.split(":")[0] if ":" in value else None
        return m.group(1) + (f"{a}:{a}" if a is not None else "1")
    command = re.sub(r"(--frames[ =])([0-9]+(?::[0-9]+)?)", first_frame, command)
    return re.sub(r" --submit\b", " --dry-run", command)


failures = 0
with tempfile.TemporaryDirectory() as work:
    os.symlink(os.path.join(src, "scenes"), os.path.join(work, "scenes"))
    bin_dir = os.path.join(work, ".bin")
    os.mkdir(bin_dir)
    os.symlink(houle, os.path.join(bin_dir, "houle"))
    env = dict(os.environ, PATH=bin_dir + os.pathsep + os.environ["PATH"])
    for command, shown in commands:
        run = shorten(command)
        r = subprocess.run(["bash", "-o", "pipefail", "-c", run], cwd=work, env=env, capture_output=True, text=True,
                           stdin=subprocess.DEVNULL)
        problem = f"exit {r.returncode}" if r.returncode != 0 else None
        if not problem and shown:
            out, at = r.stdout.splitlines(), 0
            for want in shown:
                while at < len(out) and out[at] != want:
                    at += 1
                if at == len(out):
                    problem = f"the README shows the line\n  {want}\nwhich the output does not have (in that order)"
                    break
        if problem:
            failures += 1
            print(f"FAIL {run}\n{problem}\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
    print(f"readme: {len(commands) - failures} passed, {failures} failed")
sys.exit(1 if failures or not commands else 0)
