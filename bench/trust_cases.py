#!/usr/bin/env python3
"""Trust on data nobody tuned on: sequences without a revisit that look like they have one, revisits through
low-information stretches, and the calibration of the confidences, each mapped by `seqtopo map` with its ground truth.

Cases (every one made from the real data in ../shared/data, changed as a new user's recording would be):
  * single passes with no revisit: the bundled corridor's two laps alone, each Nordland season alone;
  * tunnels: a Nordland season with a run of tunnels (near-black frames with a faint drifting light, alternating
    with daylight) spliced over 120 frames, alone (no revisit) and in the summer + winter map (the same tunnels in
    both seasons: a revisit through them), at several seeds;
  * low-information stretches: the corridor with two 60-frame dark stretches, one in each lap, and an unrelated
    outdoor walk (Nordland frames) spliced between the laps; the revisit frames on either side of the dark
    stretches should still be closed;
  * the real sequences with a revisit (corridor, Nordland summer + winter).

Usage: bench/trust_cases.py [SEQTOPO_BINARY] [--data ../shared/data] [--seeds 1 2 3] [--only NAME ...]
Prints one Markdown table: loop closures (pairs, images), F1, R@100P, ECE and the recall kept where it applies.
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


def write_gt(path, truth):
    Image.fromarray((truth > 0).astype(np.uint8) * 255).save(path)


def corridor_truth(data):
    truth = np.array(Image.open(os.path.join(data, "rtabmap-corridor", "ground_truth.bmp")))
    return truth[..., 0] if truth.ndim == 3 else truth


def corridor_frames(data):
    return [Image.open(os.path.join(data, "rtabmap-corridor", f"{k}.jpg")).convert("RGB") for k in range(1, 85)]


def nordland_frames(data, season):
    folder = os.path.join(data, "nordland-64x32", season)
    return [Image.open(os.path.join(folder, n)).convert("RGB") for n in sorted(os.listdir(folder))]


def dark_frame(rng, size, light, t):
    """A near-black frame with a faint light that drifts with t (a lamp, the tunnel's mouth)."""
    w, h = size
    yy, xx = np.mgrid[0:h, 0:w]
    cx = w * (0.5 + 0.25 * np.sin(0.3 * t + light))
    cy = h * (0.45 + 0.1 * np.cos(0.2 * t))
    glow = (8 + 25 * rng.random()) * np.exp(-((xx - cx) ** 2 + (yy - cy) ** 2) / (2 * (0.08 * w) ** 2))
    img = 6 + 3 * rng.standard_normal((h, w)) + glow
    img = np.clip(img, 0, 255).astype(np.uint8)
    return Image.fromarray(np.stack([img] * 3, axis=-1))


def tunnel_pattern(seed, length):
    """Which frames of a stretch of `length` are inside a tunnel: tunnels of 2-8 frames between 1-5 of daylight."""
    rng = np.random.default_rng(1000 + seed)
    dark = np.zeros(length, bool)
    k = 0
    while k < length:
        k += int(rng.integers(1, 6))
        n = int(rng.integers(2, 9))
        dark[k:k + n] = True
        k += n
    return dark


def with_tunnels(frames, start, pattern, seed):
    rng = np.random.default_rng(seed)
    out = list(frames)
    for k, d in enumerate(pattern):
        if d:
            out[start + k] = dark_frame(rng, frames[start + k].size, seed, k)
    return out


def save_folder(root, name, frames):
    folder = os.path.join(root, name)
    os.makedirs(folder)
    ext = "png"  # lossless: the frames as decoded
    for k, f in enumerate(frames):
        f.save(os.path.join(folder, f"{k:05d}.{ext}"))
    return folder


def run_map(seqtopo, folder, out, gt_args):
    cmd = [seqtopo, "map", folder, "--out", out, *gt_args]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit(f"trust_cases.py: {' '.join(cmd)} failed:\n{p.stderr}")
    pairs = []
    with open(os.path.join(out, "loop_closures.csv")) as f:
        next(f)
        for line in f:
            cols = line.strip().split(",")
            pairs.append((int(cols[0]), int(cols[1])))
    metrics = {}
    if os.path.exists(os.path.join(out, "metrics.json")):
        with open(os.path.join(out, "metrics.json")) as f:
            metrics = json.load(f)
    return pairs, metrics


def nordland_gt(root, name, indices):
    """Same place <=> same frame index of the route, within 2 frames (the usual tolerance)."""
    path = os.path.join(root, name + "_poses.csv")
    with open(path, "w") as f:
        f.write("index,x,y,theta\n")
        for k, i in enumerate(indices):
            f.write(f"{k},{i},0,0\n")
    return ["--ground-truth", path, "--gt-radius", "2"]


def closed_images(pairs):
    return {max(i, j) for i, j in pairs}


def main():
    ap = argparse.ArgumentParser()
    default_bin = os.path.join(HERE, "..", "build", "release", "src", "seqtopo")
    ap.add_argument("seqtopo", nargs="?", default=default_bin)
    ap.add_argument("--data", default=os.path.join(HERE, "..", "..", "shared", "data"))
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--only", nargs="+", default=None)
    ap.add_argument("--keep", default=None, help="keep the cases and maps in this folder")
    args = ap.parse_args()
    root = args.keep or tempfile.mkdtemp(prefix="trust_")
    os.makedirs(root, exist_ok=True)
    rows = []

    def want(name):
        return args.only is None or any(name.startswith(o) for o in args.only)

    def row(name, pairs, metrics, extra=""):
        lc = metrics.get("loop_closure", {})
        cal = lc.get("calibration", metrics.get("calibration", {}))
        ece = cal.get("ece", cal.get("expected_calibration_error", float("nan"))) if isinstance(cal, dict) else float("nan")
        fmt = lambda v: "—" if v is None or (isinstance(v, float) and np.isnan(v)) else f"{v:.3f}"
        rows.append(f"| {name} | {len(pairs)} ({len(closed_images(pairs))}) | {fmt(lc.get('f1'))} | "
                    f"{fmt(lc.get('recall_at_100_precision'))} | {fmt(ece)} | {extra} |")
        print(rows[-1], file=sys.stderr)

    corridor = corridor_frames(args.data)
    truth = corridor_truth(args.data)
    summer = nordland_frames(args.data, "summer")
    winter = nordland_frames(args.data, "winter")
    n = len(summer)

    if want("corridor"):
        folder = save_folder(root, "corridor", corridor)
        write_gt(folder + "_gt.png", truth)
        clean_pairs, m = run_map(args.seqtopo, folder, folder + "_map", ["--ground-truth", folder + "_gt.png"])
        row("corridor (84 frames)", clean_pairs, m)
        for name, lo, hi in (("corridor lap 1 alone", 0, 40), ("corridor lap 2 alone", 40, 84)):
            folder = save_folder(root, name.replace(" ", "_"), corridor[lo:hi])
            write_gt(folder + "_gt.png", truth[lo:hi, lo:hi])
            pairs, m = run_map(args.seqtopo, folder, folder + "_map", ["--ground-truth", folder + "_gt.png"])
            row(name, pairs, m)
        # Low-information stretches, 60 dark frames in each lap: at the same place (a tunnel driven through twice,
        # its frames the same place as the frames of the other pass at the same depth, within 2 frames) or at two
        # different places (the lights out in two corridors), with an unrelated outdoor walk spliced in.
        walk = [f.resize((512, 384)) for f in winter[600:660]]
        for variant, cut1, cut2 in (("the same place", 20, 60), ("two places", 10, 75)):
            # The walk before the first lap: between the laps it would cut the revisit of images 81-84 (0-based
            # 80-83) to 41-44, which follow image 40 without a break.
            order = [("w", k) for k in range(60)] + list(range(0, cut1)) + [("d1", k) for k in range(60)] + \
                list(range(cut1, cut2)) + [("d2", k) for k in range(60)] + list(range(cut2, 84))
            frames = []
            for o in order:
                if isinstance(o, int):
                    frames.append(corridor[o])
                elif o[0] == "w":
                    frames.append(walk[o[1]])
                else:
                    seed = 1 if o[0] == "d1" else 2
                    frames.append(dark_frame(np.random.default_rng(seed * 100 + o[1]), (512, 384), seed, o[1]))
            m = len(order)
            gt = np.zeros((m, m), np.uint8)
            for a in range(m):
                for b in range(m):
                    oa, ob = order[a], order[b]
                    if isinstance(oa, int) and isinstance(ob, int):
                        gt[a, b] = truth[oa, ob]
                    elif variant == "the same place" and not isinstance(oa, int) and not isinstance(ob, int) and \
                            {oa[0], ob[0]} == {"d1", "d2"} and abs(oa[1] - ob[1]) <= 2:
                        gt[a, b] = 255
            name = "corridor_dark_" + variant.replace(" ", "_")
            folder = save_folder(root, name, frames)
            write_gt(folder + "_gt.png", gt)
            pairs, met = run_map(args.seqtopo, folder, folder + "_map", ["--ground-truth", folder + "_gt.png"])
            clean = closed_images(clean_pairs)
            kept = {order[i] for i in closed_images(pairs) if isinstance(order[i], int)} & clean
            false = sum(1 for i, j in pairs if gt[max(i, j), min(i, j)] == 0)
            row(f"corridor, dark stretches at {variant} + a walk", pairs, met,
                f"{len(kept)} of {len(clean)} kept, {false} false pairs")

    if want("nordland"):
        for season, frames in (("summer", summer), ("winter", winter)):
            folder = save_folder(root, f"nordland_{season}", frames)
            pairs, m = run_map(args.seqtopo, folder, folder + "_map", nordland_gt(root, f"nordland_{season}", range(n)))
            row(f"Nordland {season} alone", pairs, m)
        folder = save_folder(root, "nordland_both", summer + winter)
        pairs, m = run_map(args.seqtopo, folder, folder + "_map",
                           nordland_gt(root, "nordland_both", list(range(n)) * 2))
        row("Nordland summer + winter", pairs, m)

    if want("tunnel"):
        for seed in args.seeds:
            start = 300 + 400 * (seed % 3)
            pattern = tunnel_pattern(seed, 120)
            s = with_tunnels(summer, start, pattern, seed)
            w = with_tunnels(winter, start, pattern, seed + 50)
            for season, frames in (("summer", s), ("winter", w)):
                name = f"tunnels_{season}_{seed}"
                folder = save_folder(root, name, frames)
                pairs, m = run_map(args.seqtopo, folder, folder + "_map", nordland_gt(root, name, range(n)))
                row(f"Nordland {season} with tunnels, seed {seed}", pairs, m)
            name = f"tunnels_both_{seed}"
            folder = save_folder(root, name, s + w)
            pairs, m = run_map(args.seqtopo, folder, folder + "_map", nordland_gt(root, name, list(range(n)) * 2))
            row(f"Nordland summer + winter with tunnels, seed {seed}", pairs, m)

    print("| sequence | loop closures (images) | F1 | R@100P | ECE | |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(r)


if __name__ == "__main__":
    main()
