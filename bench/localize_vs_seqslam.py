#!/usr/bin/env python3
"""`seqtopo localize` against TimQuelch/seqslam's CPU driver on the same two image folders, both directions, runs
alternating in one script (BENCHMARK.md, "Localization against SeqSLAM"). The machine is shared: the medians of
CPU time (user + sys of the process and its children) are compared as a ratio.

  bench/localize_vs_seqslam.py SEQTOPO TQ_SEQSLAM_CPU FOLDER_A FOLDER_B [--runs 3] [--tolerance 2] [-- options...]

TQ_SEQSLAM_CPU is the peer's driver, built by its build.sh from github.com/TimQuelch/seqslam at 38311ac (sequence
30, velocities 0.9-1.6, 15 trajectories, enhancement window 10, CLAHE 20: its defaults). Both run with what a
user runs: seqtopo without ground truth (no baselines to score), the peer on one thread as it is written. R@1 is
scored here for both from their result files, on the same rule: query frame k is right when its best map frame is
within --tolerance frames of k (frames in the same order in both folders); a frame either leaves unscored is
wrong. Options after -- go to `seqtopo localize`."""
import argparse
import csv
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile


def cpu_of(command):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(command, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit(f"{command[0]} failed:\n{p.stderr}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def recall_at_1(path, queries, tolerance, query_column="query", map_column="map"):
    right = 0
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row[map_column] == "":
                continue
            right += abs(int(row[map_column]) - int(row[query_column])) <= tolerance
    return right / queries


def main():
    argv = sys.argv[1:]
    extra = []
    if "--" in argv:
        split = argv.index("--")
        argv, extra = argv[:split], argv[split + 1:]
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("seqtopo")
    ap.add_argument("peer")
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--tolerance", type=int, default=2)
    a = ap.parse_args(argv)
    work = tempfile.mkdtemp(prefix="localize-vs-seqslam-")
    print("| map | query | seqtopo CPU [s] | SeqSLAM CPU [s] | seqtopo / SeqSLAM | seqtopo R@1 | SeqSLAM R@1 |")
    print("|---|---|---|---|---|---|---|")
    for map_dir, query_dir in ((a.a, a.b), (a.b, a.a)):
        queries = len(os.listdir(query_dir))
        ours, theirs = [], []
        out = os.path.join(work, "seqtopo")
        peer_csv = os.path.join(work, "peer.csv")
        for _ in range(a.runs):
            shutil.rmtree(out, ignore_errors=True)
            ours.append(cpu_of([a.seqtopo, "localize", "--map", map_dir, "--query", query_dir, "--out", out, *extra]))
            theirs.append(cpu_of([a.peer, map_dir, query_dir, peer_csv]))
        r_ours = recall_at_1(os.path.join(out, "matches.csv"), queries, a.tolerance)
        r_theirs = recall_at_1(peer_csv, queries, a.tolerance)
        o, t = statistics.median(ours), statistics.median(theirs)
        print(f"| {os.path.basename(os.path.normpath(map_dir))} | {os.path.basename(os.path.normpath(query_dir))} "
              f"| {o:.2f} | {t:.2f} | {o / t:.2f} | {r_ours:.3f} | {r_theirs:.3f} |")
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
