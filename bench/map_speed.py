#!/usr/bin/env python3
"""Wall and CPU time of `seqtopo map` per stage, two builds alternating on one input (BENCHMARK.md, "The whole
map job"). The machine is shared, so runs alternate and the medians are compared as ratios.

  bench/map_speed.py BASE_SEQTOPO NEW_SEQTOPO [--runs 3] [--out DIR] -- INPUT [map options...]

Prints one table: per stage the median seconds of each build and NEW / BASE; then wall, user + sys CPU and
peak memory of the whole run. Checks that the two builds wrote the same map.json, alignments.json and
loop_closures.csv (or says which differ)."""
import argparse
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

STAGE = re.compile(r"\[(\d+)/\d+\] (.+?) done in ([0-9.]+) s")


def run(binary, args, out):
    shutil.rmtree(out, ignore_errors=True)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    p = subprocess.run([binary, "map", *args, "--out", out], capture_output=True, text=True)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit(f"{binary} failed:\n{p.stderr}")
    stages = {m.group(2): float(m.group(3)) for m in STAGE.finditer(p.stderr)}
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return stages, wall, cpu, after.ru_maxrss / 1024.0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("base")
    ap.add_argument("new")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--out", default=None, help="folder for the two outputs (default: a temporary one)")
    argv = sys.argv[1:]
    if "--" not in argv:
        ap.error("give the map input and options after --")
    split = argv.index("--")
    a = ap.parse_args(argv[:split])
    args = argv[split + 1:]
    work = a.out or tempfile.mkdtemp(prefix="map-speed-")
    results = {"base": [], "new": []}
    for _ in range(a.runs):
        for name, binary in (("base", a.base), ("new", a.new)):
            results[name].append(run(binary, args, os.path.join(work, name)))
    stages = list(dict.fromkeys(s for r in results["base"] + results["new"] for s in r[0]))
    print(f"| stage | base [s] | new [s] | new / base |\n|---|---|---|---|")

    def row(label, base, new):
        ratio = f"{new / base:.2f}" if base > 0 else "-"
        print(f"| {label} | {base:.2f} | {new:.2f} | {ratio} |")

    for s in stages:
        b = statistics.median(r[0].get(s, 0.0) for r in results["base"])
        n = statistics.median(r[0].get(s, 0.0) for r in results["new"])
        row(s, b, n)
    for label, k in (("wall, whole run", 1), ("CPU (user + sys), whole run", 2)):
        row(label, statistics.median(r[k] for r in results["base"]), statistics.median(r[k] for r in results["new"]))
    print(f"\npeak memory: base {max(r[3] for r in results['base']):.0f} MB, "
          f"new {max(r[3] for r in results['new']):.0f} MB; {a.runs} runs each, alternating")
    for f in ("map.json", "alignments.json", "loop_closures.csv"):
        same = open(os.path.join(work, "base", f), "rb").read() == open(os.path.join(work, "new", f), "rb").read()
        print(f"{f}: {'identical' if same else 'DIFFERS'}")
    if not a.out:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
