"""What `pip install .` shows while it builds: pip hides a build backend's output unless run with -v, so the
build writes its stages and the compiler's progress straight to the terminal (/dev/tty) when there is one:

    seqtopo build: configuring with CMake in build/pip-py311
    seqtopo build: compiling 37 % (91/246)
    seqtopo build: done in 412 s: seqtopo._core and the seqtopo command

Without a terminal (CI, a log) nothing extra is written; `pip install -v .` shows the whole build instead.
"""

import os
import re
import subprocess
import sys
import time

_NINJA = re.compile(rb"^\[(\d+)/(\d+)\]")
_MAKE = re.compile(rb"^\[\s*(\d+)%\]")


class BuildProgress:
    def __init__(self, stream=None):
        self.start = time.monotonic()
        self.stream = stream
        if self.stream is None:
            try:
                self.stream = open("/dev/tty", "w")
            except OSError:
                self.stream = None
        self.last = 0.0

    def say(self, text, same_line=False):
        if not self.stream:
            return
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
                self.last = now
                if ninja:
                    done, total = int(ninja.group(1)), int(ninja.group(2))
                    self.say("compiling %3d %% (%d/%d), %.0f s" % (100 * done // max(total, 1), done, total,
                                                                    now - self.start), same_line=True)
                else:
                    self.say("compiling %3d %%, %.0f s" % (int(make.group(1)), now - self.start), same_line=True)
                shown = True
        status = process.wait()
        if shown and self.stream:
            self.stream.write("\r\x1b[2K")
            self.stream.flush()
        if status != 0:
            self.say("failed: %s (pip install -v . shows the whole output)" % " ".join(command[:3]))
            raise subprocess.CalledProcessError(status, command)

    def done(self, text):
        self.say("done in %.0f s: %s" % (time.monotonic() - self.start, text))
