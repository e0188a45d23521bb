"""Progress on stderr, seen as a person sees it: on a pseudo-terminal a bar redrawn in place (carriage returns,
percentage, rate, ETA), through a pipe plain lines (no control characters) with every stage numbered k/n,
announced and timed as it ends, and no silence longer than about 2 s while a long stage runs.

Run by ctest (tests/CMakeLists.txt) with SEQTOPO_CLI (the seqtopo binary) and SEQTOPO_DATA_DIR.
"""

import os
import pty
import re
import select
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

CLI = os.environ.get("SEQTOPO_CLI", "")
DATA = os.environ.get("SEQTOPO_DATA_DIR", "")


def run_on_pty(args, cwd, columns=120):
    """Runs seqtopo with stderr on a pseudo-terminal (stdout a pipe); returns (status, what the terminal got)."""
    master, slave = pty.openpty()
    env = dict(os.environ, COLUMNS=str(columns))
    env.pop("SEQTOPO_PROGRESS", None)
    p = subprocess.Popen([CLI] + args, cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=slave,
                         env=env)
    os.close(slave)
    out = b""
    while True:
        ready, _, _ = select.select([master], [], [], 0.5)
        if ready:
            try:
                chunk = os.read(master, 65536)
            except OSError:  # the child closed the terminal
                break
            if not chunk:
                break
            out += chunk
        elif p.poll() is not None:
            break
    os.close(master)
    return p.wait(timeout=300), out.decode(errors="replace")


def run_on_pipe(args, cwd):
    """Runs seqtopo with stderr on a pipe; returns (status, [(seconds since start, line)])."""
    env = dict(os.environ)
    env.pop("SEQTOPO_PROGRESS", None)
    start = time.monotonic()
    p = subprocess.Popen([CLI] + args, cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, env=env)
    lines = []
    for raw in p.stderr:
        lines.append((time.monotonic() - start, raw.decode(errors="replace").rstrip("\n")))
    return p.wait(timeout=300), lines


def write_loop(folder, frames=3400, dim=32):
    """A route driven twice (descriptors.npy, a smooth random walk) and its poses.csv ground truth."""
    rng = np.random.default_rng(7)
    half = frames // 2
    walk = np.cumsum(rng.normal(size=(half, dim)), axis=0).astype(np.float32)
    walk += rng.normal(scale=3.0, size=(half, dim)).astype(np.float32)
    seq = np.concatenate([walk, walk + rng.normal(scale=1.0, size=walk.shape).astype(np.float32)])
    np.save(os.path.join(folder, "walk.npy"), seq)
    with open(os.path.join(folder, "poses.csv"), "w") as f:
        f.write("index,x,y\n" + "".join("%d,%d,0\n" % (k, k % half) for k in range(frames)))


