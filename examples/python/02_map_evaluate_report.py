"""Map the bundled corridor walk, score it against its ground truth, write the interactive report; then localize
the walk's second half in its first half and score that too. Each result prints as a one-line summary.

    PYTHONPATH=build/release/python python3 examples/python/02_map_evaluate_report.py out/
"""

import os
import sys
import tempfile

import seqtopo

HERE = os.path.dirname(os.path.abspath(__file__))
CORRIDOR = os.path.join(HERE, "..", "..", "data", "rtabmap-corridor")


def main(out: str) -> None:
    # The whole `seqtopo map` job: similarity, alignments, places and topology, accuracy beside the baseline.
    run = seqtopo.map_sequence(CORRIDOR, ground_truth=os.path.join(CORRIDOR, "ground_truth.bmp"))
    print(run)
    print(run.map)
    print(run.map.alignments[0])
    seqtopo.write_report(run, os.path.join(out, "map"))  # report.html: hover a loop closure to see its images

    # Localization: images 41-84 (the second walk) in images 1-40 (the first); query q is map frame q.
    with tempfile.TemporaryDirectory() as folder:
        for name, images in (("first", range(1, 41)), ("second", range(41, 85))):
            os.makedirs(os.path.join(folder, name))
            for k in images:
                os.symlink(os.path.abspath(os.path.join(CORRIDOR, "%d.jpg" % k)),
                           os.path.join(folder, name, "%d.jpg" % k))
        located = seqtopo.localize_sequences(os.path.join(folder, "first"), os.path.join(folder, "second"),
                                             ground_truth=[(q, q) for q in range(40)])
        print(located)
        seqtopo.write_report(located, os.path.join(out, "localize"))
    print("reports in", out)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "seqtopo-example-out")
