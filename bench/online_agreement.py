#!/usr/bin/env python3
"""How often the online map's loop closures differ from the offline map's (bench/online.sh): per image, its best
loop closure online (online_loop_closures.csv) against offline (loop_closures.csv) of one output folder."""
import csv
import sys


def best(path, score):
    out = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            i, j, c = int(row["i"]), int(row["j"]), float(row[score])
            if i not in out or c > out[i][1]:
                out[i] = (j, c)
    return out


folder = sys.argv[1]
online = best(f"{folder}/online_loop_closures.csv", "confidence")
offline = best(f"{folder}/loop_closures.csv", "confidence")
both = set(online) & set(offline)
near = sum(1 for i in both if abs(online[i][0] - offline[i][0]) <= 2)
print(f"images with a loop closure: online {len(online)}, offline {len(offline)}, both {len(both)} "
      f"({near} within 2 frames of each other), online only {len(set(online) - set(offline))}, "
      f"offline only {len(set(offline) - set(online))}")
