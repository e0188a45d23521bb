#!/usr/bin/env python3
"""`seqtopo localize` when the query was driven at another speed than the map (or recorded at another frame
rate): the query resampled to 0.5-2 map frames per query frame, in both directions of Nordland (summer and winter,
../shared/data), with the default speeds searched and with `--speeds 1` (the query as recorded only, as before the
speeds were searched), beside the SeqSLAM baseline of the same run (its standard velocities 0.9-1.6).

Usage: bench/localize_speeds.py [SEQTOPO_BINARY] [--data ../shared/data] [--speeds 0.5 0.75 1 1.25 1.5 2]
Prints a Markdown table: R@1, R@100P and the calibration error (within 2 map frames) per speed and setting, and the
CPU time of each run.
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def resampled(folder, speed, scratch, name):
    """The query's images at `speed` map frames per query frame (image round(k * speed)), as links, and the truth."""
    names = sorted(os.listdir(folder))
    out = os.path.join(scratch, name)
    os.makedirs(out, exist_ok=True)
    truth = os.path.join(scratch, name + ".csv")
    with open(truth, "w") as f:
        f.write("query,map\n")
        k = 0
        while round(k * speed) < len(names):
            i = round(k * speed)
            os.symlink(os.path.join(folder, names[i]), os.path.join(out, f"{k:05d}.png"))
            f.write(f"{k},{i}\n")
            k += 1
    return out, truth


def run(binary, args, out):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([binary, "localize", *map(str, args), "--out", out], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    with open(os.path.join(out, "metrics.json")) as f:
        return json.load(f), cpu


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary", nargs="?", default=os.path.join(HERE, "..", "build", "release", "src", "seqtopo"))
    ap.add_argument("--data", default=os.path.join(HERE, "..", "..", "shared", "data"))
    ap.add_argument("--speeds", nargs="+", type=float, default=[0.5, 0.75, 1.0, 1.25, 1.5, 2.0])
    args = ap.parse_args()
    nordland = os.path.join(args.data, "nordland-64x32")
    rows = []
    with tempfile.TemporaryDirectory(prefix="seqtopo-speeds-") as scratch:
        for map_season, query_season in (("summer", "winter"), ("winter", "summer")):
            for speed in args.speeds:
                name = f"{query_season}_{speed:g}"
                query, truth = resampled(os.path.join(nordland, query_season), speed, scratch, name)
                for label, extra in (("default speeds", []), ("--speeds 1", ["--speeds", "1"])):
                    out = os.path.join(scratch, "out")
                    m, cpu = run(args.binary, ["--map", os.path.join(nordland, map_season), "--query", query,
                                               "--ground-truth", truth, "--tolerance", 2, *extra], out)
                    rows.append((f"{query_season} in {map_season}", speed, label, m["recall_at_1"],
                                 m["recall_at_100_precision"], m["calibration"]["ece"],
                                 m["baselines"]["seqslam"]["recall_at_1"], cpu))
    print("| query in map | speed (map frames per query frame) | seqtopo | R@1 | R@100P | ECE | SeqSLAM R@1 | CPU s |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r[0]} | {r[1]:g} | {r[2]} | {r[3]:.3f} | {r[4]:.3f} | {r[5]:.3f} | {r[6]:.3f} | {r[7]:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
