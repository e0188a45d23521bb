"""01: descriptors from a NumPy array -> similarity -> topological map -> a figure (PNG).

A robot walks places 0..59, a new stretch 60..69, places 15..39 again in the same direction, another new
stretch 70..79 and places 55..42 again backwards. Each place has its own appearance (a random descriptor); every visit sees it with noise.
seqtopo compares every pair of images, finds the revisited stretches by local alignment (forward and
reverse) and merges the images of each revisited place into one place label.

    /usr/bin/python3 examples/python/01_descriptors_to_map.py [OUT.png]
"""

import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import seqtopo  # noqa: E402


def walk(seed: int = 7, dim: int = 48):
    rng = np.random.default_rng(seed)
    appearance = rng.random((80, dim)) + 0.1
    route = np.concatenate([np.arange(0, 60), np.arange(60, 70), np.arange(15, 40), np.arange(70, 80),
                            np.arange(55, 41, -1)])
    descriptors = appearance[route] + 0.25 * rng.random((len(route), dim))
    return descriptors.astype(np.float32), route


def main(out: str = "seqtopo-map.png") -> None:
    descriptors, route = walk()

    # 1. Similarity S = 1 - kappa * D of every pair (cosine distance; kappa chosen from the data).
    s = seqtopo.similarity(descriptors)
    # 2. Alignments -> pruning -> place labels -> topology, with the library's default settings.
    result = seqtopo.build_map(s.similarity, seqtopo.MapConfig())

    kept = [a for a, k in zip(result.alignments, result.kept) if k]
    print(f"{result.images} images, kappa {s.kappa:.3g}: {len(result.alignments)} alignments ({len(kept)} kept), "
          f"{len(result.places)} places, {len(result.junctions)} junctions, "
          f"{len(result.loop_closures)} loop-closure pairs")

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 5), constrained_layout=True)
    left.imshow(result.scores, cmap="gray", interpolation="nearest")
    for a, k in zip(result.alignments, result.kept):
        left.plot(a.pairs[:, 1], a.pairs[:, 0], color="red" if k else "tab:blue", linewidth=2,
                  label=f"{a.direction} ({'kept' if k else 'pruned'})")
    handles, labels = left.get_legend_handles_labels()
    unique = dict(zip(labels, handles))
    left.legend(unique.values(), unique.keys(), loc="lower left", fontsize=8)
    left.set_title("Aligned scores (contrast-enhanced S) and alignments")
    left.set_xlabel("image j")
    left.set_ylabel("image i")

    # Every image's place label against the place it really saw: a revisited place gets one label.
    right.scatter(route, result.labels, s=12, c=np.arange(result.images), cmap="viridis")
    right.set_xlabel("true place (simulation)")
    right.set_ylabel("place label found by seqtopo")
    right.set_title(f"{len(result.places)} places from {result.images} images")
    fig.savefig(out, dpi=100)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
