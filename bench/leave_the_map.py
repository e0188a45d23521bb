#!/usr/bin/env python3
"""A query that leaves the map: does `seqtopo localize` say so? Map: Nordland summer frames 0-899. Query: winter
frames 300-599 (in the map, same index + 300) then winter frames 1200-1499 (a stretch the map does not hold).
Offline, --online and --online --lag 10, each scored against the pairs of the first half (the second half has no true match): R@1,
R@100P, ECE, frames declared in the map and their precision, and how many of the 300 off-map frames were declared
in the map.

Usage: bench/leave_the_map.py [SEQTOPO_BINARY] [--data ../shared/data]
"""
import argparse
import csv
import json
import os
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("binary", nargs="?", default=os.path.join(HERE, "..", "build", "release", "src", "seqtopo"))
    parser.add_argument("--data", default=os.path.join(HERE, "..", "..", "shared", "data"))
    args = parser.parse_args()
    nordland = os.path.join(args.data, "nordland-64x32")
    summer = sorted(os.listdir(os.path.join(nordland, "summer")))
    winter = sorted(os.listdir(os.path.join(nordland, "winter")))
    with tempfile.TemporaryDirectory() as scratch:
        for name in ("map", "query"):
            os.makedirs(os.path.join(scratch, name))
        for k, f in enumerate(summer[:900]):
            os.symlink(os.path.join(nordland, "summer", f), os.path.join(scratch, "map", f"m{k:05d}.png"))
        for k, f in enumerate(winter[300:600] + winter[1200:1500]):
            os.symlink(os.path.join(nordland, "winter", f), os.path.join(scratch, "query", f"q{k:05d}.png"))
        truth = os.path.join(scratch, "pairs.csv")
        with open(truth, "w") as f:
            f.write("query,map\n" + "".join(f"{q},{q + 300}\n" for q in range(300)))
        print("| mode | R@1 | R@100P | ECE | in the map | precision | off-map frames in the map |")
        print("|---|---|---|---|---|---|---|")
        for mode in ("offline", "online", "online, --lag 10"):
            out = os.path.join(scratch, mode.replace(", --", "_").replace(" ", "_"))
            command = [args.binary, "localize", "--map", os.path.join(scratch, "map"), "--query",
                       os.path.join(scratch, "query"), "--gt", truth, "--out", out]
            if mode.startswith("online"):
                command.append("--online")
            if mode.endswith("--lag 10"):
                command += ["--lag", "10"]
            subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            with open(os.path.join(out, "metrics.json")) as f:
                m = json.load(f)
            with open(os.path.join(out, "matches.csv")) as f:
                off = sum(1 for r in csv.DictReader(f) if int(r["query"]) >= 300 and r["in_map"] == "1")
            d = m["in_map"]
            print(f"| {mode} | {m['recall_at_1']:.3f} | {m['recall_at_100_precision']:.3f} | "
                  f"{m['calibration']['ece']:.3f} | {d['frames']} | {d['precision']:.3f} | {off} of 300 |")


if __name__ == "__main__":
    main()
