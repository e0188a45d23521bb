#!/usr/bin/env python3
"""The default map on smooth descriptors with a planted revisit, at several frame rates: AR(1) sequences with a
correlation length of 3, 10 and 30 frames and a random walk (1,600 frames, 64-D), whose frames 1,001-1,160 repeat
200-359 (forward or backwards) with noise of 0.5 of the descriptors' spread, mapped with --every 1 to 4.
The ground truth counts only the nearest frame kept (radius every / 2 frames): a map that pairs a frame with the
neighbour of its own partner is wrong here, as it would be with a tight radius in metres.

Usage: bench/smooth_revisits.py [SEQTOPO_BINARY] [--seeds 3] [--online]
Prints one Markdown row per texture: seqtopo's F1 mean and worst over directions, rates and seeds, and the
SeqSLAM-style baseline's mean F1 on the same scores (with --online: the online map's loop closures, no baseline).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

import numpy as np


def sequence(folder, texture, length, reverse, seed, n=1600, revisit=160, dim=64):
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n, dim))
    if texture == "walk":
        x = np.cumsum(e, axis=0)
    else:
        rho = np.exp(-1 / length)
        x = np.empty_like(e)
        x[0] = e[0]
        for i in range(1, n):
            x[i] = rho * x[i - 1] + np.sqrt(1 - rho * rho) * e[i]
    pos = np.arange(n, dtype=float)
    src, dst = n // 8, n // 2 + n // 8 + 1  # an odd offset: the kept frames of the two laps differ in phase
    for k in range(revisit):
        s = src + (revisit - 1 - k if reverse else k)
        x[dst + k] = x[s] + 0.5 * rng.standard_normal(dim) * x[s].std()
        pos[dst + k] = pos[s]
    pos[dst + revisit:] += 10 * n
    os.makedirs(folder, exist_ok=True)
    np.save(os.path.join(folder, "x.npy"), x.astype(np.float32))
    with open(os.path.join(folder, "poses.csv"), "w") as f:
        f.write("index,x,y\n" + "".join(f"{i},{p},0\n" for i, p in enumerate(pos)))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("binary", nargs="?", default=os.path.join(here, "..", "build", "release", "src", "seqtopo"))
    p.add_argument("--seeds", type=int, default=3)
    p.add_argument("--online", action="store_true", help="score `seqtopo map --online`'s loop closures")
    args = p.parse_args()
    mode = ["--online", "--no-offline-outputs"] if args.online else []
    print("| texture | maps | seqtopo F1 mean | worst | SeqSLAM-style F1 mean |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as root:
        for texture, length in (("AR(1), 3 frames", 3), ("AR(1), 10 frames", 10), ("AR(1), 30 frames", 30),
                                ("random walk", 0)):
            ours, baseline = [], []
            for reverse in (False, True):
                for every in (1, 2, 3, 4):
                    for seed in range(1, args.seeds + 1):
                        folder = os.path.join(root, f"{length}_{reverse}_{every}_{seed}")
                        sequence(folder, "walk" if length == 0 else "ar1", length, reverse, seed)
                        r = subprocess.run([args.binary, "map", os.path.join(folder, "x.npy"), "--every", str(every),
                                            "--ground-truth", os.path.join(folder, "poses.csv"), "--gt-radius",
                                            str(every / 2 + 0.01), "--out", os.path.join(folder, "out"), *mode],
                                           capture_output=True, text=True)
                        if r.returncode != 0:
                            sys.exit(r.stderr.strip().splitlines()[-1])
                        if args.online:
                            with open(os.path.join(folder, "out", "online.json")) as f:
                                ours.append(json.load(f)["metrics"]["f1"])
                            continue
                        with open(os.path.join(folder, "out", "metrics.json")) as f:
                            m = json.load(f)
                        ours.append(m["loop_closure"]["f1"])
                        baseline.append(m["baseline"]["f1"])
            base = "—" if args.online else f"{statistics.mean(baseline):.3f}"
            print(f"| {texture} | {len(ours)} | {statistics.mean(ours):.3f} | {min(ours):.3f} | {base} |", flush=True)


if __name__ == "__main__":
    main()
