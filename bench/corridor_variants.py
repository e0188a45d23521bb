#!/usr/bin/env python3
"""The default map on the bundled corridor changed as another camera or another day would change it: smaller and
larger images, grey, noisy, recompressed, in reverse order, and with its second lap darker (each with the ground
truth rearranged to match). Prints one Markdown table: seqtopo's F1 and the SeqSLAM-style baseline's, and which
descriptor the map left out of the fusion, if any (docs/significance.md, "Other cameras and conditions").

Usage: bench/corridor_variants.py [SEQTOPO_BINARY]   (needs numpy and PIL: /usr/bin/python3 on Debian)
"""
import os
import sys
import tempfile

import numpy as np
from PIL import Image, ImageEnhance

from frame_rates import map_folder

FRAMES = 84


def variants(rng):
    return [
        ("as recorded", lambda im, k: im, None),
        ("160 x 120", lambda im, k: im.resize((160, 120)), None),
        ("1024 x 768", lambda im, k: im.resize((1024, 768)), None),
        ("grey", lambda im, k: im.convert("L").convert("RGB"), None),
        ("Gaussian noise, 20 grey levels",
         lambda im, k: Image.fromarray(np.clip(np.asarray(im, float) + rng.normal(0, 20, np.asarray(im).shape), 0,
                                               255).astype(np.uint8)), None),
        ("JPEG quality 10", lambda im, k: im, 10),
        ("frames in reverse order", lambda im, k: im, "reverse"),
        ("second lap 40 % darker", lambda im, k: ImageEnhance.Brightness(im).enhance(0.6) if k >= 40 else im, None),
    ]


def make(root, data, name, change, special):
    folder = os.path.join(root, name.replace(" ", "_").replace("%", "pc"))
    os.makedirs(folder)
    order = list(range(FRAMES - 1, -1, -1)) if special == "reverse" else list(range(FRAMES))
    quality = special if isinstance(special, int) else 90
    for new, old in enumerate(order):
        image = change(Image.open(os.path.join(data, f"{old + 1}.jpg")).convert("RGB"), old)
        image.save(os.path.join(folder, f"{new:05d}.jpg"), quality=quality)
    truth = np.array(Image.open(os.path.join(data, "ground_truth.bmp")))
    if truth.ndim == 3:
        truth = truth[..., 0]
    index = np.array(order)
    moved = truth[index[:, None], index[None, :]]
    moved = np.tril(np.maximum(moved, moved.T))  # the later image of each pair first, as the original
    Image.fromarray(moved.astype(np.uint8)).save(folder + "_gt.png")
    return folder


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    binary = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "build", "release", "src", "seqtopo")
    data = os.path.join(here, "..", "data", "rtabmap-corridor")
    rng = np.random.default_rng(0)
    print("| corridor variant | seqtopo F1 | SeqSLAM-style F1 | left out of the fusion |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory() as root:
        for name, change, special in variants(rng):
            folder = make(root, data, name, change, special)
            out = folder + "_out"
            m, significance, error = map_folder(binary, folder, ["--ground-truth", folder + "_gt.png"], out)
            if error:
                print(f"| {name} | failed: {error} | | |")
                continue
            blind = significance.get("blind_descriptors", [])
            names = ["joint histogram", "patch thumbnail"]
            print(f"| {name} | {m['loop_closure']['f1']:.3f} | {m.get('baseline', {}).get('f1', float('nan')):.3f} | "
                  f"{', '.join(names[k] for k in blind) or '—'} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
