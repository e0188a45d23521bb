#!/usr/bin/env python3
"""Every mode next to the offline map, on the same frames: `seqtopo localize` (offline and --online, the default
descriptors and each one alone; online also with --lag 10, each frame answered ten frames later with their evidence)
in both directions, and `seqtopo map` offline and --online.

Pairs of traversals (from ../shared/data): the bundled corridor split into its two laps (images 1-40 and 41-84,
the ground truth from its image), and Nordland summer and winter (same index, within 2 frames).

Usage: bench/mode_parity.py [SEQTOPO_BINARY] [--data ../shared/data] [--only corridor|nordland]
Prints two Markdown tables: localization (R@1, R@100P, ECE, frames in the map and their precision) and the map.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
LAG = 10  # frames: `localize --online --lag` (fixed-lag smoothing), measured beside the answers given at once


def run(binary, args, out):
    subprocess.run([binary, *map(str, args), "--out", out], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "metrics.json")) as f:
        return json.load(f)


def corridor_laps(data, scratch):
    corridor = os.path.join(data, "rtabmap-corridor")
    laps = []
    for name, frames in (("lap1", range(1, 41)), ("lap2", range(41, 85))):
        folder = os.path.join(scratch, name)
        os.makedirs(folder, exist_ok=True)
        for k in frames:
            link = os.path.join(folder, f"{k:03d}.jpg")
            if not os.path.exists(link):
                os.symlink(os.path.join(corridor, f"{k}.jpg"), link)
        laps.append(folder)
    truth = np.array(Image.open(os.path.join(corridor, "ground_truth.bmp")))
    truth = truth[..., 0] if truth.ndim == 3 else truth
    truth = (truth > 0) | (truth.T > 0)
    files = {}
    for query, map_, q0, m0, qn, mn in (("lap2", "lap1", 40, 0, 44, 40), ("lap1", "lap2", 0, 40, 40, 44)):
        path = os.path.join(scratch, f"{query}_in_{map_}.csv")
        with open(path, "w") as f:
            f.write("query,map\n")
            for q in range(qn):
                for m in range(mn):
                    if truth[q0 + q, m0 + m]:
                        f.write(f"{q},{m}\n")
        files[(query, map_)] = path
    return laps, files


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary", nargs="?", default=os.path.join(HERE, "..", "build", "release", "src", "seqtopo"))
    ap.add_argument("--data", default=os.path.join(HERE, "..", "..", "shared", "data"))
    ap.add_argument("--only", choices=["corridor", "nordland"])
    args = ap.parse_args()
    rows, map_rows = [], []
    with tempfile.TemporaryDirectory(prefix="seqtopo-parity-") as scratch:
        cases = []
        if args.only in (None, "corridor"):
            (lap1, lap2), truth = corridor_laps(args.data, scratch)
            cases.append(("corridor lap 2 in lap 1", lap1, lap2, ["--ground-truth", truth[("lap2", "lap1")]]))
            cases.append(("corridor lap 1 in lap 2", lap2, lap1, ["--ground-truth", truth[("lap1", "lap2")]]))
        if args.only in (None, "nordland"):
            nordland = os.path.join(args.data, "nordland-64x32")
            summer, winter = os.path.join(nordland, "summer"), os.path.join(nordland, "winter")
            cases.append(("Nordland winter in summer", summer, winter, ["--ground-truth", "same-index"]))
            cases.append(("Nordland summer in winter", winter, summer, ["--ground-truth", "same-index"]))
        for name, map_, query, truth in cases:
            for mode in ("offline", "online", f"online, --lag {LAG}"):
                for descriptor in (None, "joint-histogram", "patch"):
                    if mode.startswith("online,") and descriptor:
                        continue  # the lag with the default descriptors only
                    extra = [] if mode == "offline" else ["--online"]
                    if mode.startswith("online,"):
                        extra += ["--lag", str(LAG)]
                    if descriptor:
                        extra += ["--descriptor", descriptor]
                    out = os.path.join(scratch, "out")
                    m = run(args.binary, ["localize", "--map", map_, "--query", query, *truth, *extra], out)
                    d = m.get("in_map", {})
                    rows.append((name, mode, descriptor or "default (fused)", m["recall_at_1"],
                                 m["recall_at_100_precision"], m.get("calibration", {}).get("ece", float("nan")),
                                 d.get("frames", 0), d.get("precision", float("nan")),
                                 m["baselines"]["seqslam"]["recall_at_1"]))
        if args.only in (None, "corridor"):
            corridor = os.path.join(args.data, "rtabmap-corridor")
            gt = ["--ground-truth", os.path.join(corridor, "ground_truth.bmp")]
            for mode in ("offline", "online"):
                out = os.path.join(scratch, "map")
                extra = ["--online"] if mode == "online" else []
                subprocess.run([args.binary, "map", corridor, *gt, *extra, "--out", out], check=True,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                with open(os.path.join(out, "online.json" if mode == "online" else "metrics.json")) as f:
                    m = json.load(f)
                lc = m["metrics"] if mode == "online" else m["loop_closure"]
                map_rows.append(("corridor (84 frames)", mode, lc["precision"], lc["recall"], lc["f1"]))
    print("| traversals | mode | descriptors | R@1 | R@100P | ECE | in the map | its precision | SeqSLAM R@1 |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r[0]} | {r[1]} | {r[2]} | {r[3]:.3f} | {r[4]:.3f} | {r[5]:.3f} | {r[6]} | {r[7]:.3f} | {r[8]:.3f} |")
    if map_rows:
        print()
        print("| sequence | map | precision | recall | F1 |")
        print("|---|---|---|---|---|")
        for r in map_rows:
            print(f"| {r[0]} | {r[1]} | {r[2]:.3f} | {r[3]:.3f} | {r[4]:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
