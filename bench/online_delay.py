#!/usr/bin/env python3
"""Revisit detection delay of `seqtopo map --online` (bench/online.sh): for every true revisit (a run of frames
that each have a ground-truth partner at least SEP frames earlier, within RADIUS metres in poses.csv), the frames
from its first frame until the first correct loop closure of one of its frames is emitted (events.jsonl's
`frame`). Prints the median, the 90th percentile and the maximum over the revisits, and how many were found;
then the same for the earliest report, a correct loop closure or a correct revisit candidate (`revisit_candidate`,
its cell the same place), and how many candidates were confirmed, withdrawn, and correct (their cell the same
place)."""
import collections
import json
import sys


def main():
    events_path, poses_path = sys.argv[1], sys.argv[2]
    radius, sep, min_len = float(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]) if len(sys.argv) > 5 else 10
    pos = []
    with open(poses_path) as f:
        next(f)
        for line in f:
            parts = line.strip().split(",")
            pos.append((float(parts[1]), float(parts[2])))
    cell = collections.defaultdict(list)
    partner = []
    for i, (x, y) in enumerate(pos):
        cx, cy = int(x // radius), int(y // radius)
        found = False
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for j in cell.get((cx + dx, cy + dy), ()):
                    if i - j >= sep and (pos[j][0] - x) ** 2 + (pos[j][1] - y) ** 2 <= radius * radius:
                        found = True
                        break
                if found:
                    break
            if found:
                break
        partner.append(found)
        cell[(cx, cy)].append(i)
    segments, start = [], None
    for i, p in enumerate(partner + [False]):
        if p and start is None:
            start = i
        elif not p and start is not None:
            if i - start >= min_len:
                segments.append((start, i))
            start = None

    def same(i, j):
        return (pos[i][0] - pos[j][0]) ** 2 + (pos[i][1] - pos[j][1]) ** 2 <= radius * radius

    first, earliest = {}, {}
    candidates, confirmed, withdrawn, correct = 0, 0, 0, 0
    with open(events_path) as f:
        for line in f:
            e = json.loads(line)
            kind = e["event"]
            if kind == "revisit_candidate":
                candidates += 1
                correct += same(e["i"], e["j"])
            elif kind == "revisit_begin" and "candidate" in e:
                confirmed += 1
            elif kind == "correction" and "candidate" in e:
                withdrawn += 1
            if kind not in ("loop_closure", "revisit_candidate") or not same(e["i"], e["j"]):
                continue
            for k, (b, end) in enumerate(segments):
                if b <= e["i"] < end:
                    earliest.setdefault(k, e["frame"] - b)
                    if kind == "loop_closure":
                        first.setdefault(k, e["frame"] - b)

    def summary(found):
        delays = sorted(found.values())
        if not delays:
            return f"revisits {len(segments)}, none detected"
        n = len(delays)
        median = delays[n // 2] if n % 2 else 0.5 * (delays[n // 2 - 1] + delays[n // 2])
        p90 = delays[min(n - 1, int(0.9 * n))]
        return f"revisits {len(segments)}, detected {n}, delay median {median} p90 {p90} max {delays[-1]} frames"

    print("loop closures: " + summary(first))
    print("first report (loop closure or candidate): " + summary(earliest))
    print(f"candidates {candidates}: confirmed {confirmed}, withdrawn {withdrawn}, their cell the same place {correct}")


if __name__ == "__main__":
    main()
