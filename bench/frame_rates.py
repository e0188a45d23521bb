#!/usr/bin/env python3
"""The default map at other frame rates: the bundled corridor and Nordland (summer + winter as one sequence) as
recorded, every 2nd frame, and every frame repeated, each with its ground truth resampled the same way; and, when
ffmpeg is on the PATH, the corridor as a video (H.264 and Motion JPEG, 10 fps) as recorded, at --every 2 (with
the whole recording's ground truth, which --every thins) and with every frame 5 times.

Usage: bench/frame_rates.py [SEQTOPO_BINARY] [--data ../shared/data] [--repeat-nordland]
Prints one Markdown table: seqtopo's F1, precision, recall and the SeqSLAM-style baseline's F1 (docs/significance.md).
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image


def corridor_variant(root, data, name, frames):
    folder = os.path.join(root, f"corridor_{name}")
    os.makedirs(folder)
    src = os.path.join(data, "rtabmap-corridor")
    for new, old in enumerate(frames):
        os.symlink(os.path.join(src, f"{old + 1}.jpg"), os.path.join(folder, f"{new:05d}.jpg"))
    truth = np.array(Image.open(os.path.join(src, "ground_truth.bmp")))
    if truth.ndim == 3:
        truth = truth[..., 0]
    index = np.array(frames)
    Image.fromarray(truth[index[:, None], index[None, :]].astype(np.uint8)).save(folder + "_gt.png")
    return folder, ["--ground-truth", folder + "_gt.png"]


def corridor_video(codec):
    """A maker of the corridor variant's frames as a video, encoded with ffmpeg (`codec`: its -c:v arguments)."""
    def make(root, data, name, frames):
        folder, truth = corridor_variant(root, data, f"{name}_{codec[1]}", frames)
        video = folder + (".mp4" if codec[1] == "libx264" else ".avi")
        subprocess.run(["ffmpeg", "-loglevel", "error", "-y", "-framerate", "10", "-i",
                        os.path.join(folder, "%05d.jpg"), *codec, video], check=True)
        return video, truth
    return make


def nordland_variant(root, data, name, frames):
    folder = os.path.join(root, f"nordland_{name}")
    os.makedirs(folder)
    src = os.path.join(data, "nordland-64x32")
    names = sorted(os.listdir(os.path.join(src, "summer")))
    with open(folder + "_poses.csv", "w") as poses:
        poses.write("index,x,y,theta\n")
        for new, old in enumerate(frames):
            season = "summer" if old < len(names) else "winter"
            os.symlink(os.path.join(src, season, names[old % len(names)]), os.path.join(folder, f"{new:05d}.png"))
            poses.write(f"{new},{old % len(names)},0,0\n")
    return folder, ["--ground-truth", folder + "_poses.csv", "--gt-radius", "2"]


def map_folder(binary, folder, args, out):
    """`seqtopo map FOLDER ARGS --out OUT`: (metrics.json, alignments.json' significance), or the error's last line."""
    r = subprocess.run([binary, "map", folder, *args, "--out", out], capture_output=True, text=True)
    if r.returncode != 0:
        return None, None, r.stderr.strip().splitlines()[-1]
    with open(os.path.join(out, "metrics.json")) as f:
        metrics = json.load(f)
    with open(os.path.join(out, "alignments.json")) as f:
        significance = json.load(f)["significance"]
    return metrics, significance, None


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("binary", nargs="?", default=os.path.join(here, "..", "build", "release", "src", "seqtopo"))
    p.add_argument("--data", default=os.path.join(here, "..", "..", "shared", "data"))
    p.add_argument("--repeat-nordland", action="store_true", help="also Nordland with every frame 3 times (10,800)")
    a = p.parse_args()
    corridor = 84
    nordland = 2 * len(os.listdir(os.path.join(a.data, "nordland-64x32", "summer")))
    cases = [
        ("corridor", corridor_variant, "native", list(range(corridor))),
        ("corridor, every 2nd frame", corridor_variant, "every2", list(range(0, corridor, 2))),
        ("corridor, every 2nd frame from frame 1", corridor_variant, "odd2", list(range(1, corridor, 2))),
        ("corridor, each frame 5 times", corridor_variant, "x5", [k for k in range(corridor) for _ in range(5)]),
        ("Nordland", nordland_variant, "native", list(range(nordland))),
        ("Nordland, every 2nd frame", nordland_variant, "every2", list(range(0, nordland, 2))),
    ]
    if shutil.which("ffmpeg"):
        for label, codec in (("H.264", ["-c:v", "libx264", "-pix_fmt", "yuv420p"]),
                             ("Motion JPEG", ["-c:v", "mjpeg", "-q:v", "3"])):
            video = corridor_video(codec)
            cases += [
                (f"corridor video ({label})", video, "video", list(range(corridor))),
                (f"corridor video ({label}), --every 2", video, "video", list(range(corridor)), ["--every", "2"]),
                (f"corridor video ({label}), each frame 5 times", video, "video_x5",
                 [k for k in range(corridor) for _ in range(5)]),
            ]
    if a.repeat_nordland:
        cases.append(("Nordland, each frame 3 times", nordland_variant, "x3",
                      [k for k in range(nordland) for _ in range(3)]))
    print("| sequence | frames | seqtopo F1 | precision | recall | SeqSLAM-style F1 | frames per place |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as root:
        for n, (label, make, name, frames, *extra) in enumerate(cases):
            frames_made = os.path.join(root, f"case{n}")
            os.makedirs(frames_made)
            folder, truth = make(frames_made, a.data, name, frames)
            out = os.path.join(root, f"out{n}")
            args = extra[0] if extra else []
            every = int(args[args.index("--every") + 1]) if "--every" in args else 1
            shown = (len(frames) + every - 1) // every
            m, significance, error = map_folder(a.binary, folder, truth + args, out)
            if error:
                print(f"| {label} | {shown} | failed: {error} | | | | |")
                continue
            fpp = significance["frames_per_place"]
            lc, base = m["loop_closure"], m.get("baseline", {})
            print(f"| {label} | {shown} | {lc['f1']:.3f} | {lc['precision']:.3f} | {lc['recall']:.3f} | "
                  f"{base.get('f1', float('nan')):.3f} | {fpp:.2f} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
