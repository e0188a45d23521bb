"""What `pip install .` shows while it builds: pip hides a build backend's output unless run with -v (it reads
the build's stdout and stderr through a pipe and prints only a spinner, or "still running" lines in a log), so the
build writes its stages and the compiler's progress past pip:

    seqtopo build: configuring with CMake in build/pip-py311
    seqtopo build: compiling  37 % (40/108), 95 s
    seqtopo build: done in 412 s: seqtopo._core

- on a terminal (/dev/tty), one line redrawn in place;
- without one (CI, `pip install . 2>&1 | tee log`, a notebook's cell), as whole lines every 10 % to the standard
  error of the nearest process above the build whose standard error is not the build's own pipe: pip's, which is
  the user's log. When no such process is found nothing extra is written; `pip install -v .` shows everything.
"""

import os
import re
import subprocess
import sys
import time

_NINJA = re.compile(rb"^\[(\d+)/(\d+)\]")
_MAKE = re.compile(rb"^\[\s*(\d+)%\]")


def _identity(path):
    try:
        st = os.stat(path)
    except OSError:
        return None
    return st.st_dev, st.st_ino


def _parent(pid):
    try:
        with open("/proc/%d/stat" % pid, "rb") as stat:
            # "pid (comm) state ppid ...": comm may hold spaces and parentheses, so split after the last ')'.
            return int(stat.read().rsplit(b")", 1)[1].split()[1])
    except (OSError, IndexError, ValueError):
        return 0


def log_stream(start_pid=None):
    """The standard error of the nearest ancestor whose standard error is not the pipe this build's output goes
    into (pip's own, the user's log), opened for appending; None when there is none to be found (not Linux, or
    every ancestor writes into the same pipe)."""
    ours = {_identity("/proc/self/fd/1"), _identity("/proc/self/fd/2")}
    pid = os.getppid() if start_pid is None else start_pid
    for _ in range(8):
        if pid <= 1:
            return None
        theirs = _identity("/proc/%d/fd/2" % pid)
        if theirs is not None and theirs not in ours:
            try:
                return open("/proc/%d/fd/2" % pid, "a")
            except OSError:
                return None
        pid = _parent(pid)
    return None


class BuildProgress:
    def __init__(self, stream=None, terminal=None):
        self.start = time.monotonic()
        self.stream = stream
        self.terminal = terminal if terminal is not None else stream is not None and _isatty(stream)
        if self.stream is None:
            try:
                self.stream = open("/dev/tty", "w")
                self.terminal = True
            except OSError:
                self.stream = log_stream()
                self.terminal = False
        self.last = 0.0
        self.last_percent = -100

    def say(self, text, same_line=False):
        if not self.stream:
            return
        same_line = same_line and self.terminal  # a log gets whole lines
        self.stream.write(("\r\x1b[2K" if same_line else "") + "seqtopo build: " + text + ("" if same_line else "\n"))
        self.stream.flush()

    def run(self, command, what):
        """Runs command, its output going to pip's log (stdout), the percentage of a build to the terminal."""
        self.say(what)
        process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        shown = False
        for line in process.stdout:
            sys.stdout.buffer.write(line)
            ninja, make = _NINJA.match(line), _MAKE.match(line)
            now = time.monotonic()
            if (ninja or make) and now - self.last > 0.5:
                if ninja:
                    done, total = int(ninja.group(1)), int(ninja.group(2))
                    percent = 100 * done // max(total, 1)
                    text = "compiling %3d %% (%d/%d), %.0f s" % (percent, done, total, now - self.start)
                else:
                    percent = int(make.group(1))
                    text = "compiling %3d %%, %.0f s" % (percent, now - self.start)
                # A terminal's line is redrawn twice a second; a log gets a line every 10 %.
                if self.terminal or percent >= self.last_percent + 10:
                    self.last = now
                    self.last_percent = percent
                    self.say(text, same_line=True)
                    shown = True
        status = process.wait()
        if shown and self.stream and self.terminal:
            self.stream.write("\r\x1b[2K")
            self.stream.flush()
        if status != 0:
            self.say("failed: %s (pip install -v . shows the whole output)" % " ".join(command[:3]))
            raise subprocess.CalledProcessError(status, command)

    def done(self, text):
        self.say("done in %.0f s: %s" % (time.monotonic() - self.start, text))


def _isatty(stream):
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False