class Progress(unittest.TestCase):
    def setUp(self):
        self.assertTrue(CLI and os.access(CLI, os.X_OK), "SEQTOPO_CLI=%r is not the seqtopo binary" % CLI)
        self.dir = tempfile.mkdtemp(prefix="seqtopo-progress-")
        self.addCleanup(shutil.rmtree, self.dir, ignore_errors=True)

    def test_a_terminal_sees_a_bar_with_rate_and_eta(self):
        # No input: the bundled corridor with its ground truth, six stages.
        status, screen = run_on_pty(["map", "--out", os.path.join(self.dir, "out")], self.dir)
        self.assertEqual(status, 0, screen[-2000:])
        self.assertIn("\r\x1b[2K", screen, "the bar is not redrawn in place")
        bars = re.findall(r"\[1/6\] similarity \[[=> ]{24}\] +\d+%  \d+/\d+ [a-z ]+  [\d.]+[kM]?/s  ETA [\d:]+ [a-z]+",
                          screen)
        self.assertTrue(bars, "no progress bar with a rate and an ETA:\n" + screen[:3000])
        # Every stage ends with its time on a line of its own, the bar cleared before it.
        for k, name in enumerate(["similarity", "alignments, pruning, labels, topology", "accuracy",
                                  "SeqSLAM-style baseline", "files and figures", "report"], start=1):
            self.assertRegex(screen, r"\x1b\[2Kseqtopo map: \[%d/6\] %s done in [\d.]+ s \(peak memory \d+ MB\)\r?\n" % (k, re.escape(name)))

    def test_a_terminal_of_80_columns_sees_the_percentage_and_eta(self):
        # The full bar (counts, unit, rate, seconds) needs about 115 columns; at 80 it drops parts, never the ETA.
        status, screen = run_on_pty(["map", "--out", os.path.join(self.dir, "out")], self.dir, columns=80)
        self.assertEqual(status, 0, screen[-2000:])
        drawn = [d for d in re.split(r"\r\x1b\[2K", screen)[1:] if "\n" not in d]
        counted = [d for d in drawn if re.search(r"\d+%", d)]
        self.assertTrue(counted, "no bar with a percentage:\n" + screen[:3000])
        for d in drawn:
            self.assertLess(len(d), 80, repr(d))
        for d in counted:
            self.assertRegex(d, r"\d+%.*ETA [\d:]+ [a-z]+", repr(d))

    def test_a_pipe_sees_plain_lines_and_no_long_silence(self):
        # Long enough that one stage (the streamed alignment of 10,000 images) runs past the 2 s of a periodic line
        # even on an idle machine (7,000 took 1.7 s).
        write_loop(self.dir, frames=10000)
        status, lines = run_on_pipe(["map", "walk.npy", "--streaming", "--ground-truth", "poses.csv", "--gt-radius",
                                     "2", "--out", "out", "--threads", "2"], self.dir)
        text = "\n".join(l for _, l in lines)
        self.assertEqual(status, 0, text[-3000:])
        self.assertNotIn("\r", text)
        self.assertNotIn("\x1b", text)
        self.assertTrue(all(l.startswith("seqtopo map: ") for _, l in lines), text)
        # Consistent numbering: every stage k of n starts and ends, k = 1..n in order, n the same throughout.
        begun, ended = [], []
        for _, line in lines:
            done = re.match(r"seqtopo map: \[(\d+)/(\d+)\] .* done in ([\d.]+) s \(peak memory \d+ MB\)$", line)
            start = re.match(r"seqtopo map: \[(\d+)/(\d+)\] [^:]*$", line)
            if done:
                ended.append((int(done.group(1)), int(done.group(2)), float(done.group(3))))
            elif start:
                begun.append((int(start.group(1)), int(start.group(2))))
        n = begun[0][1]
        self.assertEqual(begun, [(k, n) for k in range(1, n + 1)], text)
        self.assertEqual([(k, m) for k, m, _ in ended], [(k, n) for k in range(1, n + 1)], text)
        # No silence longer than about 2 s (the stage lines come at least every 2 s while a stage runs).
        times = [t for t, _ in lines]
        gaps = [b - a for a, b in zip(times, times[1:])]
        self.assertLess(max(gaps), 2.6, "silent for %.1f s:\n%s" % (max(gaps), text))
        self.assertGreater(times[-1], 2.0, "the run is too short to show the periodic lines")
        periodic = [l for _, l in lines if re.search(r": (running, \d+ s|\d+% \()", l)]
        self.assertTrue(periodic, "no periodic line in a run of %.1f s:\n%s" % (times[-1], text))
        # The stages' times add up to the report's wall time.
        report = open(os.path.join(self.dir, "out", "report.html"), encoding="utf-8").read()
        rows = re.findall(r"<tr><td>([^<]*)</td><td>([\d.]+)</td></tr>", report)
        seconds = {name: float(v) for name, v in rows}
        wall = seconds.pop("wall time")
        self.assertAlmostEqual(sum(seconds.values()), wall, delta=0.002 * len(seconds) + 0.002)
        # ... and to the time the report was written (after it only the final rename of the folder happens), which
        # this side counts from the exec: the program's start-up (loading its libraries, 1 s and more under a
        # sanitizer) is outside its wall time.
        report_done = next(t for t, l in lines if re.match(r"seqtopo map: \[\d+/\d+\] report done in", l))
        start = time.monotonic()
        subprocess.run([CLI, "--version"], capture_output=True, check=True, timeout=60)
        startup = time.monotonic() - start
        self.assertLess(abs(wall - report_done), 0.6 + startup, (wall, report_done, startup))

    def test_seqtopo_progress_none_is_quiet(self):
        env = dict(os.environ, SEQTOPO_PROGRESS="none")
        r = subprocess.run([CLI, "map", os.path.join(DATA, "rtabmap-corridor"), "--out", os.path.join(self.dir, "o")],
                           capture_output=True, text=True, env=env, timeout=300)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("[1/", r.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)
